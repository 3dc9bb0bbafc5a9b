"""Malformed input through both batch hosts, as one table: every item of issue 16's campaign that a
script can reproduce, run through pymeshlab 2025.7 (in this process) and through Debian's
meshlabserver 2020.09 (a child process under Xvfb, every parameter listed in the .mlx).

For every case and host: no crash, no silent success (the filter or the load is refused), the message
names the problem and the fix (a fragment checked per case), never "Internal error", and the input is
left as it was (pymeshlab: the MeshSet's layers; meshlabserver: the layer saved after the refused
script is byte-identical to the layer saved without it).

Items of the campaign tested elsewhere because they are not refusals or need a machine state:
the bake into a folder (test_pymeshlab_bake.py), extra blocks kept through open + save
(test_pymeshlab_extra_blocks.py, tests/integration/test_extra_blocks_kept.sh), the bake's memory
estimate (tests/unit/normal_map_bake_test.cpp with a memory limit), stale temporaries after a killed
save (tests/unit/radiance_ply_test.cpp, bench/kill_during_save.sh).
"""
import os
import subprocess
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field

import numpy as np
import pymeshlab
import pytest

from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h

# A refusal of ours never reads like this: the wrapper's last resort for exceptions that no core
# turned into a sentence (plugins_shared/filter_errors.cpp).
INTERNAL = "Internal error"


@dataclass
class Case:
    inputs: tuple                 # names of files made by the `inputs` fixture, loaded as layers in order
    filter: str = ""              # MeshLab name; empty: the case is a refused load
    params: dict = field(default_factory=dict)  # MeshLab parameter names (camelCase) -> value
    message: str = ""             # in both hosts' refusals, unless a host has its own below
    python_message: str = ""      # pymeshlab's own parameter check runs before ours (enums)
    no_files: str = ""            # after the refusal no file of the inputs' folder starts with this


COORDINATES = "that single-precision geometry can be computed with: scale the mesh down"
# The remedy of COORDINATES, as each host names MeshLab's operation (the cores write "{{Transform: Scale,
# Normalize}}"; plugins_shared/host_operations names it per host).
SCALE_IN_PYMESHLAB = "MeshSet.compute_matrix_from_scaling_or_normalization() (MeshLab's Transform: Scale, Normalize)"
SCALE_IN_MESHLAB = "Filters > Normals, Curvatures and Orientation > Transform: Scale, Normalize"
CASES = {
    # Embree asserted and aborted MeshLab on a target near 1e19.
    "bake_target_at_1e19": Case(("sphere.ply", "sphere_1e19.ply"), "Bake Normal Map", {"sourceMesh": 0},
                                COORDINATES),
    # NaN normals on every output vertex at 1e20.
    "simplify_at_1e20": Case(("radiance_1e20.rply",), "Radiance: Radiance-Aware Simplification",
                             {"targetPercentage": 0.5}, COORDINATES),
    # Embree aborts on rays near 1e18: the grid's scene is refused first.
    "irradiance_grid_at_1e19": Case(("sphere_1e19.ply",), "Compute Irradiance Vector Grid",
                                    {"lightSource": 1, "rays": 4}, COORDINATES),
    # Issue 28: Embree's triangle test overflows near 1e13 and its next ray aborted the whole host
    # (assertion ray.valid()) at 1e13..1e15, inside the former 1e15 limit.
    "irradiance_grid_at_1e14": Case(("sphere_1e14.ply",), "Compute Irradiance Vector Grid",
                                    {"lightSource": 1, "rays": 4}, COORDINATES),
    # An all-zero grid, no warning (every ray missed a scene 1e-20 across).
    "irradiance_grid_at_1e-20": Case(("sphere_1e-20.ply",), "Compute Irradiance Vector Grid",
                                     {"lightSource": 1, "rays": 4}, "units across, below the 1e-06"),
    # "a vector component is not finite", naming no parameter.
    "irradiance_grid_env_scale_1e38": Case(("sphere.ply",), "Compute Irradiance Vector Grid",
                                           {"lightSource": 0, "envMap": "@bright.hdr", "envScale": 1e38, "rays": 4},
                                           "lower the parameter 'Environment intensity'"),
    # "the two layers do not overlap" for two coinciding layers at 1e15.
    "bake_layers_at_1e15": Case(("sphere_1e15.ply", "sphere_1e15_shrunk.ply"), "Bake Normal Map", {"sourceMesh": 0},
                                COORDINATES),
    # A .rpm name with a space left <name>_base.rply behind (test_refused_progressive_save_leaves_no_file).
    "simplify_rpm_name_with_space": Case(("radiance.rply",), "Radiance: Radiance-Aware Simplification",
                                         {"targetPercentage": 0.5, "progressiveFile": "@folder/my mesh.rpm"},
                                         "choose a .rpm file name without spaces", no_files="my mesh"),
    # "0.00 % ray hits" and a constant map written.
    "bake_source_far_away": Case(("sphere_far.ply", "sphere.ply"), "Bake Normal Map",
                                 {"sourceMesh": 0, "maxDistance": 0.5}, "the two layers do not overlap"),
    "evaluate_exposure_inf": Case(("radiance.rply",), "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color",
                                  {"exposure": float("inf")}, "The parameter 'exposure' is not a finite number"),
    "evaluate_exposure_negative": Case(("radiance.rply",),
                                       "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color",
                                       {"exposure": -1.0}, "The exposure must be a finite number >= 0"),
    "relight_nan_transfer": Case(("transfer_nan.rply",), "Radiance: PRT Relighting as Vertex Color",
                                 {"lighting": 1}, "transfer values are NaN or infinite"),
    "create_basis_7": Case(("sphere.ply",), "Radiance: Create Radiance Data from Analytic Material", {"basis": 7},
                           "The parameter 'basis' is 7, which is none of its choices: 0 = ",
                           python_message="Enum 7 not valid"),
    "simplify_metric_9": Case(("radiance.rply",), "Radiance: Radiance-Aware Simplification",
                              {"metric": 9, "targetPercentage": 0.5},
                              "The parameter 'metric' is 9, which is none of its choices: 0 = ",
                              python_message="Enum 9 not valid"),
    "bake_negative_distance": Case(("sphere.ply", "sphere_shrunk.ply"), "Bake Normal Map",
                                   {"sourceMesh": 0, "maxDistance": -1.0},
                                   "The maximum ray distance must be 0 (automatic) or a positive distance"),
    "simplify_negative_normal_change": Case(("radiance.rply",), "Radiance: Radiance-Aware Simplification",
                                            {"maxNormalChange": -10.0, "targetPercentage": 0.5},
                                            "The largest normal change must be an angle in [0, 180] degrees"),
    # A file claiming 10^6 rays per vertex was used for every new vertex of a subdivision.
    "adaptive_on_a_million_rays": Case(("transfer_rays_1e6.rply",), "Radiance: Adaptive PRT Subdivision",
                                       {"budgetFactor": 2.0},
                                       "has no PRT transfer vectors. Run 'Radiance: Compute PRT Transfer' first"),
    # The reader accepted what the writer then refused.
    "load_control_character_in_block_meta": Case(("control_character.rply",),
                                                 message="contains a control character"),
    # A header claiming 1 GiB of vertices over a sparse file drove 5 GB of allocation.
    "load_sparse_file": Case(("sparse.rply",), message="normal of vertex 0 is not unit length"),
}


