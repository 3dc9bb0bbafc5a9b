"""Tests of the numpy reader/writer of Radiance PLY files, ``pymeshlab_radiance.rply``
(format: docs/radiance-ply-format.md).

The checks are independent of the code under test: files written by the C++ side (the built tools
``make_radiance_mesh`` and ``evaluate_prt``) are decoded again here with a few lines of ``struct``; the
files the reader must accept or refuse are built byte by byte here; the C++ reader (``radiance_info``)
reads what Python writes; expected counts come from the tools' arguments (midpoint subdivision of an
octahedron: V + E vertices, 4 F faces).

The C++ tools are looked up in ``$RADIANCE_BUILD_DIR/tools`` (default ``<repo>/build/tools``); a missing
tool fails the test (build the project first: scripts/setup.sh, or cmake --build build --target <tool>).
"""

import importlib.util
import math
import os
import re
import shutil
import struct
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest


def _import_rply():
    try:
        from pymeshlab_radiance import rply
        return rply
    except Exception:  # noqa: BLE001 - ImportError, or pymeshlab refusing a plugin
        # The package's __init__ loads our MeshLab plugins into pymeshlab (it needs pymeshlab and
        # working built plugins); the numpy reader/writer needs neither: test the module file itself
        # (an error in rply.py itself is raised again below).
        spec = importlib.util.find_spec("pymeshlab_radiance")
        assert spec is not None and spec.submodule_search_locations, "pymeshlab_radiance not found"
        path = Path(list(spec.submodule_search_locations)[0]) / "rply.py"
        module_spec = importlib.util.spec_from_file_location("pymeshlab_radiance_rply_under_test", path)
        module = importlib.util.module_from_spec(module_spec)
        sys.modules[module_spec.name] = module
        module_spec.loader.exec_module(module)
        return module


rply = _import_rply()
RadianceFileError = rply.RadianceFileError

REPO = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("RADIANCE_BUILD_DIR", REPO / "build"))


def tool(name):
    path = BUILD / "tools" / name
    if not (path.is_file() and os.access(path, os.X_OK)):
        pytest.fail(f"the C++ tool {path} is missing: build the project first (scripts/setup.sh, or "
                    f"'cmake --build {BUILD} --target {name}'), or point RADIANCE_BUILD_DIR at a build folder")
    return str(path)


def run(args):
    return subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, timeout=300)


# ---------------------------------------------------------------------------------------------------
# An independent PLY encoder/decoder (struct only)

_CODES = {"char": "b", "int8": "b", "uchar": "B", "uint8": "B", "short": "h", "int16": "h", "ushort": "H",
          "uint16": "H", "int": "i", "int32": "i", "uint": "I", "uint32": "I", "float": "f", "float32": "f",
          "double": "d", "float64": "d"}


def build_ply(elements, comments=(), fmt="binary_little_endian", eol="\n", extra_lines=(), tail=b""):
    """PLY bytes.  elements: [(name, props, rows)]; a prop is ("float", "x") or
    ("list", "uchar", "int", "vertex_indices"); rows are tuples of values (sequences for lists)."""
    endian = ">" if fmt == "binary_big_endian" else "<"
    head = ["ply", f"format {fmt} 1.0"] + [f"comment {c}" for c in comments] + list(extra_lines)
    body = bytearray()
    for name, props, rows in elements:
        head.append(f"element {name} {len(rows)}")
        head += ["property " + " ".join(p) for p in props]
        for row in rows:
            for p, value in zip(props, row):
                if fmt == "ascii":
                    body += (" ".join(str(x) for x in ([len(value)] + list(value))) if p[0] == "list"
                             else str(value)).encode() + b" "
                elif p[0] == "list":
                    body += struct.pack(endian + _CODES[p[1]], len(value))
                    body += struct.pack(endian + _CODES[p[2]] * len(value), *value)
                else:
                    body += struct.pack(endian + _CODES[p[0]], value)
            if fmt == "ascii":
                body += b"\n"
    head.append("end_header")
    return (eol.join(head) + eol).encode() + bytes(body) + tail


def parse_ply(data):
    """(comments, [(element, count, [property tokens])], vertex rows as dicts, faces) of a binary
    little-endian PLY whose vertex element is scalar and whose faces are 'list uchar int'."""
    end = data.index(b"end_header\n") + len(b"end_header\n")
    comments, elements = [], []
    for line in data[:end].decode().split("\n"):
        t = line.split()
        if t[:1] == ["comment"]:
            comments.append(line[len("comment "):])
        elif t[:1] == ["element"]:
            elements.append((t[1], int(t[2]), []))
        elif t[:1] == ["property"]:
            elements[-1][2].append(t[1:])
    assert [e[0] for e in elements] == ["vertex", "face"]
    (_, n, vprops), (_, nf, fprops) = elements
    assert fprops == [["list", "uchar", "int", "vertex_indices"]]
    fmt = "<" + "".join(_CODES[p[0]] for p in vprops)
    size = struct.calcsize(fmt)
    names = [p[1] for p in vprops]
    vertices = [dict(zip(names, values)) for values in struct.iter_unpack(fmt, data[end:end + n * size])]
    faces = []
    pos = end + n * size
    for _ in range(nf):
        count, a, b, c = struct.unpack_from("<Biii", data, pos)
        assert count == 3
        faces.append((a, b, c))
        pos += 13
    assert pos == len(data)
    return comments, elements, vertices, faces


def vertex_props(names, types=None):
    types = types or {}
    return [(types.get(name, "uchar" if name in ("red", "green", "blue", "alpha") else "float"), name)
            for name in names]


