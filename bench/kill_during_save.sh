#!/usr/bin/env bash
# kill_during_save.sh [ROUNDS] [VERTICES]: SIGKILLs writers of a large .rply in the middle of their
# save, ROUNDS times each, and checks what the atomic write promises (common/io/radiance_ply.h):
#   - after every kill the target is either the old file or the complete new one, never half-written;
#   - the killed writer's temporary file <target>.part-<pid>-... is stale, and the next save to that
#     target removes it (so after the final, uninterrupted save no temporary file remains).
# Writers: Debian's meshlabserver with our IO plugin (open a big .rply, save it to the target), and
# the numpy writer pymeshlab_radiance.rply (its own temporary files follow the same rule).
# The kill lands when the temporary file has reached a random fraction of the final size, so it
# always hits the write itself. Not part of CI (it takes a minute or two and needs Xvfb).
#
# Environment: RADIANCE_BUILD_DIR (default <repo>/build), MESHLAB_PREFIX (default
# $RADIANCE_BUILD_DIR/meshlab-prefix: a private prefix with our io_radiance plugin), PYTHON (a python
# with numpy; default python3), WORK (scratch folder; default $RADIANCE_BUILD_DIR/kill-during-save).
set -euo pipefail
rounds=${1:-5}
vertices=${2:-1000000}
root=$(cd "$(dirname "$0")/.." && pwd)
build=${RADIANCE_BUILD_DIR:-$root/build}
prefix=${MESHLAB_PREFIX:-$build/meshlab-prefix}
python=${PYTHON:-python3}
work=${WORK:-$build/kill-during-save}
server="$prefix/bin/meshlabserver"
[ -x "$server" ] || { echo "no meshlabserver in $prefix/bin: build the prefix first (cmake --build build --target meshlab_prefix)" >&2; exit 2; }
rm -rf "$work"
mkdir -p "$work/config"
export XDG_CONFIG_HOME="$work/config" HOME="$work"

# One X server for every run, so that the writer's own pid is the one we kill.
display=":$((100 + $$ % 400))"
Xvfb "$display" -screen 0 640x480x24 >/dev/null 2>&1 &
xvfb=$!
trap 'kill "$xvfb" 2>/dev/null || true' EXIT
export DISPLAY="$display"
sleep 1

# The inputs: a big PB4 mesh with an extra block (new content) and a small one (old content).
cat >"$work/make_inputs.py" <<EOF
import importlib.util, sys
import numpy as np
spec = importlib.util.spec_from_file_location("rply", "$root/python/pymeshlab_radiance/rply.py")
rply = importlib.util.module_from_spec(spec); sys.modules["rply"] = rply; spec.loader.exec_module(rply)
def mesh(n, seed):
    rng = np.random.default_rng(seed)
    normals = rng.normal(size=(n, 3)); normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    tangents = np.cross(normals, [0.0, 0.0, 1.0]) + np.cross(normals, [0.0, 1.0, 0.0]) * 1e-3
    tangents -= normals * np.sum(tangents * normals, axis=1, keepdims=True)
    tangents /= np.linalg.norm(tangents, axis=1, keepdims=True)
    m = rply.RadianceMesh(positions=rng.random((n, 3), dtype=np.float32),
                          faces=rng.integers(0, n, (2 * n, 3)).astype(np.int32),
                          normals=normals.astype(np.float32), basis="PB4", tangents=tangents.astype(np.float32),
                          coefficients=rng.random((n, 3, 15), dtype=np.float32))
    m.blocks["curvature"] = rply.Block(rng.random((n, 2), dtype=np.float32), {"unit": "1/m"})
    return m
rply.write_rply("$work/big.rply", mesh($vertices, 1))
rply.write_rply("$work/old.rply", mesh(100, 2))
EOF
"$python" "$work/make_inputs.py"
cat >"$work/python_writer.py" <<EOF
import importlib.util, sys
spec = importlib.util.spec_from_file_location("rply", "$root/python/pymeshlab_radiance/rply.py")
rply = importlib.util.module_from_spec(spec); sys.modules["rply"] = rply; spec.loader.exec_module(rply)
mesh = rply.read_rply(sys.argv[1])
print("read", flush=True)
rply.write_rply(sys.argv[2], mesh)
EOF

