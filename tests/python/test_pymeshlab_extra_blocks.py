"""Extra per-vertex blocks through pymeshlab 2025.7 (mirroring tests/integration/test_extra_blocks_kept.sh):
a block no plugin interprets, and a 'prt' block that is not a valid transfer field, survive
load_new_mesh + save_current_mesh byte for byte; a file whose block metadata holds a control character
is refused with the header line named and leaves the MeshSet as it was.

The input files are written here with struct in the layout of docs/radiance-ply-format.md.
"""
import struct

import pymeshlab
import pytest

import pymeshlab_radiance  # noqa: F401  (loads our plugins into pymeshlab)
import pymeshlab_test_helpers as h


def grid_file(path, meta_value="1/m"):
    n_side = 5
    pos = [(i / 4.0, j / 4.0, 0.0) for j in range(n_side) for i in range(n_side)]
    faces = []
    for j in range(n_side - 1):
        for i in range(n_side - 1):
            a = j * n_side + i
            faces += [(a, a + 1, a + n_side), (a + 1, a + n_side + 1, a + n_side)]
    head = ["ply", "format binary_little_endian 1.0", "comment radiance_format_version 1",
            "comment block prt width 3", "comment block_meta prt kind made_up",
            "comment block curvature width 2", f"comment block_meta curvature unit {meta_value}",
            f"element vertex {len(pos)}"]
    head += [f"property float {p}" for p in ("x", "y", "z", "nx", "ny", "nz")]
    head += [f"property float prt_{i}" for i in range(3)] + ["property float curvature_0", "property float curvature_1"]
    head += [f"element face {len(faces)}", "property list uchar int vertex_indices", "end_header"]
    body = bytearray()
    for v, (x, y, z) in enumerate(pos):
        body += struct.pack("<6f", x, y, z, 0.0, 0.0, 1.0)
        body += struct.pack("<3f", -v, 0.25, float("nan"))
        body += struct.pack("<2f", 10 * x + y, 100.0 + v)
    for f in faces:
        body += struct.pack("<B3i", 3, *f)
    path.write_bytes(("\n".join(head) + "\n").encode() + bytes(body))
    return path


def test_extra_blocks_survive_load_and_save(tmp_path):
    source = grid_file(tmp_path / "in.rply")
    ms = h.load(source)
    out = tmp_path / "out.rply"
    ms.save_current_mesh(str(out), save_vertex_color=False, save_vertex_quality=False)
    assert out.read_bytes() == source.read_bytes()


def test_control_character_in_block_metadata_refused_and_meshset_unchanged(tmp_path):
    good = grid_file(tmp_path / "good.rply")
    bad = grid_file(tmp_path / "bad.rply", meta_value="1/m\tsquared")
    ms = h.keep_alive(h.load(good))
    before = h.snapshot(ms)
    with pytest.raises(pymeshlab.PyMeshLabException) as caught:
        ms.load_new_mesh(str(bad))
    text = str(caught.value)
    assert "header line 7: the value of block_meta 'unit' of block 'curvature' contains a control character" in text, text
    assert "replace the control characters" in text, text
    h.assert_unchanged(before, h.snapshot(ms), "loading a file with a tab in its block metadata")
