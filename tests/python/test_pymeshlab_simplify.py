"""'Radiance: Radiance-Aware Simplification' through pymeshlab 2025.7, mirroring tests/integration/
test_simplify_radiance.sh and test_simplify_refusals.sh: the target face count reached exactly, the
level-of-detail layers, the progressive file replayed by the C++ tool, the variants, the refusals.

Checks independent of the C++ code: topology (every directed edge once with its twin, Euler
characteristic 2), half-edge collapses keep original vertices with their own radiance rows (numpy
.rply reader), expected face counts from the arguments.
"""
import pymeshlab
import numpy as np
import pytest

from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h


@pytest.fixture(scope="module")
def striped(scenes, tmp_path_factory):
    """PB4 radiance of the striped glossy sample material on a sphere of 5120 faces (C++ tool)."""
    path = tmp_path_factory.mktemp("simplify") / "sphere.rply"
    h.run_tool("make_radiance_mesh", scenes("sphere", level=4), "--material", "stripes", "--basis", "PB4",
               "--no-shadows", "-o", path)
    return path


def simplify_parameters(**overrides):
    """Every parameter, as scripts/write_simplify_mlx.sh lists them."""
    parameters = dict(metric=0, collapse=0, targetfaces=0, targetpercentage=0.25, lodlevels="",
                      geometryweight=0.01, attributeweight=0.99, preserveboundary=True, minvalence=0,
                      maxvalence=0, maxnormalchange=90.0, lazy=True, progressivefile="")
    parameters.update(overrides)
    return parameters


def saved(ms, mesh_id, path):
    ms.set_current_mesh(mesh_id)
    ms.save_current_mesh(str(path))
    return rply.read_rply(str(path))


