"""Real scans as distributed, through every filter but the fit (which needs photographs: see
test_pymeshlab_fit.py): a laser range map of a face (85,849 vertices, with 667 vertices no face uses,
whose normals are zero) and the Stanford bunny (28,088 vertices, with its holes), both shipped in the
pymeshlab wheel's test data. Before the normal repair and the degenerate-face handling, the range map
was refused by creation and by PRT subdivision; now nothing may be refused, and every result must be
finite."""
import os

import numpy as np
import pymeshlab
import pytest

import pymeshlab_radiance  # noqa: F401 -- loads our plugins into pymeshlab

import pymeshlab_test_helpers as h

SAMPLES = os.path.join(os.path.dirname(pymeshlab.__file__), "tests", "sample_meshes")
SCANS = {"face range map": "rangemaps/face000.ply", "Stanford bunny": "bunny.obj"}


def scan_path(name):
    path = os.path.join(SAMPLES, SCANS[name])
    assert os.path.exists(path), f"{path}: the pymeshlab wheel no longer ships this scan"
    return path


def finite_layer(ms, what):
    m = ms.current_mesh()
    assert np.isfinite(m.vertex_matrix()).all(), f"{what}: non-finite positions"
    if m.has_vertex_color():
        assert np.isfinite(m.vertex_color_matrix()).all(), f"{what}: non-finite colours"
    return m


@pytest.mark.parametrize("name", sorted(SCANS))
def test_every_filter_runs_on_the_real_scan(name, tmp_path):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(scan_path(name))            # layer 0: the scan as it is, the bake's source
    ms.load_new_mesh(scan_path(name))            # layer 1: the one we process
    faces = ms.current_mesh().face_number()
    ms.apply_filter(h.CREATE, degree=3)
    ms.apply_filter(h.EVALUATE, viewpoint=np.array([0.0, 0.0, 1000.0]), exposure=1.0)
    finite_layer(ms, "evaluation")
    ms.apply_filter(h.SIMPLIFY, targetpercentage=0.1)
    simplified = finite_layer(ms, "simplification")
    assert simplified.face_number() <= 0.1 * faces + 2
    ms.save_current_mesh(str(tmp_path / "simplified.rply"))
    assert (tmp_path / "simplified.rply").stat().st_size > 0

    ms.apply_filter(h.BAKE, sourcemesh=0, texturesize=2048, space=0, bits=0, gutter=4, newatlas=True,
                    diffuse=False, lean=True, assign=0, outputfile=str(tmp_path / "scan_normal.png"))
    normal_map, _ = h.read_png(tmp_path / "scan_normal.png")
    length = np.linalg.norm(normal_map * 2 - 1, axis=2)
    assert np.abs(length - 1).max() <= 0.02, "texels that are not unit normals"

    ms.apply_filter(h.TRANSFER, order=3, rays=32)
    ms.apply_filter(h.RELIGHT)
    finite_layer(ms, "relighting")
    before = ms.current_mesh().face_number()
    ms.apply_filter(h.ADAPTIVE, budgetfactor=1.3)
    subdivided = finite_layer(ms, "adaptive subdivision")
    assert before < subdivided.face_number() <= 1.3 * before
