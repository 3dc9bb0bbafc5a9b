"""Our filters through the real pymeshlab 2025.7 (MeshLab 2025.07, double precision)."""
import filecmp

import numpy as np
import pymeshlab
import pytest

import pymeshlab_radiance
from pymeshlab_radiance import rply


def sphere_with_radiance(degree=3):
    ms = pymeshlab.MeshSet()
    ms.create_sphere(subdiv=3)
    ms.apply_filter("radiance_create_radiance_data_from_analytic_material", degree=degree)
    return ms


def test_every_filter_is_known_to_pymeshlab():
    for name in pymeshlab_radiance.filter_names():
        # Raises when pymeshlab does not know the filter.
        pymeshlab.print_filter_parameter_list(name)


def test_rply_save_reload_save_is_bit_identical(tmp_path):
    ms = sphere_with_radiance()
    first, second = tmp_path / "a.rply", tmp_path / "b.rply"
    ms.save_current_mesh(str(first))
    ms.load_new_mesh(str(first))
    ms.save_current_mesh(str(second))
    assert filecmp.cmp(first, second, shallow=False)
    mesh = rply.read_rply(str(first))
    assert mesh.basis == "PB3" and mesh.coefficients.shape == (ms.current_mesh().vertex_number(), 3, 10)


def test_evaluation_toward_viewpoint_darkens_the_back_of_a_lit_sphere():
    ms = sphere_with_radiance()
    ms.apply_filter("radiance_evaluate_radiance_toward_a_viewpoint_as_vertex_color", viewpoint=[0, 0, 5])
    colours = ms.current_mesh().vertex_color_matrix()[:, :3]
    z = ms.current_mesh().vertex_matrix()[:, 2]
    # The default light comes from (0.5, 1, 1): the front (z > 0.5) is brighter than the back (z < -0.5).
    assert colours[z > 0.5].mean() > colours[z < -0.5].mean() + 0.1


def test_simplification_reaches_the_target_and_adds_levels():
    ms = sphere_with_radiance()
    faces = ms.current_mesh().face_number()
    ms.apply_filter("radiance_radiance_aware_simplification", targetpercentage=0.5, lodlevels="0.25")
    assert ms.current_mesh().face_number() == faces // 2
    assert ms.mesh_number() == 2


def test_refusal_raises_our_message_and_leaves_the_meshset_unchanged():
    ms = sphere_with_radiance()
    before = ms.current_mesh().vertex_color_matrix().copy()
    with pytest.raises(pymeshlab.PyMeshLabException, match="Degree 30 is not supported"):
        ms.apply_filter("radiance_create_radiance_data_from_analytic_material", degree=30)
    with pytest.raises(pymeshlab.PyMeshLabException, match="target of"):
        ms.apply_filter("radiance_radiance_aware_simplification", targetfaces=10**7)
    assert ms.mesh_number() == 1
    assert np.array_equal(before, ms.current_mesh().vertex_color_matrix())


def test_prt_transfer_subdivision_and_relighting():
    ms = pymeshlab.MeshSet()
    ms.create_sphere(subdiv=2)
    faces = ms.current_mesh().face_number()
    ms.apply_filter("radiance_compute_prt_transfer")
    ms.apply_filter("radiance_uniform_prt_subdivision")
    assert ms.current_mesh().face_number() >= 4 * faces
    ms.apply_filter("radiance_prt_relighting_as_vertex_color")
    colours = ms.current_mesh().vertex_color_matrix()[:, :3]
    assert colours.std() > 0.01  # a directional light shades a sphere unevenly


def test_bake_normal_map_of_a_sphere(tmp_path):
    ms = pymeshlab.MeshSet()
    ms.create_sphere(subdiv=4)
    ms.create_sphere(subdiv=1)
    ms.apply_filter("bake_normal_map", sourcemesh=0, texturesize=256, outputfile=str(tmp_path / "s_normal.png"))
    assert (tmp_path / "s_normal.png").exists()
    assert ms.current_mesh().has_wedge_tex_coord()
    with pytest.raises(pymeshlab.PyMeshLabException, match="power of two"):
        ms.apply_filter("bake_normal_map", sourcemesh=0, texturesize=100)
