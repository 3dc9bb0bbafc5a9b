"""The command line `meshlab-radiance` (python -m pymeshlab_radiance): help with a worked example for
every subcommand, one subcommand end to end with its exit status, the progress bar fed by the
filter's own progress messages, and a refusal on stderr."""

import os
import subprocess
import sys

import pytest

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

from pymeshlab_radiance import cli, rply

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
COMMANDS = ("fit", "simplify", "bake", "splats", "info", "export", "view", "filters", "batch")


def meshlab_radiance(*args, timeout=120):
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(p for p in sys.path if p)
    return subprocess.run([sys.executable, "-m", "pymeshlab_radiance", *map(str, args)], stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, timeout=timeout, env=env)


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
