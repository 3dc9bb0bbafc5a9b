"""The PRT filters through pymeshlab 2025.7 on Křivánek et al. 2004's column-on-plane scene,
mirroring tests/integration/test_prt_subdivision.sh and test_prt_refusals.sh: transfer against a
brute-force geometric visibility, save -> reload -> save bit-identical, adaptive and uniform
subdivision budgets, conforming output, refinement near the column, new vertices ray-cast,
relighting (the column's shadow; Lambert's cosine on an open plane; an HDR map), and the refusals.

The geometry checks re-implement tests/integration/check_prt.py with numpy (shares no code with the
C++ cores): make_scene column defaults = radius 0.15, height 1, 16 segments, ground [-1, 1]^2.
"""
import glob
import math
import os

import numpy as np
import pytest

from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h

RADIUS, HEIGHT, HALF, SEGMENTS = 0.15, 1.0, 1.0, 16


def transfer_parameters(**overrides):
    p = dict(order=6, rays=256, occluders=0, albedo=False, rayoffset=0.0001)
    p.update(overrides)
    return p


def adaptive_parameters(**overrides):
    p = dict(budget=0, budgetfactor=4.0, measure=3, alpha=4.0, threshold=0.0)
    p.update(overrides)
    return p


def uniform_parameters(**overrides):
    p = dict(budget=0, budgetfactor=4.0, measure=2, alpha=4.0)
    p.update(overrides)
    return p


def relight_parameters(**overrides):
    p = dict(lighting=1, environmentmap="", rotation=0.0, upaxis=2, lightdirection=np.array([0.5, 0.5, 1.0]),
             lightintensity=3.0, exposure=1.0)
    p.update(overrides)
    return p


# ---------------------------------------------------------------------------------------------------
# Geometry of the column scene (independent of the C++ code)

def rays_hit_column(origins, directions):
    """Whether the rays o + t d (t > 0) hit the closed cylinder (axis z, base z = 0). Broadcasts."""
    o = np.broadcast_to(origins, np.broadcast_shapes(origins.shape, directions.shape))
    d = np.broadcast_to(directions, o.shape)
    ox, oy, oz = o[..., 0], o[..., 1], o[..., 2]
    dx, dy, dz = d[..., 0], d[..., 1], d[..., 2]
    a = dx * dx + dy * dy
    b = 2 * (ox * dx + oy * dy)
    c = ox * ox + oy * oy - RADIUS ** 2
    disc = b * b - 4 * a * c
    hit = np.zeros(o.shape[:-1], dtype=bool)
    with np.errstate(divide="ignore", invalid="ignore"):
        root = np.sqrt(np.maximum(disc, 0))
        for sign in (-1.0, 1.0):
            t = (-b + sign * root) / (2 * a)
            z = oz + t * dz
            hit |= (a > 1e-12) & (disc >= 0) & (t > 1e-6) & (z >= 0) & (z <= HEIGHT)
        t = (HEIGHT - oz) / dz
        hit |= (np.abs(dz) > 1e-12) & (t > 1e-6) & ((ox + t * dx) ** 2 + (oy + t * dy) ** 2 <= RADIUS ** 2)
    return hit


def cosine_directions(samples=48):
    """Midpoint rule in (u = sin^2 theta, phi): uniform in the cosine-weighted measure."""
    u = (np.arange(samples) + 0.5) / samples
    phi = 2 * math.pi * (np.arange(2 * samples) + 0.5) / (2 * samples)
    u, phi = np.meshgrid(u, phi, indexing="ij")
    s = np.sqrt(u)
    return np.stack([s * np.cos(phi), s * np.sin(phi), np.sqrt(1 - u)], axis=-1).reshape(-1, 3)


def ground_vertices(positions, normals=None):
    p = positions
    keep = (np.abs(p[:, 2]) < 1e-6) & (np.hypot(p[:, 0], p[:, 1]) > RADIUS + 1e-3)
    if normals is not None:
        keep &= normals[:, 2] > 0.9
    return np.nonzero(keep)[0]


