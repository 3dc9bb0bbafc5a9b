"""3D Gaussian Splatting .ply files for the splat-transfer tests, written here independently of the
C++ reader: the property list and layout of the reference implementation's save_ply (Kerbl et al.
2023; x y z nx ny nz f_dc_0..2 f_rest_0.. opacity scale_0..2 rot_0..3, float32, binary little endian,
f_rest channel-major), its SH evaluation (sh_utils.eval_sh, camera-to-splat direction), and the
expected vertex colours of a splat field from the definitions in docs/gaussian-splats.md.

Command line (for the meshlabserver tests):
    python3 splat_writer.py SCENARIO OUT.ply
SCENARIO: sphere_splats (a view-dependent SH1 field on the unit sphere), nan, degree4, far,
sphere_mesh (a UV sphere with normals, the mesh the splats are transferred onto).
"""
import math
import sys

import numpy as np

C0 = 0.28209479177387814
C1 = 0.4886025119029199


def property_names(degree, normals=True):
    names = ["x", "y", "z"] + (["nx", "ny", "nz"] if normals else [])
    names += [f"f_dc_{i}" for i in range(3)]
    names += [f"f_rest_{i}" for i in range(3 * ((degree + 1) ** 2 - 1))]
    return names + ["opacity"] + [f"scale_{i}" for i in range(3)] + [f"rot_{i}" for i in range(4)]


def write_splats(path, positions, sh, opacity, log_scale, rotation, ascii=False):
    """sh: (N, 3, K) per channel; written as f_dc = sh[:, :, 0] and f_rest channel-major."""
    n, _, k = sh.shape
    degree = int(round(math.sqrt(k))) - 1
    columns = [positions, np.zeros((n, 3)), sh[:, :, 0], sh[:, :, 1:].reshape(n, 3 * (k - 1)),
               opacity.reshape(n, 1), log_scale, rotation]
    table = np.concatenate([np.asarray(c, dtype=np.float64).reshape(n, -1) for c in columns], axis=1)
    names = property_names(degree)
    assert table.shape[1] == len(names)
    header = "ply\nformat {} 1.0\nelement vertex {}\n".format("ascii" if ascii else "binary_little_endian", n)
    header += "".join(f"property float {name}\n" for name in names) + "end_header\n"
    with open(path, "wb") as f:
        f.write(header.encode("ascii"))
        if ascii:
            f.write("".join(" ".join(repr(float(v)) for v in row) + "\n" for row in table).encode("ascii"))
        else:
            f.write(table.astype("<f4").tobytes())


def eval_sh_band1(sh, d):
    """The reference eval_sh up to band 1, for (N, 3, 4) coefficients and (N, 3) directions d
    (camera to splat)."""
    x, y, z = d[:, 0:1], d[:, 1:2], d[:, 2:3]
    return C0 * sh[:, :, 0] - C1 * y * sh[:, :, 1] + C1 * z * sh[:, :, 2] - C1 * x * sh[:, :, 3]


def srgb_decode(c):
    c = np.clip(c, 0.0, 1.0)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def srgb_encode8(linear):
    c = np.clip(linear, 0.0, 1.0)
    return np.round(255.0 * np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1.0 / 2.4) - 0.055))


def field_coefficients(p):
    """The SH1 field of sphere_splats at surface points p (N, 3): per channel a DC colour that varies
    over the surface and a band-1 view dependence (coefficient of Y3dgs_1^1, i.e. along x)."""
    n = p.shape[0]
    sh = np.zeros((n, 3, 4))
    display = np.stack([0.55 + 0.2 * p[:, 0], 0.45 + 0.15 * p[:, 1], 0.35 + 0.1 * p[:, 2]], axis=1)
    sh[:, :, 0] = (display - 0.5) / C0
    sh[:, :, 3] = np.array([0.25, -0.15, 0.1])
    return sh