FACE_PROPS = [("list", "uchar", "int", "vertex_indices")]

# A tetrahedron with known unit normals (the vertex directions), frame tangents and PB1 coefficients.
TET_POS = [(1.0, 1.0, 1.0), (1.0, -1.0, -1.0), (-1.0, 1.0, -1.0), (-1.0, -1.0, 1.0)]
TET_FACES = [(0, 1, 2), (0, 3, 1), (0, 2, 3), (1, 3, 2)]
S3 = 1.0 / math.sqrt(3.0)
TET_NRM = [tuple(c * S3 for c in p) for p in TET_POS]


def tet_radiance_rows(order):
    """Vertex rows of the tetrahedron with PB1 radiance (K = 3); value of rf_<c>_<k> at vertex v is
    v + c / 10 + k / 100; rows follow ``order`` (property names)."""
    rows = []
    for v in range(4):
        values = {"x": TET_POS[v][0], "y": TET_POS[v][1], "z": TET_POS[v][2],
                  "nx": TET_NRM[v][0], "ny": TET_NRM[v][1], "nz": TET_NRM[v][2],
                  "rf_tx": 1.0, "rf_ty": 0.0, "rf_tz": 0.0}
        for c, ch in enumerate("rgb"):
            for k in range(3):
                values[f"rf_{ch}_{k}"] = v + c / 10 + k / 100
        rows.append(values)
    return [tuple(r[name] for name in order) for r in rows]


RADIANCE_COMMENTS = ["radiance_format_version 1", "radiance_basis PB1", "radiance_reflected 0"]
PB1_NAMES = (["x", "y", "z", "nx", "ny", "nz", "rf_tx", "rf_ty", "rf_tz"]
             + [f"rf_{c}_{k}" for c in "rgb" for k in range(3)])


def tet_radiance_file(order=PB1_NAMES, comments=RADIANCE_COMMENTS, faces=TET_FACES, **kwargs):
    return build_ply([("vertex", vertex_props(order), tet_radiance_rows(order)),
                      ("face", FACE_PROPS, [(f,) for f in faces])], comments=comments, **kwargs)


def assert_tet_radiance(mesh):
    assert mesh.basis == "PB1" and mesh.coefficient_count == 3 and mesh.vertex_count == 4
    np.testing.assert_array_equal(mesh.positions, np.array(TET_POS, np.float32))
    np.testing.assert_array_equal(mesh.normals, np.array(TET_NRM, np.float32))
    np.testing.assert_array_equal(mesh.faces, np.array(TET_FACES, np.int32))
    expected = np.array([[[v + c / 10 + k / 100 for k in range(3)] for c in range(3)] for v in range(4)], np.float32)
    np.testing.assert_array_equal(mesh.coefficients, expected)
    np.testing.assert_array_equal(mesh.tangents, np.tile(np.array([1, 0, 0], np.float32), (4, 1)))


# ---------------------------------------------------------------------------------------------------
# Files written by the C++ side

OCTAHEDRON_POS = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
OCTAHEDRON_FACES = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]


@pytest.fixture(scope="module")
def cpp_files(tmp_path_factory):
    """Files written by the C++ writer: PB2 (octahedron subdivided once), SH3 reflected (twice), and
    the PRT transfer block of evaluate_prt (SH order 2: width 4)."""
    folder = tmp_path_factory.mktemp("cpp")
    off = folder / "octahedron.off"
    off.write_text("OFF\n6 8 0\n" + "".join(f"{x} {y} {z}\n" for x, y, z in OCTAHEDRON_POS)
                   + "".join(f"3 {a} {b} {c}\n" for a, b, c in OCTAHEDRON_FACES))
    make = tool("make_radiance_mesh")
    files = {}
    for key, args in (("pb2", ["--basis", "PB2", "--subdivide", "1"]),
                      ("sh3", ["--basis", "SH3", "--reflected", "--subdivide", "2"])):
        out = folder / f"{key}.rply"
        r = run([make, str(off), "-o", str(out), "--no-shadows"] + args)
        assert r.returncode == 0, r.stderr
        files[key] = out
    r = run([tool("evaluate_prt"), "--levels", "1", "--rays", "16", "--samples", "1000", "--lights", "2",
             "--order", "2", "--size", "32x24", "--out", str(folder / "prt")])
    assert r.returncode == 0, r.stderr
    files["prt"] = folder / "prt" / "adaptive.rply"
    return files


def octahedron_subdivided_once():
    """Original vertices and edge midpoints: V + E = 18 positions, 4 F = 32 faces."""
    edges = {tuple(sorted((f[i], f[(i + 1) % 3]))) for f in OCTAHEDRON_FACES for i in range(3)}
    mids = [tuple((OCTAHEDRON_POS[a][i] + OCTAHEDRON_POS[b][i]) / 2 for i in range(3)) for a, b in edges]
    return OCTAHEDRON_POS + mids, 4 * len(OCTAHEDRON_FACES)


