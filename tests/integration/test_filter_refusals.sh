#!/usr/bin/env bash
# Filters refuse bad input with a message and leave the layer as it was:
#  - evaluating radiance on a mesh without radiance data;
#  - creating radiance data with an unsupported degree.
source "$(dirname "$0")/lib.sh"
CHECK="python3 $RADIANCE_SOURCE_DIR/tests/integration/check_radiance_ply.py"

"$MAKE_SCENE" sphere --level 2 -o "$WORK/sphere.ply"
# Reference: the mesh saved untouched through our writer.
run_meshlabserver "$WORK/ref.log" -i "$WORK/sphere.ply" -o "$WORK/reference.rply" -m vc vn \
    || { cat "$WORK/ref.log" >&2; fail "could not save the reference"; }

filter_script "$WORK/eval.mlx" "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color" \
    viewpoint=0,0,5 \
    exposure=1
run_meshlabserver "$WORK/eval.log" -i "$WORK/sphere.ply" -o "$WORK/eval.rply" -m vc vn -s "$WORK/eval.mlx" -l "$WORK/eval.filterlog" || true
cat "$WORK/eval.filterlog" >>"$WORK/eval.log" 2>/dev/null || true
grep -qF "has no radiance data" "$WORK/eval.log" || { cat "$WORK/eval.log" >&2; fail "no message for a mesh without radiance"; }
if [ -e "$WORK/eval.rply" ]; then $CHECK same "$WORK/reference.rply" "$WORK/eval.rply" || fail "layer changed by a refused filter"; fi

create_radiance_mlx "$WORK/bad_degree.mlx" 0 12 false 0.5 0
run_meshlabserver "$WORK/degree.log" -i "$WORK/sphere.ply" -o "$WORK/degree.rply" -m vc vn -s "$WORK/bad_degree.mlx" -l "$WORK/degree.filterlog" || true
cat "$WORK/degree.filterlog" >>"$WORK/degree.log" 2>/dev/null || true
grep -qF "is not supported" "$WORK/degree.log" || { cat "$WORK/degree.log" >&2; fail "no message for an unsupported degree"; }
if [ -e "$WORK/degree.rply" ]; then $CHECK same "$WORK/reference.rply" "$WORK/degree.rply" || fail "layer changed by a refused filter"; fi
note "ok"
