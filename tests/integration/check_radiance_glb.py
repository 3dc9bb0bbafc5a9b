#!/usr/bin/env python3
"""Checks a .glb written by 'Radiance: Export Radiance Functions as glTF (.glb)' against the .rply
saved from the same layer, with the standard library only (struct, json) and the independent PLY
reader: the GLB container (glTF 2.0 sec. 4.4), the positions, the coefficient attributes (SH signs
(-1)^(l+m), docs/gltf-radiance.md), COLOR_0 in [0, 1], the extension object.

    check_radiance_glb.py FILE.glb FILE.rply
"""
import json
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from ply_reader import read_ply  # noqa: E402

EXTENSION = "RADIANCE_vertex_radiance_functions"


def fail(message):
    print(f"check_radiance_glb: {message}", file=sys.stderr)
    sys.exit(1)


def main(glb_path, rply_path):
    blob = open(glb_path, "rb").read()
    magic, version, length = struct.unpack_from("<III", blob, 0)
    if magic != 0x46546C67 or version != 2 or length != len(blob):
        fail("bad GLB header")
    json_length, json_type = struct.unpack_from("<II", blob, 12)
    if json_type != 0x4E4F534A or json_length % 4:
        fail("bad JSON chunk")
    gltf = json.loads(blob[20:20 + json_length])
    bin_length, bin_type = struct.unpack_from("<II", blob, 20 + json_length)
    if bin_type != 0x004E4942 or 28 + json_length + bin_length != len(blob):
        fail("bad BIN chunk")
    binary = blob[28 + json_length:]
    prim = gltf["meshes"][0]["primitives"][0]
    about = prim["extensions"][EXTENSION]
    if about != prim["extras"]["radianceFunctions"]:
        fail("extension and extras differ")

    def floats(name, width):
        acc = gltf["accessors"][prim["attributes"][name]]
        view = gltf["bufferViews"][acc["bufferView"]]
        values = struct.unpack_from(f"<{acc['count'] * width}f", binary, view["byteOffset"])
        return [values[i:i + width] for i in range(0, len(values), width)]

    ply = read_ply(rply_path)
    vertex = ply.data["vertex"]
    n = len(vertex["x"])
    basis = ply.comment_value("radiance_basis")
    if f"{about['basis']}{about['degree']}" != basis:
        fail(f"basis {about['basis']}{about['degree']}, the .rply has {basis}")
    positions = floats("POSITION", 3)
    if len(positions) != n:
        fail(f"{len(positions)} vertices, the .rply has {n}")
    for v in range(n):
        if positions[v] != (vertex["x"][v], vertex["y"][v], vertex["z"][v]):
            fail(f"vertex {v} moved")
    for j, name in enumerate(about["attributes"]):
        sign = 1.0
        if about["basis"] == "SH":
            l = int(name.split("_")[4])
            m = int(name.split("_")[6]) - l
            sign = (-1.0) ** (l + m)
        values = floats(name, 3)
        for v in range(n):
            for c, channel in enumerate("rgb"):
                if values[v][c] != sign * vertex[f"rf_{channel}_{j}"][v]:
                    fail(f"{name} of vertex {v} is {values[v][c]}, the .rply's rf_{channel}_{j} is {vertex[f'rf_{channel}_{j}'][v]}")
    colours = floats("COLOR_0", 3)
    if not all(0.0 <= x <= 1.0 for c in colours for x in c):
        fail("COLOR_0 outside [0, 1]")
    if max(max(c) for c in colours) <= 0.0:
        fail("COLOR_0 all black")
    print(f"ok: {n} vertices, {basis}, {len(about['attributes'])} coefficient attributes")


if __name__ == "__main__":
    main(*sys.argv[1:3])
