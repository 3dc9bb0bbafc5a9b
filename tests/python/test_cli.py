"""The command line `meshlab-radiance` (python -m pymeshlab_radiance): help with a worked example for
every subcommand, one subcommand end to end with its exit status, the progress bar fed by the
filter's own progress messages, and a refusal on stderr."""

import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

import pytest

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

import numpy as np

import pymeshlab_test_helpers as h
from pymeshlab_radiance import cli, rply

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COMMANDS = ("import-cameras", "fit", "simplify", "bake", "splats", "info", "export", "view", "filters", "batch")


def meshlab_radiance(*args, timeout=120):
    return subprocess.run([sys.executable, "-m", "pymeshlab_radiance", *map(str, args)], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, timeout=timeout, env=h.python_env())


@pytest.fixture(scope="module")
def radiance_sphere(tmp_path_factory):
    """A 1280-face sphere with PB4 radiance functions, saved as .rply."""
    import pymeshlab

    path = tmp_path_factory.mktemp("cli") / "sphere.rply"
    ms = pymeshlab.MeshSet()
    ms.create_sphere(subdiv=3)
    ms.apply_filter("radiance_create_radiance_data_from_analytic_material")
    ms.save_current_mesh(str(path))
    return path


def test_console_script_is_declared():
    with open(os.path.join(REPO, "pyproject.toml"), "rb") as f:
        scripts = tomllib.load(f)["project"]["scripts"]
    assert scripts == {"meshlab-radiance": "pymeshlab_radiance.cli:main"}


def test_help_of_every_command_shows_a_worked_example(capsys):
    result = meshlab_radiance("--help")
    assert result.returncode == 0
    for command in COMMANDS:
        assert command in result.stdout
    for command in COMMANDS:
        with pytest.raises(SystemExit) as exit_status:
            cli.main([command, "--help"])
        assert exit_status.value.code == 0
        text = capsys.readouterr().out
        assert "example" in text and f"meshlab-radiance {command}" in text, text


def test_simplify_end_to_end_with_progress_from_the_filter(radiance_sphere, tmp_path):
    output = tmp_path / "sphere_100.rply"
    result = meshlab_radiance("simplify", radiance_sphere, "-o", output, "--faces", 100)
    assert result.returncode == 0, result.stderr
    mesh = rply.read_rply(str(output))
    assert mesh.face_count == 100 and mesh.basis == "PB4"
    assert "1280 -> 100 faces" in result.stdout
    # The bar advances with the filter's own progress messages (pymeshlab's verbose log).
    assert "Radiance-aware simplification" in result.stderr and "100/100" in result.stderr


def test_refusal_goes_to_stderr_with_a_nonzero_status(radiance_sphere, tmp_path):
    output = tmp_path / "never.rply"
    result = meshlab_radiance("simplify", radiance_sphere, "-o", output, "--percentage", 1.5, "--no-progress")
    assert result.returncode == 1
    assert "The target percentage must lie in [0, 1), got 1.5" in result.stderr
    assert "radiance_radiance_aware_simplification" in result.stderr
    assert not output.exists() and not [f for f in os.listdir(tmp_path) if f.startswith(".partial")]
    missing = meshlab_radiance("info", tmp_path / "nowhere.ply")
    assert missing.returncode == 2 and "nowhere.ply does not exist" in missing.stderr


def test_info_reads_counts_and_radiance_basis(radiance_sphere):
    result = meshlab_radiance("info", radiance_sphere)
    assert result.returncode == 0, result.stderr
    assert "642 vertices, 1280 faces" in result.stdout
    assert "radiance PB4, 15 coefficients per channel" in result.stdout


def test_splats_end_to_end(tmp_path):
    """A splat field on the unit sphere (tests/integration/splat_writer.py) onto a UV sphere: SH1 radiance."""
    sys.path.insert(0, os.path.join(REPO, "tests", "integration"))
    import splat_writer

    mesh, splats, output = tmp_path / "sphere.ply", tmp_path / "splats.ply", tmp_path / "sphere.rply"
    splat_writer.write_scenario("sphere_mesh", str(mesh))
    splat_writer.write_scenario("sphere_splats", str(splats))
    result = meshlab_radiance("splats", mesh, splats, "-o", output, "--no-progress")
    assert result.returncode == 0, result.stderr
    assert rply.read_rply(str(output)).basis == "SH1"
    assert "Transferred SH1 radiance functions" in result.stdout