def check_column_transfer(mesh):
    """Band 0 of ground vertices = Y00 x the cosine-weighted visible fraction (brute force here)."""
    assert "prt" in mesh.blocks, "no prt block"
    t = mesh.blocks["prt"].values
    assert np.isfinite(t).all()
    ground = ground_vertices(mesh.positions.astype(float), mesh.normals)
    assert ground.size >= 20, f"too few ground vertices ({ground.size})"
    directions = cosine_directions()
    origins = mesh.positions[ground].astype(float) + np.array([0, 0, 1e-6])
    visible = 1.0 - rays_hit_column(origins[:, None, :], directions[None, :, :]).mean(axis=1)
    expected = h.Y00 * visible
    # 256 low-discrepancy rays vs a 48 x 96 midpoint rule: a few percent of Y00.
    error = np.abs(t[ground, 0] - expected)
    assert error.max() <= 0.06 * h.Y00, \
        f"ground vertex at {mesh.positions[ground[error.argmax()]]}: t0 {t[ground[error.argmax()], 0]:.4f}, " \
        f"geometry says {expected[error.argmax()]:.4f}"
    assert (expected < 0.97 * h.Y00).sum() >= 3, "the column occludes no checked ground vertex"
    return ground.size


def check_conforming(mesh, min_faces, max_faces):
    """Face count in range; every edge (vertices matched by position) on at most two faces, consistently
    oriented; no vertex strictly inside an open edge (no T-junction); the column scene's area."""
    p = mesh.positions.astype(float)
    faces = mesh.faces
    assert min_faces <= len(faces) <= max_faces, f"{len(faces)} faces, expected {min_faces}..{max_faces}"
    _, ids = np.unique(mesh.positions, axis=0, return_inverse=True)
    ids = ids.ravel()
    f = ids[faces]
    directed = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]]).astype(np.int64)
    keys = directed[:, 0] * (1 << 32) + directed[:, 1]
    assert np.unique(keys).size == keys.size, "a directed edge is used twice: inconsistent orientation"
    undirected = np.sort(directed, axis=1)
    ukeys, counts = np.unique(undirected[:, 0] * (1 << 32) + undirected[:, 1], return_counts=True)
    assert counts.max() <= 2, "an edge is on more than two faces"
    unique_positions = np.zeros((ids.max() + 1, 3))
    unique_positions[ids] = p
    open_edges = ukeys[counts == 1]
    a = unique_positions[open_edges >> 32]
    b = unique_positions[open_edges & 0xFFFFFFFF]
    d = b - a
    w = unique_positions[None, :, :] - a[:, None, :]
    t = (w * d[:, None, :]).sum(-1) / (d * d).sum(-1)[:, None]
    dist2 = ((w - t[..., None] * d[:, None, :]) ** 2).sum(-1)
    inside = (t > 1e-6) & (t < 1 - 1e-6) & (dist2 < 1e-12 * (d * d).sum(-1)[:, None])
    assert not inside.any(), f"{int(inside.sum())} vertices lie strictly inside open edges (T-junctions)"
    e1, e2 = p[faces[:, 1]] - p[faces[:, 0]], p[faces[:, 2]] - p[faces[:, 0]]
    area = 0.5 * np.linalg.norm(np.cross(e1, e2), axis=1).sum()
    polygon = 0.5 * SEGMENTS * RADIUS ** 2 * math.sin(2 * math.pi / SEGMENTS)
    side = SEGMENTS * 2 * RADIUS * math.sin(math.pi / SEGMENTS) * HEIGHT
    expected = (2 * HALF) ** 2 + side + 2 * polygon
    assert abs(area - expected) <= 1e-4 * expected, f"total area {area:.6f}, the scene has {expected:.6f}"


def ground_face_areas(mesh):
    p = mesh.positions.astype(float)
    tri = p[mesh.faces]
    flat = np.abs(tri[:, :, 2]).max(axis=1) < 1e-6
    tri = tri[flat]
    centre = tri.mean(axis=1)
    area = 0.5 * np.abs((tri[:, 1, 0] - tri[:, 0, 0]) * (tri[:, 2, 1] - tri[:, 0, 1]) -
                        (tri[:, 2, 0] - tri[:, 0, 0]) * (tri[:, 1, 1] - tri[:, 0, 1]))
    return np.hypot(centre[:, 0], centre[:, 1]), area


