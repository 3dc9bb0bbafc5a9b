#!/usr/bin/env bash
# Fetches the real meshes and HDR environment maps listed in docs (data.md) into a local cache.
#
#   samples/fetch_data.sh                    fetch what is missing, verify everything
#   samples/fetch_data.sh --write-checksums  fetch, then (re)write samples/data.sha256 from what
#                                            was extracted (maintainers only; commit the result)
#
# Cache directory: $RADIANCE_DATA_CACHE, default <repo>/data-cache (git-ignored). Layout:
#   meshes/armadillo.off bunny00.off fandisk.off ChineseDragon-10kv.off refined_elephant.off
#                                            (libcgal-demo, OFF, positions + faces)
#   meshes/bunny.obj asteroid-low.3ds asteroid-high.3ds                 (glmark2-data)
#   hdr/{city,courtyard,forest,interior,night,studio,sunrise,sunset}.exr (blender-data, CC0,
#       1024x512 equirectangular, DWAB-compressed EXR), hdr/studiolights-license.txt (their licence)
#   hdr/preview_landscape.hdr hdr/preview_studio.hdr                    (qtcreator-data, RGBE)
#   photos/opencv-chessboard/{left,right}{01..09,11..14}.jpg            (opencv-doc: OpenCV's stereo
#       calibration samples, 640x480 greyscale photographs of a 9x6-corner chessboard; calibrated
#       into a MeshLab project by scripts/calibrate_chessboard.py)
#
# Packages are fetched with `apt-get download` (no root, no dependencies) and unpacked with
# `dpkg-deb --fsys-tarfile` in a temporary directory; the .deb files are deleted afterwards.
# When every file is present and matches samples/data.sha256, nothing is downloaded.
set -euo pipefail

SCRIPT_DIR="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
REPO_DIR="$(cd "${SCRIPT_DIR}/.." && pwd)"
CACHE_DIR="${RADIANCE_DATA_CACHE:-${REPO_DIR}/data-cache}"
SUMS_FILE="${SCRIPT_DIR}/data.sha256"

WRITE_SUMS=0
case "${1:-}" in
  "") ;;
  --write-checksums) WRITE_SUMS=1 ;;
  -h|--help) sed -n '2,19p' "${BASH_SOURCE[0]}"; exit 0 ;;
  *) echo "fetch_data.sh: unknown argument '$1' (try --help)" >&2; exit 2 ;;
esac

die() { echo "fetch_data.sh: error: $*" >&2; exit 1; }

for tool in apt-get dpkg-deb tar sha256sum; do
  command -v "$tool" >/dev/null 2>&1 || die "'$tool' not found (a Debian-based system is needed)"
done

