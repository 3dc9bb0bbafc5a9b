"""The web viewer (python -m pymeshlab_radiance.view) in Debian's headless Chromium (software WebGL2:
SwiftShader) against the project's CPU renderer (render_radiance, Embree ray casting, eq. (8)
per-fragment shading of Vanhoey et al. 2015) at the same camera (--look-at / --fov / --size on both).

Bound (docs/gltf-radiance.md, "Viewer accuracy"): both evaluate the same function at the same pixel
centres (one sample per pixel), so the differences are the rounding of the 8-bit sRGB encoding (the
CPU rounds to nearest; WebGL's float-to-unorm conversion may round the other way at a level
boundary: 1 level), and float32 arithmetic on the GPU (SwiftShader's pow / exp2 approximations in the
sRGB curve, float barycentrics) against double on the CPU, which the sRGB curve amplifies in dark
channels (slope 12.92 x 255 levels per unit of linear radiance below 0.0031): up to 2 more levels
there. Pixels next to the silhouette are left out (a pixel centre may hit the mesh in one renderer
and the background in the other). Hence, over the interior pixels: RMSE <= 1.0 level and no pixel
more than 3 levels apart (measured: RMSE 0.21, at most 2 levels, in dark blue values).
"""
import os
import subprocess
import sys

import numpy as np
import pytest
from PIL import Image

import pymeshlab_test_helpers as h
from test_pymeshlab_export_gltf import create, EXPORT

SIZE = (160, 120)
CAMERA = "0.6,0.9,2.8,0,0,0,0,1,0"
FOV = 40


def view(*args):
    env = h.python_env()
    run = subprocess.run([sys.executable, "-m", "pymeshlab_radiance.view", *map(str, args)], capture_output=True,
                         text=True, timeout=300, env=env)
    return run


def image(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=float)


def interior(a, b):
    """Pixels covered in both images whose 8 neighbours are covered too."""
    covered = (a.max(2) > 0) & (b.max(2) > 0)
    inner = covered.copy()
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            inner &= np.roll(np.roll(covered, dy, 0), dx, 1)
    inner[0, :] = inner[-1, :] = inner[:, 0] = inner[:, -1] = False
    return inner


@pytest.mark.parametrize("basis,degree,reflected", [(1, 3, False), (1, 3, True), (0, 3, False), (0, 3, True)],
                         ids=["SH3", "SH3-reflected", "PB3", "PB3-reflected"])
def test_screenshot_matches_the_cpu_renderer(basis, degree, reflected, scenes, tmp_path):
    ms = create(scenes("sphere", level=2), basis, degree, reflected, specular=0.5)
    ms.save_current_mesh(str(tmp_path / "m.rply"))
    ms.apply_filter(EXPORT, outputfile=str(tmp_path / "m.glb"))
    size = f"{SIZE[0]}x{SIZE[1]}"
    run = view(tmp_path / "m.glb", "--screenshot", tmp_path / "gl.png", "--size", size, "--look-at", CAMERA,
               "--fov", FOV)
    assert run.returncode == 0, run.stdout + run.stderr
    assert "SwiftShader" in run.stdout or "llvmpipe" in run.stdout, run.stdout
    h.run_tool("render_radiance", str(tmp_path / "m.rply"), "--look-at", CAMERA, "--fov", str(FOV), "--size", size,
               "--supersampling", "1", "--mode", "fragment", "-o", str(tmp_path / "cpu.png"))
    gl, cpu = image(tmp_path / "gl.png"), image(tmp_path / "cpu.png")
    assert gl.shape == cpu.shape == (SIZE[1], SIZE[0], 3)
    mask = interior(gl, cpu)
    assert mask.sum() > 0.2 * mask.size, "the sphere should fill a good part of the view"
    difference = gl[mask] - cpu[mask]
    rmse = float(np.sqrt((difference ** 2).mean()))
    print(f"{basis=} {reflected=}: {mask.sum()} pixels, RMSE {rmse:.3f}, max {np.abs(difference).max()}")
    assert rmse <= 1.0 and np.abs(difference).max() <= 3, (rmse, np.abs(difference).max())
    # The highlight is there (the comparison is not between two flat images).
    assert np.ptp(cpu[mask][:, 1]) > 40
    # Coverage agrees too: the silhouettes differ at most along a one-pixel band.
    assert abs(int((gl.max(2) > 0).sum()) - int((cpu.max(2) > 0).sum())) < 0.05 * mask.sum()


