"""Radiance tools for pymeshlab: our MeshLab plugins, loaded into pymeshlab when it is imported.

    import pymeshlab
    import pymeshlab_radiance            # loads the plugins (filters and the .rply format)

    ms = pymeshlab.MeshSet()
    ms.load_new_mesh('scan.ply')
    ms.apply_filter('radiance_create_radiance_data_from_analytic_material', degree=4)
    ms.save_current_mesh('scan.rply')

The filters (Vanhoey et al. 2015; Křivánek et al. 2004; Granier et al. 2007; Weber and Stamminger)
are called with ``MeshSet.apply_filter(python_name, **parameters)``; ``filter_names()`` lists their
Python names and ``pymeshlab.print_filter_parameter_list(name)`` their parameters. ``rply`` reads
and writes ``.rply`` files as numpy arrays.

The plugins are the MeshLab 2025.07 (double precision) builds that ``pip install`` compiled into
this package's ``plugins`` folder. ``PYMESHLAB_RADIANCE_PLUGIN_DIR`` points the import at another
folder (e.g. a development build's ``build/pymeshlab_plugins``).

Loading is lazy so that ``from pymeshlab_radiance import rply`` (numpy only) never imports pymeshlab:
the plugins are loaded by :func:`load`, which runs as soon as both this package and pymeshlab are
imported, in either order (if pymeshlab is imported already, at this package's import; otherwise
right after pymeshlab's own import finishes). Calling :func:`load` explicitly is allowed and loads
each plugin once.
"""

from __future__ import annotations

import glob
import importlib.abc
import importlib.machinery
import importlib.util
import os
import sys
import threading
import types
from typing import List, Optional, Sequence


__all__ = ["rply", "load", "plugin_dir", "plugin_files", "filter_names", "SUPPORTED_PYMESHLAB"]

# The pymeshlab release line the plugins are compiled against (MeshLab 2025.07, double precision):
# pymeshlab's loader refuses plugins of another MeshLab version.
SUPPORTED_PYMESHLAB: str = "2025.7"

# Python names of our filters (MeshLab derives them from the filter names).
_FILTERS: Sequence[str] = (
    "radiance_fit_radiance_functions_from_rasters",
    "radiance_create_radiance_data_from_analytic_material",
    "radiance_evaluate_radiance_toward_a_viewpoint_as_vertex_color",
    "radiance_radiance_aware_simplification",
    "radiance_compute_prt_transfer",
    "radiance_adaptive_prt_subdivision",
    "radiance_uniform_prt_subdivision",
    "radiance_prt_relighting_as_vertex_color",
    "bake_normal_map",
    "extract_level_of_detail_pop_buffer",
    "out_of_core_simplification_and_normal_map",
    "compute_irradiance_vector_grid",
    "radiance_import_cameras_as_rasters",
    "radiance_export_gltf",
    "radiance_transfer_gaussian_splats",
)


_loaded_files: List[str] = []
_load_lock = threading.RLock()  # re-entered: importing pymeshlab inside load() runs the import hook


def __getattr__(name: str) -> types.ModuleType:
    """``pymeshlab_radiance.rply`` imported on first use (numpy only), so that importing the package
    stays light for the command line's parent process and the batch jobs."""
    if name == "rply":
        import importlib

        return importlib.import_module(".rply", __name__)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def plugin_dir() -> str:
    """The folder the plugins are loaded from."""
    override = os.environ.get("PYMESHLAB_RADIANCE_PLUGIN_DIR")
    if override:
        return os.path.abspath(override)
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "plugins")


def plugin_files() -> List[str]:
    """The plugin files (IO plugin first, so '.rply' is known before any filter runs)."""
    files = sorted(glob.glob(os.path.join(plugin_dir(), "*.so")))
    return sorted(files, key=lambda f: (not os.path.basename(f).startswith("libio_"), f))


def filter_names() -> List[str]:
    """Python names of our filters, for MeshSet.apply_filter."""
    return list(_FILTERS)


def load() -> List[str]:
    """Imports pymeshlab and loads our plugins into it (once per process); returns the plugin files
    loaded. Raises ImportError naming the remedy when the installed pymeshlab is not the release
    the plugins were built for, or when no plugin is found."""
    with _load_lock:
        if _loaded_files:
            return list(_loaded_files)
        import pymeshlab

        if _loaded_files:  # the import above ran the hook, which loaded them
            return list(_loaded_files)
        _check_pymeshlab_version()
        files = plugin_files()
        if not files:
            raise ImportError(
                f"pymeshlab_radiance: no plugin found in {plugin_dir()}: install the package with "
                f"'pip install .' from the repository (it compiles them), or set PYMESHLAB_RADIANCE_PLUGIN_DIR "
                f"to a folder of built plugins (build/pymeshlab_plugins after scripts/setup.sh).")
        for f in files:
            pymeshlab.load_plugin(f)
        _loaded_files.extend(files)
        return list(_loaded_files)


def _check_pymeshlab_version() -> None:
    version = _pymeshlab_version()
    if version and not version.startswith(SUPPORTED_PYMESHLAB):
        raise ImportError(
            f"pymeshlab_radiance was built for pymeshlab {SUPPORTED_PYMESHLAB} (MeshLab 2025.07, double "
            f"precision) but pymeshlab {version} is installed: pip install 'pymeshlab==2025.7.post1', then "
            f"reinstall this package.")


def _pymeshlab_version() -> Optional[str]:
    try:
        from importlib.metadata import version
        return version("pymeshlab")
    except Exception:  # pragma: no cover - metadata missing in odd installs
        return None


class _LoadAfterPymeshlabImport(importlib.abc.MetaPathFinder):
    """Finds nothing itself: when pymeshlab is first imported, it wraps the real loader so that our
    plugins are loaded right after pymeshlab's module has run (a refusal of :func:`load` then fails
    that import with its message, as an eager load at this package's import did)."""

    def find_spec(self, fullname: str, path: Optional[Sequence[str]], target: Optional[types.ModuleType] = None
                  ) -> Optional[importlib.machinery.ModuleSpec]:
        if fullname != "pymeshlab":
            return None
        _remove_import_hook()
        spec = importlib.util.find_spec(fullname)
        if spec is None or spec.loader is None or not hasattr(spec.loader, "exec_module"):
            return spec
        run_module = spec.loader.exec_module

        def exec_module(module: types.ModuleType) -> None:
            run_module(module)
            load()

        spec.loader.exec_module = exec_module  # type: ignore[method-assign]
        return spec


def _remove_import_hook() -> None:
    sys.meta_path[:] = [f for f in sys.meta_path if not isinstance(f, _LoadAfterPymeshlabImport)]


if "pymeshlab" in sys.modules:
    load()
else:
    _remove_import_hook()
    sys.meta_path.insert(0, _LoadAfterPymeshlabImport())