def test_cpp_pb2_file_read_by_python(cpp_files):
    data = cpp_files["pb2"].read_bytes()
    comments, elements, vertices, faces = parse_ply(data)
    mesh = rply.read_rply(cpp_files["pb2"])

    positions, face_count = octahedron_subdivided_once()
    assert mesh.vertex_count == len(positions) == 18 and mesh.face_count == face_count == 32
    assert sorted(map(tuple, mesh.positions.tolist())) == sorted(tuple(float(c) for c in p) for p in positions)
    assert mesh.basis == "PB2" and mesh.reflected is False and mesh.coefficient_count == 6
    assert mesh.coefficients.shape == (18, 3, 6) and mesh.coefficients.dtype == np.float32
    assert mesh.faces.dtype == np.int32 and mesh.positions.dtype == np.float32
    # On the symmetric octahedron the (area-weighted, then interpolated) normals point away from the centre.
    unit = mesh.positions / np.linalg.norm(mesh.positions, axis=1, keepdims=True)
    np.testing.assert_allclose(mesh.normals, unit, atol=1e-5)
    np.testing.assert_allclose(np.linalg.norm(mesh.tangents, axis=1), 1.0, atol=1e-5)
    np.testing.assert_allclose(np.sum(mesh.tangents * mesh.normals, axis=1), 0.0, atol=1e-5)
    assert mesh.colors.shape == (18, 4) and np.all(mesh.colors[:, 3] == 255)
    assert mesh.quality is None and mesh.blocks == {}

    # Every value against the struct decoding.
    assert "radiance_basis PB2" in comments and "radiance_reflected 0" in comments
    for v, row in enumerate(vertices):
        assert mesh.positions[v].tolist() == [row["x"], row["y"], row["z"]]
        assert mesh.normals[v].tolist() == [row["nx"], row["ny"], row["nz"]]
        assert mesh.tangents[v].tolist() == [row["rf_tx"], row["rf_ty"], row["rf_tz"]]
        assert mesh.colors[v].tolist() == [row["red"], row["green"], row["blue"], row["alpha"]]
        for c, ch in enumerate("rgb"):
            assert mesh.coefficients[v, c].tolist() == [row[f"rf_{ch}_{k}"] for k in range(6)]
    assert mesh.faces.tolist() == [list(f) for f in faces]


def test_cpp_files_written_back_byte_identical(cpp_files, tmp_path):
    for key, path in cpp_files.items():
        mesh = rply.read_rply(path)
        out = tmp_path / f"{key}_python.rply"
        rply.write_rply(out, mesh)
        assert out.read_bytes() == path.read_bytes(), key
    sh = rply.read_rply(cpp_files["sh3"])
    assert sh.basis == "SH3" and sh.reflected is True and sh.coefficients.shape == (66, 3, 16)
    assert (sh.vertex_count, sh.face_count) == (18 + 48, 128)  # second subdivision: V + E, 4 F


def test_cpp_prt_block_read_by_python(cpp_files):
    data = cpp_files["prt"].read_bytes()
    comments, elements, vertices, _ = parse_ply(data)
    mesh = rply.read_rply(cpp_files["prt"])
    assert mesh.basis is None and mesh.coefficients is None and mesh.normals is not None
    assert list(mesh.blocks) == ["prt"]
    block = mesh.blocks["prt"]
    assert block.values.shape == (elements[0][1], 4) and block.width == 4  # SH order 2: 4 coefficients
    assert block.meta == {"kind": "sh_transfer_shadowed_diffuse", "sh_degree": "1", "channels": "1", "rays": "16"}
    assert block.values[:, 2].tolist() == [row["prt_2"] for row in vertices]
    # The writer's order: block, then its metadata sorted by key.
    assert comments[1:6] == ["block prt width 4", "block_meta prt channels 1",
                             "block_meta prt kind sh_transfer_shadowed_diffuse", "block_meta prt rays 16",
                             "block_meta prt sh_degree 1"]


# ---------------------------------------------------------------------------------------------------
# Hand-built meshes: round trips, and the C++ reader on Python's files


def unit_rows(rng, n):
    v = rng.normal(size=(n, 3))
    return (v / np.linalg.norm(v, axis=1, keepdims=True)).astype(np.float32)


def grid_mesh(n_side=5):
    ij = np.array([(i, j) for j in range(n_side) for i in range(n_side)], np.float32)
    positions = np.column_stack([ij, np.zeros(len(ij), np.float32)]).astype(np.float32)
    faces = []
    for j in range(n_side - 1):
        for i in range(n_side - 1):
            a = j * n_side + i
            faces += [(a, a + 1, a + n_side), (a + 1, a + n_side + 1, a + n_side)]
    return positions, np.array(faces, np.int32)


def make_case(name):
    rng = np.random.default_rng(7)
    positions, faces = grid_mesh()
    n = len(positions)
    if name == "geometry":
        return rply.RadianceMesh(positions=positions, faces=faces)
    if name == "colours_quality":
        quality = rng.random(n).astype(np.float32)
        quality[3] = np.uint32(0x7FC00123).view(np.float32)  # a NaN with a payload: user data, kept bitwise
        quality[4] = -0.0
        return rply.RadianceMesh(positions=positions, faces=faces, normals=unit_rows(rng, n),
                                 colors=rng.integers(0, 256, (n, 4)).astype(np.uint8), quality=quality)
    if name == "blocks_meta":
        values = rng.random((n, 3)).astype(np.float32)
        values[0, 0] = np.float32(1e-45)  # denormal
        return rply.RadianceMesh(positions=positions, faces=faces, blocks={
            "prt": rply.Block(values, {"kind": "a value with spaces", "zeta": "", "alpha": " leading blank",
                                       "Beta": "é ünïcode"}),
            "aux_2": rply.Block(rng.random((n, 1)).astype(np.float32), {})})
    if name == "sh_reflected":
        return rply.RadianceMesh(positions=positions, faces=faces, normals=unit_rows(rng, n), basis="SH2",
                                 reflected=True, tangents=unit_rows(rng, n),
                                 coefficients=rng.normal(size=(n, 3, 9)).astype(np.float32),
                                 colors=rng.integers(0, 256, (n, 4)).astype(np.uint8),
                                 quality=rng.random(n).astype(np.float32),
                                 blocks={"prt": rply.Block(rng.random((n, 2)).astype(np.float32), {"k": "v w"})})
    if name == "empty_radiance":
        return rply.RadianceMesh(positions=np.zeros((0, 3), np.float32), normals=np.zeros((0, 3), np.float32),
                                 basis="PB1", tangents=np.zeros((0, 3), np.float32),
                                 coefficients=np.zeros((0, 3, 3), np.float32),
                                 blocks={"b": rply.Block(np.zeros((0, 2), np.float32), {"k": "v"})})
    if name == "pb0_no_faces":
        return rply.RadianceMesh(positions=positions, normals=unit_rows(rng, n), basis="PB0",
                                 tangents=unit_rows(rng, n), coefficients=rng.random((n, 3, 1)).astype(np.float32))
    raise KeyError(name)


