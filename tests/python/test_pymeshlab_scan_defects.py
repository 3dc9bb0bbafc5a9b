"""Defects of real scans through pymeshlab 2025.7: a vertex whose only face is a sliver (its normal in
the file is zero, as MeshLab's area-weighted normal rounds to there), a NaN normal, an isolated vertex,
a zero-area face and a face repeating a vertex. The filters repair what they can (the frame normals
in the saved radiance data are checked against the geometry, computed here with numpy) and refuse
nothing; the simplification collapses the degenerate faces instead of refusing the mesh."""
import numpy as np

from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h


def scan_like(folder):
    vertices, faces = h.grid(4, 4)               # 25 vertices in z = 0, 32 faces facing +Z
    normals = [(0.0, 0.0, 1.0)] * len(vertices)
    # Vertex 25 forms a sliver with the border edge 0-1 (1 -> 0 so that the edge stays manifold): area
    # 2.5e-9, tilted straight up out of the plane. Its normal in the file is zero.
    vertices.append((0.5, 0.0, 1e-8))
    faces.append((1, 0, 25))
    normals.append((0.0, 0.0, 0.0))
    normals[12] = (float("nan"), 0.0, 0.0)       # an interior vertex with a NaN normal
    vertices.append((9.0, 9.0, 9.0))              # vertex 26: used by no face
    normals.append((0.0, 0.0, 0.0))
    path = folder / "scan_like.ply"
    h.write_ascii_ply(path, vertices, faces, normals)
    return path, np.array(vertices), np.array(faces)


def test_create_repairs_sliver_nan_and_isolated_normals(tmp_path):
    path, vertices, faces = scan_like(tmp_path)
    ms = h.load(path)
    assert ms.current_mesh().vertex_number() == 27, "MeshLab dropped a vertex on load"
    ms.apply_filter(h.CREATE, degree=2)
    out = tmp_path / "created.rply"
    ms.save_current_mesh(str(out))
    mesh = rply.read_rply(out)
    frames = mesh.normals.astype(float)
    assert np.isfinite(mesh.coefficients).all()
    # The sliver's vertex: the unit normal of its face's plane, from numpy.
    p1, p0, p25 = vertices[1], vertices[0], vertices[25]
    plane = np.cross(p0 - p1, p25 - p1)
    plane /= np.linalg.norm(plane)
    assert np.allclose(frames[25], plane, atol=1e-5), f"sliver vertex frame {frames[25]}, face plane {plane}"
    assert abs(plane[2]) < 1e-3  # the test discriminates: the plane is vertical, unlike the grid's
    # The NaN normal: the grid's plane. The isolated vertex: +Z. The others: as in the file.
    assert np.allclose(frames[12], [0, 0, 1], atol=1e-6)
    assert np.allclose(frames[26], [0, 0, 1], atol=1e-6)
    others = [v for v in range(25) if v not in (0, 1, 12)]
    assert np.allclose(frames[others], [0, 0, 1], atol=1e-6)


def test_simplification_collapses_zero_area_and_repeated_vertex_faces(tmp_path):
    vertices, faces = h.grid(6, 6)                # 49 vertices, 72 faces
    faces.append((2, 1, 0))                       # collinear along the border: zero area, manifold
    faces.append((20, 20, 21))                    # repeats a vertex
    path = h.write_ascii_ply(tmp_path / "defects.ply", vertices, faces, [(0.0, 0.0, 1.0)] * len(vertices))
    ms = h.load(path)
    before = ms.current_mesh().face_number()
    ms.apply_filter(h.CREATE, degree=2)
    ms.apply_filter(h.SIMPLIFY, targetfaces=30, targetpercentage=0.0, preserveboundary=False)
    after = ms.current_mesh()
    assert after.face_number() <= 30 < before
    assert np.isfinite(after.vertex_matrix()).all()
    assert np.allclose(after.vertex_matrix()[:, 2], 0.0), "a vertex left the plane"
