"""The "Compute Irradiance Vector Grid" filter through pymeshlab 2025.7 (MeshLab 2025.07), mirroring
tests/integration/test_irradiance_grid.sh.

The .ivg file is read back by check_ivg.read_ivg (an independent reader, tests/integration). The
expected values come from the scene, not from the C++ code: a red floor (vertex colour 255, 0, 0:
albedo 1, 0, 0) facing up under a directional light reflects red light only, so every green and blue
vector is zero and some red ones are not; above a lone floor nothing comes from above, so every +z
vector is zero, and the -z vectors point down (light arrives from below).
"""
import os
import sys

import numpy as np
import pymeshlab
import pytest

import pymeshlab_radiance  # noqa: F401  (loads our plugins into pymeshlab)
import pymeshlab_test_helpers as h

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "integration"))
import check_ivg  # noqa: E402

GRID = h.IRRADIANCE_GRID
SUN = dict(lightsource=1, lightdirection=np.array([0.2, 0.1, 1.0]), lightirradiance=2.0)


def floor_arrays(n):
    xs = np.linspace(-1.0, 1.0, n + 1)
    vertices = np.array([[x, y, 0.0] for y in xs for x in xs])
    faces = []
    for j in range(n):
        for i in range(n):
            a, b, c, d = j * (n + 1) + i, j * (n + 1) + i + 1, (j + 1) * (n + 1) + i + 1, (j + 1) * (n + 1) + i
            faces += [(a, b, c), (a, c, d)]
    return vertices, faces


def red_floor_binary(path, n=8):
    """The same floor as a binary little-endian PLY (what the project's PLY reader takes)."""
    import struct
    vertices, faces = floor_arrays(n)
    with open(path, "wb") as f:
        f.write(("ply\nformat binary_little_endian 1.0\n"
                 f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n"
                 "property uchar red\nproperty uchar green\nproperty uchar blue\n"
                 f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n").encode())
        for v in vertices:
            f.write(struct.pack("<fffBBB", v[0], v[1], v[2], 255, 0, 0))
        for t in faces:
            f.write(struct.pack("<Biii", 3, *t))
    return path


def red_floor(path, n=8):
    vertices, faces = floor_arrays(n)
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\n")
        f.write(f"element vertex {len(vertices)}\nproperty float x\nproperty float y\nproperty float z\n"
                "property uchar red\nproperty uchar green\nproperty uchar blue\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in vertices:
            f.write(f"{v[0]} {v[1]} {v[2]} 255 0 0\n")
        for t in faces:
            f.write(f"3 {t[0]} {t[1]} {t[2]}\n")
    return path


def test_grid_written_beside_the_layer_and_read_back(tmp_path):
    mesh = red_floor(str(tmp_path / "floor.ply"))
    ms = h.load(mesh)
    before = h.snapshot(ms)
    ms.apply_filter(GRID, resolution=4, bounces=1, rays=64, **SUN)
    h.assert_unchanged(before, h.snapshot(ms), "the grid filter")
    path = tmp_path / "floor.ivg"
    assert path.is_file(), "no floor.ivg beside floor.ply"
    cells, fields, values = check_ivg.read_ivg(str(path))
    assert cells[0] == 4 and cells[1] == 4 and cells[2] == 1, cells  # cubic cells, 4 along x and y
    v = np.array(values).reshape(-1, 6, 3, 3)  # vertex, direction, channel, xyz
    assert np.all(np.isfinite(v))
    assert np.all(v[:, :, 1:, :] == 0.0), "green or blue light from a red floor"
    assert np.count_nonzero(v[:, :, 0, :]) > 0, "no red light at all"
    assert np.all(v[:, 4] == 0.0), "+z vectors above a lone floor must be zero (rays escape)"
    assert np.all(v[:, 5, 0, 2] <= 0.0), "-z vectors must point down"
    assert fields["bounces"] == "1" and fields["rays"] == "64"


def test_grid_written_at_a_given_path(tmp_path):
    mesh = red_floor(str(tmp_path / "floor.ply"))
    ms = h.load(mesh)
    out = tmp_path / "sub" / "given.ivg"
    out.parent.mkdir()
    ms.apply_filter(GRID, resolution=3, bounces=2, rays=16, outputfile=str(out), **SUN)
    cells, fields, _ = check_ivg.read_ivg(str(out))
    assert cells[0] == 3 and fields["bounces"] == "2"
    assert not (tmp_path / "floor.ivg").exists()


def test_refusals_leave_layers_and_files_unchanged(tmp_path):
    mesh = red_floor(str(tmp_path / "floor.ply"))
    ms = h.load(mesh)
    h.expect_refusal(ms, GRID, "No environment map given", lightsource=0, envmap="")
    h.expect_refusal(ms, GRID, "missing.exr", lightsource=0, envmap=str(tmp_path / "missing.exr"))
    h.expect_refusal(ms, GRID, "The grid resolution is 0 cells", resolution=0, **SUN)
    h.expect_refusal(ms, GRID, "choose 1 (one diffuse bounce", bounces=0, **SUN)
    assert not (tmp_path / "floor.ivg").exists()
    h.reset_pymeshlab_logger()


def test_layer_without_a_file_needs_an_output_path(tmp_path):
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0.0]]),
                               face_matrix=np.array([[0, 1, 2]], dtype=np.int32)))
    h.expect_refusal(ms, GRID, "has no file to write the grid beside", **SUN)
    h.reset_pymeshlab_logger()
    out = tmp_path / "memory.ivg"
    ms.apply_filter(GRID, resolution=2, rays=8, outputfile=str(out), **SUN)
    assert out.is_file()


def test_command_line_tool_writes_the_same_kind_of_grid(tmp_path):
    mesh = red_floor_binary(str(tmp_path / "floor.ply"))
    out = h.run_tool("compute_irradiance_grid", mesh, "--resolution", 4, "--rays", 32, "--sun", "0.2,0.1,1,2")
    assert "grid: 4 x 4 x 1 cells" in out, out
    assert "vertices inside objects or behind walls" in out, out
    cells, fields, values = check_ivg.read_ivg(str(tmp_path / "floor.ivg"))
    v = np.array(values).reshape(-1, 6, 3, 3)
    assert cells == [4, 4, 1]
    assert np.all(v[:, :, 1:, :] == 0.0) and np.count_nonzero(v[:, :, 0, :]) > 0
    # No light: a usage error, no file.
    result = __import__("subprocess").run([h.tool("compute_irradiance_grid"), mesh, "-o", str(tmp_path / "x.ivg")],
                                          capture_output=True, text=True)
    assert result.returncode == 2 and "no light" in result.stderr
    assert not (tmp_path / "x.ivg").exists()
