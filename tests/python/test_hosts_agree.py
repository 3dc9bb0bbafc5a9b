"""The same input through both hosts gives the same result: Debian's meshlabserver 2020.09 (float
build, the private prefix build/meshlab-prefix, under xvfb-run, every parameter listed in the .mlx as
2020.09 requires) and pymeshlab 2025.7 (MeshLab 2025.07, double build).

  - 'Create Radiance Data from Analytic Material': the .rply files agree in geometry, frames and
    coefficients within a relative 1e-4 of the largest coefficient (float vs double hosts; the cores
    compute in their own precision, so they are expected to agree far closer).
  - 'Radiance-Aware Simplification' to 25 %: the same face count, and (by position) the same faces.
  - 'Transfer Radiance from Gaussian Splats': the same SH1 coefficients (relative 1e-4) and colours.
"""
import os
import subprocess

import numpy as np
import pymeshlab
import pytest

from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h

CREATE_CASES = {
    "pb4_glossy": dict(basis=0, degree=4, reflected=False, specular=0.5, stripes=0, lighttype=0,
                       light=(0.5, 1.0, 1.0)),
    "sh6_reflected_stripes_point": dict(basis=1, degree=6, reflected=True, specular=0.7, stripes=3, lighttype=1,
                                        light=(1.5, 2.0, 2.5)),
}


def create_in_pymeshlab(mesh, case, out):
    ms = h.load(mesh)
    ms.apply_filter(h.CREATE, basis=case["basis"], degree=case["degree"], reflected=case["reflected"],
                    albedo=pymeshlab.Color(230, 60, 40), specularcolor=pymeshlab.Color(255, 255, 255),
                    specular=case["specular"], shininess=40.0, stripes=case["stripes"], stripeaxis=1,
                    lighttype=case["lighttype"], light=np.array(case["light"]), lightintensity=3.0, ambient=0.05,
                    setcolor=True)
    ms.save_current_mesh(str(out))


@pytest.mark.parametrize("name", sorted(CREATE_CASES))
def test_create_analytic_agrees_between_hosts(name, scenes, tmp_path):
    case = CREATE_CASES[name]
    mesh = scenes("sphere", level=3)
    mlx = h.create_mlx(tmp_path / "create.mlx", case)
    server_out = tmp_path / "meshlabserver.rply"
    status, log = h.run_meshlabserver(tmp_path, "-i", mesh, "-o", server_out, "-m", "vc", "vn", "-s", mlx)
    assert status == 0 and server_out.is_file(), f"meshlabserver failed ({status}):\n{log[-3000:]}"
    python_out = tmp_path / "pymeshlab.rply"
    create_in_pymeshlab(mesh, case, python_out)

    a, b = rply.read_rply(str(server_out)), rply.read_rply(str(python_out))
    assert a.basis == b.basis == ("PB" if case["basis"] == 0 else "SH") + str(case["degree"])
    assert a.reflected == b.reflected == case["reflected"]
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.faces, b.faces)
    assert np.abs(a.normals - b.normals).max() <= 1e-6
    assert np.abs(a.tangents - b.tangents).max() <= 1e-6
    scale = np.abs(a.coefficients).max()
    assert scale > 0.01
    difference = np.abs(a.coefficients - b.coefficients).max()
    assert difference <= 1e-4 * scale, f"coefficients differ by {difference:.3g} (largest {scale:.3g})"
    assert np.abs(a.colors.astype(int) - b.colors.astype(int)).max() <= 1


def test_simplification_agrees_between_hosts(scenes, tmp_path):
    source = tmp_path / "sphere.rply"
    h.run_tool("make_radiance_mesh", scenes("sphere", level=4), "--material", "stripes", "--basis", "PB4",
               "--no-shadows", "-o", source)
    mlx = tmp_path / "simplify.mlx"
    subprocess.run(["bash", os.path.join(h.REPO, "scripts", "write_simplify_mlx.sh"), str(mlx), "0.25", "0"],
                   check=True)
    server_out = tmp_path / "meshlabserver.rply"
    status, log = h.run_meshlabserver(tmp_path, "-i", source, "-s", mlx, "-o", server_out)
    assert status == 0 and server_out.is_file(), f"meshlabserver failed ({status}):\n{log[-3000:]}"
    assert "Simplified 5120 -> 1280 faces" in log, log[-3000:]

    ms = h.load(source)
    ms.apply_filter(h.SIMPLIFY, metric=0, collapse=0, targetfaces=0, targetpercentage=0.25, lodlevels="",
                    geometryweight=0.01, attributeweight=0.99, preserveboundary=True, minvalence=0, maxvalence=0,
                    maxnormalchange=90.0, lazy=True, progressivefile="")
    python_out = tmp_path / "pymeshlab.rply"
    ms.save_current_mesh(str(python_out))

    a, b = rply.read_rply(str(server_out)), rply.read_rply(str(python_out))
    assert a.face_count == b.face_count == 1280
    faces_a, faces_b = h.face_triples(a.positions, a.faces), h.face_triples(b.positions, b.faces)
    shared = len(faces_a & faces_b) / len(faces_a)
    assert shared >= 0.99, f"only {100 * shared:.1f} % of the faces are the same in both hosts"
    # Radiance rows followed their vertices in both.
    original = rply.read_rply(str(source))
    h.check_original_vertices_and_rows(original, a, "meshlabserver")
    h.check_original_vertices_and_rows(original, b, "pymeshlab")


def test_splat_transfer_agrees_between_hosts(tmp_path):
    import splat_writer  # tests/integration (on the path through pymeshlab_test_helpers)

    mesh, splats = tmp_path / "sphere.ply", tmp_path / "splats.ply"
    splat_writer.write_scenario("sphere_mesh", str(mesh))
    splat_writer.write_scenario("sphere_splats", str(splats))
    mlx = tmp_path / "splats.mlx"
    h.filter_script(mlx, ("Radiance: Transfer Radiance from Gaussian Splats",
                          dict(splatfile=splats, maxSplatSize=10, frontTolerance=1, setColor=True)))
    server_out = tmp_path / "meshlabserver.rply"
    status, log = h.run_meshlabserver(tmp_path, "-i", mesh, "-o", server_out, "-m", "vc", "vn", "-s", mlx)
    assert status == 0 and server_out.is_file(), f"meshlabserver failed ({status}):\n{log[-3000:]}"
    ms = h.load(mesh)
    ms.apply_filter(h.SPLATS, splatfile=str(splats), maxsplatsize=10.0, fronttolerance=1.0, setcolor=True)
    python_out = tmp_path / "pymeshlab.rply"
    ms.save_current_mesh(str(python_out))

    a, b = rply.read_rply(str(server_out)), rply.read_rply(str(python_out))
    assert a.basis == b.basis == "SH1"
    assert np.array_equal(a.positions, b.positions) and np.array_equal(a.faces, b.faces)
    scale = np.abs(a.coefficients).max()
    difference = np.abs(a.coefficients - b.coefficients).max()
    assert difference <= 1e-4 * scale, f"coefficients differ by {difference:.3g} (largest {scale:.3g})"
    assert np.abs(a.colors.astype(int) - b.colors.astype(int)).max() <= 1
