#!/usr/bin/env bash
# tools/normal_map_error on a case with a known answer; needs no MeshLab and no plugin of ours.
# Target: the unit square in z = 0 (two triangles, UV = (x, y)). Map: 64 x 64, 16-bit and 8-bit
# PNGs written here by Python (zlib only) with, at each texel centre (u, v), the normal field
# n(u, v) = normalize(0.4 (u - 0.3), 0.6 (v - 0.2), 1) (not symmetric in v: a flipped v convention
# would show). Scan: a 40 x 40 grid of points 0.01 above the square with normals n(x, y) (NOFF),
# plus 25 points 5 units away.
#  - exact normals: mean error below 0.05 degrees (16-bit), below 0.5 degrees (8-bit quantisation);
#  - scan normals rotated by 10 degrees about x: mean within 0.3 degrees of 10;
#  - --max-distance 1 skips exactly the 25 far points.
# Expects RADIANCE_BUILD_DIR (set by ctest); MESHLAB_PREFIX is not used.
set -euo pipefail
: "${RADIANCE_BUILD_DIR:?set by ctest}"
TOOL="$RADIANCE_BUILD_DIR/tools/normal_map_error"
WORK="$RADIANCE_BUILD_DIR/tests/integration-work/test_normal_map_error_tool"
rm -rf "$WORK"; mkdir -p "$WORK"
fail() { echo "FAIL [test_normal_map_error_tool]: $*" >&2; exit 1; }

python3 - "$WORK" <<'PY'
import math, struct, sys, zlib
work = sys.argv[1]
def field(u, v):
    x, y, z = 0.4 * (u - 0.3), 0.6 * (v - 0.2), 1.0
    l = math.sqrt(x * x + y * y + z * z)
    return (x / l, y / l, z / l)
def png(path, w, h, rows, depth):
    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xffffffff)
    fmt = ">" + ("H" if depth == 16 else "B") * (3 * w)
    raw = b"".join(b"\0" + struct.pack(fmt, *r) for r in rows)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, depth, 2, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))
W = H = 64
for depth, top in ((16, 65535), (8, 255)):
    rows = []
    for r in range(H):
        row = []
        for c in range(W):
            n = field((c + 0.5) / W, 1 - (r + 0.5) / H)   # rows top to bottom, v up
            row += [int(round((x + 1) / 2 * top)) for x in n]
        rows.append(row)
    png(f"{work}/map{depth}.png", W, H, rows, depth)
with open(f"{work}/target.obj", "w") as f:
    f.write("v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3\nf 1/1 3/3 4/4\n")
def scan(path, tilt_deg):
    t = math.radians(tilt_deg)
    pts = []
    for i in range(40):
        for j in range(40):
            x, y = (i + 0.5) / 40, (j + 0.5) / 40
            n = field(x, y)
            n = (n[0], math.cos(t) * n[1] - math.sin(t) * n[2], math.sin(t) * n[1] + math.cos(t) * n[2])
            pts.append((x, y, 0.01) + n)
    for k in range(25):
        pts.append((0.1 * k, 0.5, 5.0, 0.0, 0.0, 1.0))
    with open(path, "w") as f:
        f.write(f"NOFF\n{len(pts)} 0 0\n")
        for p in pts:
            f.write(" ".join(f"{v:.9g}" for v in p) + "\n")
scan(f"{work}/scan.off", 0)
scan(f"{work}/scan_tilted.off", 10)
PY

# mean_of LOG: the mean error printed by the tool.
mean_of() { sed -n 's/.*: mean \([0-9.]*\) .*/\1/p' "$1"; }
check() {  # check NAME EXPR: fails unless python3 evaluates EXPR to True
    python3 -c "import sys; sys.exit(0 if ($2) else 1)" || fail "$1"
}

"$TOOL" "$WORK/scan.off" "$WORK/target.obj" "$WORK/map16.png" --max-distance 1 --histogram >"$WORK/exact16.log" 2>&1 \
    || { cat "$WORK/exact16.log" >&2; fail "tool failed on the 16-bit map"; }
grep -q "over 1600 scan vertices" "$WORK/exact16.log" || { cat "$WORK/exact16.log" >&2; fail "not 1600 vertices compared"; }
grep -q "^skipped: 25 scan vertices farther" "$WORK/exact16.log" || { cat "$WORK/exact16.log" >&2; fail "not 25 skipped"; }
m=$(mean_of "$WORK/exact16.log"); check "16-bit exact mean $m >= 0.05" "$m < 0.05"

"$TOOL" "$WORK/scan.off" "$WORK/target.obj" "$WORK/map8.png" --max-distance 1 >"$WORK/exact8.log" 2>&1 \
    || { cat "$WORK/exact8.log" >&2; fail "tool failed on the 8-bit map"; }
m8=$(mean_of "$WORK/exact8.log"); check "8-bit exact mean $m8 >= 0.5" "$m8 < 0.5"

"$TOOL" "$WORK/scan_tilted.off" "$WORK/target.obj" "$WORK/map16.png" --max-distance 1 >"$WORK/tilted.log" 2>&1 \
    || { cat "$WORK/tilted.log" >&2; fail "tool failed on the tilted scan"; }
mt=$(mean_of "$WORK/tilted.log"); check "tilted mean $mt not within 0.3 of 10" "abs($mt - 10) < 0.3"

# Without --max-distance the far points count (their normal (0,0,1) is compared too): 1625 vertices.
"$TOOL" "$WORK/scan.off" "$WORK/target.obj" "$WORK/map16.png" >"$WORK/all.log" 2>&1 || fail "tool failed without --max-distance"
grep -q "over 1625 scan vertices" "$WORK/all.log" || { cat "$WORK/all.log" >&2; fail "not 1625 vertices"; }
echo "[test_normal_map_error_tool] exact 16-bit mean $m, 8-bit mean $m8, tilted 10 deg mean $mt: ok"
