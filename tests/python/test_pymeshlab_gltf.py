"""'Bake Normal Map' with the glTF 2.0 export (gltf=True) through pymeshlab 2025.7: the .glb is
parsed by pygltflib (a glTF reader from PyPI) and checked against what it must hold, computed here
independently of the writer:
  - the container parses without warnings; POSITION's min / max equal the decoded positions';
    every position is a vertex of the layer and every vertex is there;
  - TANGENT: unit, orthogonal to NORMAL, w = +1 or -1, and equal to the MikkTSpace tangent of
    the per-triangle atlas (each corner its own vertex: dP/du projected on the normal's plane,
    Mikkelsen 2008), with w the sign of the UV triangle's area;
  - three textures (normal, base colour, metallic-roughness), decodable PNGs;
  - the glTF normal texture, decoded the MikkTSpace way with the glTF's own TANGENT and NORMAL,
    gives back the object-space map baked at the same time (same texels), within 8-bit error;
  - roughness (G) never below the base roughness, metallic (B) 0;
  - Blender (Debian's package, headless) imports the file without an error and finds the mesh,
    the normal map and the same vertex count.
"""
import io
import os
import struct
import warnings

import numpy as np
import pygltflib
import pytest

import pymeshlab_test_helpers as h
from test_pymeshlab_bake import mikktspace_corner_tangents, scan_and_target, meshes  # noqa: F401 (fixture)

SIZE = 256


def accessor_array(gltf, blob, index):
    accessor = gltf.accessors[index]
    view = gltf.bufferViews[accessor.bufferView]
    width = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}[accessor.type]
    dtype = {5126: np.float32, 5125: np.uint32}[accessor.componentType]
    start = view.byteOffset + (accessor.byteOffset or 0)
    data = np.frombuffer(blob, dtype=dtype, count=accessor.count * width, offset=start)
    return data.reshape(accessor.count, width) if width > 1 else data


def image_bytes(gltf, blob, image_index):
    view = gltf.bufferViews[gltf.images[image_index].bufferView]
    return blob[view.byteOffset:view.byteOffset + view.byteLength]


@pytest.fixture(scope="module")
def baked(meshes, tmp_path_factory):
    out = tmp_path_factory.mktemp("gltf")
    ms = scan_and_target(meshes)
    ms.apply_filter(h.BAKE, sourcemesh=0, texturesize=SIZE, space=0, bits=0, gltf=True, gltfroughness=0.5,
                    outputfile=str(out / "coarse_normal.png"))
    return ms, out


def test_glb_parses_and_holds_the_layer(baked):
    ms, out = baked
    path = out / "coarse.glb"
    assert path.exists(), sorted(os.listdir(out))
    assert not list(out.glob("*.part*")), "temporary files left behind"
    assert "gltf = coarse.glb" in (out / "coarse_bake.txt").read_text().splitlines()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        gltf = pygltflib.GLTF2().load_binary(str(path))
    blob = gltf.binary_blob()
    assert gltf.asset.version == "2.0"
    assert len(gltf.meshes) == 1 and len(gltf.meshes[0].primitives) == 1
    prim = gltf.meshes[0].primitives[0]
    assert prim.mode == 4
    positions = accessor_array(gltf, blob, prim.attributes.POSITION)
    normals = accessor_array(gltf, blob, prim.attributes.NORMAL)
    uv = accessor_array(gltf, blob, prim.attributes.TEXCOORD_0)
    tangents = accessor_array(gltf, blob, prim.attributes.TANGENT)
    indices = accessor_array(gltf, blob, prim.indices)
    acc = gltf.accessors[prim.attributes.POSITION]
    assert np.array_equal(np.array(acc.min, dtype=np.float32), positions.min(0))
    assert np.array_equal(np.array(acc.max, dtype=np.float32), positions.max(0))
    target = ms.current_mesh()
    vertices = target.vertex_matrix().astype(np.float32)
    assert len(indices) == 3 * target.face_number()
    # Same vertex set (glTF splits vertices at seams: positions repeat).
    assert {tuple(p) for p in positions} == {tuple(v) for v in vertices}
    assert np.abs(np.linalg.norm(normals, axis=1) - 1).max() < 1e-5
    assert np.abs(np.linalg.norm(tangents[:, :3], axis=1) - 1).max() < 1e-5
    assert set(np.unique(tangents[:, 3])) <= {-1.0, 1.0}
    assert np.abs((tangents[:, :3] * normals).sum(1)).max() < 1e-4
    assert uv.min() >= 0 and uv.max() <= 1

    # Tangents against the MikkTSpace closed form of the per-triangle atlas, triangle by triangle.
    tri = indices.reshape(-1, 3)
    wedge_uv = np.stack([uv[:, 0], 1.0 - uv[:, 1]], axis=1)[tri].reshape(-1, 2)  # back to v up
    plain_faces = np.arange(3 * len(tri)).reshape(-1, 3)
    corner_positions = positions[tri].reshape(-1, 3).astype(np.float64)
    corner_normals = normals[tri].reshape(-1, 3).astype(np.float64)
    worst = 0.0
    for f in range(len(tri)):
        expected, sign = mikktspace_corner_tangents(corner_positions, plain_faces, wedge_uv, f, corner_normals)
        got = tangents[tri[f]]
        worst = max(worst, np.abs(got[:, :3] - expected).max())
        assert np.all(got[:, 3] == sign), f"triangle {f}: signs {got[:, 3]}, UV orientation {sign}"
    assert worst < 1e-4, f"tangents differ from MikkTSpace's closed form by {worst}"