# ---------------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def column(scenes):
    return scenes("column")


@pytest.fixture(scope="module")
def transfer_file(column, tmp_path_factory):
    ms = h.load(column)
    ms.apply_filter(h.TRANSFER, **transfer_parameters())
    path = tmp_path_factory.mktemp("prt") / "transfer.rply"
    ms.save_current_mesh(str(path))
    return path


def face_count(path):
    return rply.read_rply(str(path)).face_count


def test_transfer_matches_geometric_visibility(transfer_file, tmp_path):
    mesh = rply.read_rply(str(transfer_file))
    assert mesh.blocks["prt"].width == 36  # order 6
    check_column_transfer(mesh)
    # save -> reload -> save is bit-identical, the transfer included.
    again = h.load(transfer_file)
    again.save_current_mesh(str(tmp_path / "reload.rply"))
    assert transfer_file.read_bytes() == (tmp_path / "reload.rply").read_bytes()


def test_adaptive_subdivision_within_a_factor_budget(transfer_file, tmp_path):
    faces = face_count(transfer_file)
    ms = h.load(transfer_file)
    ms.apply_filter(h.ADAPTIVE, **adaptive_parameters())
    ms.save_current_mesh(str(tmp_path / "adaptive.rply"))
    mesh = rply.read_rply(str(tmp_path / "adaptive.rply"))
    check_conforming(mesh, faces + 1, 4 * faces)
    radius, area = ground_face_areas(mesh)
    near, far = area[radius < 0.45], area[radius > 0.8]
    assert near.size and far.size and near.mean() < 0.5 * far.mean(), \
        f"near-column ground faces (mean area {near.mean():.5f}) not smaller than far ones ({far.mean():.5f})"
    # New vertices are ray-cast, not interpolated: the same geometric check on the subdivided ground.
    assert check_column_transfer(mesh) > len(ground_vertices(rply.read_rply(str(transfer_file)).positions))
    quality = ms.current_mesh().face_scalar_array()
    assert quality.shape == (mesh.face_count,) and np.isfinite(quality).all() and quality.min() >= 0
    assert quality.max() > quality.min(), "face quality (the refinement estimate) is constant"


@pytest.mark.parametrize("budget,factor", [(600, 0.0), (0, 2.5), (288, 0.0)])
def test_adaptive_budget_is_respected(budget, factor, transfer_file):
    faces = face_count(transfer_file)
    limit = budget if budget else int(factor * faces)
    ms = h.load(transfer_file)
    ms.apply_filter(h.ADAPTIVE, **adaptive_parameters(budget=budget, budgetfactor=factor))
    result = ms.current_mesh().face_number()
    assert faces <= result <= limit, f"{result} faces for a budget of {limit}"
    if limit >= faces + 50:
        assert result >= limit - 20, f"{result} faces: the budget of {limit} was far from used"


@pytest.mark.parametrize("budget,factor,levels", [(0, 4.0, 1), (0, 16.0, 2), (0, 15.9, 1), (4 * 288 - 1, 0.0, 0)])
def test_uniform_subdivision_levels_fit_the_budget(budget, factor, levels, transfer_file, tmp_path):
    faces = face_count(transfer_file)
    assert faces == 288
    ms = h.load(transfer_file)
    ms.apply_filter(h.UNIFORM, **uniform_parameters(budget=budget, budgetfactor=factor))
    ms.save_current_mesh(str(tmp_path / "uniform.rply"))
    mesh = rply.read_rply(str(tmp_path / "uniform.rply"))
    expected = faces * 4 ** levels
    check_conforming(mesh, expected, expected)
    if levels:
        check_column_transfer(mesh)


