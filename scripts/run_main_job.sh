#!/usr/bin/env bash
# The README's first command: sets everything up, then runs the main job on real data.
# Main job: a real scan (the CGAL bunny, 37,706 vertices) is photographed virtually (40 calibrated
# photographs of a glossy, spatially varying material with cast shadows, written as a MeshLab
# project), the scan and the photographs (raster layers) are opened in pymeshlab 2025.7 and our
# filter "Fit Radiance Functions from Rasters" fits PB(4) radiance functions; the result is saved in
# the radiance PLY format, and a picture compares a photograph with the fitted radiance rendered from
# the same camera (photo | rendering | 4x difference). The fitted mesh is then simplified
# (radiance-aware, with levels of detail) and compared in image space with the colour and geometry
# baselines and with directional reduction: table, heat maps and an error-memory plot. Then a normal
# map is baked from the scan onto a copy decimated by MeshLab to 2 %, and PRT runs on the column scene
# (transfer, adaptive subdivision, relighting), followed by the adaptive/uniform evaluations.
# The job itself is the Python batch script scripts/main_job.py (pymeshlab with our package, which
# this script installs into build/python-venv first); the meshlabserver 2020.09 path is covered by
# the integration tests (scripts/test.sh).
# Outputs go to out/ (override with OUT_DIR).
set -euo pipefail
REPO="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
BUILD_DIR="${BUILD_DIR:-$REPO/build}"
OUT_DIR="${OUT_DIR:-$REPO/out}"
DATA="${RADIANCE_DATA_CACHE:-$REPO/data-cache}"
export BUILD_DIR
source "$REPO/scripts/compiler_cache.sh"  # the package build below reuses the cmake build's core objects

bash "$REPO/scripts/setup.sh"

# Our package into the venv that has pymeshlab 2025.7 (pip install compiles the cores and the
# MeshLab 2025.07 plugins with scikit-build-core, incrementally, in build/python-package).
VENV="$BUILD_DIR/python-venv"
echo "[main] pip install of the Python package into $VENV (compiles the MeshLab 2025.07 plugins)"
"$VENV/bin/python" -m pip install -q --disable-pip-version-check --no-build-isolation --no-deps "$REPO"

# The job, with the installed package's plugins (not a development folder set in the environment).
env -u PYMESHLAB_RADIANCE_PLUGIN_DIR -u PYTHONPATH "$VENV/bin/python" "$REPO/scripts/main_job.py" \
    --build-dir "$BUILD_DIR" --out-dir "$OUT_DIR" --data-dir "$DATA"