CASES = ["geometry", "colours_quality", "blocks_meta", "sh_reflected", "pb0_no_faces", "empty_radiance"]


def bits(a):
    return None if a is None else np.ascontiguousarray(a).view(np.uint8).tobytes()


@pytest.mark.parametrize("name", CASES)
def test_round_trip(name, tmp_path):
    mesh = make_case(name)
    path = tmp_path / f"{name}.rply"
    rply.write_rply(path, mesh)
    data = path.read_bytes()
    back = rply.read_rply(path)
    for attr in ("positions", "faces", "normals", "colors", "quality", "tangents", "coefficients"):
        assert bits(getattr(back, attr)) == bits(getattr(mesh, attr)), attr
    assert back.basis == mesh.basis and back.reflected == mesh.reflected
    assert list(back.blocks) == list(mesh.blocks)
    for prefix, block in mesh.blocks.items():
        assert bits(back.blocks[prefix].values) == bits(block.values)
        assert back.blocks[prefix].meta == block.meta
    # The record size of the specification: 12 + 12 [normals or radiance] + 4 [colors] + 4 [quality]
    # + (12 + 12 K) [radiance] + 4 sum(widths); faces 13 bytes.
    n, f = len(mesh.positions), len(mesh.faces)
    K = mesh.coefficients.shape[2] if mesh.coefficients is not None else 0
    record = (12 + 12 * (mesh.normals is not None) + 4 * (mesh.colors is not None) + 4 * (mesh.quality is not None)
              + (12 + 12 * K) * (mesh.basis is not None) + 4 * sum(b.values.shape[1] for b in mesh.blocks.values()))
    header_end = data.index(b"end_header\n") + len(b"end_header\n")
    assert len(data) == header_end + n * record + 13 * f
    # Writing again gives the same bytes; no temporary file is left.
    rply.write_rply(tmp_path / "again.rply", back)
    assert (tmp_path / "again.rply").read_bytes() == data
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted([f"{name}.rply", "again.rply"])


def test_written_header_lines(tmp_path):
    path = tmp_path / "m.rply"
    rply.write_rply(path, make_case("blocks_meta"))
    head = path.read_bytes().split(b"end_header\n")[0].decode("utf-8").split("\n")
    assert head[:13] == [
        "ply", "format binary_little_endian 1.0", "comment radiance_format_version 1",
        "comment block prt width 3",
        "comment block_meta prt Beta é ünïcode",          # sorted by key, bytewise: 'B' < 'a' < 'k' < 'z'
        "comment block_meta prt alpha  leading blank",
        "comment block_meta prt kind a value with spaces",
        "comment block_meta prt zeta",                     # empty value: no trailing blank
        "comment block aux_2 width 1",
        "element vertex 25", "property float x", "property float y", "property float z"]
    assert head[13:] == ["property float prt_0", "property float prt_1", "property float prt_2",
                         "property float aux_2_0", "element face 32", "property list uchar int vertex_indices", ""]


def parse_radiance_info(text):
    m = re.match(r".*: (\d+) vertices, (\d+) triangles((?:, \w+)*)\n", text)
    assert m, text
    return int(m.group(1)), int(m.group(2)), m.group(3)


@pytest.mark.parametrize("name", CASES)
def test_python_file_read_by_cpp(name, tmp_path):
    mesh = make_case(name)
    path = tmp_path / f"{name}.rply"
    rply.write_rply(path, mesh)
    r = run([tool("radiance_info"), str(path)])
    assert r.returncode == 0, r.stderr
    n, f, extras = parse_radiance_info(r.stdout)
    assert (n, f) == (len(mesh.positions), len(mesh.faces))
    expected_extras = "".join(s for s, a in ((", normals", mesh.normals), (", colours", mesh.colors),
                                             (", quality", mesh.quality)) if a is not None)
    assert extras == (expected_extras if len(mesh.positions) else "")  # (empty arrays print nothing)
    if mesh.basis is None:
        assert "no radiance data" in r.stdout
    else:
        K = mesh.coefficients.shape[2]
        assert (f"radiance {mesh.basis}{' (reflected)' if mesh.reflected else ''}: {3 * K} coefficients per "
                f"vertex ({K} per channel)") in r.stdout
        lo, hi = re.search(r"coefficient range \[(\S+), (\S+)\]", r.stdout).groups()
        if mesh.coefficients.size:
            assert float(lo) == pytest.approx(float(mesh.coefficients.min()), rel=1e-5)
            assert float(hi) == pytest.approx(float(mesh.coefficients.max()), rel=1e-5)
    # The extra blocks, with or without radiance.
    for prefix, block in mesh.blocks.items():
        assert f"extra block {prefix}: {block.values.shape[1]} floats per vertex" in r.stdout