# start_save WRITER TARGET: starts a save in the background; $! is the writer process itself.
start_save() {
    if [ "$1" = meshlab ]; then
        "$server" -i "$work/big.rply" -o "$2" -m vc vn vq >"$work/meshlab.log" 2>&1 &
    else
        "$python" "$work/python_writer.py" "$work/big.rply" "$2" >"$work/python.log" 2>&1 &
    fi
}
save() { start_save "$1" "$2"; wait $! || { echo "FAIL: $1 could not save $2" >&2; cat "$work/$1.log" >&2; exit 1; }; }
parts() { find "$work" -maxdepth 1 -name "$(basename "$1").part-*" | wc -l; }
old_sum=$(sha256sum <"$work/old.rply")

failures=0
for writer in meshlab python; do
    # The complete new file, written without interruption.
    save "$writer" "$work/reference_$writer.rply"
    new_sum=$(sha256sum <"$work/reference_$writer.rply")
    size=$(stat -c %s "$work/reference_$writer.rply")
    echo "$writer: new file $size bytes ($vertices vertices, PB4 + a 2-float block); old file $(stat -c %s "$work/old.rply") bytes"
    target="$work/target_$writer.rply"
    cp "$work/old.rply" "$target"
    killed_mid_write=0
    for round in $(seq 1 "$rounds"); do
        fraction=$(( (RANDOM % 90) + 5 ))  # percent of the final size written when the kill lands
        start_save "$writer" "$target"
        pid=$!
        # This writer's temporary file is <target>.part-<pid>-...: wait until it holds `fraction` %.
        hit=""
        for _ in $(seq 1 12000); do
            part=$(find "$work" -maxdepth 1 -name "$(basename "$target").part-$pid-*" -printf '%s %p\n' 2>/dev/null | head -n 1)
            if [ -n "$part" ] && [ "${part%% *}" -ge $(( size / 100 * fraction )) ]; then hit=${part#* }; break; fi
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.01
        done
        kill -KILL "$pid" 2>/dev/null || true
        wait "$pid" 2>/dev/null || true
        sum=$(sha256sum <"$target")
        state=other
        [ "$sum" = "$old_sum" ] && state=old
        [ "$sum" = "$new_sum" ] && state=new
        stale=$(parts "$target")
        [ -n "$hit" ] && killed_mid_write=$((killed_mid_write + 1))
        echo "$writer round $round: killed at ${fraction}% of the write${hit:+ (temporary file at $(stat -c %s "$hit" 2>/dev/null || echo '?') bytes)}: the target is the $state file; $stale stale temporary file(s)"
        if [ "$state" = other ]; then echo "FAIL: $target is neither the old nor the new file" >&2; failures=$((failures + 1)); fi
        # Each save removes the temporaries of the writers killed before it: only the last one stays.
        if [ "$stale" -gt 1 ]; then echo "FAIL: $stale temporary files: the saves did not remove the stale ones" >&2; failures=$((failures + 1)); fi
    done
    [ "$killed_mid_write" -gt 0 ] || { echo "FAIL: no kill landed during a write" >&2; failures=$((failures + 1)); }
    save "$writer" "$target"
    stale=$(parts "$target")
    if [ "$(sha256sum <"$target")" != "$new_sum" ] || [ "$stale" -ne 0 ]; then
        echo "FAIL: after a complete save the target is $( [ "$(sha256sum <"$target")" = "$new_sum" ] && echo complete || echo wrong) and $stale temporary file(s) are left" >&2
        failures=$((failures + 1))
    else
        echo "$writer: $killed_mid_write of $rounds kills landed mid-write; after the next complete save the target is the new file and no temporary file remains"
    fi
done
[ "$failures" -eq 0 ] && echo "ok" || { echo "$failures failure(s)" >&2; exit 1; }