def test_glb_textures_match_the_maps(baked):
    ms, out = baked
    gltf = pygltflib.GLTF2().load_binary(str(out / "coarse.glb"))
    blob = gltf.binary_blob()
    assert len(gltf.textures) == 3 and len(gltf.images) == 3
    material = gltf.materials[0]
    pbr = material.pbrMetallicRoughness
    assert material.normalTexture is not None and pbr.baseColorTexture is not None
    assert pbr.metallicRoughnessTexture is not None
    assert pbr.metallicFactor == 0

    def png(texture_index, name):
        data = image_bytes(gltf, blob, gltf.textures[texture_index].source)
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        path = out / f"extracted_{name}.png"
        path.write_bytes(data)
        return h.read_png(path)

    normal_map, depth = png(material.normalTexture.index, "normal")
    assert depth == 8 and normal_map.shape[:2] == (SIZE, SIZE)
    rough, _ = png(pbr.metallicRoughnessTexture.index, "roughness")
    assert rough.shape[:2] == (SIZE // 2, SIZE // 2)  # LEAN level 1
    assert (np.round(rough[:, :, 1] * 255) >= 127).all(), "roughness below the base roughness 0.5"
    assert (rough[:, :, 2] == 0).all(), "metallic is not 0"
    assert (np.round(rough[:, :, 1] * 255) > 128).any(), "the LEAN spread raised no roughness anywhere"
    colour, _ = png(pbr.baseColorTexture.index, "colour")
    assert colour.shape[:2] == (SIZE, SIZE)

    # The glTF normal map decoded as a glTF renderer does equals the object-space map of the bake.
    object_map, _ = h.read_png(out / "coarse_normal.png")
    prim = gltf.meshes[0].primitives[0]
    positions = accessor_array(gltf, blob, prim.attributes.POSITION).astype(np.float64)
    normals = accessor_array(gltf, blob, prim.attributes.NORMAL).astype(np.float64)
    uv = accessor_array(gltf, blob, prim.attributes.TEXCOORD_0).astype(np.float64)
    tangents = accessor_array(gltf, blob, prim.attributes.TANGENT).astype(np.float64)
    tri = accessor_array(gltf, blob, prim.indices).reshape(-1, 3)
    wedge_uv = np.stack([uv[:, 0], 1.0 - uv[:, 1]], axis=1)[tri].reshape(-1, 2)
    errors = []
    for f, col, row, _, normal, weights in h.texels_inside_faces(positions, tri, wedge_uv, normals, SIZE, SIZE,
                                                                 with_weights=True):
        t = weights @ tangents[tri[f], :3]
        b = tangents[tri[f][0], 3] * np.cross(normal, t)
        code = normal_map[row, col] * 2 - 1
        decoded = code[:, :1] * t + code[:, 1:2] * b + code[:, 2:3] * normal
        errors.append(h.angle_degrees(decoded, object_map[row, col] * 2 - 1))
    errors = np.concatenate(errors)
    print(f"glTF normal map vs object-space map: {errors.size} texels, mean {errors.mean():.3f}, "
          f"max {errors.max():.3f} degrees")
    assert errors.size > 10000
    # 8 bit: a level is ~0.45 degrees.
    assert errors.mean() < 0.3 and errors.max() < 1.5


def test_blender_imports_the_glb(baked, tmp_path):
    _, out = baked
    log, words = h.blender_import_glb(out / "coarse.glb", tmp_path, (
        "nodes = mesh.materials[0].node_tree.nodes\n"
        "print('IMPORTED vertices', len(mesh.vertices), 'normal_map_nodes',"
        " sum(1 for n in nodes if n.type == 'NORMAL_MAP'), 'images', len(bpy.data.images))\n"))
    assert "Error" not in log, log
    line = " ".join(words)
    gltf = pygltflib.GLTF2().load_binary(str(out / "coarse.glb"))
    count = gltf.accessors[gltf.meshes[0].primitives[0].attributes.POSITION].count
    # Blender merges the glTF's split vertices back where only the UVs differ; it cannot have more.
    assert 0 < int(words[2]) <= count, line
    assert int(words[4]) == 1, f"no normal map node: {line}"
    assert int(words[6]) == 3, f"not three images: {line}"
