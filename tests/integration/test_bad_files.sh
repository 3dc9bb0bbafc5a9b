#!/usr/bin/env bash
# Truncated, garbage, empty and NaN-carrying .rply files are refused by the real meshlabserver
# through our IO plugin: no crash, nothing written, and our message in the output.
source "$(dirname "$0")/lib.sh"

"$MAKE_SCENE" sphere --level 2 -o "$WORK/sphere.ply"
create_radiance_mlx "$WORK/create.mlx" 0 4 false 0.5 0
run_meshlabserver "$WORK/create.log" -i "$WORK/sphere.ply" -o "$WORK/good.rply" -m vc vn -s "$WORK/create.mlx" \
    || { cat "$WORK/create.log" >&2; fail "could not make the valid file"; }
size=$(stat -c %s "$WORK/good.rply")

head -c $((size / 2)) "$WORK/good.rply" >"$WORK/truncated.rply"
head -c 200 "$WORK/good.rply" >"$WORK/truncated_header.rply"
: >"$WORK/empty.rply"
head -c 5000 /dev/urandom >"$WORK/garbage.rply"
# A NaN in the first coefficient of the last vertex (independent byte surgery in Python).
python3 - "$WORK/good.rply" "$WORK/nan.rply" <<'PY'
import sys, struct
sys.path.insert(0, sys.argv[0] and __import__("os").environ["RADIANCE_SOURCE_DIR"] + "/tests/integration")
import ply_reader
src, dst = sys.argv[1], sys.argv[2]
data = bytearray(open(src, "rb").read())
ply = ply_reader.read_ply(src)
header_end = data.index(b"end_header\n") + len(b"end_header\n")
names = [p[0] for p in ply["layout"]["vertex"]]
sizes = [p[1] for p in ply["layout"]["vertex"]]
stride = sum(sizes)
offset = sum(sizes[: names.index("rf_r_0")])
count = len(ply["elements"]["vertex"]["x"])
pos = header_end + (count - 1) * stride + offset
data[pos:pos + 4] = struct.pack("<f", float("nan"))
open(dst, "wb").write(bytes(data))
PY

for case in "truncated:truncat" "truncated_header:truncat|header" "empty:empty|not a PLY" "garbage:not a PLY" "nan:NaN|finite"; do
    bad="${case%%:*}"; expected_phrase="${case#*:}"
    status=0
    run_meshlabserver "$WORK/$bad.log" -i "$WORK/$bad.rply" -o "$WORK/$bad.out.rply" -m vc vn -l "$WORK/$bad.openlog" || status=$?
    [ "$status" -ne 0 ] || fail "$bad: meshlabserver reported success"
    [ ! -e "$WORK/$bad.out.rply" ] || fail "$bad: a file was written from a bad input"
    # Our IO plugin's own message (meshlabserver prints it as "Opening Failure: ...").
    cat "$WORK/$bad.openlog" >>"$WORK/$bad.log" 2>/dev/null || true
    grep -qF "cannot load" "$WORK/$bad.log" || { cat "$WORK/$bad.log" >&2; fail "$bad: our error message is missing"; }
    grep -qiE "$expected_phrase" "$WORK/$bad.log" || { cat "$WORK/$bad.log" >&2; fail "$bad: message does not say '$expected_phrase'"; }
    note "$bad refused (status $status)"
done
note "ok"