def nerfstudio_capture(folder):
    """Three 64x48 photographs and their nerfstudio transforms.json: cameras at (0.2 k, 0, 3) looking
    down -z (camera-to-world = translation only, OpenGL axes), focal 60 px, centre (32, 24); the
    second with a radial distortion k1 = -0.1, the others pinhole. Returns the camera centres."""
    (folder / "images").mkdir(parents=True)
    frames, centres = [], []
    for k in range(3):
        h.write_png(folder / "images" / f"v{k}.png", np.full((48, 64, 3), 60 * k + 20, dtype=np.uint8))
        centre = [0.2 * k, 0.0, 3.0]
        matrix = np.eye(4)
        matrix[:3, 3] = centre
        frames.append({"file_path": f"images/v{k}.png", "transform_matrix": matrix.tolist(), "w": 64, "h": 48,
                       "fl_x": 60.0, "fl_y": 60.0, "cx": 32.0, "cy": 24.0, "camera_model": "OPENCV",
                       "k1": -0.1 if k == 1 else 0.0})
        centres.append(centre)
    (folder / "transforms.json").write_text(json.dumps({"frames": frames}))
    return centres


def test_import_cameras_writes_a_project_that_fit_reads(tmp_path):
    import pymeshlab

    centres = nerfstudio_capture(tmp_path)
    ms = pymeshlab.MeshSet()
    ms.create_sphere(subdiv=2)
    ms.save_current_mesh(str(tmp_path / "scan.ply"))
    project = tmp_path / "out" / "scan.mlp"
    result = meshlab_radiance("import-cameras", tmp_path / "scan.ply", tmp_path / "transforms.json",
                              "--cache", tmp_path / "cache", "-o", project)
    assert result.returncode == 0, result.stderr
    assert "3 raster layers in" in result.stdout
    # The bar advances with the import's own progress messages (reading, undistorting).
    assert "Undistorting photographs" in result.stderr and "100/100" in result.stderr
    assert not [f for f in os.listdir(project.parent) if f.startswith(".partial")]

    root = ET.parse(str(project)).getroot()
    meshes = [os.path.normpath(project.parent / m.get("filename")) for m in root.iter("MLMesh")]
    assert meshes == [str(tmp_path / "scan.ply")]
    rasters = list(root.iter("MLRaster"))
    assert [r.get("label") for r in rasters] == [f"images/v{k}.png" for k in range(3)]
    for k, raster in enumerate(rasters):
        camera = raster.find("VCGCamera")
        values = {name: [float(x) for x in camera.get(name).split()] for name in
                  ("TranslationVector", "RotationMatrix", "FocalMm", "PixelSizeMm", "CenterPx", "ViewportPx")}
        # vcg's translation is minus the camera centre; the rotation is the identity (OpenGL axes both).
        assert np.allclose(values["TranslationVector"][:3], -np.array(centres[k]), atol=1e-9), values
        assert np.allclose(values["RotationMatrix"], np.eye(4).ravel(), atol=1e-9), values
        assert values["ViewportPx"] == [64, 48]
        image = os.path.normpath(project.parent / raster.find("Plane").get("fileName"))
        assert os.path.isfile(image)
        if k == 1:  # undistorted once, into the cache
            assert os.path.dirname(image) == str(tmp_path / "cache")
        else:  # pinhole photographs are used as they are, with their own intrinsics
            assert image == str(tmp_path / "images" / f"v{k}.png")
            assert values["FocalMm"][0] / values["PixelSizeMm"][0] == pytest.approx(60.0)
            assert values["CenterPx"] == pytest.approx([32.0, 48 - 24.0])

    fit = meshlab_radiance("fit", tmp_path / "scan.ply", project, "-o", tmp_path / "fit.rply", "--degree", 1,
                           "--no-progress")
    assert fit.returncode == 0, fit.stderr
    assert "from 3 of 3 rasters" in fit.stdout
    assert rply.read_rply(str(tmp_path / "fit.rply")).basis == "PB1"


def test_import_cameras_refusals(tmp_path):
    nerfstudio_capture(tmp_path)
    (tmp_path / "empty").mkdir()
    mesh = tmp_path / "scan.ply"
    h.write_ascii_ply(mesh, [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    project = tmp_path / "scan.mlp"
    # Photographs not in the image folder: the filter's refusal, nothing written.
    result = meshlab_radiance("import-cameras", mesh, tmp_path / "transforms.json", "--images", tmp_path / "empty",
                              "-o", project, "--no-progress")
    assert result.returncode == 1
    assert "3 of the 3 photographs cannot be used, nothing was imported" in result.stderr
    assert "radiance_import_cameras_as_rasters" in result.stderr
    assert not project.exists()
    # The output must be a project (rasters have no place in a mesh file); a missing camera file.
    wrong = meshlab_radiance("import-cameras", mesh, tmp_path / "transforms.json", "-o", tmp_path / "scan.ply2.ply")
    assert wrong.returncode == 2 and "must be a MeshLab project (.mlp)" in wrong.stderr
    missing = meshlab_radiance("import-cameras", mesh, tmp_path / "nowhere.json", "-o", project)
    assert missing.returncode == 2 and "nowhere.json does not exist" in missing.stderr