def test_large_file_reads_quickly(tmp_path):
    """300,000 vertices of PB4 (65 MB): a vectorised reader takes a fraction of a second; a loop over
    vertices in Python takes many seconds."""
    rng = np.random.default_rng(3)
    n = 300_000
    mesh = rply.RadianceMesh(positions=rng.random((n, 3), dtype=np.float32),
                             faces=rng.integers(0, n, (2 * n, 3)).astype(np.int32),
                             normals=unit_rows(rng, n), basis="PB4", tangents=unit_rows(rng, n),
                             coefficients=rng.random((n, 3, 15), dtype=np.float32))
    path = tmp_path / "large.rply"
    rply.write_rply(path, mesh)
    assert path.stat().st_size > 216 * n
    start = time.perf_counter()
    back = rply.read_rply(path)
    seconds = time.perf_counter() - start
    assert bits(back.coefficients) == bits(mesh.coefficients) and bits(back.faces) == bits(mesh.faces)
    assert seconds < 3.0, f"reading {n} PB4 vertices took {seconds:.2f} s"


# ---------------------------------------------------------------------------------------------------
# Reader tolerance (specification, "Accepted beyond what the writer produces")


def read_bytes(tmp_path, data, name="f.ply"):
    path = tmp_path / name
    path.write_bytes(data)
    return rply.read_rply(path)


def test_reader_accepts_reordered_properties(tmp_path):
    order = list(reversed(PB1_NAMES[6:])) + ["nz", "x", "ny", "z", "nx", "y"]
    assert_tet_radiance(read_bytes(tmp_path, tet_radiance_file(order=order)))


def test_reader_skips_unknown_scalar_vertex_properties(tmp_path):
    order = ["confidence"] + PB1_NAMES[:3] + ["flags"] + PB1_NAMES[3:]
    types = {"confidence": "double", "flags": "short"}
    rows = [(0.25,) + r[:3] + (-7,) + r[3:] for r in tet_radiance_rows(PB1_NAMES)]
    data = build_ply([("vertex", vertex_props(order, types), rows), ("face", FACE_PROPS, [(f,) for f in TET_FACES])],
                     comments=RADIANCE_COMMENTS)
    mesh = read_bytes(tmp_path, data)
    assert_tet_radiance(mesh)
    # Nothing is dropped silently: the reader says what it did not load.
    assert len(mesh.skipped) == 1
    assert mesh.skipped[0].startswith("vertex properties 'confidence', 'flags' of the file are not part of the "
                                      "radiance PLY format and were not loaded"), mesh.skipped


def test_reader_skips_extra_elements(tmp_path):
    material = ("material", [("float", "shininess"), ("uchar", "id"), ("double", "ior")],
                [(1.5, 2, 1.33), (3.0, 4, 1.5)])
    edge = ("edge", [("int", "vertex1"), ("int", "vertex2")], [(0, 1), (1, 2), (2, 3)])
    data = build_ply([material, ("vertex", vertex_props(PB1_NAMES), tet_radiance_rows(PB1_NAMES)),
                      ("face", FACE_PROPS, [(f,) for f in TET_FACES]), edge], comments=RADIANCE_COMMENTS)
    mesh = read_bytes(tmp_path, data)
    assert_tet_radiance(mesh)
    assert [s.split(" is not part")[0] for s in mesh.skipped] == ["element 'material' (2 records)",
                                                                  "element 'edge' (3 records)"]


def test_reader_accepts_colours_without_alpha(tmp_path):
    names = ["x", "y", "z", "red", "green", "blue"]
    rows = [p + (10 * v, 20 * v, 30 * v) for v, p in enumerate(TET_POS)]
    data = build_ply([("vertex", vertex_props(names), rows), ("face", FACE_PROPS, [(f,) for f in TET_FACES])])
    mesh = read_bytes(tmp_path, data)
    assert mesh.colors.tolist() == [[10 * v, 20 * v, 30 * v, 255] for v in range(4)]
    assert mesh.basis is None and mesh.normals is None


def test_reader_accepts_crlf_obj_info_aliases_and_face_variants(tmp_path):
    """\\r\\n header, obj_info and blank lines, type aliases, 'vertex_index' with uint indices and an
    int length, extra face properties (a scalar and MeshLab's texcoord list), no radiance comments."""
    names = ["x", "y", "z"]
    vprops = [("float32", n) for n in names] + [("uint8", "red"), ("uint8", "green"), ("uint8", "blue"),
                                                ("uint8", "alpha")]
    rows = [p + (1, 2, 3, 4) for p in TET_POS]
    fprops = [("uchar", "flags"), ("list", "int", "uint", "vertex_index"), ("list", "uchar", "float", "texcoord")]
    frows = [(9, f, [0.5] * 6) for f in TET_FACES]
    data = build_ply([("vertex", vprops, rows), ("face", fprops, frows)], eol="\r\n",
                     extra_lines=["obj_info made by hand", ""], comments=["a foreign comment"])
    mesh = read_bytes(tmp_path, data)
    np.testing.assert_array_equal(mesh.positions, np.array(TET_POS, np.float32))
    assert mesh.faces.tolist() == [list(f) for f in TET_FACES]
    assert mesh.colors.tolist() == [[1, 2, 3, 4]] * 4


