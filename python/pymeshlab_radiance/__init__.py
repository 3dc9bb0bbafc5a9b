"""Radiance tools for pymeshlab: loads our MeshLab plugins into pymeshlab at import.

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
"""

import glob
import os

import pymeshlab

from . import rply  # noqa: F401  (numpy reader/writer of .rply)

__all__ = ["rply", "plugin_dir", "plugin_files", "filter_names", "SUPPORTED_PYMESHLAB"]

# The pymeshlab release line the plugins are compiled against (MeshLab 2025.07, double precision):
# pymeshlab's loader refuses plugins of another MeshLab version.
SUPPORTED_PYMESHLAB = "2025.7"

# Python names of our filters (MeshLab derives them from the filter names).
_FILTERS = (
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
)


def plugin_dir():
    """The folder the plugins are loaded from."""
    override = os.environ.get("PYMESHLAB_RADIANCE_PLUGIN_DIR")
    if override:
        return os.path.abspath(override)
    return os.path.join(os.path.dirname(os.path.abspath(__file__)), "plugins")


def plugin_files():
    """The plugin files (IO plugin first, so '.rply' is known before any filter runs)."""
    files = sorted(glob.glob(os.path.join(plugin_dir(), "*.so")))
    return sorted(files, key=lambda f: (not os.path.basename(f).startswith("libio_"), f))


def filter_names():
    """Python names of our filters, for MeshSet.apply_filter."""
    return list(_FILTERS)


def _load():
    version = _pymeshlab_version()
    if version and not version.startswith(SUPPORTED_PYMESHLAB):
        raise ImportError(
            f"pymeshlab_radiance was built for pymeshlab {SUPPORTED_PYMESHLAB} (MeshLab 2025.07, double "
            f"precision) but pymeshlab {version} is installed: pip install 'pymeshlab==2025.7.post1', then "
            f"reinstall this package.")
    files = plugin_files()
    if not files:
        raise ImportError(
            f"pymeshlab_radiance: no plugin found in {plugin_dir()}: install the package with "
            f"'pip install .' from the repository (it compiles them), or set PYMESHLAB_RADIANCE_PLUGIN_DIR "
            f"to a folder of built plugins (build/pymeshlab_plugins after scripts/setup.sh).")
    for f in files:
        pymeshlab.load_plugin(f)


def _pymeshlab_version():
    try:
        from importlib.metadata import version
        return version("pymeshlab")
    except Exception:  # pragma: no cover - metadata missing in odd installs
        return None


_load()
