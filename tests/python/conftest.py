"""pytest configuration of the Python tests: makes ``<repo>/python`` importable when the package
``pymeshlab_radiance`` is not installed (e.g. when the tests run from a source checkout), points the
package at the build tree's plugins when it has none of its own, and provides the shared fixtures of
the pymeshlab tests (``pymeshlab_test_helpers.py`` holds their helper functions).

Environment:
  RADIANCE_BUILD_DIR              build folder (default ``<repo>/build``): C++ tools, private MeshLab prefix
  PYMESHLAB_RADIANCE_PLUGIN_DIR   plugins loaded by ``import pymeshlab_radiance``; defaults to
                                  ``$RADIANCE_BUILD_DIR/pymeshlab_plugins`` ONLY when the package found has
                                  no ``plugins`` folder with plugins in it (a source checkout); an installed
                                  package (pip install .) uses its own plugins.
"""

import glob
import importlib.util
import os
import sys

_REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_PYTHON_DIR = os.path.join(_REPO, "python")

if importlib.util.find_spec("pymeshlab_radiance") is None and _PYTHON_DIR not in sys.path:
    sys.path.insert(0, _PYTHON_DIR)


def _package_has_plugins():
    spec = importlib.util.find_spec("pymeshlab_radiance")
    if spec is None or not spec.submodule_search_locations:
        return False
    folder = os.path.join(list(spec.submodule_search_locations)[0], "plugins")
    return bool(glob.glob(os.path.join(folder, "*.so")))


BUILD_DIR = os.path.abspath(os.environ.get("RADIANCE_BUILD_DIR", os.path.join(_REPO, "build")))
if not os.environ.get("PYMESHLAB_RADIANCE_PLUGIN_DIR") and not _package_has_plugins():
    os.environ["PYMESHLAB_RADIANCE_PLUGIN_DIR"] = os.path.join(BUILD_DIR, "pymeshlab_plugins")
# Absolute from here on: pymeshlab changes the process's working directory (below), and the tests
# start fresh Python processes that must load the same plugins.
if os.environ.get("PYMESHLAB_RADIANCE_PLUGIN_DIR"):
    os.environ["PYMESHLAB_RADIANCE_PLUGIN_DIR"] = os.path.abspath(os.environ["PYMESHLAB_RADIANCE_PLUGIN_DIR"])
if os.environ.get("RADIANCE_BUILD_DIR"):
    os.environ["RADIANCE_BUILD_DIR"] = BUILD_DIR
_START_DIR = os.getcwd()

# ------------------------------------------------------------------------------------------------
# Fixtures of the pymeshlab tests. pymeshlab is imported lazily so that the numpy-only tests
# (test_rply_numpy.py) still run where pymeshlab or the plugins are unusable.

import pytest  # noqa: E402


@pytest.fixture(scope="session")
def build_dir():
    return BUILD_DIR


@pytest.fixture(scope="session")
def repo_dir():
    return _REPO


@pytest.fixture(scope="session")
def scenes(tmp_path_factory):
    """Input meshes made by the C++ tool make_scene (binary PLY, exact normals), made on first use:
    scenes('sphere', level=3) -> path."""
    import pymeshlab_test_helpers as h

    folder = tmp_path_factory.mktemp("scenes")
    made = {}

    def make(scene, **options):
        key = (scene,) + tuple(sorted(options.items()))
        if key not in made:
            name = scene + "".join(f"_{k}{v}" for k, v in sorted(options.items())) + ".ply"
            args = [scene]
            for k, v in sorted(options.items()):
                args += [f"--{k}", str(v)]
            h.run_tool("make_scene", *args, "-o", str(folder / name))
            made[key] = str(folder / name)
        return made[key]

    return make


@pytest.fixture(autouse=True)
def _isolate_pymeshlab_host_bugs():
    """Two host bugs of pymeshlab 2025.7 must not let one test disturb the next:

    - a load_new_mesh that fails (ours or MeshLab's own PLY importer alike) leaves the process's
      working directory in the file's folder: the directory is restored after every test;
    - pymeshlab keeps a pointer to the log of the MeshSet of the last filter that raised
      (meshset_helper.cpp, applyFilterRPL: VerbosityManager::staticLogger is reset only on success);
      once that MeshSet is freed, the next progress callback anywhere (a load_new_mesh in another
      MeshSet, any plugin) writes into freed memory: std::bad_alloc or a segmentation fault, seen
      with MeshLab's own filters too (e.g. meshing_close_holes on a non-manifold mesh). Tests keep
      refused MeshSets alive (pymeshlab_test_helpers.expect_refusal / keep_alive), and after every
      test one successful filter on a scratch MeshSet resets the pointer.
    """
    yield
    os.chdir(_START_DIR)
    if "pymeshlab" in sys.modules:
        import pymeshlab_test_helpers as h

        h.reset_pymeshlab_logger()
