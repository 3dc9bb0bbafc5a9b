#!/usr/bin/env python3
"""Independent checks of radiance PLY files written through meshlabserver, using the project's
stand-alone pure-Python PLY reader (ply_reader.py), not the C++ code under test.

  check_radiance_ply.py lambert FILE BASIS DEGREE LX LY LZ E AMBIENT R G B
      The file holds the radiance of a Lambertian material (no lobe) of sRGB albedo (R, G, B) under
      a directional light toward (LX, LY, LZ) of irradiance E plus an ambient radiance: the RF of
      every vertex is the constant albedo/pi * E * max(0, n.l) + albedo * ambient, computed here
      from the file's normals. For PB the constant is coefficient 0 (u^0 v^0 = 1); for SH it is
      coefficient 0 divided by Y_0^0 = 1 / (2 sqrt(pi)). Every other coefficient must vanish, and
      the vertex colour must be the sRGB encoding of the constant.
  check_radiance_ply.py lambert_sphere FILE BASIS DEGREE LX LY LZ E AMBIENT R G B
      As `lambert`, for a sphere centred on the origin: the normal is taken from the vertex POSITION
      (normalised), not from the file's normals, so a radiance row attached to the wrong vertex is
      caught even though coefficients and frames travel together.
  check_radiance_ply.py same FILE_A FILE_B
      Both files hold the same vertices, faces and properties, bit for bit.
  check_radiance_ply.py directional FILE
      Some vertex has a clearly non-constant RF (a glossy material was projected).
"""
import math
import os
import struct
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ply_reader  # noqa: E402


def fail(message):
    print("check_radiance_ply: FAIL: " + message)
    sys.exit(1)


def load(path):
    return ply_reader.read_ply(path)


def comments(ply):
    out = {}
    for line in ply["comments"]:
        parts = line.split(None, 1)
        if len(parts) == 2:
            out[parts[0]] = parts[1].strip()
    return out


def srgb_decode(s):
    s /= 255.0
    return s / 12.92 if s <= 0.04045 else ((s + 0.055) / 1.055) ** 2.4


def srgb_encode(x):
    x = min(max(x, 0.0), 1.0)
    e = 12.92 * x if x <= 0.0031308 else 1.055 * x ** (1 / 2.4) - 0.055
    return int(round(e * 255))


def coefficient_count(basis, degree):
    return (degree + 1) * (degree + 2) // 2 if basis == "PB" else (degree + 1) ** 2


def check_lambert(path, basis, degree, light, irradiance, ambient, albedo_srgb, normal_from_position=False):
    ply = load(path)
    meta = comments(ply)
    if meta.get("radiance_basis") != f"{basis}{degree}":
        fail(f"header says basis {meta.get('radiance_basis')}, expected {basis}{degree}")
    vertex = ply["elements"]["vertex"]
    k_count = coefficient_count(basis, degree)
    for c in "rgb":
        for k in range(k_count):
            if f"rf_{c}_{k}" not in vertex:
                fail(f"property rf_{c}_{k} missing")
        if f"rf_{c}_{k_count}" in vertex:
            fail(f"unexpected property rf_{c}_{k_count}")
    norm = math.sqrt(sum(x * x for x in light))
    l = [x / norm for x in light]
    albedo = [srgb_decode(x) for x in albedo_srgb]
    scale = 1.0 if basis == "PB" else 2.0 * math.sqrt(math.pi)   # c0 = f / Y00
    count = len(vertex["x"])
    if count == 0:
        fail("no vertices")
    worst = 0.0
    for v in range(count):
        n = [vertex["nx"][v], vertex["ny"][v], vertex["nz"][v]]
        if normal_from_position:
            p = [vertex["x"][v], vertex["y"][v], vertex["z"][v]]
            length = math.sqrt(sum(x * x for x in p))
            p = [x / length for x in p]
            if max(abs(a - b) for a, b in zip(n, p)) > 1e-4:
                fail(f"vertex {v}: radiance frame normal {n} is not the sphere normal {p}: rows mixed up")
            n = p
        cos = max(0.0, sum(a * b for a, b in zip(n, l)))
        for ci, c in enumerate("rgb"):
            expected = albedo[ci] / math.pi * irradiance * cos + albedo[ci] * ambient
            got = vertex[f"rf_{c}_0"][v] / scale
            worst = max(worst, abs(got - expected) / max(1e-3, expected))
            if abs(got - expected) > 1e-4 * max(1.0, expected):
                fail(f"vertex {v} channel {c}: constant term {got}, expected {expected}")
            for k in range(1, k_count):
                if abs(vertex[f"rf_{c}_{k}"][v]) > 2e-5:
                    fail(f"vertex {v}: coefficient rf_{c}_{k} = {vertex[f'rf_{c}_{k}'][v]} for a constant RF")
            colour = vertex[("red", "green", "blue")[ci]][v]
            if abs(colour - srgb_encode(expected)) > 1:
                fail(f"vertex {v}: colour {colour} is not sRGB({expected}) = {srgb_encode(expected)}")
    print(f"lambert ok: {count} vertices, worst relative error of the constant term {worst:.2e}")


def check_same(path_a, path_b):
    a, b = load(path_a), load(path_b)
    for element in ("vertex", "face"):
        ea, eb = a["elements"][element], b["elements"][element]
        if sorted(ea) != sorted(eb):
            fail(f"{element} properties differ: {sorted(ea)} vs {sorted(eb)}")
        for name in ea:
            va, vb = ea[name], eb[name]
            if len(va) != len(vb):
                fail(f"{element}.{name}: {len(va)} vs {len(vb)} values")
            for i, (x, y) in enumerate(zip(va, vb)):
                if isinstance(x, float):
                    if struct.pack("<f", x) != struct.pack("<f", y):
                        fail(f"{element}.{name}[{i}]: {x!r} != {y!r}")
                elif x != y:
                    fail(f"{element}.{name}[{i}]: {x!r} != {y!r}")
    ca = {k: v for k, v in comments(a).items()}
    cb = {k: v for k, v in comments(b).items()}
    if ca != cb:
        fail(f"header comments differ: {ca} vs {cb}")
    print(f"same ok: {len(a['elements']['vertex']['x'])} vertices identical")


def check_directional(path):
    ply = load(path)
    vertex = ply["elements"]["vertex"]
    biggest = 0.0
    for name, values in vertex.items():
        if name.startswith("rf_") and not name.endswith("_0") and name[3] in "rgb" and name[4] == "_":
            biggest = max(biggest, max(abs(x) for x in values))
    if biggest < 1e-2:
        fail(f"all directional coefficients are below {biggest}: the glossy lobe is missing")
    print(f"directional ok: largest non-constant coefficient {biggest:.3f}")


def main():
    mode = sys.argv[1]
    if mode in ("lambert", "lambert_sphere"):
        path, basis, degree = sys.argv[2], sys.argv[3], int(sys.argv[4])
        light = [float(x) for x in sys.argv[5:8]]
        irradiance, ambient = float(sys.argv[8]), float(sys.argv[9])
        albedo = [int(x) for x in sys.argv[10:13]]
        check_lambert(path, basis, degree, light, irradiance, ambient, albedo, mode == "lambert_sphere")
    elif mode == "same":
        check_same(sys.argv[2], sys.argv[3])
    elif mode == "directional":
        check_directional(sys.argv[2])
    else:
        fail("unknown mode " + mode)


if __name__ == "__main__":
    main()