def test_simplification_to_a_percentage_with_levels_of_detail(striped, tmp_path):
    original = rply.read_rply(str(striped))
    faces = original.face_count
    assert faces == 5120
    ms = h.load(striped)
    progressive = tmp_path / "sphere.rpm"
    ms.apply_filter(h.SIMPLIFY, **simplify_parameters(lodlevels="0.5 0.1", progressivefile=str(progressive)))
    # The layer itself is simplified in place; one new layer per level of detail.
    assert ms.mesh_number() == 3
    assert ms.current_mesh_id() == 0 and ms.current_mesh().face_number() == faces // 4
    levels = {ms.mesh(i).label(): ms.mesh(i).face_number() for i in (1, 2)}
    assert levels == {"sphere_LOD50": faces // 2, "sphere_LOD10": faces // 10}, levels
    for mesh_id, target in ((0, faces // 4), (1, faces // 2), (2, faces // 10)):
        mesh = saved(ms, mesh_id, tmp_path / f"layer{mesh_id}.rply")
        assert mesh.face_count == target
        h.check_closed_genus0_manifold(mesh.faces, f"layer {mesh_id}")
        h.check_original_vertices_and_rows(original, mesh, f"layer {mesh_id}")
        assert mesh.basis == "PB4"
    # The progressive mesh, replayed by the C++ tool, gives exactly the layer's faces.
    assert progressive.stat().st_size > 0 and (tmp_path / "sphere_base.rply").stat().st_size > 0
    h.run_tool("simplify_radiance", progressive, "-o", tmp_path / "replay", "--ratios", "0.25,0.1")
    for layer, replay in ((0, "replay_250.rply"), (2, "replay_100.rply")):
        mine = rply.read_rply(str(tmp_path / f"layer{layer}.rply"))
        theirs = rply.read_rply(str(tmp_path / replay))
        assert h.face_triples(mine.positions, mine.faces) == h.face_triples(theirs.positions, theirs.faces), \
            f"the replayed {replay} differs from layer {layer}"


def test_simplification_to_an_absolute_target(striped, tmp_path):
    ms = h.load(striped)
    ms.apply_filter(h.SIMPLIFY, **simplify_parameters(targetfaces=1000, targetpercentage=0.0))
    assert ms.mesh_number() == 1 and ms.current_mesh().face_number() == 1000
    mesh = saved(ms, 0, tmp_path / "thousand.rply")
    h.check_closed_genus0_manifold(mesh.faces, "1000 faces")
    h.check_original_vertices_and_rows(rply.read_rply(str(striped)), mesh, "1000 faces")


@pytest.mark.parametrize("metric", [1, 2, 3], ids=["lightfield", "color-qem", "geometry"])
def test_other_metrics_reach_the_target(metric, striped, tmp_path):
    ms = h.load(striped)
    ms.apply_filter(h.SIMPLIFY, **simplify_parameters(metric=metric))
    assert ms.current_mesh().face_number() == 1280
    mesh = saved(ms, 0, tmp_path / "out.rply")
    h.check_closed_genus0_manifold(mesh.faces, f"metric {metric}")
    h.check_original_vertices_and_rows(rply.read_rply(str(striped)), mesh, f"metric {metric}")


def test_full_collapse_on_spherical_harmonics(scenes, tmp_path):
    sh = tmp_path / "sphere_sh.rply"
    h.run_tool("make_radiance_mesh", scenes("sphere", level=4), "--material", "glossy", "--basis", "SH4",
               "--no-shadows", "-o", sh)
    ms = h.load(sh)
    ms.apply_filter(h.SIMPLIFY, **simplify_parameters(collapse=1))
    assert ms.current_mesh().face_number() == 1280
    mesh = saved(ms, 0, tmp_path / "full.rply")
    h.check_closed_genus0_manifold(mesh.faces, "full collapse")
    assert mesh.basis == "SH4" and np.isfinite(mesh.coefficients).all()
    # Full collapses place new vertices: some are not original positions.
    original = {tuple(p) for p in rply.read_rply(str(sh)).positions.tolist()}
    assert any(tuple(p) not in original for p in mesh.positions.tolist())


def test_default_radiance_quadric_places_new_vertices_and_functions(striped, tmp_path):
    """Every parameter at its default: the accumulating radiance quadric (Hoppe 1999) with full
    collapses, on a PB field. New vertices get new positions and new radiance rows, within the range of
    the original rows (the optimum is an area-weighted average of the faces' attribute planes), and
    the recorded progressive mesh replays to exactly the layer, rows included."""
    original = rply.read_rply(str(striped))
    ms = h.load(striped)
    progressive = tmp_path / "quadric.rpm"
    ms.apply_filter(h.SIMPLIFY, targetpercentage=0.25, progressivefile=str(progressive))
    assert ms.current_mesh().face_number() == 1280
    mesh = saved(ms, 0, tmp_path / "quadric.rply")
    h.check_closed_genus0_manifold(mesh.faces, "radiance quadric")
    assert mesh.basis == "PB4" and np.isfinite(mesh.coefficients).all()
    before = {tuple(p) for p in original.positions.tolist()}
    moved = sum(tuple(p) not in before for p in mesh.positions.tolist())
    assert moved > mesh.positions.shape[0] // 2, f"only {moved} vertices were placed anew"
    constant = lambda m: m.coefficients.reshape(m.coefficients.shape[0], 3, -1)[:, :, 0]
    lo, hi = constant(original).min(axis=0), constant(original).max(axis=0)
    margin = 0.1 * (hi - lo)
    assert (constant(mesh) >= lo - margin).all() and (constant(mesh) <= hi + margin).all(), \
        "a new radiance function left the range of the original ones"
    # The sphere stays a sphere: every vertex within 2 % of the radius (positions by the planes).
    radii = np.linalg.norm(mesh.positions, axis=1)
    radius = np.linalg.norm(original.positions, axis=1).mean()
    assert np.abs(radii / radius - 1).max() < 0.02
    h.run_tool("simplify_radiance", progressive, "-o", tmp_path / "replay", "--ratios", "0.25")
    replay = rply.read_rply(str(tmp_path / "replay_250.rply"))
    assert h.face_triples(mesh.positions, mesh.faces) == h.face_triples(replay.positions, replay.faces)
    rows = {tuple(p): c for p, c in zip(mesh.positions.tolist(), mesh.coefficients)}
    for p, c in zip(replay.positions.tolist(), replay.coefficients):
        assert np.array_equal(rows[tuple(p)], c), "the replayed rows differ from the layer's"


def test_open_strip_stops_at_its_boundary(tmp_path):
    """A 2 x 8 strip of quads: its 7 interior vertices go, the 20 boundary vertices stay (boundary
    preserved), so the target of 16 faces (50 %) stops at 18 faces."""
    vertices, faces = h.grid(8, 2)
    ms = h.load(h.write_ascii_ply(tmp_path / "strip.ply", vertices, faces))
    ms.apply_filter(h.SIMPLIFY, **simplify_parameters(metric=3, targetpercentage=0.5))
    assert ms.current_mesh().face_number() == 18 and ms.current_mesh().vertex_number() == 20


def test_open_grid_merges_along_its_boundary_under_the_radiance_quadric(tmp_path):
    """A 12 x 12 grid of quads (288 faces, 48 boundary vertices) with created radiance, simplified by
    the default radiance quadric and full collapses to 10 % (28 faces): merging boundary vertices along
    the boundary (the default) reaches it, keeping all 48 cannot (a polygon of 48 vertices needs 46
    triangles). Either way the square keeps its outline: its area and its corners."""
    vertices, faces = h.grid(12, 12)
    path = h.write_ascii_ply(tmp_path / "grid.ply", vertices, faces)
    for along in (True, False):
        ms = h.load(path)
        ms.apply_filter(h.CREATE)
        progressive = tmp_path / f"along_{along}.rpm"
        ms.apply_filter(h.SIMPLIFY, **simplify_parameters(metric=4, collapse=1, targetpercentage=0.1,
                                                          collapsealongboundary=along,
                                                          progressivefile=str(progressive)))
        out = saved(ms, 0, tmp_path / f"along_{along}.rply")
        if along:
            assert out.face_count <= 28, out.face_count
        else:
            assert out.face_count >= 46, out.face_count
        # The progressive mesh, replayed by the C++ tool, gives exactly the layer's faces.
        h.run_tool("simplify_radiance", progressive, "-o", tmp_path / f"replay_{along}", "--ratios", "0.1")
        replay = rply.read_rply(str(tmp_path / f"replay_{along}_100.rply"))
        assert h.face_triples(out.positions, out.faces) == h.face_triples(replay.positions, replay.faces)
        p = out.positions
        corners = {(x, y) for x, y in p[:, :2].tolist() if x in (0.0, 12.0) and y in (0.0, 12.0)}
        assert corners == {(0.0, 0.0), (12.0, 0.0), (0.0, 12.0), (12.0, 12.0)}
        a, b, c = p[out.faces[:, 0]], p[out.faces[:, 1]], p[out.faces[:, 2]]
        doubled = (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])
        assert np.all(doubled > 0) and abs(0.5 * doubled.sum() - 144.0) < 1e-3


# ---------------------------------------------------------------------------------------------------
# Refusals: our message in the exception, the MeshSet as it was (layers, vertices, faces, colours).

def test_refuses_a_mesh_without_radiance(scenes):
    h.expect_refusal(h.load(scenes("sphere", level=2)), h.SIMPLIFY, "The current mesh has no radiance data",
                     **simplify_parameters(targetpercentage=0.5))


def test_refuses_a_target_not_below_the_face_count(striped, tmp_path):
    ms = h.load(striped)
    ms.save_current_mesh(str(tmp_path / "before.rply"))
    h.expect_refusal(ms, h.SIMPLIFY, "is not below the layer's",
                     **simplify_parameters(targetfaces=100000, targetpercentage=0.0))
    ms.save_current_mesh(str(tmp_path / "after.rply"))
    assert (tmp_path / "before.rply").read_bytes() == (tmp_path / "after.rply").read_bytes()


def test_refuses_full_collapse_on_a_pb_field(striped, tmp_path):
    ms = h.load(striped)
    h.expect_refusal(ms, h.SIMPLIFY, "full edge collapse with the radiance metric needs spherical harmonics",
                     **simplify_parameters(collapse=1))
    ms.save_current_mesh(str(tmp_path / "after.rply"))
    assert striped.read_bytes() == (tmp_path / "after.rply").read_bytes(), "the refused filter changed the layer"


def strip_with_a_non_manifold_edge():
    """The 2 x 8 strip with two more faces on the edge (0, 1): three faces on one edge."""
    vertices, faces = h.grid(8, 2)
    return vertices + [(0.5, -0.5, 1.0), (0.5, -0.5, -1.0)], faces + [(1, 0, 27), (0, 1, 28)]


@pytest.mark.parametrize("case,message", [("nonmanifold", "non-manifold edge"), ("points", "has no faces")])
def test_refuses_bad_geometry(case, message, tmp_path):
    if case == "nonmanifold":  # refused only with a free boundary, naming both fixes
        vertices, faces = strip_with_a_non_manifold_edge()
        message = "turn 'Preserve boundary' on, or run 'Cleaning and Repairing: Repair non Manifold Edges'"
    else:
        vertices, faces = h.grid(8, 2)[0], []
    ms = h.load(h.write_ascii_ply(tmp_path / f"{case}.ply", vertices, faces))
    h.expect_refusal(ms, h.SIMPLIFY, message,
                     **simplify_parameters(metric=3, targetpercentage=0.5, preserveboundary=False))


def test_a_non_manifold_edge_is_kept_with_a_preserved_boundary(tmp_path):
    """The strip's interior vertices go; the edge on three faces keeps its vertices where they are."""
    vertices, faces = strip_with_a_non_manifold_edge()
    ms = h.load(h.write_ascii_ply(tmp_path / "nonmanifold.ply", vertices, faces))
    ms.apply_filter(h.SIMPLIFY, **simplify_parameters(metric=3, targetpercentage=0.5))
    out = ms.current_mesh()
    assert out.face_number() < len(faces)
    kept = {tuple(p) for p in out.vertex_matrix().tolist()}
    assert {tuple(vertices[0]), tuple(vertices[1])} <= kept


def test_a_repeated_face_is_removed_and_the_rest_simplified(tmp_path):
    """A face listed twice (as scans have): the copy is removed (the meshlabserver test checks the log
    line) and the result is the clean strip's (same vertices and faces)."""
    vertices, faces = h.grid(8, 2)
    results = {}
    for case, extra in (("clean", []), ("duplicate", [faces[3]])):
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(h.write_ascii_ply(tmp_path / f"{case}.ply", vertices, faces + extra))
        ms.apply_filter(h.SIMPLIFY, **simplify_parameters(metric=3, targetpercentage=0.5))
        m = ms.current_mesh()
        results[case] = (m.vertex_matrix().copy(), m.face_matrix().copy())
    assert np.array_equal(results["clean"][0], results["duplicate"][0])
    assert np.array_equal(results["clean"][1], results["duplicate"][1])
    assert results["clean"][1].shape[0] < len(faces)


def test_meshset_still_works_after_a_refusal(striped):
    ms = h.load(striped)
    h.expect_refusal(ms, h.SIMPLIFY, "is not below the layer's",
                     **simplify_parameters(targetfaces=100000, targetpercentage=0.0))
    ms.apply_filter(h.SIMPLIFY, **simplify_parameters(targetpercentage=0.5))
    assert ms.current_mesh().face_number() == 2560