def test_directional_relighting_casts_the_column_shadow(transfer_file):
    ms = h.load(transfer_file)
    ms.apply_filter(h.ADAPTIVE, **adaptive_parameters())
    light = np.array([1.0, 0.3, 0.8])
    ms.apply_filter(h.RELIGHT, **relight_parameters(lightdirection=light, lightintensity=3.0))
    m = ms.current_mesh()
    p = m.vertex_matrix()
    value = m.vertex_color_matrix()[:, :3].sum(1)
    ground = (np.abs(p[:, 2]) < 1e-6) & (np.hypot(p[:, 0], p[:, 1]) > RADIUS + 1e-3) & (np.abs(p[:, :2]).max(1) < 0.95)
    shadowed = rays_hit_column(p + np.array([0, 0, 1e-6]), h.normalized(light)[None, :])
    in_shadow, lit = value[ground & shadowed], value[ground & ~shadowed]
    assert in_shadow.size >= 3 and lit.size >= 3
    assert in_shadow.mean() < 0.8 * lit.mean(), f"shadow {in_shadow.mean():.3f} vs lit {lit.mean():.3f}"


def test_relighting_an_open_plane_follows_lamberts_cosine(tmp_path):
    """Unoccluded plane (every ray escapes): the relit radiance scales with the light's cosine and
    intensity (ratios, in linear units; the SH windowing only changes the overall scale)."""
    vertices, faces = h.grid(3, 3)
    ms = h.load(h.write_ascii_ply(tmp_path / "plane.ply", vertices, faces, normals=[(0, 0, 1)] * len(vertices)))
    ms.apply_filter(h.TRANSFER, **transfer_parameters())

    def relit(theta, intensity):
        d = np.array([math.sin(math.radians(theta)), 0.0, math.cos(math.radians(theta))])
        ms.apply_filter(h.RELIGHT, **relight_parameters(lightdirection=d, lightintensity=intensity))
        return h.srgb_decode(ms.current_mesh().vertex_color_matrix()[:, :3] * 255.0).mean()

    normal = relit(0, 1.0)
    assert 0.05 < normal < 0.9
    assert relit(60, 1.0) / normal == pytest.approx(0.5, abs=0.03)
    assert relit(30, 1.0) / normal == pytest.approx(math.cos(math.radians(30)), abs=0.03)
    assert relit(0, 0.5) / normal == pytest.approx(0.5, abs=0.03)


def test_relighting_with_an_hdr_map(transfer_file, repo_dir):
    maps = sorted(glob.glob(os.path.join(repo_dir, "data-cache", "hdr", "*.exr")) +
                  glob.glob(os.path.join(repo_dir, "data-cache", "hdr", "*.hdr")))
    assert maps, "no HDR map in data-cache/hdr (scripts/setup.sh fetches them)"
    ms = h.load(transfer_file)
    seen = []
    for rotation in (0.0, 90.0):
        ms.apply_filter(h.RELIGHT, **relight_parameters(lighting=0, environmentmap=maps[0], rotation=rotation))
        colours = ms.current_mesh().vertex_color_matrix()[:, :3]
        assert np.isfinite(colours).all() and colours.std() > 0.005, "the map lights the scene uniformly?"
        seen.append(colours)
    assert np.abs(seen[0] - seen[1]).max() > 0.01, "rotating the map about the up axis changed nothing"


def test_open_plane_transfer_is_unoccluded(tmp_path):
    """A lone ground plane: every ray escapes; band 0 = Y00, band 1 of a vertical normal is only
    Y_1^0 (index 2) = 2/3 x 0.4886 (the clamped cosine's), within 0.02 for 256 rays."""
    vertices, faces = h.grid(3, 3)
    ms = h.load(h.write_ascii_ply(tmp_path / "plane.ply", vertices, faces, normals=[(0, 0, 1)] * len(vertices)))
    ms.apply_filter(h.TRANSFER, **transfer_parameters(order=3, rays=256))
    ms.save_current_mesh(str(tmp_path / "plane.rply"))
    t = rply.read_rply(str(tmp_path / "plane.rply")).blocks["prt"].values
    assert t.shape == (16, 9)
    assert np.abs(t[:, 0] - h.Y00).max() <= 1e-5
    assert np.abs(t[:, 2] - 2.0 / 3.0 * 0.4886025119029199).max() <= 0.02


# ---------------------------------------------------------------------------------------------------
# Refusals (tests/integration/test_prt_refusals.sh): our message, the MeshSet as it was.

