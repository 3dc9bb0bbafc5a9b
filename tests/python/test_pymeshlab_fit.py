"""'Radiance: Fit Radiance Functions from Rasters' through pymeshlab 2025.7, with the photographs
read as raster layers by MeshSet.load_project, mirroring tests/integration/test_fit_from_rasters.sh
and test_fit_refusals.sh.

The photographs are made by the built tool virtual_acquisition (a sphere, 16 views, 320 x 240, the
glossy sample material without spatial variation). The check is independent of the C++ code: the
.mlp camera model is implemented here (as tests/integration/check_fit_against_photos.py: rotation
rows = camera right, up, backwards; TranslationVector = -centre; px from the left, py from the
bottom), the PNG photographs are decoded by tests/integration/png_reader.py, the fitted PB functions
(numpy .rply reader) are evaluated here toward each camera and compared with what the photograph
shows at the vertex's projection.
"""
import os
import re
import xml.etree.ElementTree as ET

import numpy as np
import pymeshlab
import pytest

from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h

VIEWS = 16


@pytest.fixture(scope="module")
def photos(scenes, tmp_path_factory):
    folder = tmp_path_factory.mktemp("fit") / "photos"
    h.run_tool("virtual_acquisition", scenes("sphere", level=4), "-o", folder, "--views", VIEWS,
               "--size", "320x240", "--no-variation")
    for name in ("mesh.ply", "project.mlp"):
        assert (folder / name).is_file(), f"virtual_acquisition wrote no {name}"
    return folder


def fit_parameters(**overrides):
    """Every parameter, as fit_mlx of tests/integration/lib.sh lists them."""
    parameters = dict(visibleonly=False, basis=0, degree=4, regularization=0.001,
                      depthtolerance=pymeshlab.PureValue(0.003), grazingangle=80.0, bordermargin=2, minsamples=3,
                      reflected=False, quality=0, setcolor=True)
    parameters.update(overrides)
    return parameters


def with_rasters(photos, project="project.mlp"):
    ms = h.load(photos / "mesh.ply")
    ms.load_project(str(photos / project))
    return ms


def read_cameras(project):
    cameras = []
    for raster in ET.parse(str(project)).getroot().iter("MLRaster"):
        cam = raster.find("VCGCamera")
        nums = lambda key: np.array([float(x) for x in cam.get(key).split()])  # noqa: E731
        rotation = nums("RotationMatrix").reshape(4, 4)[:3, :3]
        image, _ = h.read_png(os.path.join(os.path.dirname(str(project)), raster.find("Plane").get("fileName")))
        cameras.append(dict(rows=rotation, centre=-nums("TranslationVector")[:3], focal=float(cam.get("FocalMm")),
                            pixel=nums("PixelSizeMm"), centre_px=nums("CenterPx"), image=image[:, :, :3]))
    return cameras


def photo_errors(fit, cameras, min_cos=0.5):
    """|fitted - photographed| in 8-bit sRGB levels over (vertex, camera, channel) with n.w >= min_cos."""
    p = fit.positions.astype(float)
    n = fit.normals.astype(float)
    errors = []
    for cam in cameras:
        w = h.normalized(cam["centre"][None, :] - p)
        d = p - cam["centre"][None, :]
        cp = d @ cam["rows"].T
        depth = -cp[:, 2]
        ok = ((n * w).sum(1) >= min_cos) & (depth > 0)
        px = cp[:, 0] * cam["focal"] / np.where(depth > 0, depth, 1) / cam["pixel"][0] + cam["centre_px"][0]
        py = cp[:, 1] * cam["focal"] / np.where(depth > 0, depth, 1) / cam["pixel"][1] + cam["centre_px"][1]
        height, width, _ = cam["image"].shape
        x = px - 0.5
        y = (height - py) - 0.5
        ok &= (x >= 1) & (y >= 1) & (x <= width - 2) & (y <= height - 2)
        x, y = x[ok], y[ok]
        x0, y0 = x.astype(int), y.astype(int)
        fx, fy = (x - x0)[:, None], (y - y0)[:, None]
        linear = h.srgb_decode(cam["image"] * 255.0)
        seen = ((linear[y0, x0] * (1 - fx) + linear[y0, x0 + 1] * fx) * (1 - fy) +
                (linear[y0 + 1, x0] * (1 - fx) + linear[y0 + 1, x0 + 1] * fx) * fy)
        fitted = h.evaluate_pb(fit, w)[ok]
        errors.append(np.abs(h.srgb_encode(fitted) - h.srgb_encode(seen)).ravel())
    return np.concatenate(errors)


