"""Our plugins inside the real pymeshlab 2025.7 (MeshLab 2025.07, double precision), as
tests/integration/test_plugins_listed.sh checks them in meshlabserver 2020.09: every plugin file
loaded, every filter known under its Python name with the parameters of the 2020.09 scripts (the
same names, lower-cased), each parameter with a description and a help text, and the .rply format
read and written by pymeshlab's load_new_mesh / save_current_mesh.

(pymeshlab exposes no filter-level help text: the filters' descriptions are checked in the
meshlabserver -d dump by the integration test; the parameters' texts are checked here through the
filter script pymeshlab records, which carries each parameter's description and tooltip.)
"""
import os
import xml.etree.ElementTree as ET

import numpy as np
import pymeshlab
import pytest

import pymeshlab_radiance
from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h
import splat_writer

# Parameters of each filter, as the meshlabserver 2020.09 scripts list them (tests/integration/lib.sh,
# scripts/write_simplify_mlx.sh, scripts/write_prt_mlx.sh, scripts/bake_normal_map_filter.sh).
EXPECTED_PARAMETERS = {
    h.CREATE: ["basis", "degree", "reflected", "albedo", "specularColor", "specular", "shininess", "stripes",
               "stripeAxis", "lightType", "light", "lightIntensity", "ambient", "setColor"],
    h.EVALUATE: ["viewpoint", "exposure"],
    h.EXPORT_GLTF: ["outputFile"],
    h.FIT: ["visibleOnly", "basis", "degree", "regularization", "depthTolerance", "grazingAngle", "borderMargin",
            "minSamples", "reflected", "quality", "setColor", "validation", "robust", "exposureCompensation",
            "fitModel", "sharedGuard", "lightDistance", "heldOutEvery"],
    h.SIMPLIFY: ["metric", "collapse", "targetFaces", "targetPercentage", "lodLevels", "geometryWeight",
                 "attributeWeight", "preserveBoundary", "collapseAlongBoundary", "minValence", "maxValence", "maxNormalChange", "lazy",
                 "progressiveFile"],
    h.TRANSFER: ["order", "rays", "occluders", "albedo", "rayOffset"],
    h.ADAPTIVE: ["budget", "budgetFactor", "measure", "alpha", "threshold"],
    h.UNIFORM: ["budget", "budgetFactor", "measure", "alpha"],
    h.RELIGHT: ["lighting", "environmentMap", "rotation", "upAxis", "lightDirection", "lightIntensity", "exposure"],
    h.BAKE: ["sourceMesh", "textureSize", "space", "tangentFrame", "bits", "maxDistance", "gutter", "newAtlas", "diffuse", "lean",
             "gltf", "gltfRoughness", "assign", "outputFile"],
    h.POP_LEVELS: ["levels", "correction"],
    h.OUT_OF_CORE: ["plyFile", "targetFaces", "textureSize", "gutter", "bits", "outputFile"],
    h.IRRADIANCE_GRID: ["resolution", "bounces", "rays", "lightSource", "envMap", "lightCount", "envScale",
                        "lightDirection", "lightIrradiance", "outputFile"],
    h.IMPORT_CAMERAS: ["camerafile", "imagefolder", "cachefolder"],
    h.SPLATS: ["splatfile", "maxSplatSize", "frontTolerance", "setColor"],
}


def test_every_plugin_file_is_loaded():
    loaded = {os.path.basename(f) for f in pymeshlab_radiance.plugin_files()}
    missing = [f for f in h.PLUGIN_FILES if f not in loaded]
    assert not missing, (f"plugins missing from {pymeshlab_radiance.plugin_dir()}: {missing} (build them: "
                         f"cmake --build build, or pip install . which compiles them into the package)")


def test_every_filter_is_listed_by_pymeshlab():
    listed = set(pymeshlab.filter_list())
    missing = [name for name in h.FILTERS.values() if name not in listed]
    assert not missing, f"pymeshlab does not list {missing}"
    assert sorted(pymeshlab_radiance.filter_names()) == sorted(h.FILTERS.values())


@pytest.mark.parametrize("name", sorted(EXPECTED_PARAMETERS))
def test_parameters_are_those_of_the_2020_scripts(name, scenes):
    ms = h.load(scenes("sphere", level=1))
    values = ms.filter_parameter_values(name)
    assert values, f"{name} has no parameters"
    assert sorted(values) == sorted(p.lower() for p in EXPECTED_PARAMETERS[name]), \
        f"{name}: pymeshlab parameters {sorted(values)}"


