"""'Radiance: Create Radiance Data from Analytic Material' and 'Radiance: Evaluate Radiance toward a
Viewpoint as Vertex Color' through pymeshlab 2025.7, mirroring tests/integration/
test_create_save_reload.sh and test_attribute_follows_meshlab_edits.sh.

Expected values are computed here with numpy from the material's definition (the filter's help text
and common/radiance/analytic_material.h's header comment):
    L(p, n, w_o) = albedo * ambient + sum over lights of f(w_i, w_o) E_i max(0, n.w_i),
    f = albedo / pi + ks (e + 8) / (8 pi) max(0, n.h)^e,
with E_i the irradiance of a directional light, or I / d^2 for a point light at distance d; colours
read as sRGB and used linear. A Lambertian RF is the constant albedo / pi * E * cos + albedo * ambient:
PB coefficient 0 (u^0 v^0 = 1) or SH coefficient 0 / Y00; every other coefficient vanishes. The .rply
files are decoded by the numpy reader (pymeshlab_radiance.rply, independent of the C++ reader); PB
functions are evaluated here from their definition (u^i v^j in the vertex's frame).
"""
import math

import numpy as np
import pymeshlab
import pytest

from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h

ALBEDO_SRGB = (230, 60, 40)
LIGHT = np.array([0.5, 1.0, 1.0])
IRRADIANCE = 3.0
AMBIENT = 0.05


def material(**overrides):
    """Every parameter of the create filter, as the 2020.09 scripts list them (lib.sh)."""
    parameters = dict(basis=0, degree=4, reflected=False, albedo=pymeshlab.Color(*ALBEDO_SRGB),
                      specularcolor=pymeshlab.Color(255, 255, 255), specular=0.0, shininess=40.0, stripes=0,
                      stripeaxis=1, lighttype=0, light=LIGHT, lightintensity=IRRADIANCE, ambient=AMBIENT,
                      setcolor=True)
    parameters.update(overrides)
    return parameters


def lambert_radiance(normals):
    """Linear RGB radiance (N, 3) of the Lambertian material under the directional light + ambient."""
    albedo = h.srgb_decode(ALBEDO_SRGB)
    cos = np.maximum(0.0, h.normalized(normals) @ h.normalized(LIGHT))
    return albedo[None, :] / math.pi * IRRADIANCE * cos[:, None] + albedo[None, :] * AMBIENT


def analytic_glossy(normals, directions, specular, shininess):
    """L(w_o) of the glossy material (white lobe) under the directional light + ambient."""
    albedo = h.srgb_decode(ALBEDO_SRGB)
    l = h.normalized(LIGHT)
    n = h.normalized(normals)
    half = h.normalized(directions + l[None, :])
    lobe = specular * (shininess + 8) / (8 * math.pi) * np.maximum(0.0, (n * half).sum(1)) ** shininess
    brdf = albedo[None, :] / math.pi + lobe[:, None]
    return albedo[None, :] * AMBIENT + brdf * IRRADIANCE * np.maximum(0.0, n @ l)[:, None]


def create(path, **parameters):
    ms = h.load(path)
    ms.apply_filter(h.CREATE, **material(**parameters))
    return ms


def sphere_normals_from_positions(mesh):
    return h.normalized(mesh.positions.astype(float))


@pytest.mark.parametrize("basis,degree,reflected", [(0, 4, False), (1, 6, False), (0, 3, True), (1, 4, True)],
                         ids=["PB4", "SH6", "PB3-reflected", "SH4-reflected"])
def test_lambert_sphere_matches_the_closed_form(basis, degree, reflected, scenes, tmp_path):
    ms = create(scenes("sphere", level=3), basis=basis, degree=degree, reflected=reflected)
    ms.save_current_mesh(str(tmp_path / "lambert.rply"))
    mesh = rply.read_rply(str(tmp_path / "lambert.rply"))
    name = ("PB" if basis == 0 else "SH") + str(degree)
    assert mesh.basis == name and mesh.reflected == reflected
    count = (degree + 1) * (degree + 2) // 2 if basis == 0 else (degree + 1) ** 2
    assert mesh.coefficients.shape == (642, 3, count)
    # The normal is taken from the vertex POSITION (a sphere centred on the origin): a radiance row
    # attached to the wrong vertex is caught even though rows and frames travel together.
    from_positions = sphere_normals_from_positions(mesh)
    assert np.abs(mesh.normals - from_positions).max() < 1e-4, "frame normals are not the sphere's: rows mixed up"
    expected = lambert_radiance(from_positions)
    scale = 1.0 if basis == 0 else 2.0 * math.sqrt(math.pi)  # SH: c0 = f / Y00
    constant = mesh.coefficients[:, :, 0] / scale
    assert np.abs(constant - expected).max() <= 1e-4 * max(1.0, expected.max()), \
        f"constant term off by {np.abs(constant - expected).max():.3g}"
    assert np.abs(mesh.coefficients[:, :, 1:]).max() <= 2e-5, "a constant RF has non-zero higher coefficients"
    # Vertex colour := the mean over the hemisphere = the constant, sRGB-encoded (file and layer).
    code = np.rint(h.srgb_encode(expected))
    assert np.abs(mesh.colors[:, :3].astype(float) - code).max() <= 1
    layer = ms.current_mesh().vertex_color_matrix()[:, :3] * 255.0
    assert np.abs(layer - code).max() <= 1.0 + 1e-6


