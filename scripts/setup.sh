#!/usr/bin/env bash
# One-stop setup used by both README commands: apt packages, the MeshLab 2020.09 source headers,
# the data cache, configure + build, and the private MeshLab prefix. Idempotent: a second run only
# rebuilds what changed.
#
# Environment knobs:
#   BUILD_DIR       build directory (default: <repo>/build)
#   SKIP_APT=1      do not touch apt (packages already there)
#   SKIP_DATA=1     do not fetch sample data
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
THIRD_PARTY="$REPO/third_party"
JOBS="$(nproc 2>/dev/null || echo 2)"

log() { printf '[setup] %s\n' "$*"; }

SUDO=""
if [ "$(id -u)" != "0" ]; then SUDO="sudo"; fi

APT_PACKAGES=(
  meshlab                      # the real meshlab / meshlabserver and libmeshlab-common.so we link to
  qtbase5-dev libqt5opengl5-dev  # Qt5 headers for the plugin adapters
  libglew-dev                  # MeshLab's GL headers include GLEW
  libeigen3-dev                # Debian removed MeshLab's bundled Eigen; vcglib and our cores use it
  libembree-dev                # ray casting (visibility, PRT transfer, baking)
  libstb-dev                   # stb_image / stb_image_write: JPEG and PNG photographs, PNG output, Radiance .hdr maps
  libpng-dev                   # libpng: 16-bit PNG normal maps (stb_image_write writes only 8-bit PNG)
  libopenexr-dev               # OpenEXR: the HDR environment maps (.exr) used for lighting
  libgtest-dev                 # unit tests
  cmake g++ make dpkg-dev      # build, and apt-get source
  xvfb xauth                   # meshlabserver needs an X display, even for batch work
  libgl1-mesa-dri              # Mesa llvmpipe: software OpenGL under Xvfb (no GPU here)
  imagemagick xdotool          # GUI test: screenshots and key presses
  python3                      # small test helpers (image comparison, PLY checks)
)

apt_missing() {
  local missing=()
  for p in "${APT_PACKAGES[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
  done
  echo "${missing[@]:-}"
}

# Add deb-src entries derived from the machine's own apt configuration (no host is named here):
# every enabled "Types: deb" stanza of *.sources and every "deb " line of sources.list gets a twin.
enable_deb_src() {
  local out=/etc/apt/sources.list.d/radiance-tools-src.sources
  local outlist=/etc/apt/sources.list.d/radiance-tools-src.list
  [ -f "$out" ] || [ -f "$outlist" ] && return 0
  local tmp; tmp="$(mktemp)"
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    # Only stanzas that carry the debian archive keyring: source packages come from Debian itself.
    awk 'BEGIN{RS=""; ORS="\n\n"} /Types:[ \t]*deb([ \t\n]|$)/ && /debian-archive-keyring/ {
           sub(/Types:[ \t]*deb/, "Types: deb-src"); print }' "$f" >> "$tmp"
  done
  if [ -s "$tmp" ]; then
    $SUDO cp "$tmp" "$out"
  elif [ -f /etc/apt/sources.list ]; then
    grep -E '^[[:space:]]*deb[[:space:]]' /etc/apt/sources.list | sed -E 's/^([[:space:]]*)deb /\1deb-src /' > "$tmp" || true
    [ -s "$tmp" ] && $SUDO cp "$tmp" "$outlist"
  fi
  rm -f "$tmp"
  APT_UPDATED=0
}

APT_UPDATED=0
apt_update_once() {
  if [ "$APT_UPDATED" = "0" ]; then
    log "apt-get update"
    $SUDO apt-get update -qq
    APT_UPDATED=1
  fi
}

if [ "${SKIP_APT:-0}" != "1" ]; then
  missing="$(apt_missing)"
  if [ -n "$missing" ]; then
    apt_update_once
    log "installing: $missing"
    # shellcheck disable=SC2086
    $SUDO apt-get install -y -qq --no-install-recommends $missing
  else
    log "apt packages already installed"
  fi
fi

# MeshLab source headers: the Debian source package of exactly the installed binary version.
MESHLAB_VERSION="$(dpkg-query -W -f='${Version}' meshlab)"
MESHLAB_UPSTREAM="${MESHLAB_VERSION#*:}"; MESHLAB_UPSTREAM="${MESHLAB_UPSTREAM%-*}"
MESHLAB_SRC=""
for d in "$THIRD_PARTY"/meshlab-*; do
  if [ -f "$d/src/common/interfaces.h" ] && [ -f "$d/.debian-version" ] && \
     [ "$(cat "$d/.debian-version")" = "$MESHLAB_VERSION" ]; then MESHLAB_SRC="$d"; fi
done
if [ -z "$MESHLAB_SRC" ]; then
  log "fetching the MeshLab $MESHLAB_VERSION source package (headers only are used)"
  enable_deb_src
  apt_update_once
  mkdir -p "$THIRD_PARTY/src-download"
  ( cd "$THIRD_PARTY/src-download" && apt-get source --download-only -qq "meshlab=$MESHLAB_VERSION" )
  ( cd "$THIRD_PARTY/src-download" && rm -rf extracted && dpkg-source --no-check -x ./*.dsc extracted >/dev/null )
  rm -rf "$THIRD_PARTY/meshlab-$MESHLAB_UPSTREAM"
  mv "$THIRD_PARTY/src-download/extracted" "$THIRD_PARTY/meshlab-$MESHLAB_UPSTREAM"
  echo "$MESHLAB_VERSION" > "$THIRD_PARTY/meshlab-$MESHLAB_UPSTREAM/.debian-version"
  rm -rf "$THIRD_PARTY/src-download"
  MESHLAB_SRC="$THIRD_PARTY/meshlab-$MESHLAB_UPSTREAM"
fi
log "MeshLab source tree: $MESHLAB_SRC"

if [ "${SKIP_DATA:-0}" != "1" ]; then
  "$REPO/samples/fetch_data.sh"
fi

log "configuring in $BUILD_DIR"
cmake -S "$REPO" -B "$BUILD_DIR" -DCMAKE_BUILD_TYPE=Release -DMESHLAB_SOURCE_DIR="$MESHLAB_SRC" >/dev/null
log "building with $JOBS jobs"
cmake --build "$BUILD_DIR" -j "$JOBS"
log "private MeshLab prefix"
cmake --build "$BUILD_DIR" --target meshlab_prefix >/dev/null
log "done"
