#!/usr/bin/env python3
"""Figures of the glTF export and the web viewer on a large mesh (docs/gltf-radiance.md):

  1. the mesh: data-cache/meshes/refined_elephant.off, midpoint-subdivided (MeshLab's filter, edges
     longer than --threshold % of the diagonal, 3 passes) to about 437k vertices;
  2. radiance: an analytic glossy material projected on SH3 (and PB4) by our filter;
  3. export: radiance_export_gltf, the file's size and time;
  4. compression, measured on the file's own streams: float32 as written, 16-bit quantised
     coefficients (one scale per attribute, as KHR_mesh_quantization's normalized shorts would need),
     each with meshoptimizer's vertex / index codecs (EXT_meshopt_compression's byte format), and the
     radiance error the quantisation makes (the 3DGS evaluation of the coefficient error, random
     directions);
  5. the viewer in headless Chromium (SwiftShader, CPU): time of each of --frames frames at --size.

    PYTHONPATH=python PYMESHLAB_RADIANCE_PLUGIN_DIR=build/pymeshlab_plugins \\
        build/python-venv/bin/python bench/gltf_viewer_bench.py [--data data-cache] [--size 800x600]
"""
import argparse
import json
import os
import struct
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def glb_streams(path):
    blob = open(path, "rb").read()
    json_length = struct.unpack_from("<I", blob, 12)[0]
    gltf = json.loads(blob[20:20 + json_length])
    binary = blob[28 + json_length:]
    prim = gltf["meshes"][0]["primitives"][0]

    def data(index):
        acc = gltf["accessors"][index]
        view = gltf["bufferViews"][acc["bufferView"]]
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4}[acc["type"]]
        dtype = np.float32 if acc["componentType"] == 5126 else np.uint32
        return np.frombuffer(binary, dtype, acc["count"] * width, view["byteOffset"]).reshape(acc["count"], -1)

    about = prim["extensions"]["RADIANCE_vertex_radiance_functions"]
    coefficients = np.stack([data(prim["attributes"][n]) for n in about["attributes"]], axis=2)  # (N, 3, K)
    return data(prim["attributes"]["POSITION"]), data(prim["indices"]).reshape(-1), coefficients, about


def sh3(d):
    """3DGS's real SH basis (its eval_sh constants), degree 3, at directions d (M, 3): (M, 16)."""
    x, y, z = d[:, 0], d[:, 1], d[:, 2]
    xx, yy, zz = x * x, y * y, z * z
    return np.stack([0.28209479177387814 + 0 * x, -0.4886025119029199 * y, 0.4886025119029199 * z,
                     -0.4886025119029199 * x, 1.0925484305920792 * x * y, -1.0925484305920792 * y * z,
                     0.31539156525252005 * (2 * zz - xx - yy), -1.0925484305920792 * x * z,
                     0.5462742152960396 * (xx - yy), -0.5900435899266435 * y * (3 * xx - yy),
                     2.890611442640554 * x * y * z, -0.4570457994644658 * y * (4 * zz - xx - yy),
                     0.3731763325901154 * z * (2 * zz - 3 * xx - 3 * yy), -0.4570457994644658 * x * (4 * zz - xx - yy),
                     1.445305721320277 * z * (xx - yy), -0.5900435899266435 * x * (xx - 3 * yy)], axis=1)


