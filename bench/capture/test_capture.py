"""pytest for render_capture.py + check_capture.py (needs mitsuba: skipped without it).

A tiny capture (4 views, 128x96, 4 spp) of a sphere-like closed mesh must pass every camera check,
and the same capture with its project.mlp's principal point moved by half a pixel, or its image
x axis flipped, must fail them: the check can tell a right camera from a nearly right one.
"""
import os
import re
import sys

import numpy as np
import pytest

pytest.importorskip("mitsuba")
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import check_capture  # noqa: E402
import render_capture  # noqa: E402


def icosphere(level):
    t = (1 + 5 ** 0.5) / 2
    V = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    F = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    V = [np.array(v, float) / np.linalg.norm(v) for v in V]
    for _ in range(level):
        cache, out = {}, []

        def mid(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = V[a] + V[b]
                V.append(m / np.linalg.norm(m))
                cache[key] = len(V) - 1
            return cache[key]
        for a, b, c in F:
            ab, bc, ca = mid(a, b), mid(b, c), mid(c, a)
            out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        F = out
    V = np.array(V) * np.array([1.0, 0.7, 0.8])  # an ellipsoid: not symmetric under axis swaps
    return V, np.array(F)


@pytest.fixture(scope="module")
def capture(tmp_path_factory):
    folder = tmp_path_factory.mktemp("capture")
    V, F = icosphere(3)
    off = folder / "blob.off"
    with open(off, "w") as f:
        f.write(f"OFF\n{len(V)} {len(F)} 0\n")
        f.writelines(f"{x} {y} {z}\n" for x, y, z in V)
        f.writelines(f"3 {a} {b} {c}\n" for a, b, c in F)
    out = folder / "cap"
    assert render_capture.main(["--mesh", str(off), "--views", "4", "--width", "128", "--height", "96",
                                "--spp", "4", "--noise-twin", "--out", str(out)]) == 0
    return out


def test_capture_files(capture):
    for name in ("mesh.ply", "project.mlp", "project_with_mesh.mlp", "cameras.json", "capture.json",
                 "photos/view_003.png", "photos_twin/view_003.png", "masks/view_000.png"):
        assert (capture / name).is_file(), name
    V, N, F = check_capture.read_ply(str(capture / "mesh.ply"))
    assert np.allclose(np.linalg.norm(N, axis=1), 1, atol=1e-5)
    assert "vertex_color" not in (capture / "mesh.ply").read_bytes()[:400].decode("ascii", "replace")
    assert b"property float r" not in (capture / "mesh.ply").read_bytes()[:400]


def test_right_cameras_pass(capture):
    assert check_capture.main([str(capture), "--aov-views", "2"]) == 0


@pytest.mark.parametrize("edit", ["half_pixel", "mirror"])
def test_wrong_cameras_fail(capture, tmp_path, edit):
    text = (capture / "project.mlp").read_text()
    if edit == "half_pixel":
        text = text.replace('CenterPx="64 48"', 'CenterPx="64.5 48"')
    else:  # negate the image x axis (row 0 of the rotation)
        def flip(m):
            vals = m.group(1).split()
            vals[0:3] = [str(-float(v)) for v in vals[0:3]]
            return 'RotationMatrix="' + " ".join(vals) + ' "'
        text = re.sub(r'RotationMatrix="([^"]*)"', flip, text)
    assert text != (capture / "project.mlp").read_text()
    (capture / f"wrong_{edit}.mlp").write_text(text)
    assert check_capture.main([str(capture), "--project", f"wrong_{edit}.mlp", "--aov-views", "2"]) == 1
