"""'Radiance: Export Radiance Functions as glTF (.glb)' (radiance_export_gltf) through pymeshlab 2025.7.
The .glb is parsed by pygltflib (a glTF reader from PyPI) and checked against what the layer holds,
read independently of the writer (the .rply saved from the same layer, decoded by the numpy reader):
  - positions and faces are the layer's; NORMAL the RF frame normal; TANGENT the frame tangent (PB);
  - COLOR_0 of a Lambertian material (constant RF) is the closed-form radiance of the material;
  - the coefficients are the .rply's, SH ones times (-1)^(l+m) (the documented 3DGS sign convention),
    and 3D Gaussian Splatting's evaluation (its published eval_sh's conventions) at the viewing ray gives the
    colours of the filter 'Evaluate Radiance toward a Viewpoint as Vertex Color';
  - the extension object and extras say basis, degree, reflection and colour space;
  - Blender (Debian's package, headless) imports the file and finds COLOR_0 as a colour attribute;
  - refusals (no radiance, a folder that does not exist, not .glb) leave no file and the layers as they were.
"""
import math
import os
import subprocess
import warnings

import numpy as np
import pygltflib
import pytest

from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h

EXPORT = "radiance_export_gltf"
EXTENSION = "RADIANCE_vertex_radiance_functions"
ALBEDO = (230, 60, 40)
LIGHT = np.array([0.5, 1.0, 1.0])


def create(path, basis, degree, reflected=False, specular=0.0):
    import pymeshlab
    ms = h.load(path)
    ms.apply_filter(h.CREATE, basis=basis, degree=degree, reflected=reflected, albedo=pymeshlab.Color(*ALBEDO),
                    specularcolor=pymeshlab.Color(255, 255, 255), specular=specular, shininess=20.0, stripes=0,
                    stripeaxis=1, lighttype=0, light=LIGHT, lightintensity=3.0, ambient=0.05, setcolor=True)
    return ms