def tangent_quaternions(normals):
    """Quaternions (w x y z) of the shortest rotation taking +z to each normal: the splat's third axis
    (the thin one) along the normal, i.e. splats flat on the surface. Near -z: a half turn about x."""
    q = np.stack([1.0 + normals[:, 2], -normals[:, 1], normals[:, 0], np.zeros(len(normals))], axis=1)
    flip = q[:, 0] < 1e-6
    q[flip] = [0.0, 1.0, 0.0, 0.0]
    return q / np.linalg.norm(q, axis=1, keepdims=True)


def sphere_splats(count=3000, seed=1):
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(count, 3))
    p /= np.linalg.norm(p, axis=1, keepdims=True)
    q = tangent_quaternions(p)
    sh = field_coefficients(p)
    log_scale = np.tile(np.log([0.04, 0.04, 0.004]), (count, 1))
    return p, sh, np.full(count, 2.0), log_scale, q


def expected_mean_colors(points, normals, samples=4000):
    """The vertex colour the transfer must give (docs/gaussian-splats.md): the mean over the vertex's
    hemisphere of the sRGB-decoded display colour of the field at the vertex, seen from w, encoded.
    Directions: a Fibonacci sphere, the half with n.w >= 0."""
    i = np.arange(samples) + 0.5
    z = 1.0 - 2.0 * i / samples
    r = np.sqrt(1.0 - z * z)
    phi = math.pi * (3.0 - math.sqrt(5.0)) * i
    dirs = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
    sh = field_coefficients(points)
    out = np.zeros((points.shape[0], 3))
    for v in range(points.shape[0]):
        w = dirs[dirs @ normals[v] >= 0.0]
        display = eval_sh_band1(np.repeat(sh[v:v + 1], len(w), axis=0), -w) + 0.5
        out[v] = srgb_decode(np.maximum(display, 0.0)).mean(axis=0)
    return srgb_encode8(out)


def write_sphere_mesh(path, stacks=16, slices=32):
    """A UV sphere of radius 1 with its exact normals (ASCII PLY)."""
    vertices = [(0.0, 0.0, 1.0)]
    for i in range(1, stacks):
        t = math.pi * i / stacks
        for j in range(slices):
            ph = 2 * math.pi * j / slices
            vertices.append((math.sin(t) * math.cos(ph), math.sin(t) * math.sin(ph), math.cos(t)))
    vertices.append((0.0, 0.0, -1.0))
    faces = []
    ring = lambda i, j: 1 + (i - 1) * slices + (j % slices)  # noqa: E731
    for j in range(slices):
        faces.append((0, ring(1, j), ring(1, j + 1)))
        faces.append((len(vertices) - 1, ring(stacks - 1, j + 1), ring(stacks - 1, j)))
    for i in range(1, stacks - 1):
        for j in range(slices):
            a, b, c, d = ring(i, j), ring(i, j + 1), ring(i + 1, j), ring(i + 1, j + 1)
            faces += [(a, c, d), (a, d, b)]
    with open(path, "w") as f:
        f.write(f"ply\nformat ascii 1.0\nelement vertex {len(vertices)}\n")
        f.write("property float x\nproperty float y\nproperty float z\n")
        f.write("property float nx\nproperty float ny\nproperty float nz\n")
        f.write(f"element face {len(faces)}\nproperty list uchar int vertex_indices\nend_header\n")
        for v in vertices:
            f.write("{0} {1} {2} {0} {1} {2}\n".format(*v))
        for face in faces:
            f.write("3 {} {} {}\n".format(*face))


def write_scenario(name, path):
    if name == "sphere_mesh":
        write_sphere_mesh(path)
        return
    p, sh, opacity, log_scale, q = sphere_splats()
    if name == "nan":
        sh[17, 1, 2] = float("nan")
    elif name == "degree4":
        sh = np.concatenate([sh, np.zeros((sh.shape[0], 3, 21))], axis=2)
    elif name == "far":
        p = p + 100.0
    elif name != "sphere_splats":
        raise SystemExit(f"unknown scenario {name}")
    write_splats(path, p, sh, opacity, log_scale, q)


if __name__ == "__main__":
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    write_scenario(sys.argv[1], sys.argv[2])
