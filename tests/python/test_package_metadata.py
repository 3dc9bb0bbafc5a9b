"""The package as a user installs it: the numpy reader importable without pymeshlab, the plugins
loaded whichever of pymeshlab and pymeshlab_radiance is imported first, one version shared by
pyproject.toml and CMake, the licence and the typing marker shipped.

Each import check runs in a fresh Python process (pymeshlab_test_helpers.run_python), since this
process has imported pymeshlab already.
"""
import os
import shutil
import subprocess
import sys

import pytest

import pymeshlab_test_helpers as h

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10
    import tomli as tomllib

_REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_PACKAGE = os.path.join(_REPO, "python", "pymeshlab_radiance")


def _pyproject():
    with open(os.path.join(_REPO, "pyproject.toml"), "rb") as f:
        return tomllib.load(f)


def test_rply_reads_and_writes_without_importing_pymeshlab():
    result = h.run_python(
        "import sys\n"
        "import numpy as np\n"
        "from pymeshlab_radiance import rply\n"
        "import os, tempfile\n"
        "mesh = rply.RadianceMesh(positions=np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0]], np.float32),\n"
        "                         faces=np.array([[0, 1, 2]], np.int32))\n"
        "path = os.path.join(tempfile.mkdtemp(), 't.rply')\n"
        "rply.write_rply(path, mesh)\n"
        "back = rply.read_rply(path)\n"
        "print('faces', back.face_count, 'pymeshlab imported:', 'pymeshlab' in sys.modules)\n")
    assert result.returncode == 0, result.stdout
    assert "faces 1 pymeshlab imported: False" in result.stdout, result.stdout


@pytest.mark.parametrize("imports", ["import pymeshlab_radiance\nimport pymeshlab",
                                     "import pymeshlab\nimport pymeshlab_radiance",
                                     "from pymeshlab_radiance import rply\nimport pymeshlab"])
def test_our_filter_runs_whichever_module_is_imported_first(imports):
    result = h.run_python(
        imports + "\n"
        "ms = pymeshlab.MeshSet()\n"
        "ms.create_sphere(subdiv=1)\n"
        "ms.apply_filter('radiance_create_radiance_data_from_analytic_material', degree=2)\n"
        "print('vertices with radiance', ms.current_mesh().vertex_number())\n")
    assert result.returncode == 0, result.stdout
    assert "vertices with radiance 42" in result.stdout, result.stdout


def test_load_returns_every_plugin_once():
    result = h.run_python(
        "import pymeshlab_radiance as p\n"
        "first = p.load()\n"
        "second = p.load()\n"
        "print(len(first), first == second == p.plugin_files())\n")
    assert result.returncode == 0, result.stdout
    assert result.stdout.split()[-1] == "True", result.stdout
    assert int(result.stdout.split()[-2]) >= 2, result.stdout


def test_cmake_reads_the_version_of_pyproject():
    cmake = shutil.which("cmake")
    assert cmake, "cmake is needed to build the package (scripts/setup.sh installs it)"
    result = subprocess.run([cmake, "-DRADIANCE_PRINT_VERSION=ON", "-P",
                             os.path.join(_REPO, "cmake", "ProjectVersion.cmake")],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
    assert result.returncode == 0, result.stdout
    assert result.stdout.strip() == "-- " + _pyproject()["project"]["version"], result.stdout
    with open(os.path.join(_REPO, "CMakeLists.txt")) as f:
        assert "project(radiance_tools VERSION ${RADIANCE_VERSION}" in f.read()


def test_licence_and_typing_marker_ship_with_the_package():
    project = _pyproject()
    with open(os.path.join(_REPO, "LICENSE")) as f:
        head = f.read(200)
    assert "GNU GENERAL PUBLIC LICENSE" in head and "Version 3" in head
    assert project["project"]["license"] == {"text": "GPL-3.0-or-later"}
    assert "LICENSE" in project["tool"]["scikit-build"]["wheel"]["license-files"]
    assert os.path.isfile(os.path.join(_PACKAGE, "py.typed"))
    assert set(project["project"]["optional-dependencies"]) >= {"test", "plots"}


def test_the_web_viewer_ships_with_the_package():
    """python -m pymeshlab_radiance.view needs its page inside the package folder (which the wheel's
    wheel.packages copies whole), with the markers view.py fills in."""
    page = os.path.join(_PACKAGE, "viewer", "viewer.html")
    assert os.path.isfile(page)
    with open(page, encoding="utf-8") as f:
        text = f.read()
    assert "webgl2" in text and "/*CONFIG*/{}/*END*/" in text and "<!--MODEL-->" in text
