"""Batch recipes: an ordered list of pymeshlab filters with their parameters, and what to save
(``EXAMPLE`` below: radiance from an analytic material, then a simplification to a quarter).

Parameter values are TOML values passed to ``MeshSet.apply_filter`` as they are (enumerations by
their index), except: a string ending in ``%`` (``"0.5%"``) becomes ``pymeshlab.PercentageValue``, a
table ``{ abs = 0.003 }`` becomes ``pymeshlab.PureValue``, and ``{stem}``, ``{output_dir}``,
``{input_dir}`` in strings name the object's stem, the output folder and the input mesh's folder
(e.g. ``outputfile = "{output_dir}/{stem}_normal.png"``). ``[output]`` takes ``format`` (an extension
pymeshlab saves: rply, ply, obj, off, stl...) and optional ``params`` for ``save_current_mesh``
(``{ binary = true, save_textures = true }``). This module reads and checks the recipe's form with the
standard library only; which filters and parameters exist is asked of pymeshlab in a separate process
(``batch_job.probe``), before any job runs.
"""

import hashlib
import json
import os

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

# A whole recipe: radiance from an analytic material on the input mesh, simplified to a quarter of its
# triangles, saved as a radiance PLY (the documentation's example; the tests and the throughput
# benchmark run it).
EXAMPLE = """[[step]]
filter = "radiance_create_radiance_data_from_analytic_material"
[[step]]
filter = "radiance_radiance_aware_simplification"
params = { targetpercentage = 0.25 }
[output]
format = "rply"
"""

__all__ = ["EXAMPLE", "RecipeError", "Recipe", "load_recipe", "parse_recipe", "expand_value"]


class RecipeError(ValueError):
    """A recipe that cannot run: the message names what is wrong and how to fix it."""


class Recipe:
    def __init__(self, steps, output, source="<recipe>"):
        self.steps = steps          # [{"filter": str, "params": dict}]
        self.output = output        # {"format": str, "params": dict}
        self.source = source

    def to_json(self):
        return {"steps": self.steps, "output": self.output}

    def sha256(self):
        """Hash of what the recipe does (not of its file's spelling): the manifest's recipe key."""
        canonical = json.dumps(self.to_json(), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(canonical.encode()).hexdigest()

    def filter_names(self):
        return [step["filter"] for step in self.steps]


def load_recipe(path):
    try:
        with open(path, "rb") as f:
            data = tomllib.load(f)
    except OSError as e:
        raise RecipeError(f"cannot read the recipe {path}: {e.strerror}") from None
    except tomllib.TOMLDecodeError as e:
        raise RecipeError(f"the recipe {path} is not valid TOML: {e}") from None
    return parse_recipe(data, source=path)


def parse_recipe(data, source="<recipe>"):
    """Checks the recipe's form: at least one [[step]] with a filter name, params a table, an
    [output] table with a format; unknown keys are refused (a typo must not be silently ignored)."""
    _only_keys(data, {"step", "output"}, f"{source}", "top level")
    raw_steps = data.get("step")
    if not isinstance(raw_steps, list) or not raw_steps:
        raise RecipeError(f"{source}: no [[step]] table: a recipe lists its filters as [[step]] tables, each with "
                          f"filter = \"<pymeshlab filter name>\" and optionally params = {{ ... }}")
    steps = []
    for number, step in enumerate(raw_steps, 1):
        where = f"{source}, step {number}"
        if not isinstance(step, dict):
            raise RecipeError(f"{where}: a step must be a table ([[step]])")
        _only_keys(step, {"filter", "params"}, where, "[[step]]")
        name = step.get("filter")
        if not isinstance(name, str) or not name.strip():
            raise RecipeError(f"{where}: filter = \"<pymeshlab filter name>\" is missing")
        params = step.get("params", {})
        if not isinstance(params, dict):
            raise RecipeError(f"{where}: params must be a table, e.g. params = {{ targetpercentage = 0.25 }}")
        steps.append({"filter": name.strip(), "params": params})
    output = data.get("output", {})
    if not isinstance(output, dict):
        raise RecipeError(f"{source}: [output] must be a table, e.g. [output] format = \"rply\"")
    _only_keys(output, {"format", "params"}, f"{source}, [output]", "[output]")
    fmt = output.get("format", "ply")
    if not isinstance(fmt, str) or not fmt.strip(".").isalnum():
        raise RecipeError(f"{source}, [output]: format must be a file extension such as \"rply\", \"ply\", \"obj\"")
    save_params = output.get("params", {})
    if not isinstance(save_params, dict):
        raise RecipeError(f"{source}, [output]: params must be a table, e.g. params = {{ binary = true }}")
    return Recipe(steps, {"format": fmt.strip(".").lower(), "params": save_params}, source)


def _only_keys(table, allowed, where, what):
    unknown = sorted(set(table) - allowed)
    if unknown:
        raise RecipeError(f"{where}: unknown key(s) {', '.join(unknown)} in {what} (allowed: {', '.join(sorted(allowed))})")


def expand_value(value, names):
    """A recipe value as apply_filter wants it (see the module's text). `names` holds stem,
    output_dir, input_dir for the placeholders. Imports pymeshlab: call it in the job process."""
    import pymeshlab

    if isinstance(value, str):
        for key, text in names.items():
            value = value.replace("{" + key + "}", text)
        if value.endswith("%"):
            try:
                return pymeshlab.PercentageValue(float(value[:-1]))
            except ValueError:
                return value
        return value
    if isinstance(value, dict) and set(value) == {"abs"}:
        return pymeshlab.PureValue(float(value["abs"]))
    return value


def default_output_name(key, fmt):
    """The output file of an object: its path in the collection with '/' as '__', new extension."""
    stem = os.path.splitext(key)[0].replace("/", "__").replace(os.sep, "__")
    return f"{stem}.{fmt}"
