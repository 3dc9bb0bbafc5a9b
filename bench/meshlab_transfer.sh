#!/usr/bin/env bash
# MeshLab's own normal-map bake, timed: "Transfer: Vertex Attributes to Texture (1 or 2 meshes)"
# (filter_texture, FP_TRANSFER_TO_TEXTURE) through Debian's meshlabserver under Xvfb, on a scan with
# vertex normals and a target OBJ with per-wedge texture coordinates; the baseline our normal
# baker is compared with (tools/normal_map_error scores both maps).
#
# Usage:
#   bench/meshlab_transfer.sh prepare SCAN OUTDIR FACES [TEXSIZE]
#       Makes a test case with MeshLab itself: OUTDIR/source.ply = SCAN with "Re-Compute Vertex
#       Normals" (by area), OUTDIR/target.obj = "Simplification: Quadric Edge Collapse Decimation"
#       to FACES faces + "Parametrization: Trivial Per-Triangle" (TEXSIZE, default 1024, border 2),
#       saved twice from the same run: OUTDIR/target.ply (for meshlabserver) and OUTDIR/target.obj
#       (for tools/normal_map_error).
#   bench/meshlab_transfer.sh run SOURCE TARGET.ply SIZE UPPERBOUND OUT.png [REPEATS]
#       Bakes a SIZE x SIZE normal map into OUT.png, REPEATS times (default 3), and prints the
#       filter's wall time: the median over the repeats of (load + filter) - (load only), both
#       measured as whole meshlabserver runs (meshlabserver 2020.09 prints no filter timings: its
#       progress callback prints the bare messages, and the load time is only in a comment).
#   Environment: MESHLABSERVER (default /usr/bin/meshlabserver).
#
# What the filter does (rastering.h, TransferColorSampler::AddTextureSample, mode 1 = normal):
#   - it rasterises the target's texture triangles (vcg SurfaceSampling::Texture); for each texel
#     the point p on the target is found, then the NEAREST POINT OF THE SOURCE to p within
#     upperBound (uniform grid over the source faces); texels with nothing within upperBound stay
#     empty (then pull-push filled, vcg's PullPush on the 8-bit image, if pullpush=true).
#   - the normal stored is the source's vertex normals interpolated with the barycentrics of that
#     nearest point, normalised: OBJECT SPACE (no tangent frame, the target's own normal is not
#     used). Encoding: c = (n + 1) / 2 * 255, converted to vcg::Color4b, i.e. TRUNCATED to an
#     integer: code k stands for [k, k + 1) / 255 * 2 - 1 (decode at k + 0.5 for no bias:
#     normal_map_error --code-offset 0.5). 8-bit RGB(A) PNG only, written by QImage.
#   - a point-cloud source (no faces) takes the nearest vertex's normal with a different mapping,
#     n * 128 + 128 as int (n = 1 overflows to 256 and wraps to 0 in qRgba): use a source with
#     faces.
#   - texel convention: pixel (x, H - 1 - y) of the QImage for raster sample (x, y): rows top to
#     bottom, v up, as ours (bake/texture_atlas.h).
#   - the file is written next to the TARGET's file as <textName without extension>.png (textName
#     may not contain a path); the target must exist as a file; with two meshes, the current mesh
#     (the last loaded) must be the target or the target must already have a texture, otherwise
#     no image is written at all. Single-threaded.
#
# Why the target goes in as PLY: Debian's meshlabserver 2020.09 aborts on loading ANY OBJ file,
# even a one-triangle one or its own export ("import_obj.h:640: Assertion `(numTriangles
# +numVertices) == numVerticesPlusFaces+extraTriangles' failed") (Debian 12's 2020.09 package). Its PLY
# importer reads per-wedge texture coordinates (face property "texcoord", -m wt) fine; its OBJ
# exporter works. So MeshLab gets PLY and our tools get the OBJ export of the same mesh.
set -euo pipefail

REPO="$(cd "$(dirname "$0")/.." && pwd)"
MESHLABSERVER="${MESHLABSERVER:-/usr/bin/meshlabserver}"
die() { echo "meshlab_transfer: $*" >&2; exit 1; }
abspath() { echo "$(cd "$(dirname "$1")" && pwd)/$(basename "$1")"; }

server() {  # server LOG ARGS...
    local log="$1"; shift
    timeout 3600 xvfb-run -a -s "-screen 0 1280x1024x24" "$MESHLABSERVER" "$@" >"$log" 2>&1
}
now() { date +%s.%N; }