def test_subdivision_refuses_a_mesh_without_transfer(column):
    h.expect_refusal(h.load(column), h.ADAPTIVE, "has no PRT transfer vectors", **adaptive_parameters())
    h.expect_refusal(h.load(column), h.UNIFORM, "has no PRT transfer vectors", **uniform_parameters())
    h.expect_refusal(h.load(column), h.RELIGHT, "has no PRT transfer vectors", **relight_parameters())


@pytest.mark.parametrize("name,parameters", [(h.ADAPTIVE, adaptive_parameters(budget=100, budgetfactor=0.0)),
                                             (h.UNIFORM, uniform_parameters(budget=100, budgetfactor=0.0))])
def test_subdivision_refuses_a_budget_below_the_face_count(name, parameters, transfer_file):
    text = h.expect_refusal(h.load(transfer_file), name, "is below the layer's", **parameters)
    assert "100" in text and "288" in text


@pytest.mark.parametrize("case,message", [("nonmanifold", "non-manifold edge (shared by more than two faces"),
                                          ("zero_area", "Zero Area")])
def test_subdivision_refuses_bad_geometry(case, message, tmp_path):
    vertices, faces = h.grid(3, 3)
    if case == "nonmanifold":  # a fin below the plane on edge (0, 1)
        vertices, faces = vertices + [(0.5, -1.0, 0.0)], faces + [(0, 1, 16), (1, 0, 16)]
    else:  # three collinear vertices
        vertices, faces = vertices + [(4.0, 0.0, 0.0), (5.0, 0.0, 0.0), (6.0, 0.0, 0.0)], faces + [(16, 17, 18)]
    ms = h.load(h.write_ascii_ply(tmp_path / f"{case}.ply", vertices, faces, normals=[(0, 0, 1)] * len(vertices)))
    ms.apply_filter(h.TRANSFER, **transfer_parameters(order=3, rays=16))  # the transfer accepts them
    h.expect_refusal(ms, h.ADAPTIVE, message, **adaptive_parameters())


def test_transfer_refuses_vertices_without_normals(tmp_path):
    cloud = tmp_path / "points.ply"
    cloud.write_text("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
                     "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n1 1 1\n")
    h.expect_refusal(h.load(cloud), h.TRANSFER, "vertices has a usable normal and there are no faces", **transfer_parameters())


def test_subdivision_refuses_an_albedo_transfer(column):
    ms = h.load(column)
    ms.apply_filter(h.TRANSFER, **transfer_parameters(order=3, rays=16, albedo=True))
    h.expect_refusal(ms, h.ADAPTIVE, "include the albedo", **adaptive_parameters())


def test_relighting_refuses_a_missing_map(transfer_file, tmp_path):
    missing = str(tmp_path / "no_such_map.exr")
    h.expect_refusal(h.load(transfer_file), h.RELIGHT, "no_such_map.exr",
                     **relight_parameters(lighting=0, environmentmap=missing))


@pytest.mark.parametrize("key,value", [("rays", "1000000"), ("rays", "0"), ("ray_offset", "0.5"), ("ray_offset", "nan")])
def test_transfer_with_impossible_ray_settings_is_not_used(key, value, transfer_file, tmp_path):
    """A file whose transfer claims settings the transfer filter would refuse: the block is not
    taken as transfer vectors (a subdivision would cast that many rays per new vertex), the
    subdivision says how to get valid ones, and a save keeps the block as it was."""
    mesh = rply.read_rply(str(transfer_file))
    mesh.blocks["prt"].meta[key] = value
    edited = tmp_path / "edited.rply"
    rply.write_rply(str(edited), mesh)
    ms = h.load(edited)
    h.expect_refusal(ms, h.ADAPTIVE, "has no PRT transfer vectors. Run 'Radiance: Compute PRT Transfer' first",
                     budgetfactor=2.0)
    ms.save_current_mesh(str(tmp_path / "saved.rply"))
    kept = rply.read_rply(str(tmp_path / "saved.rply")).blocks["prt"]
    assert kept.meta[key] == value
    assert np.array_equal(kept.values, mesh.blocks["prt"].values)
