"""The "Extract Level of Detail (POP Buffer)" filter through pymeshlab 2025.7 (MeshLab 2025.07).

Every expected value is computed here with numpy from the definitions (Limper et al. 2013's grid of
2^L cells per axis over the bounding box, a triangle kept when its three corners are in three
different cells; Weber & Stamminger's Alg. 1, exact on a plane with linear texture coordinates), not
from the C++ code: the layer's vertices lie on the cell centres of the chosen level, its face count
is the count of non-degenerate triangles, and corrected texture coordinates are the plane's linear
map at the (projected) snapped position.
"""
import numpy as np
import pymeshlab
import pytest

import pymeshlab_radiance  # noqa: F401  (loads our plugins into pymeshlab)
import pymeshlab_test_helpers as h

POP = h.POP_LEVELS

# A tilted plane p = ORIGIN + s A + t B over (s, t) in [0, 1]^2, texture coordinates uv = M (s, t) + O.
ORIGIN = np.array([0.2, -0.4, 1.0])
A = np.array([2.0, 0.0, 0.5])
B = np.array([0.0, 1.5, 0.75])
M = np.array([[0.6, 0.2], [-0.1, 0.5]])
O = np.array([0.1, 0.3])


def plane_grid(n=40, seed=5):
    rng = np.random.default_rng(seed)
    s, t = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    inner = (s > 0) & (s < 1) & (t > 0) & (t < 1)
    s = s + inner * rng.uniform(-0.3, 0.3, s.shape) / (n - 1)
    t = t + inner * rng.uniform(-0.3, 0.3, t.shape) / (n - 1)
    st = np.stack([s.ravel(), t.ravel()], axis=1)
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a, b, c, d = j * n + i, j * n + i + 1, (j + 1) * n + i + 1, (j + 1) * n + i
            faces += [(a, b, c), (a, c, d)]
    return st, np.array(faces, dtype=np.int32)


def uv_of_points(points):
    """The plane's map at the orthogonal projection of `points` onto the plane (least squares in s, t)."""
    basis = np.stack([A, B], axis=1)
    st, *_ = np.linalg.lstsq(basis, (points - ORIGIN).T, rcond=None)
    return (M @ st).T + O


def cells(points, lo, hi, level):
    extent = hi - lo
    flat = extent == 0
    c = np.floor((points - lo) / np.where(flat, 1, extent) * 2.0 ** level)
    return np.minimum(c, 2 ** level - 1) * ~flat


def drawn_faces(vertices, faces, level):
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    c = cells(vertices, lo, hi, level)[faces]  # (F, 3 corners, 3 axes)
    same = lambda i, j: np.all(c[:, i] == c[:, j], axis=1)  # noqa: E731
    return ~(same(0, 1) | same(1, 2) | same(0, 2))


def check_on_grid(points, lo, hi, level):
    extent = hi - lo
    for k in range(3):
        if extent[k] == 0:
            assert np.all(points[:, k] == lo[k])
            continue
        index = (points[:, k] - lo[k]) / (extent[k] / 2 ** level) - 0.5
        # (The cores compute in single precision: the positions are float32 values, 1e-4 cell at most.)
        assert np.max(np.abs(index - np.round(index))) < 1e-4, f"axis {k}: vertices off the level-{level} grid"
        assert index.min() > -1e-4 and index.max() < 2 ** level - 1 + 1e-4


def textured_meshset(per_vertex):
    st, faces = plane_grid()
    # float32 values, as the cores see them (MeshLab 2025.07 holds doubles; the cores take floats), so
    # that the bounding box and the cells computed here are the ones of the filter.
    vertices = (ORIGIN + st[:, :1] * A + st[:, 1:] * B).astype(np.float32).astype(np.float64)
    uv = (M @ st.T).T + O
    ms = pymeshlab.MeshSet()
    if per_vertex:
        ms.add_mesh(pymeshlab.Mesh(vertices, faces, v_tex_coords_matrix=uv), "plane")
    else:
        ms.add_mesh(pymeshlab.Mesh(vertices, faces, w_tex_coords_matrix=uv[faces.ravel()]), "plane")
    return ms, vertices, faces