mode="${1:-}"; shift || true
case "$mode" in
prepare)
    [ $# -ge 3 ] || die "usage: prepare SCAN OUTDIR FACES [TEXSIZE]"
    scan="$(abspath "$1")"; out="$2"; faces="$3"; tex="${4:-1024}"
    mkdir -p "$out"; out="$(cd "$out" && pwd)"
    export XDG_CONFIG_HOME="$out/config"; mkdir -p "$XDG_CONFIG_HOME"
    bash "$REPO/scripts/filter_script.sh" --out "$out/normals.mlx" --filter "Re-Compute Vertex Normals" weightMode=2
    server "$out/normals.log" -i "$scan" -s "$out/normals.mlx" -o "$out/source.ply" -m vn \
        || { cat "$out/normals.log" >&2; die "normals failed"; }
    {
        echo '<!DOCTYPE FilterScript>'; echo '<FilterScript>'
        bash "$REPO/scripts/meshlab_decimation_filter.sh" "$faces" false
        bash "$REPO/scripts/filter_script.sh" --elements-only --out - \
            --filter "Parametrization: Trivial Per-Triangle" sidedim=0 textdim="$tex" border=2 method=0
        echo '</FilterScript>'
    } >"$out/target.mlx"
    server "$out/target.log" -i "$out/source.ply" -s "$out/target.mlx" -o "$out/target.ply" -m wt -o "$out/target.obj" -m wt \
        || { cat "$out/target.log" >&2; die "simplification + parametrization failed"; }
    echo "prepared $out/source.ply (area-weighted vertex normals) and $out/target.ply = $out/target.obj ($faces faces, per-triangle UVs)"
    ;;
run)
    [ $# -ge 5 ] || die "usage: run SOURCE TARGET.ply SIZE UPPERBOUND OUT.png [REPEATS]"
    source_mesh="$(abspath "$1")"; target="$(abspath "$2")"; size="$3"; bound="$4"; outpng="$5"; repeats="${6:-3}"
    work="$(mktemp -d "${TMPDIR:-/tmp}/meshlab_transfer.XXXXXX")"
    trap 'rm -rf "$work"' EXIT
    export XDG_CONFIG_HOME="$work/config"; mkdir -p "$XDG_CONFIG_HOME"
    case "$target" in *.ply|*.PLY) ;; *) die "the target must be a PLY with per-wedge texcoords (meshlabserver 2020.09 cannot load OBJ, see above)";; esac
    # The texture goes next to the target: bake into a private copy, loaded last so that it is the
    # current mesh the texture is created for (a target without texture gets none otherwise).
    cp "$target" "$work/target.ply"
    bash "$REPO/scripts/filter_script.sh" --layers 2 --out "$work/transfer.mlx" \
        --filter "Transfer: Vertex Attributes to Texture (1 or 2 meshes)" sourceMesh=0 targetMesh=1 AttributeEnum=1 \
        upperBound="$bound" textName=baked.png textW="$size" textH="$size" overwrite=false assign=true pullpush=true
    loads=(); totals=()
    for ((i = 0; i < repeats; ++i)); do
        t0=$(now); server "$work/load.log" -i "$source_mesh" -i "$work/target.ply" \
            || { cat "$work/load.log" >&2; die "loading failed"; }
        t1=$(now); rm -f "$work/baked.png"
        server "$work/transfer.log" -i "$source_mesh" -i "$work/target.ply" -s "$work/transfer.mlx" \
            || { cat "$work/transfer.log" >&2; die "transfer failed"; }
        t2=$(now)
        [ -s "$work/baked.png" ] || { cat "$work/transfer.log" >&2; die "no texture written"; }
        loads+=("$t0,$t1"); totals+=("$t1,$t2")
    done
    cp "$work/baked.png" "$outpng"
    python3 - "${#loads[@]}" "${loads[@]}" "${totals[@]}" <<'PY'
import statistics, sys
span = lambda s: float(s.split(",")[1]) - float(s.split(",")[0])
n = int(sys.argv[1]); loads = [span(x) for x in sys.argv[2:2 + n]]; totals = [span(x) for x in sys.argv[2 + n:]]
diffs = [t - l for t, l in zip(totals, loads)]
print("meshlabserver load only:     median %.2f s  (runs: %s)" % (statistics.median(loads), " ".join("%.2f" % x for x in loads)))
print("meshlabserver load + filter: median %.2f s  (runs: %s)" % (statistics.median(totals), " ".join("%.2f" % x for x in totals)))
print("filter wall time:            median %.2f s" % statistics.median(diffs))
PY
    echo "map written to $outpng"
    ;;
*)
    die "usage: $0 prepare SCAN OUTDIR FACES [TEXSIZE] | run SOURCE TARGET.ply SIZE UPPERBOUND OUT.png [REPEATS]"
    ;;
esac