# ---------------------------------------------------------------------------------------------------
# Inputs

def _write_like(path, template, positions):
    """`template`'s .rply with new positions (everything else as it was)."""
    mesh = rply.read_rply(str(template))
    mesh.positions = np.asarray(positions, dtype=mesh.positions.dtype)
    rply.write_rply(str(path), mesh)


@pytest.fixture(scope="module")
def inputs(scenes, tmp_path_factory):
    folder = tmp_path_factory.mktemp("malformed")
    sphere = scenes("sphere", level=2)
    made = {"sphere.ply": sphere}
    ms = h.load(sphere)
    m = ms.current_mesh()
    v, f, n = m.vertex_matrix(), m.face_matrix(), m.vertex_normal_matrix()
    for name, positions in (("sphere_1e19.ply", v * 1e19), ("sphere_far.ply", v + np.array([1000.0, 0.0, 0.0])),
                            ("sphere_shrunk.ply", v * 0.98), ("sphere_1e14.ply", v * 1e14),
                            ("sphere_1e-20.ply", v * 1e-20), ("sphere_1e15.ply", v * 1e15),
                            ("sphere_1e15_shrunk.ply", v * 0.98e15)):
        h.write_binary_ply(folder / name, positions, f, n)
        made[name] = str(folder / name)

    # A bright 4 x 2 environment map (radiance 1024 everywhere; flat RGBE): times 1e38 beyond float.
    (folder / "bright.hdr").write_bytes(b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 2 +X 4\n" + bytes([128, 128, 128, 139]) * 8)
    made["bright.hdr"] = str(folder / "bright.hdr")
    made["folder"] = str(folder)

    radiance = folder / "radiance.rply"
    h.run_tool("make_radiance_mesh", sphere, "--material", "stripes", "--basis", "PB4", "--no-shadows", "-o", radiance)
    made["radiance.rply"] = str(radiance)
    _write_like(folder / "radiance_1e20.rply", radiance, rply.read_rply(str(radiance)).positions * 1e20)
    made["radiance_1e20.rply"] = str(folder / "radiance_1e20.rply")

    ms = h.load(sphere)
    ms.apply_filter(h.TRANSFER, order=3, rays=16)
    transfer = folder / "transfer.rply"
    ms.save_current_mesh(str(transfer))
    mesh = rply.read_rply(str(transfer))
    mesh.blocks["prt"].values[5, 2] = np.nan
    rply.write_rply(str(folder / "transfer_nan.rply"), mesh)
    made["transfer_nan.rply"] = str(folder / "transfer_nan.rply")
    mesh = rply.read_rply(str(transfer))
    mesh.blocks["prt"].meta["rays"] = "1000000"
    rply.write_rply(str(folder / "transfer_rays_1e6.rply"), mesh)
    made["transfer_rays_1e6.rply"] = str(folder / "transfer_rays_1e6.rply")

    # A block's metadata with a tab: the transfer file otherwise.
    text = transfer.read_bytes()
    end = text.index(b"element vertex")
    bad = text[:end] + b"comment block_meta prt note made\tup\n" + text[end:]
    (folder / "control_character.rply").write_bytes(bad)
    made["control_character.rply"] = str(folder / "control_character.rply")

    # 1 GiB of zero vertices behind a plausible radiance header (PB1: 72 bytes per vertex), without
    # using the disk (a sparse file). Zero normals are refused in the first chunk read.
    vertices = (1 << 30) // 72
    names = ["x", "y", "z", "nx", "ny", "nz", "rf_tx", "rf_ty", "rf_tz"]
    names += [f"rf_{c}_{k}" for c in "rgb" for k in range(3)]
    head = ("ply\nformat binary_little_endian 1.0\ncomment radiance_format_version 1\ncomment radiance_basis PB1\n"
            f"comment radiance_reflected 0\nelement vertex {vertices}\n" +
            "".join(f"property float {p}\n" for p in names) +
            "element face 0\nproperty list uchar int vertex_indices\nend_header\n").encode()
    with open(folder / "sparse.rply", "wb") as out:
        out.write(head)
        out.truncate(len(head) + 72 * vertices)
    made["sparse.rply"] = str(folder / "sparse.rply")
    yield made
    os.remove(folder / "sparse.rply")


def test_inputs_are_what_the_cases_say(inputs):
    """The inputs carry the defect each case names (so that a refusal is for that defect)."""
    assert np.abs(rply.read_rply(inputs["radiance_1e20.rply"]).positions).max() > 1e19
    transfer = rply.read_rply(inputs["transfer_nan.rply"]).blocks["prt"]
    assert np.isnan(transfer.values).sum() == 1 and transfer.width == 9  # order 3
    assert rply.read_rply(inputs["transfer_rays_1e6.rply"]).blocks["prt"].meta["rays"] == "1000000"
    assert os.path.getsize(inputs["sparse.rply"]) > (1 << 30)


# ---------------------------------------------------------------------------------------------------
# pymeshlab

def _resolve(value, inputs):
    """'@name' is the path of an input made by the fixture; '@folder/x' a file in its folder."""
    if isinstance(value, str) and value.startswith("@"):
        head, _, tail = value[1:].partition("/")
        return os.path.join(inputs[head], tail) if tail else inputs[head]
    return value


def _python_params(case, inputs):
    params = {}
    for name, value in case.params.items():
        key = name.lower()
        value = _resolve(value, inputs)
        if name == "maxDistance":
            value = pymeshlab.PureValue(value)
        params[key] = value
    return params


@pytest.mark.parametrize("name", sorted(CASES))
def test_pymeshlab_refuses(name, inputs):
    case = CASES[name]
    expected = case.python_message or case.message
    ms = h.keep_alive(pymeshlab.MeshSet())
    if not case.filter:
        with pytest.raises(pymeshlab.PyMeshLabException) as caught:
            ms.load_new_mesh(inputs[case.inputs[0]])
        text = str(caught.value)
        assert ms.mesh_number() == 0, "a refused load added a layer"
    else:
        for layer in case.inputs:
            ms.load_new_mesh(inputs[layer])
        before = h.snapshot(ms)
        with pytest.raises(Exception) as caught:
            ms.apply_filter(h.FILTERS[case.filter], **_python_params(case, inputs))
        text = str(caught.value)
        assert isinstance(caught.value, (pymeshlab.PyMeshLabException, pymeshlab.InvalidEnumException)), \
            f"{type(caught.value).__name__}: {text}"
        h.assert_unchanged(before, h.snapshot(ms), name)
    assert expected in text, f"{name}: expected '{expected}' in:\n{text}"
    assert INTERNAL not in text, text
    assert "{{" not in text and "Filters >" not in text, text
    if case.message == COORDINATES:
        assert SCALE_IN_PYMESHLAB in text, text
    _assert_no_files(case, inputs)


def _assert_no_files(case, inputs):
    if case.no_files:
        left = [n for n in os.listdir(inputs["folder"]) if n.startswith(case.no_files)]
        assert left == [], f"a refusal left {left}"


# ---------------------------------------------------------------------------------------------------
# meshlabserver 2020.09

def _script(case, work, inputs):
    """A complete .mlx for the case: the repository's script writers (every parameter the filter
    declares, as meshlabserver 2020.09 requires: scripts/filter_script.sh), then the case's values put
    in verbatim: the writers would refuse the out-of-range ones, whose refusal by meshlabserver's side
    is what a case checks."""
    mlx = work / "case.mlx"
    scripts = os.path.join(h.REPO, "scripts")
    if case.filter == "Bake Normal Map":
        element = subprocess.run(["bash", os.path.join(scripts, "bake_normal_map_filter.sh"), "0", "256", "0", "1",
                                  "true", "false", str(work / "baked.png")], check=True, stdout=subprocess.PIPE,
                                 text=True).stdout
        mlx.write_text("<!DOCTYPE FilterScript>\n<FilterScript>\n" + element + "</FilterScript>\n")
    elif case.filter == "Radiance: Radiance-Aware Simplification":
        subprocess.run(["bash", os.path.join(scripts, "write_simplify_mlx.sh"), str(mlx), "0.5"], check=True)
    elif case.filter == "Radiance: Adaptive PRT Subdivision":
        subprocess.run(["bash", os.path.join(scripts, "write_prt_mlx.sh"), str(mlx), "adaptive:2"], check=True)
    elif case.filter == "Radiance: PRT Relighting as Vertex Color":
        subprocess.run(["bash", os.path.join(scripts, "write_prt_mlx.sh"), str(mlx), "relight-dir:0:0:1"], check=True)
    elif case.filter == "Radiance: Create Radiance Data from Analytic Material":
        h.create_mlx(mlx, dict(basis=0, degree=4, reflected=False, specular=0.5, stripes=0, lighttype=0,
                               light=(0.5, 1.0, 1.0)))
    elif case.filter == "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color":
        h.filter_script(mlx, (case.filter, dict(viewpoint=(0, 0, 5), exposure=1)))
    elif case.filter == "Compute Irradiance Vector Grid":
        h.filter_script(mlx, (case.filter, dict(resolution=4, bounces=1, rays=16, lightSource=1, lightCount=16,
                                                lightDirection=(0, 0, 1), outputFile=work / "grid.ivg")))
    else:
        raise AssertionError(f"no script writer for {case.filter}")
    tree = ET.parse(str(mlx))
    params = {p.get("name"): p for p in tree.getroot().iter("Param")}
    for name, value in case.params.items():
        assert name in params, f"{case.filter} has no parameter {name} in the written script"
        value = _resolve(value, inputs)
        params[name].set("value", str(value).lower() if isinstance(value, bool) else
                         value if isinstance(value, str) else repr(value))
    text = ET.tostring(tree.getroot(), encoding="unicode")
    mlx.write_text("<!DOCTYPE FilterScript>\n" + text + "\n")
    return mlx


@pytest.mark.parametrize("name", sorted(CASES))
def test_meshlabserver_refuses(name, inputs, tmp_path):
    case = CASES[name]
    layers = []
    for layer in case.inputs:
        layers += ["-i", inputs[layer]]
    ext = os.path.splitext(case.inputs[-1])[1]
    if not case.filter:
        status, log = h.run_meshlabserver(tmp_path, *layers, "-o", tmp_path / f"out{ext}")
        assert status != 0, f"{name}: the load succeeded:\n{log[-3000:]}"
        assert not (tmp_path / f"out{ext}").exists(), f"{name}: a refused load still wrote a file"
    else:
        reference = tmp_path / f"reference{ext}"
        status, log = h.run_meshlabserver(tmp_path, *layers, "-o", reference)
        assert status == 0 and reference.is_file(), f"{name}: cannot save the input as it is:\n{log[-3000:]}"
        out = tmp_path / f"out{ext}"
        status, log = h.run_meshlabserver(tmp_path, *layers, "-s", _script(case, tmp_path, inputs), "-o", out)
        assert status != 0 and "Problem with filter" in log, f"{name}: the filter succeeded:\n{log[-3000:]}"
        if out.exists():
            assert out.read_bytes() == reference.read_bytes(), f"{name}: the layer changed under a refused filter"
    assert case.message in log, f"{name}: expected '{case.message}' in:\n{log[-3000:]}"
    assert INTERNAL not in log, log[-3000:]
    assert "{{" not in log, log[-3000:]
    if case.message == COORDINATES:
        assert SCALE_IN_MESHLAB in log, log[-3000:]
    _assert_no_files(case, inputs)