def load_glb(path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gltf = pygltflib.GLTF2().load_binary(str(path))
    return gltf, gltf.binary_blob()


def accessor(gltf, blob, index):
    acc = gltf.accessors[index]
    view = gltf.bufferViews[acc.bufferView]
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[acc.type]
    dtype = {5126: np.float32, 5125: np.uint32}[acc.componentType]
    data = np.frombuffer(blob, dtype=dtype, count=acc.count * width, offset=view.byteOffset + (acc.byteOffset or 0))
    return data.reshape(acc.count, width) if width > 1 else data


def attribute(gltf, blob, name):
    prim = gltf.meshes[0].primitives[0]
    attrs = prim.attributes.__dict__ if hasattr(prim.attributes, "__dict__") else prim.attributes
    index = getattr(prim.attributes, name, None)
    if index is None:
        index = attrs.get(name)
    assert index is not None, f"no attribute {name}"
    return accessor(gltf, blob, index)


def eval_sh_3dgs(degree, sh, dirs):
    """The SH evaluation of 3D Gaussian Splatting (Kerbl et al. 2023): sh (..., C, (degree+1)^2),
    dirs (..., 3); the real-SH normalisations with the Condon-Shortley signs its published eval_sh uses."""
    C0 = 0.28209479177387814
    C1 = 0.4886025119029199
    C2 = [1.0925484305920792, -1.0925484305920792, 0.31539156525252005, -1.0925484305920792, 0.5462742152960396]
    C3 = [-0.5900435899266435, 2.890611442640554, -0.4570457994644658, 0.3731763325901154, -0.4570457994644658,
          1.445305721320277, -0.5900435899266435]
    result = C0 * sh[..., 0]
    x, y, z = (dirs[..., i] for i in range(3))
    if degree > 0:
        result = result - C1 * y * sh[..., 1] + C1 * z * sh[..., 2] - C1 * x * sh[..., 3]
    if degree > 1:
        xx, yy, zz, xy, yz, xz = x * x, y * y, z * z, x * y, y * z, x * z
        result = (result + C2[0] * xy * sh[..., 4] + C2[1] * yz * sh[..., 5] + C2[2] * (2.0 * zz - xx - yy) * sh[..., 6]
                  + C2[3] * xz * sh[..., 7] + C2[4] * (xx - yy) * sh[..., 8])
        if degree > 2:
            result = (result + C3[0] * y * (3 * xx - yy) * sh[..., 9] + C3[1] * xy * z * sh[..., 10]
                      + C3[2] * y * (4 * zz - xx - yy) * sh[..., 11] + C3[3] * z * (2 * zz - 3 * xx - 3 * yy) * sh[..., 12]
                      + C3[4] * x * (4 * zz - xx - yy) * sh[..., 13] + C3[5] * z * (xx - yy) * sh[..., 14]
                      + C3[6] * x * (xx - 3 * yy) * sh[..., 15])
    return result


@pytest.mark.parametrize("basis,degree,reflected", [(0, 3, False), (1, 3, False), (1, 2, True)],
                         ids=["PB3", "SH3", "SH2-reflected"])
def test_glb_holds_the_layer_and_its_radiance(basis, degree, reflected, scenes, tmp_path):
    ms = create(scenes("sphere", level=2), basis, degree, reflected, specular=0.5)
    ms.save_current_mesh(str(tmp_path / "layer.rply"))
    ms.apply_filter(EXPORT, outputfile=str(tmp_path / "layer.glb"))
    assert sorted(os.listdir(tmp_path)) == ["layer.glb", "layer.rply"], "temporary files left behind"
    mesh = rply.read_rply(str(tmp_path / "layer.rply"))
    gltf, blob = load_glb(tmp_path / "layer.glb")
    assert gltf.asset.version == "2.0"
    prim = gltf.meshes[0].primitives[0]
    assert prim.mode == 4
    np.testing.assert_array_equal(attribute(gltf, blob, "POSITION"), mesh.positions)
    np.testing.assert_array_equal(accessor(gltf, blob, prim.indices).reshape(-1, 3), mesh.faces)
    np.testing.assert_allclose(attribute(gltf, blob, "NORMAL"), mesh.normals, atol=1e-6)
    k = mesh.coefficients.shape[2]
    if basis == 0:
        tangent = attribute(gltf, blob, "TANGENT")
        np.testing.assert_allclose(tangent[:, :3], mesh.tangents, atol=1e-6)
        assert np.all(tangent[:, 3] == 1.0)
        names = [f"_RF_PB_COEF_{j}" for j in range(k)]
        signs = np.ones(k)
    else:
        assert prim.attributes.TANGENT is None, "SH needs no tangent"
        names = [f"_RF_SH_DEGREE_{l}_COEF_{l + m}" for l in range(degree + 1) for m in range(-l, l + 1)]
        signs = np.array([(-1.0) ** (l + m) for l in range(degree + 1) for m in range(-l, l + 1)])
    for j, name in enumerate(names):
        np.testing.assert_array_equal(attribute(gltf, blob, name), mesh.coefficients[:, :, j] * signs[j], err_msg=name)
    description = prim.extensions[EXTENSION]
    assert description == prim.extras["radianceFunctions"]
    assert description["basis"] == ("PB" if basis == 0 else "SH") and description["degree"] == degree
    assert description["reflected"] == reflected and description["colorSpace"] == "srgb-linear"
    assert description["attributes"] == names
    assert EXTENSION in gltf.extensionsUsed and not gltf.extensionsRequired


def test_color_0_is_the_mean_of_a_lambertian_rf(scenes, tmp_path):
    """Lambert: the RF is constant, its mean the closed form albedo/pi E max(0, n.l) + albedo ambient."""
    ms = create(scenes("sphere", level=2), 1, 2)
    ms.apply_filter(EXPORT, outputfile=str(tmp_path / "lambert.glb"))
    gltf, blob = load_glb(tmp_path / "lambert.glb")
    normals = h.normalized(attribute(gltf, blob, "POSITION").astype(float))  # a unit sphere
    albedo = h.srgb_decode(ALBEDO)
    expected = albedo / math.pi * 3.0 * np.maximum(0.0, normals @ h.normalized(LIGHT))[:, None] + albedo * 0.05
    np.testing.assert_allclose(attribute(gltf, blob, "COLOR_0"), np.clip(expected, 0, 1), atol=2e-3)


def test_3dgs_evaluation_gives_the_filter_colours(scenes, tmp_path):
    """eval_sh of 3DGS on the file's coefficients at d = normalize(p - eye) against the colours of the
    'Evaluate toward a Viewpoint' filter (8-bit sRGB) on the vertices that face the eye."""
    ms = create(scenes("sphere", level=2), 1, 3, specular=0.5)
    ms.apply_filter(EXPORT, outputfile=str(tmp_path / "glossy.glb"))
    eye = np.array([0.5, 0.8, 3.0])
    ms.apply_filter(h.EVALUATE, viewpoint=eye, exposure=1.0)
    colours = ms.current_mesh().vertex_color_matrix()[:, :3] * 255.0
    gltf, blob = load_glb(tmp_path / "glossy.glb")
    positions = attribute(gltf, blob, "POSITION").astype(float)
    normals = attribute(gltf, blob, "NORMAL").astype(float)
    sh = np.stack([attribute(gltf, blob, f"_RF_SH_DEGREE_{l}_COEF_{l + m}") for l in range(4)
                   for m in range(-l, l + 1)], axis=2).astype(float)  # (N, 3, 16)
    d = h.normalized(positions - eye)
    radiance = eval_sh_3dgs(3, sh, d[:, None, :])
    facing = (normals * -d).sum(1) > 0.1
    assert facing.sum() > 20
    error = np.abs(h.srgb_encode(radiance[facing]) - colours[facing])
    assert error.max() <= 1.0, error.max()
    assert np.ptp(colours[facing][:, 1]) > 40, "the test needs a view-dependent highlight"


def test_blender_imports_the_glb_with_color_0(scenes, tmp_path):
    ms = create(scenes("sphere", level=2), 0, 2)
    path = tmp_path / "pb.glb"
    ms.apply_filter(EXPORT, outputfile=str(path))
    _, words = h.blender_import_glb(path, tmp_path, (
        "layers = mesh.color_attributes if hasattr(mesh, 'color_attributes') else mesh.vertex_colors\n"
        "names = [a.name for a in layers]\n"
        "layer = layers[0]\n"
        "import statistics\n"
        "mean = [statistics.fmean(d.color[c] for d in layer.data) for c in range(3)]\n"
        "print('IMPORTED', len(mesh.vertices), ','.join(names), *('%.4f' % m for m in mean))\n"))
    gltf, blob = load_glb(path)
    colours = attribute(gltf, blob, "COLOR_0")
    assert int(words[1]) == len(colours)
    assert "Col" in words[2] or "COLOR_0" in words[2], words
    # Blender keeps the colours (linear); their mean over the vertices is the file's.
    np.testing.assert_allclose([float(w) for w in words[3:6]], colours.mean(0), atol=2e-3)


def test_refusals_write_nothing(scenes, tmp_path):
    plain = h.load(scenes("sphere", level=1))
    h.expect_refusal(plain, EXPORT, "no radiance data", outputfile=str(tmp_path / "none.glb"))
    ms = create(scenes("sphere", level=1), 1, 2)
    h.expect_refusal(ms, EXPORT, "does not exist", outputfile=str(tmp_path / "missing" / "x.glb"))
    h.expect_refusal(ms, EXPORT, "does not end in .glb", outputfile=str(tmp_path / "x.gltf"))
    h.expect_refusal(ms, EXPORT, "none given", outputfile="")
    assert os.listdir(tmp_path) == []


def test_command_line_export(scenes, tmp_path):
    """meshlab-radiance export: the same file as the filter, and a refusal on stderr with status 1."""
    import sys

    ms = create(scenes("sphere", level=1), 1, 2)
    ms.save_current_mesh(str(tmp_path / "s.rply"))
    ms.apply_filter(EXPORT, outputfile=str(tmp_path / "direct.glb"))
    env = h.python_env()

    def cli(*args):
        return subprocess.run([sys.executable, "-m", "pymeshlab_radiance", "export", *map(str, args)],
                              capture_output=True, text=True, timeout=300, env=env)

    run = cli(tmp_path / "s.rply", "-o", tmp_path / "cli.glb")
    assert run.returncode == 0, run.stdout + run.stderr
    a, blob_a = load_glb(tmp_path / "direct.glb")
    b, blob_b = load_glb(tmp_path / "cli.glb")
    assert blob_a == blob_b, "the command line's file differs from the filter's"
    run = cli(tmp_path / "s.rply", "-o", tmp_path / "missing" / "x.glb")
    assert run.returncode == 1 and "does not exist" in run.stderr, run.stderr