def compression(glb_path):
    import meshoptimizer

    positions, indices, coefficients, about = glb_streams(glb_path)
    n, _, k = coefficients.shape
    per_attribute = coefficients.transpose(2, 0, 1)  # (K, N, 3)
    scale = np.abs(per_attribute).reshape(k, -1).max(1)
    scale[scale == 0] = 1
    quantised = np.round(per_attribute / scale[:, None, None] * 32767).astype(np.int16)
    float_bytes = per_attribute.nbytes
    # meshopt's vertex codec wants strides that are multiples of 4: int16 VEC3 is padded to 8 bytes,
    # as EXT_meshopt_compression stores normalized shorts (VEC4 with padding).
    padded = np.zeros((k, n, 4), np.int16)
    padded[:, :, :3] = quantised
    meshopt_float = sum(len(meshoptimizer.encode_vertex_buffer(np.ascontiguousarray(a), n, 12)) for a in per_attribute)
    meshopt_short = sum(len(meshoptimizer.encode_vertex_buffer(np.ascontiguousarray(a), n, 8)) for a in padded)
    index_plain = indices.nbytes
    index_meshopt = len(meshoptimizer.encode_index_buffer(indices.astype(np.uint32), len(indices), n))
    print(f"  coefficients ({k} VEC3 attributes): float32 {float_bytes / 2**20:.1f} MiB; meshopt on float32 "
          f"{meshopt_float / 2**20:.1f} MiB; 16-bit quantised {padded.nbytes / 2**20:.1f} MiB (VEC4-padded), "
          f"+ meshopt {meshopt_short / 2**20:.1f} MiB")
    print(f"  indices: {index_plain / 2**20:.1f} MiB, meshopt {index_meshopt / 2**20:.1f} MiB")
    if about["basis"] == "SH" and about["degree"] == 3:
        rng = np.random.default_rng(1)
        sample = rng.choice(n, size=min(n, 20000), replace=False)
        d = rng.normal(size=(len(sample), 3))
        d /= np.linalg.norm(d, axis=1, keepdims=True)
        error = (quantised[:, sample, :] / 32767.0 * scale[:, None, None]) - per_attribute[:, sample, :]  # (K, S, 3)
        radiance_error = np.einsum("ksc,sk->sc", error, sh3(d))
        print(f"  16-bit quantisation: radiance error max {np.abs(radiance_error).max():.2e}, "
              f"RMS {np.sqrt((radiance_error ** 2).mean()):.2e} (linear; one 8-bit sRGB level at 0.2 is ~3.5e-3)")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--data", default=os.path.join(HERE, "..", "data-cache"))
    parser.add_argument("--threshold", type=float, default=0.195, help="subdivision edge threshold, % of diagonal")
    parser.add_argument("--size", default="800x600")
    parser.add_argument("--frames", type=int, default=5)
    parser.add_argument("--bases", default="SH3,PB4")
    args = parser.parse_args()

    import pymeshlab_radiance  # noqa: F401  (loads our plugins into pymeshlab)
    import pymeshlab

    work = tempfile.mkdtemp(prefix="gltf-bench-")
    for name in args.bases.split(","):
        basis, degree = (0 if name[:2] == "PB" else 1), int(name[2:])
        ms = pymeshlab.MeshSet()
        ms.load_new_mesh(os.path.join(args.data, "meshes", "refined_elephant.off"))
        ms.meshing_surface_subdivision_midpoint(iterations=3, threshold=pymeshlab.PercentageValue(args.threshold))
        mesh = ms.current_mesh()
        t0 = time.time()
        ms.apply_filter("radiance_create_radiance_data_from_analytic_material", basis=basis, degree=degree,
                        specular=0.5, shininess=20.0, light=np.array([0.5, 1.0, 1.0]), lightintensity=3.0)
        t1 = time.time()
        glb = os.path.join(work, f"elephant_{name}.glb")
        ms.apply_filter("radiance_export_gltf", outputfile=glb)
        t2 = time.time()
        print(f"{name}: {mesh.vertex_number()} vertices, {mesh.face_number()} faces; radiance {t1 - t0:.1f} s; "
              f"export {t2 - t1:.2f} s, {os.path.getsize(glb) / 2**20:.1f} MiB")
        compression(glb)
        box = mesh.bounding_box()
        centre, diagonal = box.center(), box.diagonal()
        eye = centre + np.array([0.3, 0.4, 1.0]) / np.linalg.norm([0.3, 0.4, 1.0]) * 1.4 * diagonal
        look = ",".join(f"{x:.6g}" for x in (*eye, *centre, 0, 1, 0))
        run = subprocess.run([sys.executable, "-m", "pymeshlab_radiance.view", glb, "--screenshot",
                              os.path.join(work, f"elephant_{name}.png"), "--size", args.size, "--look-at", look,
                              "--fov", "40", "--frames", str(args.frames), "--times-json",
                              os.path.join(work, f"elephant_{name}.json")], capture_output=True, text=True, timeout=900)
        if run.returncode != 0:
            print(run.stdout + run.stderr)
            return 1
        report = json.load(open(os.path.join(work, f"elephant_{name}.json")))
        times = report["frameTimesMs"]
        print(f"  viewer {args.size}, {report['renderer']}: frames "
              + ", ".join(f"{t:.0f}" for t in times) + f" ms (median {sorted(times)[len(times) // 2]:.0f} ms)")
    print(f"files in {work}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
