"""Bad input through pymeshlab 2025.7, mirroring tests/integration/test_filter_refusals.sh and
test_bad_files.sh: a pymeshlab.PyMeshLabException whose text is our explanation (what is wrong and
how to fix it), the MeshSet unchanged afterwards (mesh count, current layer, vertex matrix, faces,
colours; the radiance too, through a byte comparison of the saved .rply), the MeshSet still usable,
and the Python process alive (checked in a separate process, so that a crash cannot take the test
session with it).

The bad files are made here from a valid file written through pymeshlab: cut in half, cut inside the
header, empty, random bytes, a NaN coefficient put in by byte surgery (offsets from the header, in
Python), an ASCII variant of the header.
"""
import os
import struct
import textwrap

import numpy as np
import pymeshlab
import pytest

import pymeshlab_radiance  # noqa: F401  (loads our plugins into pymeshlab)
import pymeshlab_test_helpers as h

SH = 1


@pytest.fixture(scope="module")
def good_file(scenes, tmp_path_factory):
    ms = h.load(scenes("sphere", level=2))
    ms.apply_filter(h.CREATE, degree=4)
    path = tmp_path_factory.mktemp("refusals") / "good.rply"
    ms.save_current_mesh(str(path))
    return path


def vertex_layout(data):
    """(end of header, record size, offset of rf_r_0) of a binary .rply, from its header text."""
    end = data.index(b"end_header\n") + len(b"end_header\n")
    sizes = {"float": 4, "uchar": 1, "int": 4, "double": 8}
    offset, record, target, in_vertex = 0, 0, None, False
    for line in data[:end].decode("ascii").splitlines():
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            in_vertex = True
        elif words[:1] == ["element"]:
            in_vertex = False
        elif in_vertex and words[:1] == ["property"]:
            if words[2] == "rf_r_0":
                target = record
            record += sizes[words[1]]
    return end, record, target


def make_bad_files(good, folder):
    data = good.read_bytes()
    end, record, offset = vertex_layout(data)
    count = (len(data) - end - 320 * 13) // record  # 320 faces of 13 bytes after the vertices
    assert count == 162 and end + 162 * record + 320 * 13 == len(data)
    nan = bytearray(data)
    position = end + (count - 1) * record + offset
    nan[position:position + 4] = struct.pack("<f", float("nan"))
    header = data[:end].decode("ascii").replace("binary_little_endian", "ascii")
    files = {
        "truncated": data[:len(data) // 2],
        "truncated_header": data[:200],
        "empty": b"",
        "garbage": np.random.default_rng(3).integers(0, 256, 5000, dtype=np.uint8).tobytes(),
        "nan": bytes(nan),
        "ascii": (header + "0 0 0\n").encode("ascii"),
        "ascii_bare": b"ply\nformat ascii 1.0\n",
    }
    paths = {}
    for name, content in files.items():
        paths[name] = folder / f"{name}.rply"
        paths[name].write_bytes(content)
    return paths


BAD_FILES = [("truncated", "truncated"), ("truncated_header", "truncated inside its header"),
             ("empty", "the file is empty"), ("garbage", "not a PLY file"),
             ("nan", "not a finite number (NaN or infinity)"), ("ascii", "ASCII format, which is not supported"),
             ("ascii_bare", "ASCII format, which is not supported")]


@pytest.mark.parametrize("name,phrase", BAD_FILES, ids=[b[0] for b in BAD_FILES])
def test_bad_rply_is_refused_with_our_message(name, phrase, good_file, tmp_path):
    bad = make_bad_files(good_file, tmp_path)[name]
    # Into a MeshSet that already holds a layer: the layer stays, nothing is added.
    ms = h.keep_alive(h.load(good_file))
    before = h.snapshot(ms)
    with pytest.raises(pymeshlab.PyMeshLabException) as caught:
        ms.load_new_mesh(str(bad))
    text = str(caught.value)
    assert f"cannot load '{bad.name}'" in text, text  # MeshLab passes the name, in the file's folder
    assert phrase in text, text
    h.assert_unchanged(before, h.snapshot(ms), f"loading {name}")
    ms.save_current_mesh(str(tmp_path / "after.rply"))
    assert (tmp_path / "after.rply").read_bytes() == good_file.read_bytes()
    # Into an empty MeshSet: still empty.
    empty = h.keep_alive(pymeshlab.MeshSet())
    with pytest.raises(pymeshlab.PyMeshLabException, match="cannot load"):
        empty.load_new_mesh(str(bad))
    assert empty.mesh_number() == 0


def test_ascii_refusal_says_how_to_fix(good_file, tmp_path):
    bad = make_bad_files(good_file, tmp_path)["ascii"]
    with pytest.raises(pymeshlab.PyMeshLabException) as caught:
        h.keep_alive(pymeshlab.MeshSet()).load_new_mesh(str(bad))
    assert "export it again as PLY with the 'Binary encoding' box checked" in str(caught.value)


@pytest.mark.parametrize("degree,basis,expected", [(9, 0, "Degree 9 is not supported for PB"),
                                                   (11, SH, "Degree 11 is not supported for SH"),
                                                   (-1, 0, "Degree -1 is not supported for PB")])
def test_create_refuses_a_degree_out_of_range(degree, basis, expected, good_file, tmp_path):
    """On a layer that already has radiance: refused, and the radiance it had is still there."""
    ms = h.load(good_file)
    text = h.expect_refusal(ms, h.CREATE, expected, degree=degree, basis=basis)
    assert "use PB degrees 0..8 or SH degrees 0..10" in text
    ms.save_current_mesh(str(tmp_path / "after.rply"))
    assert (tmp_path / "after.rply").read_bytes() == good_file.read_bytes(), "the refused filter changed the radiance"
    # The MeshSet still works.
    ms.apply_filter(h.CREATE, degree=2)
    ms.save_current_mesh(str(tmp_path / "pb2.rply"))
    assert b"comment radiance_basis PB2\n" in (tmp_path / "pb2.rply").read_bytes()[:400]


@pytest.mark.parametrize("parameters,message", [
    (dict(specular=-1.0), "The specular strength and colour must be finite and >= 0"),
    (dict(shininess=-3.0), "The shininess (Blinn-Phong exponent) must be finite and >= 0"),
    (dict(ambient=-0.5), "The ambient radiance must be finite and >= 0"),
    (dict(lightintensity=-1.0), "The light intensity must be finite and >= 0"),
    # Not finite: refused by the check every filter shares, naming the parameter.
    (dict(shininess=float("nan")), "The parameter 'shininess' is not a finite number"),
    (dict(lightintensity=float("inf")), "The parameter 'lightIntensity' is not a finite number"),
    (dict(light=np.zeros(3)), "The direction toward a directional light must be a finite, non-zero vector"),
    (dict(stripes=-2), "Stripes must be between 0"),
])
def test_create_refuses_bad_material_parameters(parameters, message, scenes):
    ms = h.load(scenes("sphere", level=2))
    ms.apply_filter("compute_color_by_function_per_vertex", x="50", y="100", z="150")
    h.expect_refusal(ms, h.CREATE, message, **parameters)


def test_create_refuses_vertices_without_normals(tmp_path):
    cloud = tmp_path / "cloud.ply"
    cloud.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                     "property float z\nend_header\n0 0 1\n0.1 0 1\n0 0.1 1\n")
    h.expect_refusal(h.load(cloud), h.CREATE, "vertices has a usable normal and there are no faces")