def test_point_light_on_a_plane_matches_inverse_square_falloff(tmp_path):
    vertices, faces = h.grid(10, 10)
    vertices = [((x - 5) / 5.0, (y - 5) / 5.0, 0.0) for x, y, _ in vertices]
    plane = h.write_ascii_ply(tmp_path / "plane.ply", vertices, faces, normals=[(0, 0, 1)] * len(vertices))
    light = np.array([0.3, -0.2, 1.5])
    ms = create(plane, degree=2, lighttype=1, light=light, lightintensity=2.0, ambient=0.0)
    ms.save_current_mesh(str(tmp_path / "plane.rply"))
    mesh = rply.read_rply(str(tmp_path / "plane.rply"))
    to_light = light[None, :] - mesh.positions.astype(float)
    distance = np.linalg.norm(to_light, axis=1)
    irradiance = 2.0 * (to_light[:, 2] / distance) / distance ** 2
    expected = h.srgb_decode(ALBEDO_SRGB)[None, :] / math.pi * irradiance[:, None]
    assert np.abs(mesh.coefficients[:, :, 0] - expected).max() <= 1e-5 * expected.max()
    assert np.abs(mesh.coefficients[:, :, 1:]).max() <= 2e-5
    # The falloff is real: the vertex nearest below the light is the brightest.
    nearest = np.argmin(np.linalg.norm(mesh.positions[:, :2] - light[:2], axis=1))
    assert np.argmax(mesh.coefficients[:, 0, 0]) == nearest


def test_glossy_projection_approximates_the_analytic_material(scenes, tmp_path):
    """PB6 of a broad lobe (shininess 8): the least-squares RF, evaluated here, stays within a few
    percent of the analytic radiance over the hemisphere of every vertex."""
    ms = create(scenes("sphere", level=3), degree=6, specular=0.5, shininess=8.0)
    ms.save_current_mesh(str(tmp_path / "glossy.rply"))
    mesh = rply.read_rply(str(tmp_path / "glossy.rply"))
    n = mesh.normals.astype(float)
    rng = np.random.default_rng(7)
    errors, signal = [], []
    for _ in range(64):
        w = h.normalized(rng.normal(size=n.shape))
        w = np.where(((w * n).sum(1) < 0)[:, None], -w, w)  # upper hemisphere
        truth = analytic_glossy(n, w, 0.5, 8.0)
        errors.append(np.abs(h.evaluate_pb(mesh, w) - truth))
        signal.append(truth)
    errors, signal = np.concatenate(errors), np.concatenate(signal)
    assert errors.mean() < 0.03 * signal.mean(), f"mean error {errors.mean():.4f} vs mean radiance {signal.mean():.4f}"
    # The lobe is there: the RF is far from constant (directional coefficients).
    assert np.abs(mesh.coefficients[:, :, 1:]).max() > 1e-2


def test_evaluation_of_a_lambertian_rf_is_the_closed_form_from_every_viewpoint(scenes):
    ms = create(scenes("sphere", level=3), degree=4)
    expected = lambert_radiance(h.normalized(ms.current_mesh().vertex_matrix()))
    for eye, exposure in (([0.0, 0.0, 5.0], 1.0), ([3.0, -4.0, 1.0], 0.7)):
        ms.apply_filter(h.EVALUATE, viewpoint=np.array(eye), exposure=exposure)
        colours = ms.current_mesh().vertex_color_matrix()[:, :3] * 255.0
        # Every vertex, even facing away (the hemisphere border extension of a constant is the constant).
        assert np.abs(colours - h.srgb_encode(exposure * expected)).max() <= 0.5 + 1e-6, f"eye {eye}"


