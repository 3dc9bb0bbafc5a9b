"""pytest configuration of the Python tests: makes ``<repo>/python`` importable when the package
``pymeshlab_radiance`` is not installed (e.g. when the tests run from a source checkout)."""

import importlib.util
import os
import sys

_PYTHON_DIR = os.path.join(os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__)))), "python")

if importlib.util.find_spec("pymeshlab_radiance") is None and _PYTHON_DIR not in sys.path:
    sys.path.insert(0, _PYTHON_DIR)