def test_evaluation_refuses_a_mesh_without_radiance(scenes):
    ms = h.load(scenes("sphere", level=2))
    text = h.expect_refusal(ms, h.EVALUATE, "has no radiance data", viewpoint=np.array([0.0, 0.0, 5.0]),
                            exposure=1.0)
    assert "Radiance: Create Radiance Data from Analytic Material" in text  # says how to get some


def test_fit_refuses_a_degree_out_of_range(scenes):
    h.expect_refusal(h.load(scenes("sphere", level=2)), h.FIT, "Degree 9 is not supported for PB", degree=9)


def test_the_process_survives_every_refusal(good_file, scenes, tmp_path):
    """All the refusals above in one fresh Python process, then real work: exit status 0 and the
    final line printed (a crash or an abort would kill that process, not this session)."""
    bad = make_bad_files(good_file, tmp_path)
    code = textwrap.dedent(f"""
        import numpy as np, pymeshlab, pymeshlab_radiance
        refused = []   # kept alive: pymeshlab 2025.7 keeps a pointer to a raising MeshSet's log
        def refuse(ms, call):
            refused.append(ms)
            try:
                call()
            except pymeshlab.PyMeshLabException:
                return
            raise SystemExit("not refused")
        for path in {[str(p) for p in bad.values()]!r}:
            ms = pymeshlab.MeshSet(); refuse(ms, lambda: ms.load_new_mesh(path))
        sphere = {scenes("sphere", level=2)!r}
        for kwargs in ({{'degree': 9}}, {{'degree': 11, 'basis': 1}}, {{'specular': -1.0}},
                       {{'light': np.zeros(3)}}):
            ms = pymeshlab.MeshSet(); ms.load_new_mesh(sphere)
            refuse(ms, lambda: ms.apply_filter({h.CREATE!r}, **kwargs))
        ms = pymeshlab.MeshSet(); ms.load_new_mesh(sphere)
        refuse(ms, lambda: ms.apply_filter({h.EVALUATE!r}))
        refuse(ms, lambda: ms.apply_filter({h.SIMPLIFY!r}, targetpercentage=0.5))
        refuse(ms, lambda: ms.apply_filter({h.ADAPTIVE!r}))
        refuse(ms, lambda: ms.apply_filter({h.FIT!r}))
        refuse(ms, lambda: ms.apply_filter({h.BAKE!r}, sourcemesh=0, texturesize=1000))
        ms = pymeshlab.MeshSet(); ms.load_new_mesh({str(good_file)!r})
        ms.apply_filter({h.SIMPLIFY!r}, targetpercentage=0.5)
        ms.apply_filter({h.EVALUATE!r})
        ms.save_current_mesh({str(tmp_path / "survivor.rply")!r})
        print("survived", ms.current_mesh().face_number())
    """)
    result = h.run_python(code)
    assert result.returncode == 0, f"the Python process died (status {result.returncode}):\n{result.stdout[-3000:]}"
    assert result.stdout.strip().splitlines()[-1] == "survived 160", result.stdout[-2000:]
    assert os.path.getsize(tmp_path / "survivor.rply") > 0