# Manifest: one line per file: PACKAGE  PATH-INSIDE-PACKAGE  DESTINATION (relative to the cache).
# For libcgal-demo the path is inside the nested data.tar.gz (INNER_CGAL_TAR below).
INNER_CGAL_TAR="./usr/share/doc/libcgal-dev/data.tar.gz"
GLMARK="./usr/share/glmark2/models"
STUDIO="./usr/share/blender/datafiles/studiolights/world"
QTIMG="./usr/share/qtcreator/qml/qmlpuppet/mockfiles/images"
CVDATA="./usr/share/doc/opencv-doc/examples/data"
MANIFEST="
libcgal-demo   data/meshes/armadillo.off           meshes/armadillo.off
libcgal-demo   data/meshes/bunny00.off             meshes/bunny00.off
libcgal-demo   data/meshes/fandisk.off             meshes/fandisk.off
libcgal-demo   data/meshes/ChineseDragon-10kv.off  meshes/ChineseDragon-10kv.off
libcgal-demo   data/meshes/refined_elephant.off    meshes/refined_elephant.off
glmark2-data   ${GLMARK}/bunny.obj                 meshes/bunny.obj
glmark2-data   ${GLMARK}/asteroid-low.3ds          meshes/asteroid-low.3ds
glmark2-data   ${GLMARK}/asteroid-high.3ds         meshes/asteroid-high.3ds
blender-data   ${STUDIO}/city.exr                  hdr/city.exr
blender-data   ${STUDIO}/courtyard.exr             hdr/courtyard.exr
blender-data   ${STUDIO}/forest.exr                hdr/forest.exr
blender-data   ${STUDIO}/interior.exr              hdr/interior.exr
blender-data   ${STUDIO}/night.exr                 hdr/night.exr
blender-data   ${STUDIO}/studio.exr                hdr/studio.exr
blender-data   ${STUDIO}/sunrise.exr               hdr/sunrise.exr
blender-data   ${STUDIO}/sunset.exr                hdr/sunset.exr
blender-data   ${STUDIO}/license.txt               hdr/studiolights-license.txt
qtcreator-data ${QTIMG}/preview_landscape.hdr      hdr/preview_landscape.hdr
qtcreator-data ${QTIMG}/preview_studio.hdr         hdr/preview_studio.hdr
opencv-doc     ${CVDATA}/left01.jpg                   photos/opencv-chessboard/left01.jpg
opencv-doc     ${CVDATA}/left02.jpg                   photos/opencv-chessboard/left02.jpg
opencv-doc     ${CVDATA}/left03.jpg                   photos/opencv-chessboard/left03.jpg
opencv-doc     ${CVDATA}/left04.jpg                   photos/opencv-chessboard/left04.jpg
opencv-doc     ${CVDATA}/left05.jpg                   photos/opencv-chessboard/left05.jpg
opencv-doc     ${CVDATA}/left06.jpg                   photos/opencv-chessboard/left06.jpg
opencv-doc     ${CVDATA}/left07.jpg                   photos/opencv-chessboard/left07.jpg
opencv-doc     ${CVDATA}/left08.jpg                   photos/opencv-chessboard/left08.jpg
opencv-doc     ${CVDATA}/left09.jpg                   photos/opencv-chessboard/left09.jpg
opencv-doc     ${CVDATA}/left11.jpg                   photos/opencv-chessboard/left11.jpg
opencv-doc     ${CVDATA}/left12.jpg                   photos/opencv-chessboard/left12.jpg
opencv-doc     ${CVDATA}/left13.jpg                   photos/opencv-chessboard/left13.jpg
opencv-doc     ${CVDATA}/left14.jpg                   photos/opencv-chessboard/left14.jpg
opencv-doc     ${CVDATA}/right01.jpg                  photos/opencv-chessboard/right01.jpg
opencv-doc     ${CVDATA}/right02.jpg                  photos/opencv-chessboard/right02.jpg
opencv-doc     ${CVDATA}/right03.jpg                  photos/opencv-chessboard/right03.jpg
opencv-doc     ${CVDATA}/right04.jpg                  photos/opencv-chessboard/right04.jpg
opencv-doc     ${CVDATA}/right05.jpg                  photos/opencv-chessboard/right05.jpg
opencv-doc     ${CVDATA}/right06.jpg                  photos/opencv-chessboard/right06.jpg
opencv-doc     ${CVDATA}/right07.jpg                  photos/opencv-chessboard/right07.jpg
opencv-doc     ${CVDATA}/right08.jpg                  photos/opencv-chessboard/right08.jpg
opencv-doc     ${CVDATA}/right09.jpg                  photos/opencv-chessboard/right09.jpg
opencv-doc     ${CVDATA}/right11.jpg                  photos/opencv-chessboard/right11.jpg
opencv-doc     ${CVDATA}/right12.jpg                  photos/opencv-chessboard/right12.jpg
opencv-doc     ${CVDATA}/right13.jpg                  photos/opencv-chessboard/right13.jpg
opencv-doc     ${CVDATA}/right14.jpg                  photos/opencv-chessboard/right14.jpg
"

manifest_lines() { printf '%s\n' "$MANIFEST" | sed -e '/^[[:space:]]*$/d'; }

# Expected checksum of a destination path, empty when unknown.
expected_sum() {
  [ -f "$SUMS_FILE" ] || return 0
  awk -v f="$1" '$2 == f { print $1; exit }' "$SUMS_FILE"
}

# 0 when the cached file exists and matches its recorded checksum.
file_ok() {
  local dest="$1" want have
  [ -f "${CACHE_DIR}/${dest}" ] || return 1
  want="$(expected_sum "$dest")"
  [ -n "$want" ] || return 1
  have="$(sha256sum "${CACHE_DIR}/${dest}" | awk '{ print $1 }')"
  [ "$have" = "$want" ]
}

if [ "$WRITE_SUMS" -eq 0 ]; then
  [ -f "$SUMS_FILE" ] || die "checksum file ${SUMS_FILE} is missing (maintainers: run with --write-checksums)"
  while read -r _pkg _src dest; do
    [ -n "$(expected_sum "$dest")" ] || die "${SUMS_FILE} has no checksum for '${dest}' (maintainers: run with --write-checksums)"
  done < <(manifest_lines)
