"""'Radiance: Transfer Radiance from Gaussian Splats' (ms.apply_filter('radiance_transfer_gaussian_splats',
splatfile=PATH)) through pymeshlab 2025.7, as tests/integration/test_gaussian_splats.sh does through
meshlabserver 2020.09.

The splat files are written by tests/integration/splat_writer.py (the reference implementation's
save_ply layout), and the expected vertex colours come from its numpy evaluation of the splat field
(the reference eval_sh, + 0.5, sRGB decoding, the hemisphere mean), independent of the C++ code.
"""
import numpy as np
import pymeshlab
import pytest

import pymeshlab_radiance  # noqa: F401  (loads our plugins into pymeshlab)
from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h
import splat_writer

TRANSFER = h.SPLATS


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    folder = tmp_path_factory.mktemp("splats")
    paths = {}
    for name in ("sphere_mesh", "sphere_splats", "nan", "degree4", "far"):
        paths[name] = folder / f"{name}.ply"
        splat_writer.write_scenario(name, str(paths[name]))
    return paths


def test_sphere_field_transfers_within_three_levels(files, tmp_path):
    ms = h.load(files["sphere_mesh"])
    ms.apply_filter(TRANSFER, splatfile=str(files["sphere_splats"]))
    mesh = ms.current_mesh()
    got = np.round(mesh.vertex_color_matrix()[:, :3] * 255.0)
    points = mesh.vertex_matrix()
    expected = splat_writer.expected_mean_colors(points, points / np.linalg.norm(points, axis=1, keepdims=True))
    error = np.abs(got - expected).mean()
    print(f"mean colour error {error:.2f} levels, worst {np.abs(got - expected).max():.0f}")
    assert error <= 3.0, f"mean colour error {error:.2f} 8-bit levels (target 3)"
    # The radiance is SH of the splats' degree (1), saved and read back by the numpy reader.
    out = tmp_path / "transferred.rply"
    ms.save_current_mesh(str(out))
    saved = rply.read_rply(out)
    assert saved.basis == "SH1" and not saved.reflected
    assert saved.coefficients.shape == (points.shape[0], 3, 4)
    # The view dependence along x came across: band-1 x coefficient (index 3) of red is positive
    # (the splats' Y3dgs_1^1 coefficient 0.25 on -x of the camera-to-splat direction, i.e. +x toward
    # the viewer, times the positive slope of the sRGB decoding).
    assert np.median(saved.coefficients[:, 0, 3]) > 0.0
    assert np.median(saved.coefficients[:, 1, 3]) < 0.0


BAD = [("not_a_splat_file", "not a 3D Gaussian splat file"),
       ("nan", "not a finite number"),
       ("degree4", "degree 4"),
       ("missing_folder", "cannot be opened"),
       ("far", "no vertex of the mesh has a splat near it")]


@pytest.mark.parametrize("case,message", BAD, ids=[c for c, _ in BAD])
def test_bad_input_is_refused_and_the_layers_stay(files, case, message):
    ms = h.load(files["sphere_mesh"])
    path = {"not_a_splat_file": files["sphere_mesh"], "missing_folder": files["nan"].parent / "no_such_folder" / "s.ply"}
    splatfile = str(path.get(case, files.get(case)))
    text = h.expect_refusal(ms, TRANSFER, message, splatfile=splatfile)
    assert any(w in text.lower() for w in ("give", "check", "retrain", "remove")), f"no remedy in: {text}"