@pytest.fixture(scope="module")
def recorded_script(scenes, tmp_path_factory):
    """Every filter of ours applied once successfully; the filter scripts pymeshlab recorded."""
    work = tmp_path_factory.mktemp("listed")
    ms = h.load(scenes("sphere", level=2))
    ms.apply_filter(h.CREATE, degree=2)
    ms.apply_filter(h.EVALUATE)
    ms.apply_filter(h.EXPORT_GLTF, outputfile=str(work / "radiance.glb"))
    ms.apply_filter(h.SIMPLIFY, targetpercentage=0.5)
    ms.apply_filter(h.TRANSFER, order=3, rays=16)
    ms.apply_filter(h.UNIFORM, budget=0, budgetfactor=4)
    ms.apply_filter(h.ADAPTIVE, budget=0, budgetfactor=1.5)
    ms.apply_filter(h.RELIGHT)
    ms.load_new_mesh(scenes("sphere", level=1))
    ms.apply_filter(h.BAKE, sourcemesh=0, texturesize=128, outputfile=str(work / "baked_normal.png"))
    ms.apply_filter(h.POP_LEVELS, levels="4")  # on the baked layer's texture coordinates
    ms.apply_filter(h.OUT_OF_CORE, plyfile=scenes("sphere", level=3), targetfaces=200, texturesize=256,
                    outputfile=str(work / "ooc"))
    ms.apply_filter(h.IRRADIANCE_GRID, resolution=2, rays=4, lightsource=1, outputfile=str(work / "grid.ivg"))
    ms.save_filter_script(str(work / "filters.mlx"))

    h.run_tool("virtual_acquisition", scenes("sphere", level=2), "-o", work / "photos", "--views", 4,
               "--size", "64x48", "--no-variation", "--supersampling", 1)
    fit = h.load(work / "photos" / "mesh.ply")
    fit.load_project(str(work / "photos" / "project.mlp"))
    fit.apply_filter(h.FIT, degree=1)
    fit.save_filter_script(str(work / "fit.mlx"))
    # The photographs' cameras as a COLMAP text model (PINHOLE; only that it imports matters here).
    (work / "colmap").mkdir()
    (work / "colmap" / "cameras.txt").write_text("1 PINHOLE 64 48 60 60 32 24\n")
    photo = "images/" + sorted(p.name for p in (work / "photos" / "images").iterdir() if p.suffix == ".png")[0]
    (work / "colmap" / "images.txt").write_text(f"1 1 0 0 0 0 0 3 1 {photo}\n\n")
    imported = pymeshlab.MeshSet()
    imported.apply_filter(h.IMPORT_CAMERAS, camerafile=str(work / "colmap"), imagefolder=str(work / "photos"))
    assert imported.raster_number() == 1
    imported.save_filter_script(str(work / "import.mlx"))
    splat_writer.write_scenario("sphere_splats", str(work / "splats.ply"))
    splatted = h.load(scenes("sphere", level=2))
    splatted.apply_filter(h.SPLATS, splatfile=str(work / "splats.ply"))
    splatted.save_filter_script(str(work / "splats.mlx"))
    filters = {}
    for script in ("filters.mlx", "fit.mlx", "import.mlx", "splats.mlx"):
        for element in ET.parse(str(work / script)).getroot().iter("filter"):
            filters[element.get("name")] = element
    return filters


@pytest.mark.parametrize("meshlab_name", sorted(h.FILTERS))
def test_every_parameter_has_a_description_and_help_text(meshlab_name, recorded_script):
    element = recorded_script.get(meshlab_name)
    assert element is not None, f"'{meshlab_name}' was not recorded: {sorted(recorded_script)}"
    params = element.findall("Param")
    names = [p.get("name") for p in params]
    assert sorted(names) == sorted(EXPECTED_PARAMETERS[h.FILTERS[meshlab_name]]), names
    for p in params:
        assert (p.get("description") or "").strip(), f"{meshlab_name}: parameter {p.get('name')} has no description"
        assert len((p.get("tooltip") or "").strip()) >= 15, \
            f"{meshlab_name}: parameter {p.get('name')} has no help text ({p.get('tooltip')!r})"


def test_rply_load_and_save_through_pymeshlab(scenes, tmp_path):
    """A .rply written by the C++ tool is read by pymeshlab through our IO plugin (the layer has the
    radiance: the evaluation filter accepts it) and written back byte for byte."""
    written = tmp_path / "x.rply"
    h.run_tool("make_radiance_mesh", scenes("sphere", level=2), "--basis", "SH3", "--no-shadows", "-o", written)
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(str(written))
    assert ms.mesh_number() == 1 and ms.current_mesh().label() == "x.rply"
    expected = rply.read_rply(str(written))
    assert np.array_equal(ms.current_mesh().vertex_matrix(), expected.positions.astype(float))
    assert np.array_equal(ms.current_mesh().face_matrix(), expected.faces)
    again = tmp_path / "y.rply"
    ms.save_current_mesh(str(again))
    assert written.read_bytes() == again.read_bytes(), "load_new_mesh + save_current_mesh changed the .rply"
    ms.apply_filter(h.EVALUATE, viewpoint=np.array([0.0, 0.0, 5.0]))
    assert ms.current_mesh().vertex_color_matrix()[:, :3].max() > 0.1
