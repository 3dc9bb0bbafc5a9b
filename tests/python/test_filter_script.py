"""The .mlx writer of the scripts and tests (tools/meshlab2020/write_filter_script.cpp, through
scripts/filter_script.sh): every parameter each filter declares, in the filter's order, the values
named on the command line and nothing else changed; mistakes refused before anything is written.

The parameter lists it writes are those the filters declare to MeshLab 2020.09; they must equal the
names pinned in test_pymeshlab_plugins_listed.py, which pymeshlab 2025.7 is checked against: one
declaration, both hosts, every script."""
import os
import subprocess
import xml.etree.ElementTree as ET

import pytest

import pymeshlab_test_helpers as h
from test_pymeshlab_plugins_listed import EXPECTED_PARAMETERS

SCRIPT = os.path.join(h.REPO, "scripts", "filter_script.sh")


def write(tmp_path, *args, name="out.mlx"):
    """Runs the writer; returns (exit status, stderr, path)."""
    path = tmp_path / name
    run = subprocess.run(["bash", SCRIPT, "--out", str(path), *args], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE, text=True, env=dict(os.environ, RADIANCE_BUILD_DIR=h.BUILD))
    return run.returncode, run.stderr, path


def params(path, index=0):
    filters = list(ET.parse(str(path)).getroot().iter("filter"))
    return filters[index].get("name"), {p.get("name"): p for p in filters[index].iter("Param")}, \
        [p.get("name") for p in filters[index].iter("Param")]


@pytest.mark.parametrize("menu_name", sorted(h.FILTERS))
def test_every_declared_parameter_is_written_in_order(tmp_path, menu_name):
    status, err, path = write(tmp_path, "--layers", "2", "--filter", menu_name)
    assert status == 0, err
    name, by_name, order = params(path)
    assert name == menu_name
    assert order == EXPECTED_PARAMETERS[h.FILTERS[menu_name]]
    assert all(p.get("type", "").startswith("Rich") for p in by_name.values())


def test_named_values_land_and_the_rest_keep_the_defaults(tmp_path):
    create = "Radiance: Create Radiance Data from Analytic Material"
    status, err, default_path = write(tmp_path, "--filter", create, name="default.mlx")
    assert status == 0, err
    status, err, path = write(tmp_path, "--filter", create, "degree=7", "reflected=1",
                              "basis=Spherical harmonics SH(d), global frame",
                              "albedo=10,20,30", "light=1.5,-2,0.25", "specular=0.125")
    assert status == 0, err
    _, defaults, _ = params(default_path)
    _, written, _ = params(path)
    assert written["degree"].get("value") == "7"
    assert written["reflected"].get("value") == "true"
    assert written["basis"].get("value") == "1"  # the label of the enum's second choice
    assert [written["albedo"].get(c) for c in "rgb"] == ["10", "20", "30"]
    assert written["albedo"].get("a") == defaults["albedo"].get("a")
    assert [written["light"].get(c) for c in "xyz"] == ["1.5", "-2", "0.25"]
    assert written["specular"].get("value") == "0.125"
    changed = {"degree", "reflected", "basis", "albedo", "light", "specular"}
    for name, element in defaults.items():
        if name not in changed:
            assert written[name].attrib == element.attrib, name


def test_several_filters_in_order_with_a_layer_index(tmp_path):
    status, err, path = write(tmp_path, "--layers", "3",
                              "--filter", "Bake Normal Map", "sourceMesh=2", "textureSize=64",
                              "--filter", "Simplification: Quadric Edge Collapse Decimation", "TargetFaceNum=100")
    assert status == 0, err
    name, bake, _ = params(path, 0)
    assert name == "Bake Normal Map" and bake["sourceMesh"].get("value") == "2"
    assert bake["textureSize"].get("value") == "64"
    name, decimation, _ = params(path, 1)
    assert name == "Simplification: Quadric Edge Collapse Decimation"
    assert decimation["TargetFaceNum"].get("value") == "100"


@pytest.mark.parametrize("args, message", [
    (["--filter", "Radiance: No Such Filter"], "no filter named 'Radiance: No Such Filter'; filters of that group: "),
    (["--filter", "Radiance: Radiance-Aware Simplification", "targetPercent=0.5"],
     "has no parameter 'targetPercent'; its parameters: metric, collapse, targetFaces, targetPercentage"),
    (["--filter", "Radiance: Radiance-Aware Simplification", "metric=9"], "takes one of its labels or their index"),
    (["--filter", "Radiance: Radiance-Aware Simplification", "lazy=yes"], "takes true or false, not 'yes'"),
    (["--filter", "Radiance: Radiance-Aware Simplification", "targetFaces=many"], "takes an integer"),
    (["--filter", "Radiance: Radiance-Aware Simplification", "geometryWeight=0.1.2"], "takes a number"),
    (["--filter", "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color", "viewpoint=1,2"],
     "is not three numbers"),
    (["--filter", "Radiance: Create Radiance Data from Analytic Material", "albedo=red"], "is not a colour"),
    (["--layers", "0", "--filter", "Bake Normal Map"], "--layers takes a positive number"),
])
def test_mistakes_are_refused_and_nothing_is_written(tmp_path, args, message):
    status, err, path = write(tmp_path, *args)
    assert status == 2, err
    assert message in err, err
    assert not path.exists()
    assert list(tmp_path.iterdir()) == []  # no temporary file left either


def test_a_refused_rewrite_keeps_the_earlier_script(tmp_path):
    status, err, path = write(tmp_path, "--filter", "Radiance: Radiance-Aware Simplification", "targetPercentage=0.5")
    assert status == 0, err
    before = path.read_bytes()
    status, err, _ = write(tmp_path, "--filter", "Radiance: Radiance-Aware Simplification", "targetPercentage=x")
    assert status == 2
    assert path.read_bytes() == before