fi

# Packages with at least one missing or mismatching file.
NEEDED=""
while read -r pkg _src dest; do
  if [ "$WRITE_SUMS" -eq 1 ] || ! file_ok "$dest"; then
    case " $NEEDED " in *" $pkg "*) ;; *) NEEDED="${NEEDED:+$NEEDED }$pkg" ;; esac
  fi
done < <(manifest_lines)

if [ -z "$NEEDED" ]; then
  echo "data cache complete (${CACHE_DIR})"
  exit 0
fi

WORK_DIR="$(mktemp -d "${TMPDIR:-/tmp}/radiance-fetch.XXXXXX")"
cleanup() { rm -rf "$WORK_DIR"; }
trap cleanup EXIT
# apt-get download drops privileges to _apt when it can; let that user write here.
chmod 755 "$WORK_DIR"

mkdir -p "${CACHE_DIR}/meshes" "${CACHE_DIR}/hdr" "${CACHE_DIR}/photos/opencv-chessboard"
start_time="$(date +%s)"

for pkg in $NEEDED; do
  echo "fetching ${pkg}..."
  pkg_dir="${WORK_DIR}/${pkg}"
  mkdir -p "$pkg_dir"
  chmod 755 "$pkg_dir"
  if ! (cd "$pkg_dir" && apt-get download "$pkg" >"${pkg_dir}.log" 2>&1); then
    sed -e 's/^/  /' "${pkg_dir}.log" >&2 || true
    die "'apt-get download ${pkg}' failed; run 'apt-get update' (as root) and retry"
  fi
  set -- "$pkg_dir"/"${pkg}"_*.deb
  [ -f "$1" ] || die "'apt-get download ${pkg}' produced no ${pkg}_*.deb"
  [ "$#" -eq 1 ] || die "several ${pkg}_*.deb were downloaded: $*"
  deb="$1"

  # Paths this package must provide.
  srcs=()
  dests=()
  while read -r p src dest; do
    [ "$p" = "$pkg" ] || continue
    srcs+=("$src")
    dests+=("$dest")
  done < <(manifest_lines)

  extract_dir="${pkg_dir}/root"
  mkdir -p "$extract_dir"
  if [ "$pkg" = "libcgal-demo" ]; then
    dpkg-deb --fsys-tarfile "$deb" | tar -x -C "$extract_dir" "$INNER_CGAL_TAR" \
      || die "could not extract ${INNER_CGAL_TAR} from $(basename "$deb")"
    tar -xzf "${extract_dir}/${INNER_CGAL_TAR}" -C "$extract_dir" "${srcs[@]}" \
      || die "could not extract the meshes from the nested data.tar.gz of $(basename "$deb")"
    rm -f "${extract_dir}/${INNER_CGAL_TAR}"
  else
    dpkg-deb --fsys-tarfile "$deb" | tar -x -C "$extract_dir" "${srcs[@]}" \
      || die "could not extract the expected files from $(basename "$deb")"
  fi
  rm -f "$deb"

  for i in "${!srcs[@]}"; do
    src="${extract_dir}/${srcs[$i]}"
    [ -f "$src" ] || die "${srcs[$i]} is missing from ${pkg}"
    mv -f "$src" "${CACHE_DIR}/${dests[$i]}"
  done
  rm -rf "$pkg_dir"
done

if [ "$WRITE_SUMS" -eq 1 ]; then
  (cd "$CACHE_DIR" && while read -r _pkg _src dest; do sha256sum "$dest"; done < <(manifest_lines)) \
    >"${SUMS_FILE}.tmp"
  mv -f "${SUMS_FILE}.tmp" "$SUMS_FILE"
  echo "wrote ${SUMS_FILE}"
fi

# Verify everything against the recorded checksums.
bad=0
while read -r _pkg _src dest; do
  if ! file_ok "$dest"; then
    echo "fetch_data.sh: checksum mismatch for ${CACHE_DIR}/${dest}:" >&2
    echo "  expected $(expected_sum "$dest")" >&2
    echo "  got      $(sha256sum "${CACHE_DIR}/${dest}" 2>/dev/null | awk '{ print $1 }')" >&2
    bad=1
  fi
done < <(manifest_lines)
if [ "$bad" -ne 0 ]; then
  die "the packaged data differ from samples/data.sha256 (a new package version?); the files were kept for inspection"
fi

echo "data cache complete (${CACHE_DIR}), fetched ${NEEDED} in $(( $(date +%s) - start_time )) s"