def test_reader_accepts_plain_ply_and_unknown_comments(tmp_path):
    data = build_ply([("vertex", vertex_props(["x", "y", "z"]), TET_POS),
                      ("face", FACE_PROPS, [(f,) for f in TET_FACES])],
                     comments=["block prt width 3", "radiance_future_key 5"])  # foreign without the version
    mesh = read_bytes(tmp_path, data)
    assert mesh.vertex_count == 4 and mesh.face_count == 4 and mesh.blocks == {} and mesh.basis is None


# ---------------------------------------------------------------------------------------------------
# Refusals (specification, "Refused with RadianceFileError"); the C++ reader refuses the same files


def tet_plain(faces=TET_FACES, **kwargs):
    return build_ply([("vertex", vertex_props(["x", "y", "z"]), TET_POS), ("face", FACE_PROPS, [(f,) for f in faces])],
                     **kwargs)


def without_radiance_comments(data):
    head, body = data.split(b"end_header\n", 1)
    lines = [line for line in head.split(b"\n") if not line.startswith(b"comment radiance_")]
    return b"\n".join(lines) + b"end_header\n" + body


BAD_FILES = {
    "empty": (lambda c: b"", "not a PLY file"),
    "ascii": (lambda c: tet_plain(fmt="ascii"), "ASCII format"),
    "big_endian": (lambda c: tet_plain(fmt="binary_big_endian"), "binary big endian"),
    "truncated": (lambda c: c["pb2"].read_bytes()[:-7], "file truncated"),
    "truncated_vertices": (lambda c: c["pb2"].read_bytes()[:1500], "bytes of vertex data"),
    "truncated_header": (lambda c: c["pb2"].read_bytes()[:200], "truncated inside its header"),
    "trailing_bytes": (lambda c: c["pb2"].read_bytes() + b"\0", "unexpected data after the last element"),
    "rf_without_basis": (lambda c: without_radiance_comments(c["pb2"].read_bytes()), "no radiance_basis comment"),
    "basis_without_version": (lambda c: tet_radiance_file(comments=RADIANCE_COMMENTS[1:]),
                              "without comment radiance_format_version"),
    "newer_version": (lambda c: tet_radiance_file(comments=["radiance_format_version 2"] + RADIANCE_COMMENTS[1:]),
                      "newer version"),
    "unknown_basis": (lambda c: tet_radiance_file(comments=["radiance_format_version 1", "radiance_basis XY3",
                                                            "radiance_reflected 0"]), "unknown radiance basis"),
    "wrong_basis": (lambda c: tet_radiance_file(comments=["radiance_format_version 1", "radiance_basis PB2",
                                                          "radiance_reflected 0"]), "missing radiance coefficient"),
    "missing_x": (lambda c: build_ply([("vertex", vertex_props(["y", "z"]), [p[1:] for p in TET_POS])]),
                  "missing vertex property 'x'"),
    "face_index_out_of_range": (lambda c: tet_plain(faces=TET_FACES[:3] + [(1, 4, 2)]), "vertex index out of range"),
    "negative_face_index": (lambda c: tet_plain(faces=[(0, -1, 2)]), "negative vertex index"),
    "quad": (lambda c: tet_plain(faces=[(0, 1, 2, 3)]), "only triangle meshes are supported"),
    "nan_position": (lambda c: build_ply([("vertex", vertex_props(["x", "y", "z"]), [(0.0, float("nan"), 0.0)])]),
                     "not a finite number"),
    "non_unit_normal": (lambda c: build_ply([("vertex", vertex_props(PB1_NAMES[:6] + PB1_NAMES[6:]),
                                              [tuple(2.0 if i == 3 else x for i, x in enumerate(r))
                                               for r in tet_radiance_rows(PB1_NAMES)])],
                                            comments=RADIANCE_COMMENTS), "not unit length"),
    "undeclared_block_meta": (lambda c: tet_plain(comments=["radiance_format_version 1", "block_meta prt kind x"]),
                              "block_meta for undeclared block"),
    "reserved_block_prefix": (lambda c: tet_plain(comments=["radiance_format_version 1", "block rf_x width 1"]),
                              "invalid block prefix"),
    "missing_block_property": (lambda c: build_ply(
        [("vertex", vertex_props(["x", "y", "z", "aux_0"]), [p + (1.0,) for p in TET_POS])],
        comments=["radiance_format_version 1", "block aux width 2"]), "missing vertex property 'aux_1' of block"),
    "double_position": (lambda c: build_ply([("vertex", [("double", "x"), ("float", "y"), ("float", "z")], TET_POS)]),
                        "is double but must be float"),
    "list_element": (lambda c: build_ply([("vertex", vertex_props(["x", "y", "z"]), TET_POS),
                                          ("edges", [("list", "uchar", "int", "v")], [([0, 1],)])]),
                     "has list properties"),
    # Hostile input: refused by both readers with the same sentence.
    "empty_list_element": (lambda c: build_ply([("vertex", vertex_props(["x", "y", "z"]), TET_POS),
                                                ("edges", [("list", "uchar", "int", "v")], [])]),
                           "element 'edges' has list properties"),
    "block_meta_value_with_tab": (lambda c: block_file("block_meta aux note a\tb"),
                                  "header line 5: the value of block_meta 'note' of block 'aux' contains a control "
                                  "character ('a\\x09b')"),
    "block_meta_value_with_cr": (lambda c: block_file("block_meta aux note a\rb"),
                                 "the value of block_meta 'note' of block 'aux' contains a control character"),
    "block_meta_key_with_control": (lambda c: block_file("block_meta aux k\x01 v"),
                                    "block_meta key 'k\\x01' of block 'aux' contains a control character"),
    "vertex_count_beyond_the_file": (lambda c: tet_plain().replace(b"element vertex 4", b"element vertex 1000000"),
                                     "expected 12000000 bytes of vertex data, found 100: the header declares 1000000 "
                                     "vertices of 12 bytes each"),
}