@pytest.mark.parametrize("per_vertex", [False, True], ids=["wedge", "per_vertex"])
def test_levels_lie_on_the_grid_keep_the_non_degenerate_faces_and_correct_the_texture(per_vertex):
    ms, vertices, faces = textured_meshset(per_vertex)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    ms.apply_filter(POP, levels="3,4-5", correction=True)
    assert ms.mesh_number() == 4
    ms.set_current_mesh(0)
    assert np.array_equal(ms.current_mesh().vertex_matrix(), vertices)  # the input layer is untouched
    for mesh_id, level in zip((1, 2, 3), (3, 4, 5)):
        lod = ms.mesh(mesh_id)
        v = lod.vertex_matrix()
        check_on_grid(v, lo, hi, level)
        expected_faces = int(drawn_faces(vertices, faces, level).sum())
        assert 0 < expected_faces < len(faces)
        assert lod.face_number() == expected_faces, f"level {level}"
        if per_vertex:
            assert lod.has_vertex_tex_coord()
            uv = lod.vertex_tex_coord_matrix()
            expected = uv_of_points(v)
        else:
            assert lod.has_wedge_tex_coord()
            uv = lod.wedge_tex_coord_matrix()
            expected = uv_of_points(v[lod.face_matrix().ravel()])
        assert np.max(np.abs(uv - expected)) < 1e-5, f"level {level}: corrected texture coordinates"


def test_without_correction_every_vertex_keeps_the_coordinates_of_an_input_vertex_of_its_cell():
    ms, vertices, faces = textured_meshset(per_vertex=True)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    ms.apply_filter(POP, levels="4", correction=False)
    lod = ms.mesh(1)
    v, uv = lod.vertex_matrix(), lod.vertex_tex_coord_matrix()
    input_uv = ms.mesh(0).vertex_tex_coord_matrix()
    cell_of_input = cells(vertices, lo, hi, 4)
    cell_of_output = cells(v, lo, hi, 4)
    moved_texture = 0.0
    for i in range(len(v)):
        same_cell = np.all(cell_of_input == cell_of_output[i], axis=1)
        assert same_cell.any()
        assert np.min(np.abs(input_uv[same_cell] - uv[i]).max(axis=1)) < 1e-6
        moved_texture = max(moved_texture, np.abs(uv[i] - uv_of_points(v[i:i + 1])[0]).max())
    assert moved_texture > 1e-3  # without the correction the texture slid


def expect_refusal(ms, words, **params):
    before = ms.current_mesh().vertex_matrix().copy()
    count = ms.mesh_number()
    with pytest.raises(pymeshlab.PyMeshLabException) as raised:
        ms.apply_filter(POP, **params)
    assert words in str(raised.value), str(raised.value)
    assert ms.mesh_number() == count
    after = ms.current_mesh().vertex_matrix()
    assert after.shape == before.shape and np.array_equal(np.isnan(after), np.isnan(before))
    assert np.array_equal(np.nan_to_num(after), np.nan_to_num(before))


def test_refusals_leave_the_meshset_unchanged():
    st, faces = plane_grid(6)
    vertices = ORIGIN + st[:, :1] * A + st[:, 1:] * B
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertices, faces), "untextured")
    expect_refusal(ms, "has no texture coordinates to correct", levels="4", correction=True)
    ms.apply_filter(POP, levels="4", correction=False)  # without the correction it is fine
    assert ms.mesh_number() == 2
    ms.set_current_mesh(0)
    expect_refusal(ms, "Level 17 does not exist", levels="17", correction=False)
    expect_refusal(ms, "is not a level", levels="four", correction=False)

    broken = vertices.copy()
    broken[3, 1] = np.nan
    ms_nan = pymeshlab.MeshSet()
    ms_nan.add_mesh(pymeshlab.Mesh(broken, faces), "nan")
    expect_refusal(ms_nan, "non-finite coordinate", levels="4", correction=False)

    ms_points = pymeshlab.MeshSet()
    ms_points.add_mesh(pymeshlab.Mesh(vertices), "points")
    expect_refusal(ms_points, "has no faces", levels="4", correction=False)
