#!/usr/bin/env bash
# "Import Cameras as Raster Layers" through the real meshlabserver 2020.09: virtual photographs of a
# sphere, their MeshLab project converted here to a COLMAP text model (PINHOLE cameras, written from
# the .mlp camera conventions by an independent Python script), imported back:
#  - the log counts the cameras; the saved project (-w) has every raster, each projecting points
#    where the original project's camera does (within 0.01 pixel);
#  - the fit from the imported rasters equals the fit from the original project (same photographs,
#    same cameras up to float rounding): vertex colours within 1 8-bit level;
#  - an unsupported COLMAP camera model is refused by name and the mesh is unchanged.
source "$(dirname "$0")/lib.sh"

"$MAKE_SCENE" sphere --level 3 -o "$WORK/sphere.ply"
"$VIRTUAL_ACQUISITION" "$WORK/sphere.ply" -o "$WORK/photos" --views 8 --size 160x120 --no-variation \
    >"$WORK/acquisition.log" 2>&1 || { cat "$WORK/acquisition.log" >&2; fail "virtual acquisition failed"; }

# The project's cameras as a COLMAP text model: vcg rows (right, up, backward) -> COLMAP rows
# (right, down, forward); t = -R C; fx = FocalMm / PixelSizeMm.x; cx = CenterPx.x;
# cy = height - CenterPx.y (vcg's py counts from the bottom edge, COLMAP's v from the top).
mkdir -p "$WORK/colmap"
python3 - "$WORK/photos/project.mlp" "$WORK/colmap" <<'PY' || fail "cannot write the COLMAP model"
import math, sys, xml.etree.ElementTree as ET
import numpy as np
root = ET.parse(sys.argv[1]).getroot()
cams, imgs = [], []
for i, r in enumerate(root.iter("MLRaster"), start=1):
    c = r.find("VCGCamera")
    get = lambda k: np.array([float(x) for x in c.get(k).split()])
    rows = get("RotationMatrix").reshape(4, 4)[:3, :3]
    R = np.array([rows[0], -rows[1], -rows[2]])
    C = -get("TranslationVector")[:3]
    t = -R @ C
    w, h = get("ViewportPx").astype(int)
    fx = float(get("FocalMm")[0] / get("PixelSizeMm")[0])
    fy = float(get("FocalMm")[0] / get("PixelSizeMm")[1])
    cx, cy = float(get("CenterPx")[0]), float(h - get("CenterPx")[1])
    t = [float(x) for x in t]
    # Rotation matrix -> unit quaternion (w, x, y, z).
    qw = math.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    qx = math.copysign(math.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    qy = math.copysign(math.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    qz = math.copysign(math.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    cams.append(f"{i} PINHOLE {w} {h} {fx!r} {fy!r} {cx!r} {cy!r}")
    imgs.append(f"{i} {qw!r} {qx!r} {qy!r} {qz!r} {t[0]!r} {t[1]!r} {t[2]!r} {i} {r.find('Plane').get('fileName')}\n")
open(sys.argv[2] + "/cameras.txt", "w").write("# CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n" + "\n".join(cams) + "\n")
open(sys.argv[2] + "/images.txt", "w").write("# IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n" + "\n".join(imgs))
PY

import_params() {
    echo "camerafile=$1"
    echo "imagefolder=$2"
    echo "cachefolder=$WORK/cache"
}
mapfile -t IMPORT < <(import_params "$WORK/colmap/images.txt" "$WORK/photos")
filter_script "$WORK/import.mlx" "Import Cameras as Raster Layers" "${IMPORT[@]}"
run_meshlabserver "$WORK/import.log" -i "$WORK/photos/mesh.ply" -s "$WORK/import.mlx" -w "$WORK/imported.mlp" \
    || { cat "$WORK/import.log" >&2; fail "import failed"; }
grep -qF "COLMAP text model '$WORK/colmap/images.txt': 8 cameras usable, 0 skipped" "$WORK/import.log" \
    || { cat "$WORK/import.log" >&2; fail "no camera count in the log"; }
grep -qE "Added 8 raster layers in [0-9.]+ s" "$WORK/import.log" || { cat "$WORK/import.log" >&2; fail "no summary in the log"; }

python3 - "$WORK/photos/project.mlp" "$WORK/imported.mlp" <<'PY' || fail "imported cameras differ from the project's"
import sys, xml.etree.ElementTree as ET
import numpy as np
def cameras(path):
    out = {}
    for r in ET.parse(path).getroot().iter("MLRaster"):
        c = r.find("VCGCamera")
        out[r.find("Plane").get("fileName").split("/")[-1]] = {k: np.array([float(x) for x in c.get(k).split()]) for k in
            ("TranslationVector", "RotationMatrix", "FocalMm", "PixelSizeMm", "CenterPx", "ViewportPx")}
    return out
def project(c, X):
    R = c["RotationMatrix"].reshape(4, 4)[:3, :3]
    p = R @ (X + c["TranslationVector"][:3])
    return np.array([p[0] * c["FocalMm"][0] / -p[2] / c["PixelSizeMm"][0] + c["CenterPx"][0],
                     p[1] * c["FocalMm"][0] / -p[2] / c["PixelSizeMm"][1] + c["CenterPx"][1]])
a, b = cameras(sys.argv[1]), cameras(sys.argv[2])
assert sorted(a) == sorted(b) and len(a) == 8, (sorted(a), sorted(b))
rng = np.random.default_rng(1)
worst = 0.0
for name in a:
    assert np.array_equal(a[name]["ViewportPx"], b[name]["ViewportPx"])
    for X in rng.uniform(-1, 1, (50, 3)):
        worst = max(worst, np.abs(project(a[name], X) - project(b[name], X)).max())
assert worst < 0.01, worst
print(f"imported cameras project within {worst:.2e} px of the project's")
PY

# The fit from the imported rasters against the fit from the project.
fit_mlx "$WORK/fit.mlx" 0 2 false 0
run_meshlabserver "$WORK/fit_project.log" -i "$WORK/photos/mesh.ply" -p "$WORK/photos/project.mlp" -s "$WORK/fit.mlx" \
    -o "$WORK/from_project.ply" -m vc || { cat "$WORK/fit_project.log" >&2; fail "fit from the project failed"; }
{
    echo '<!DOCTYPE FilterScript>'; echo '<FilterScript>'
    sed -n '/<filter /,/<\/filter>/p' "$WORK/import.mlx"
    sed -n '/<filter /,/<\/filter>/p' "$WORK/fit.mlx"
    echo '</FilterScript>'
} >"$WORK/import_fit.mlx"
run_meshlabserver "$WORK/fit_import.log" -i "$WORK/photos/mesh.ply" -s "$WORK/import_fit.mlx" -o "$WORK/from_import.ply" -m vc \
    || { cat "$WORK/fit_import.log" >&2; fail "fit from the imported rasters failed"; }
python3 - "$WORK/from_project.ply" "$WORK/from_import.ply" "$PLY_READER" <<'PY' || fail "fits differ"
import sys, importlib.util
import numpy as np
spec = importlib.util.spec_from_file_location("ply_reader", sys.argv[3]); r = importlib.util.module_from_spec(spec); spec.loader.exec_module(r)
def colours(path):
    v = r.read_ply(path)["elements"]["vertex"]
    return np.array([v["red"], v["green"], v["blue"]], dtype=float).T
a, b = colours(sys.argv[1]), colours(sys.argv[2])
assert a.shape == b.shape and a.max() > 50, (a.shape, b.shape, a.max())
diff = np.abs(a - b)
print(f"vertex colours: mean |difference| {diff.mean():.3f}, max {diff.max():.0f} levels")
assert diff.max() <= 1, diff.max()
PY

# Refused: a camera model the import does not read; the mesh is unchanged.
mkdir -p "$WORK/unsupported"
cp "$WORK/colmap/images.txt" "$WORK/unsupported/"
awk '/^#/ {print; next} {printf "%s EUCM %s %s 100 100 80 60 0.5 1.0\n", $1, $3, $4}' "$WORK/colmap/cameras.txt" >"$WORK/unsupported/cameras.txt"
mapfile -t BAD < <(import_params "$WORK/unsupported" "$WORK/photos")
filter_script "$WORK/bad.mlx" "Import Cameras as Raster Layers" "${BAD[@]}"
expect_refusal unsupported_model "camera model EUCM is not supported" "$WORK/photos/mesh.ply" "$WORK/bad.mlx"
note "ok"