def block_file(meta_comment):
    """The tetrahedron with a one-float block 'aux' and the given block_meta comment (header line 5)."""
    return build_ply([("vertex", vertex_props(["x", "y", "z", "aux_0"]), [p + (1.0,) for p in TET_POS])],
                     comments=["radiance_format_version 1", "block aux width 1", meta_comment])


@pytest.mark.parametrize("name", sorted(BAD_FILES))
def test_reader_refuses(name, cpp_files, tmp_path):
    make, phrase = BAD_FILES[name]
    path = tmp_path / f"{name}.rply"
    path.write_bytes(make(cpp_files))
    with pytest.raises(RadianceFileError) as error:
        rply.read_rply(path)
    message = str(error.value)
    assert message.startswith(f"cannot load '{path}': ") and phrase in message, message
    assert isinstance(error.value, ValueError)
    # The C++ reader refuses the same file with the same phrase.
    r = run([tool("radiance_info"), str(path)])
    assert r.returncode == 1 and phrase in r.stderr, r.stderr


def test_reader_truncation_after_variable_size_faces(tmp_path):
    """Faces with extra lists are larger than the smallest face record the size check assumes: an
    element after them that the file does not hold completely is reported as truncated."""
    fprops = FACE_PROPS + [("list", "uchar", "float", "texcoord")]
    frows = [(f, [0.5] * 6) for f in TET_FACES]
    vertex = ("vertex", vertex_props(["x", "y", "z"]), TET_POS)
    edge = ("edge", [("int", "a")], [(1,)])
    cases = {"edge_after_faces": (build_ply([vertex, ("face", fprops, frows), edge])[:-3],
                                  "expected 4 bytes of data for element 'edge', found 1"),
             "vertices_after_faces": (build_ply([("face", fprops, frows), vertex])[:-20],
                                      "expected 48 bytes of vertex data, found 28")}
    for name, (data, phrase) in cases.items():
        path = tmp_path / f"{name}.ply"
        path.write_bytes(data)
        with pytest.raises(RadianceFileError, match="file truncated") as error:
            rply.read_rply(path)
        assert phrase in str(error.value)
        r = run([tool("radiance_info"), str(path)])
        assert r.returncode == 1 and phrase in r.stderr, r.stderr  # the same sentence there too


def test_refusal_messages_say_how_to_fix(tmp_path):
    path = tmp_path / "ascii.ply"
    path.write_bytes(tet_plain(fmt="ascii"))
    with pytest.raises(RadianceFileError, match="Binary encoding"):
        rply.read_rply(path)
    path.write_bytes(tet_plain(faces=[(0, 1, 2, 3)]))
    with pytest.raises(RadianceFileError, match="triangulate the mesh"):
        rply.read_rply(path)
    with pytest.raises(RadianceFileError, match="cannot open the file"):
        rply.read_rply(tmp_path / "missing.rply")


def bad_writes():
    def edit(name, **changes):
        mesh = make_case(name)
        for key, value in changes.items():
            setattr(mesh, key, value)
        return mesh

    positions, faces = grid_mesh()
    nan_positions = positions.copy()
    nan_positions[6, 1] = np.nan
    bad_faces = faces.copy()
    bad_faces[5, 2] = len(positions)
    rng = np.random.default_rng(1)
    return {
        "nan_position": (edit("geometry", positions=nan_positions), "vertex 6 has a position that is not a finite"),
        "face_out_of_range": (edit("geometry", faces=bad_faces), "face 5 references vertex 25"),
        "non_unit_normals": (edit("sh_reflected", normals=2 * make_case("sh_reflected").normals), "not unit length"),
        "wrong_coefficient_shape": (edit("sh_reflected", basis="SH3"), "coefficients has shape"),
        "coefficients_without_basis": (edit("sh_reflected", basis=None), "basis is None"),
        "radiance_without_normals": (edit("sh_reflected", normals=None), "needs the per-vertex frame normals"),
        "reserved_prefix": (edit("geometry", blocks={"rf_x": rply.Block(np.zeros((25, 1), np.float32))}), "reserved"),
        "bad_prefix": (edit("geometry", blocks={"2d": rply.Block(np.zeros((25, 1), np.float32))}),
                       "not an identifier"),
        "meta_line_break": (edit("geometry", blocks={"a": rply.Block(np.zeros((25, 1), np.float32), {"k": "x\ny"})}),
                            "control character"),
        "meta_key_blank": (edit("geometry", blocks={"a": rply.Block(np.zeros((25, 1), np.float32), {"k k": "v"})}),
                           "contains whitespace"),
        "block_rows": (edit("geometry", blocks={"a": rply.Block(np.zeros((24, 1), np.float32))}),
                       "expected (25, width)"),
        "colour_floats": (edit("geometry", colors=rng.random((25, 4))), "expected uint8"),
        "unknown_basis": (edit("sh_reflected", basis="PB9"), "unknown radiance basis"),
    }