def test_fit_reproduces_the_photographs(photos, tmp_path):
    ms = with_rasters(photos)
    assert ms.mesh_number() == 1 and ms.raster_number() == VIEWS, "load_project did not add the raster layers"
    ms.apply_filter(h.FIT, **fit_parameters())
    ms.save_current_mesh(str(tmp_path / "fit_pb4.rply"))
    fit = rply.read_rply(str(tmp_path / "fit_pb4.rply"))
    assert fit.basis == "PB4" and not fit.reflected and fit.vertex_count == 2562
    errors = np.sort(photo_errors(fit, read_cameras(photos / "project.mlp")))
    assert errors.size > 3000, f"only {errors.size} comparisons: the cameras do not see the mesh?"
    median, p90 = errors[errors.size // 2], errors[int(0.9 * errors.size)]
    # The same bounds as the integration test (median 2, 90th percentile 8 sRGB levels).
    assert median <= 2.0 and p90 <= 8.0, f"median {median:.2f}, 90th percentile {p90:.2f} sRGB levels"
    # Vertex quality = sample count: every vertex of a sphere seen from 16 directions all around is
    # seen several times, and none by more than the 16 photographs.
    quality = ms.current_mesh().vertex_scalar_array()
    assert np.all(quality == np.round(quality)) and quality.min() >= 1 and quality.max() <= VIEWS
    assert quality.mean() > 3


def test_fit_is_a_real_fit_not_a_copy_of_any_one_photograph(photos, tmp_path):
    """Against a wrong camera (the photographs shuffled by one) the same check fails: the comparison
    is discriminating."""
    ms = with_rasters(photos)
    ms.apply_filter(h.FIT, **fit_parameters())
    ms.save_current_mesh(str(tmp_path / "fit.rply"))
    cameras = read_cameras(photos / "project.mlp")
    shuffled = [dict(c, image=cameras[(i + 1) % len(cameras)]["image"]) for i, c in enumerate(cameras)]
    errors = np.sort(photo_errors(rply.read_rply(str(tmp_path / "fit.rply")), shuffled))
    assert errors[int(0.9 * errors.size)] > 8.0


def test_sh_reflected_fit_with_residual_quality(photos, tmp_path):
    ms = with_rasters(photos)
    ms.apply_filter(h.FIT, **fit_parameters(basis=1, degree=3, reflected=True, quality=1))
    ms.save_current_mesh(str(tmp_path / "fit_sh.rply"))
    fit = rply.read_rply(str(tmp_path / "fit_sh.rply"))
    assert fit.basis == "SH3" and fit.reflected and fit.coefficients.shape == (2562, 3, 16)
    assert np.isfinite(fit.coefficients).all() and np.abs(fit.coefficients).max() > 0.01
    residual = ms.current_mesh().vertex_scalar_array()
    assert np.isfinite(residual).all() and residual.min() >= 0 and residual.max() > 0
    assert not np.all(residual == np.round(residual)), "quality holds counts, not residuals"


def test_fit_refuses_a_document_without_rasters(photos, tmp_path):
    ms = h.load(photos / "mesh.ply")
    h.expect_refusal(ms, h.FIT, "The document has no raster layers", **fit_parameters())


def test_fit_refuses_when_every_raster_is_unusable(photos):
    text = (photos / "project.mlp").read_text()
    (photos / "all_bad.mlp").write_text(re.sub(r'FocalMm="[^"]*"', 'FocalMm="0"', text))
    ms = with_rasters(photos, "all_bad.mlp")
    assert ms.raster_number() == VIEWS
    h.expect_refusal(ms, h.FIT, f"None of the {VIEWS} raster layers is usable", **fit_parameters())


def test_fit_refuses_cameras_turned_away(photos):
    def flip(match):
        v = match.group(1).split()
        for k in (4, 5, 6, 8, 9, 10):
            v[k] = repr(-float(v[k]))
        return 'RotationMatrix="' + " ".join(v) + '"'

    text = (photos / "project.mlp").read_text()
    (photos / "turned_away.mlp").write_text(re.sub(r'RotationMatrix="([^"]*)"', flip, text))
    ms = with_rasters(photos, "turned_away.mlp")
    h.expect_refusal(ms, h.FIT, "No vertex is seen by any raster", **fit_parameters())


def test_fit_refuses_a_point_cloud_without_normals(photos, tmp_path):
    cloud = tmp_path / "cloud.ply"
    cloud.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nend_header\n0 0 1\n0.1 0 1\n0 0.1 1\n")
    ms = h.load(cloud)
    ms.load_project(str(photos / "project.mlp"))
    h.expect_refusal(ms, h.FIT, "vertices has a usable normal and there are no faces",
                     **fit_parameters())