def test_mean_colour_toggle_and_exposure(scenes, tmp_path):
    """Lambert: the RF is its own mean, so RF and COLOR_0 pictures agree; exposure 0.5 halves the
    linear radiance of the RF picture: its 8-bit codes are those of half the decoded RF picture, within
    the two roundings (0.5 level each; halving shrinks a level by at most 2^(1/2.4): under 1.2 levels)."""
    ms = create(scenes("sphere", level=2), 1, 2)
    ms.apply_filter(EXPORT, outputfile=str(tmp_path / "l.glb"))
    common = ["--size", "96x72", "--look-at", CAMERA, "--fov", FOV]
    for name, extra in [("rf", []), ("mean", ["--mean-color"]), ("half", ["--exposure", "0.5"])]:
        run = view(tmp_path / "l.glb", "--screenshot", tmp_path / f"{name}.png", *common, *extra)
        assert run.returncode == 0, run.stdout + run.stderr
    rf, mean, half = (image(tmp_path / f"{n}.png") for n in ("rf", "mean", "half"))
    mask = interior(rf, mean)
    assert mask.sum() > 500
    # COLOR_0 is interpolated linearly across triangles, the RF evaluated per fragment: on a Lambertian
    # RF both are the linear interpolation of the vertex values.
    assert np.abs(rf[mask] - mean[mask]).max() <= 1
    unclipped = (rf[mask] < 254).all(1)
    expected = h.srgb_encode(0.5 * h.srgb_decode(rf[mask][unclipped]))
    assert np.abs(half[mask][unclipped] - expected).max() <= 1.2
    assert np.abs(half[mask] - rf[mask]).max() > 40, "exposure had no effect"


def test_served_on_loopback(scenes, tmp_path):
    """Without --output / --screenshot the viewer is served on 127.0.0.1: the page and the model."""
    import urllib.request

    ms = create(scenes("sphere", level=1), 0, 1)
    ms.apply_filter(EXPORT, outputfile=str(tmp_path / "p.glb"))
    env = h.python_env()
    server = subprocess.Popen([sys.executable, "-m", "pymeshlab_radiance.view", str(tmp_path / "p.glb"), "--no-browser"],
                              stdout=subprocess.PIPE, text=True, env=env)
    try:
        line = server.stdout.readline()
        assert line.startswith("Radiance viewer at http://127.0.0.1:"), line
        url = line.split()[3]
        page = urllib.request.urlopen(url, timeout=30).read().decode()
        assert "webgl2" in page and '"model": "/model.glb"' in page
        assert urllib.request.urlopen(url + "model.glb", timeout=30).read() == (tmp_path / "p.glb").read_bytes()
    finally:
        server.terminate()
        server.wait(30)


def test_standalone_page_and_refusals(scenes, tmp_path):
    ms = create(scenes("sphere", level=1), 1, 1)
    ms.apply_filter(EXPORT, outputfile=str(tmp_path / "s.glb"))
    run = view(tmp_path / "s.glb", "--output", tmp_path / "s.html")
    assert run.returncode == 0, run.stderr
    page = (tmp_path / "s.html").read_text()
    assert '<script id="model" type="application/octet-stream">' in page
    assert "http://" not in page and "https://" not in page, "the page must not reach the network"
    ms.save_current_mesh(str(tmp_path / "s.ply"))
    for args, message in [([tmp_path / "s.ply", "--output", tmp_path / "x.html"], "not a binary glTF"),
                          ([tmp_path / "absent.glb", "--output", tmp_path / "x.html"], "cannot read"),
                          ([tmp_path / "s.glb", "--output", tmp_path / "no" / "x.html"], "does not exist"),
                          ([tmp_path / "s.glb", "--screenshot", tmp_path / "x.png", "--look-at", "1,2"], "9 comma")]:
        run = view(*args)
        assert run.returncode == 1 and message in run.stderr, (args, run.stderr)
    assert not (tmp_path / "x.html").exists() and not (tmp_path / "x.png").exists()