@pytest.mark.parametrize("name", sorted(bad_writes()))
def test_writer_refuses_and_keeps_existing_file(name, tmp_path):
    mesh, phrase = bad_writes()[name]
    target = tmp_path / "existing.rply"
    target.write_bytes(b"previous content")
    with pytest.raises(RadianceFileError) as error:
        rply.write_rply(target, mesh)
    message = str(error.value)
    assert message.startswith(f"cannot save '{target}': ") and phrase in message, message
    assert target.read_bytes() == b"previous content"
    assert [p.name for p in tmp_path.iterdir()] == ["existing.rply"]  # no temporary file left


def test_writer_failure_in_missing_folder(tmp_path):
    with pytest.raises(RadianceFileError, match="check that the folder exists"):
        rply.write_rply(tmp_path / "no" / "such" / "folder.rply", make_case("geometry"))


def test_write_replaces_atomically(tmp_path, cpp_files):
    target = tmp_path / "t.rply"
    shutil.copy(cpp_files["pb2"], target)
    rply.write_rply(target, make_case("geometry"))
    assert rply.read_rply(target).basis is None
    assert [p.name for p in tmp_path.iterdir()] == ["t.rply"]


# ---------------------------------------------------------------------------------------------------
# Hostile input: memory, extra blocks, stale temporary files


def test_sparse_file_refused_without_allocating_its_size(tmp_path):
    """512 MiB of zeros behind a plausible PB1 header (a sparse file: no disk used).  Reading it whole
    would touch 512 MiB of arrays; refused after the first chunk it touches a few MiB.  Measured in a
    fresh interpreter (ru_maxrss is a high-water mark)."""
    rec = 4 * len(PB1_NAMES)  # 72 bytes
    n = (512 << 20) // rec
    results = {}
    for faces in (0, 1_000_000):
        head = build_ply([("vertex", vertex_props(PB1_NAMES), []), ("face", FACE_PROPS, [])],
                         comments=RADIANCE_COMMENTS)
        head = head.replace(b"element vertex 0", f"element vertex {n}".encode())
        head = head.replace(b"element face 0", f"element face {faces}".encode())
        path = tmp_path / f"sparse_{faces}.rply"
        with open(path, "wb") as f:
            f.write(head)
            f.truncate(len(head) + rec * n + 13 * faces)
        code = (
            "import importlib.util, resource, sys\n"
            f"spec = importlib.util.spec_from_file_location('rply_under_test', {str(rply.__file__)!r})\n"
            "m = importlib.util.module_from_spec(spec); sys.modules['rply_under_test'] = m; spec.loader.exec_module(m)\n"
            "before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
            "try:\n"
            f"    m.read_rply({str(path)!r}); print('LOADED')\n"
            "except m.RadianceFileError as e:\n"
            "    print(e)\n"
            "print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before)\n")
        r = run([sys.executable, "-c", code])
        assert r.returncode == 0, r.stderr
        message, grown_kb = r.stdout.strip().rsplit("\n", 1)
        results[faces] = message
        assert int(grown_kb) < 64 * 1024, (faces, grown_kb)
    assert "normal of vertex 0 is not unit length" in results[0], results[0]
    assert "face 0 has 0 vertices" in results[1_000_000], results[1_000_000]


def test_extra_blocks_other_than_prt_kept_byte_identical_with_cpp(tmp_path):
    """A block the plugins do not interpret survives Python -> C++ (radiance_info lists it with its
    metadata) and Python -> Python byte for byte."""
    positions, faces = grid_mesh()
    n = len(positions)
    mesh = rply.RadianceMesh(positions=positions, faces=faces)
    mesh.blocks["curvature"] = rply.Block(np.arange(2 * n, dtype=np.float32).reshape(n, 2) / 8,
                                          {"unit": "1/m", "note": "principal  curvatures"})
    a = tmp_path / "a.rply"
    rply.write_rply(a, mesh)
    r = run([tool("radiance_info"), str(a)])
    assert r.returncode == 0, r.stderr
    assert "extra block curvature: 2 floats per vertex, note=principal  curvatures, unit=1/m" in r.stdout
    back = rply.read_rply(a)
    np.testing.assert_array_equal(back.blocks["curvature"].values, mesh.blocks["curvature"].values)
    b = tmp_path / "b.rply"
    rply.write_rply(b, back)
    assert a.read_bytes() == b.read_bytes()


def test_writer_removes_stale_temporaries_of_dead_writers_only(tmp_path):
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()  # reaped: its pid names no process
    target = tmp_path / "t.rply"
    stale = tmp_path / f"t.rply.part-{child.pid}-0-99"
    live = tmp_path / f"t.rply.part-{os.getppid()}-1-5"  # our parent runs
    unrelated = [tmp_path / "t.rply.part-notes", tmp_path / f"u.rply.part-{child.pid}-0-1"]
    for p in [stale, live] + unrelated:
        p.write_bytes(b"x" * 1000)
    rply.write_rply(target, make_case("geometry"))
    assert not stale.exists()
    assert live.exists() and all(p.exists() for p in unrelated)
    assert rply.read_rply(target).vertex_count == len(make_case("geometry").positions)


@pytest.mark.parametrize("path", sorted((REPO / "tests" / "unit" / "data" / "rply_fuzz_regressions").glob("*.rply")),
                         ids=lambda p: p.stem)
def test_fuzz_regressions_refused(path):
    """Inputs the libFuzzer harness found on the C++ reader before issue 16 (block metadata with
    control characters, accepted then but unsaveable): the numpy reader refuses them too."""
    with pytest.raises(RadianceFileError, match=r": header line \d+: .*contains a control character"):
        rply.read_rply(path)