def test_evaluation_of_a_glossy_rf_is_the_pb_polynomial_toward_the_eye(scenes, tmp_path):
    ms = create(scenes("sphere", level=3), degree=6, specular=0.5, shininess=8.0)
    ms.save_current_mesh(str(tmp_path / "glossy.rply"))
    mesh = rply.read_rply(str(tmp_path / "glossy.rply"))
    seen = []
    for eye in ([0.0, 0.0, 5.0], [4.0, 2.0, -1.0]):
        eye = np.array(eye)
        ms.apply_filter(h.EVALUATE, viewpoint=eye, exposure=1.0)
        colours = ms.current_mesh().vertex_color_matrix()[:, :3] * 255.0
        w = h.normalized(eye[None, :] - mesh.positions.astype(float))
        front = (w * mesh.normals).sum(1) > 0.05
        assert front.sum() > 100
        expected = h.srgb_encode(h.evaluate_pb(mesh, w))
        assert np.abs(colours[front] - expected[front]).max() <= 0.5 + 1e-3, f"eye {eye}"
        seen.append(colours)
    # View dependence: the same vertices look different from the two eyes.
    assert np.abs(seen[0] - seen[1]).max() > 20


def test_plain_and_reflected_storage_evaluate_to_the_same_radiance(scenes):
    """'Either evaluates to the same radiance' (the reflected parameter's help text)."""
    eye = np.array([1.0, 2.0, 4.0])
    colours = []
    for reflected in (False, True):
        ms = create(scenes("sphere", level=3), degree=6, specular=0.5, shininess=8.0, reflected=reflected)
        ms.apply_filter(h.EVALUATE, viewpoint=eye)
        colours.append(ms.current_mesh().vertex_color_matrix()[:, :3] * 255.0)
    positions = ms.current_mesh().vertex_matrix()
    w = h.normalized(eye[None, :] - positions)
    front = (w * h.normalized(positions)).sum(1) > 0.1
    assert np.abs(colours[0][front] - colours[1][front]).max() <= 2.0


@pytest.mark.parametrize("basis,degree,reflected,specular", [(0, 4, False, 0.0), (1, 6, False, 0.0),
                                                             (0, 6, True, 0.5), (1, 8, True, 0.5)],
                         ids=["pb4_lambert", "sh6_lambert", "pb6_glossy_reflected", "sh8_glossy_reflected"])
def test_save_reload_save_is_bit_identical(basis, degree, reflected, specular, scenes, tmp_path):
    ms = create(scenes("sphere", level=3), basis=basis, degree=degree, reflected=reflected, specular=specular)
    first, second = tmp_path / "first.rply", tmp_path / "second.rply"
    ms.save_current_mesh(str(first))
    again = pymeshlab.MeshSet()
    again.load_new_mesh(str(first))
    again.save_current_mesh(str(second))
    assert first.read_bytes() == second.read_bytes(), "save -> reload -> save changed the file"
    mesh = rply.read_rply(str(first))
    assert mesh.reflected == reflected and mesh.basis == ("PB" if basis == 0 else "SH") + str(degree)
    if specular > 0:
        assert np.abs(mesh.coefficients[:, :, 1:]).max() > 1e-2, "the glossy lobe is missing"
    # The reloaded layer is the same mesh.
    assert np.array_equal(again.current_mesh().vertex_matrix(), mesh.positions.astype(float))


def test_radiance_follows_meshlab_own_vertex_deletion(scenes, tmp_path):
    """MeshLab's own filters select and delete half of the vertices (pymeshlab compacts the vectors
    after every filter): each remaining vertex still has its own RF (Lambert: a function of its
    position on the sphere)."""
    ms = create(scenes("sphere", level=3), degree=3)
    before = ms.current_mesh().vertex_number()
    ms.apply_filter("compute_selection_by_condition_per_vertex", condselect="(x > 0.1)")
    ms.apply_filter("meshing_remove_selected_vertices")
    after = ms.current_mesh().vertex_number()
    assert 0 < after < before, "MeshLab deleted nothing: the test would prove nothing"
    ms.save_current_mesh(str(tmp_path / "edited.rply"))
    mesh = rply.read_rply(str(tmp_path / "edited.rply"))
    assert mesh.vertex_count == after and mesh.positions[:, 0].max() <= 0.1 + 1e-6
    from_positions = sphere_normals_from_positions(mesh)
    assert np.abs(mesh.normals - from_positions).max() < 1e-4
    expected = lambert_radiance(from_positions)
    assert np.abs(mesh.coefficients[:, :, 0] - expected).max() <= 1e-4
    # And the evaluation filter still runs on the edited layer.
    ms.apply_filter(h.EVALUATE, viewpoint=np.array([0.0, 0.0, 5.0]))
    assert ms.current_mesh().vertex_color_matrix().shape[0] == after
