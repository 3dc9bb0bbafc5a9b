"""'Out-of-Core Simplification and Normal Map' through pymeshlab 2025.7: a PLY scan read from disk
(never loaded as a layer) becomes a NEW simplified layer with wedge texture coordinates and the
normal map as its texture; malformed files are refused and the document is left as it was.

Expected values come from the definitions, computed here with numpy: the scan is a sphere of radius
1 (make_scene, exact normals), so every vertex of the simplified mesh lies near the sphere, and the
map, decoded with the documented encoding ((x + 1) / 2 * 65535), holds the sphere's normal at the
texel's point, i.e. its direction from the centre.
"""
import os

import numpy as np
import pytest

import pymeshlab_radiance  # noqa: F401  (loads our plugins into pymeshlab)
import pymeshlab_test_helpers as h

OOC = h.OUT_OF_CORE


def run(ms, ply, work, target=400, size=256):
    ms.apply_filter(OOC, plyfile=str(ply), targetfaces=target, texturesize=size, outputfile=str(work / "scan"))


def test_runs_on_an_empty_meshset(scenes, tmp_path):
    # The scan too large to open is the reason for the filter: no layer is needed.
    import pymeshlab
    ms = pymeshlab.MeshSet()
    h.keep_alive(ms)
    run(ms, scenes("sphere", level=5), tmp_path)
    assert ms.mesh_number() == 1
    layer = ms.current_mesh()
    assert 250 <= layer.face_number() <= 550, layer.face_number()
    assert np.all(np.abs(np.linalg.norm(layer.vertex_matrix(), axis=1) - 1.0) < 0.05)
    assert layer.has_wedge_tex_coord() and layer.texture_number() == 1
    assert (tmp_path / "scan_normal.png").exists()


def test_new_layer_with_texture_and_a_map_of_the_sphere(scenes, tmp_path):
    scan = scenes("sphere", level=5)  # 20,480 triangles, radius 1
    ms = h.load(scenes("sphere", level=1))  # a current layer, left alone
    h.keep_alive(ms)
    before = ms.current_mesh().vertex_matrix().copy()
    run(ms, scan, tmp_path)
    assert ms.mesh_number() == 2
    assert np.array_equal(ms.mesh(0).vertex_matrix(), before), "the current layer was changed"
    layer = ms.mesh(1)  # the new layer (not made current, like the other filters' new layers)
    faces, vertices = layer.face_matrix(), layer.vertex_matrix()
    assert 250 <= len(faces) <= 550, len(faces)
    radius = np.linalg.norm(vertices, axis=1)
    assert np.all(np.abs(radius - 1.0) < 0.05), radius
    assert layer.has_wedge_tex_coord()
    uv = layer.wedge_tex_coord_matrix()
    assert uv.shape == (3 * len(faces), 2) and uv.min() >= 0.0 and uv.max() <= 1.0
    assert layer.texture_number() == 1
    png = tmp_path / "scan_normal.png"
    desc = tmp_path / "scan_bake.txt"
    assert png.exists() and desc.exists()
    assert "space = object" in desc.read_text()

    # Decode the map at the centre of each face's UV triangle and compare with the sphere's normal
    # at the face's centroid.
    image, depth = h.read_png(png)
    assert depth == 16
    height, width = image.shape[:2]
    normals = image[:, :, :3] * 2.0 - 1.0
    corner_uv = uv.reshape(-1, 3, 2).mean(axis=1)
    columns = np.clip((corner_uv[:, 0] * width).astype(int), 0, width - 1)
    rows_ = np.clip(((1.0 - corner_uv[:, 1]) * height).astype(int), 0, height - 1)
    sampled = h.normalized(normals[rows_, columns])
    centroids = vertices[faces].mean(axis=1)
    expected = h.normalized(centroids)
    angles = np.degrees(np.arccos(np.clip(np.sum(sampled * expected, axis=1), -1, 1)))
    assert angles.mean() < 2.0, angles.mean()
    assert np.percentile(angles, 95) < 5.0


@pytest.mark.parametrize("case,content,message", [
    ("truncated", None, "truncated"),
    ("not_ply", b"OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n", "not a PLY file"),
    ("bad_index", None, "out of range"),
    ("missing", None, "does not exist"),
])
def test_malformed_ply_is_refused_and_the_document_is_unchanged(scenes, tmp_path, case, content, message):
    path = tmp_path / (case + ".ply")
    good = open(scenes("sphere", level=2), "rb").read()
    if case == "truncated":
        path.write_bytes(good[: len(good) - 100])
    elif case == "not_ply":
        path.write_bytes(content)
    elif case == "bad_index":
        h.write_ascii_ply(path, [(0, 0, 0), (1, 0, 0), (0, 1, 0)], [(0, 1, 7)])
    ms = h.load(scenes("sphere", level=1))
    text = h.expect_refusal(ms, OOC, message, plyfile=str(path), targetfaces=100, texturesize=128,
                            outputfile=str(tmp_path / "out"))
    assert "unchanged" in text
    assert not any(f.startswith("out") for f in os.listdir(tmp_path)), os.listdir(tmp_path)


def test_bad_texture_size_is_refused(scenes, tmp_path):
    ms = h.load(scenes("sphere", level=1))
    h.expect_refusal(ms, OOC, "power of two", plyfile=scenes("sphere", level=2), targetfaces=100, texturesize=100,
                     outputfile=str(tmp_path / "out"))


def test_a_target_too_large_for_the_atlas_is_refused_before_reading_and_the_gutter_helps(scenes, tmp_path):
    """1500 triangles (+25 % = 1875) with a 4-texel gutter need more than 256^2; with a 1-texel gutter
    they fit. Cells of two triangles are 2 + 1 + 2 (gutter + 1) texels wide (docs/out-of-core.md): 13
    with gutter 4, 19 x 19 cells, 722 triangles; 7 with gutter 1, 36 x 36 cells, 2592; 9 with gutter
    2, 28 x 28, 1568: gutter 1 is the widest that fits, and 512^2 the smallest texture (39 x 39
    cells, 3042)."""
    ms = h.load(scenes("sphere", level=1))
    message = h.expect_refusal(ms, OOC, "holds at most 722 triangles in the per-triangle atlas with a 4-texel gutter",
                               plyfile=scenes("sphere", level=5), targetfaces=1500, texturesize=256, gutter=4,
                               outputfile=str(tmp_path / "out"))
    assert "1875 are needed" in message and "texture of 512 x 512" in message and "a gutter of 1" in message, message
    ms.apply_filter(OOC, plyfile=scenes("sphere", level=5), targetfaces=1500, texturesize=256, gutter=1,
                    outputfile=str(tmp_path / "out"))
    assert ms.mesh_number() == 2


def test_the_new_layer_feeds_the_radiance_pipeline(scenes, tmp_path):
    """The simplified layer goes on unchanged: radiance functions are created on it and the
    radiance-aware simplification runs on it (vertex clustering may leave non-manifold spots on
    real scans; on this sphere it must not, and the simplification must accept it)."""
    import pymeshlab
    ms = pymeshlab.MeshSet()
    h.keep_alive(ms)
    run(ms, scenes("sphere", level=5), tmp_path, target=800, size=512)
    faces = ms.current_mesh().face_number()
    ms.apply_filter(h.CREATE, basis=0, degree=2, reflected=False, albedo=pymeshlab.Color(200, 120, 80),
                    specularcolor=pymeshlab.Color(255, 255, 255), specular=0.5, shininess=30.0, stripes=False,
                    stripeaxis=1, lighttype=0, light=np.array([0.3, 0.5, 1.0]), lightintensity=2.0, ambient=0.05,
                    setcolor=True)
    ms.apply_filter(h.SIMPLIFY, metric=0, collapse=0, targetfaces=faces // 2, targetpercentage=0.0, lodlevels="",
                    geometryweight=0.01, attributeweight=0.99, preserveboundary=True, minvalence=0, maxvalence=0,
                    maxnormalchange=90.0, lazy=True, progressivefile="")
    simplified = ms.current_mesh()
    assert abs(simplified.face_number() - faces // 2) <= 4, (faces, simplified.face_number())
    out = tmp_path / "pipeline.rply"
    ms.save_current_mesh(str(out))
    assert out.stat().st_size > 0


# ---------------------------------------------------------------------------------------------------
# Issue 28: scale and stray vertices, folders, file-size limits.

def _scan_variant(scenes, path, scale=1.0, stray=None):
    """The level-4 sphere scan as a binary PLY without normals, scaled, with an optional unreferenced vertex."""
    ms = h.load(scenes("sphere", level=4))
    m = ms.current_mesh()
    v, f = m.vertex_matrix() * scale, m.face_matrix()
    n = m.vertex_normal_matrix()
    if stray is not None:
        v = np.vstack([v, np.asarray(stray, dtype=float)])
        n = np.vstack([n, [[0.0, 0.0, 1.0]]])
    h.write_binary_ply(path, v, f, n)
    return path


def test_an_unreferenced_far_vertex_changes_nothing(scenes, tmp_path):
    """One stray vertex 1e6 away, used by no face, turned a 400-triangle target into 36 triangles."""
    clean = _scan_variant(scenes, tmp_path / "clean.ply")
    stray = _scan_variant(scenes, tmp_path / "stray.ply", stray=[1e6, 0.0, 0.0])
    counts = []
    for ply in (clean, stray):
        ms = h.keep_alive(h.load(scenes("sphere", level=1)))
        ms.apply_filter(OOC, plyfile=str(ply), targetfaces=400, texturesize=256,
                        outputfile=str(tmp_path / ply.stem))
        counts.append(ms.mesh(1).face_number())
        assert np.all(np.abs(np.linalg.norm(ms.mesh(1).vertex_matrix(), axis=1) - 1.0) < 0.05)
    assert counts[0] == counts[1] and 300 <= counts[1] <= 550, counts


@pytest.mark.parametrize("scale,message", [(1e-12, "units across, below the 1e-06"), (1e-30, "scale it up"),
                                           (1e15, "scale the mesh down"), (1e20, "scale the mesh down")])
def test_scales_the_cores_cannot_compute_with_are_refused(scenes, tmp_path, scale, message):
    """At 1e-30 every point landed in one texel, at 1e20 none was used, at 1e-12 and 1e15 the map drifted."""
    ply = _scan_variant(scenes, tmp_path / "scaled.ply", scale=scale)
    ms = h.keep_alive(h.load(scenes("sphere", level=1)))
    text = h.expect_refusal(ms, OOC, message, plyfile=str(ply), targetfaces=100, texturesize=128,
                            outputfile=str(tmp_path / "out"))
    assert "unchanged" in text
    assert sorted(os.listdir(tmp_path)) == ["scaled.ply"], os.listdir(tmp_path)


def test_a_folder_is_named_as_a_folder(scenes, tmp_path):
    (tmp_path / "scan.ply").mkdir()
    ms = h.keep_alive(h.load(scenes("sphere", level=1)))
    h.expect_refusal(ms, OOC, "is a folder, not a PLY file", plyfile=str(tmp_path / "scan.ply"), targetfaces=100,
                     texturesize=128, outputfile=str(tmp_path / "out"))


def test_an_8bit_map_beyond_a_file_size_limit_is_refused(scenes, tmp_path):
    """stb's 8-bit PNG writer ignored write errors: under a file-size limit the filter reported success
    with a truncated map. Run in a child Python (Python ignores SIGXFSZ, so the write fails with EFBIG)."""
    import subprocess
    import sys
    scan = scenes("sphere", level=5)
    code = f"""
import resource, sys
import pymeshlab, pymeshlab_radiance
ms = pymeshlab.MeshSet()
resource.setrlimit(resource.RLIMIT_FSIZE, (20000, 20000))
try:
    ms.apply_filter({OOC!r}, plyfile={str(scan)!r}, targetfaces=2000, texturesize=1024, bits=1,
                    outputfile={str(tmp_path / 'limited')!r})
except pymeshlab.PyMeshLabException as e:
    print("REFUSED", e)
    sys.exit(0)
print("ACCEPTED")
"""
    env = h.python_env()
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300, env=env)
    assert "REFUSED" in done.stdout, done.stdout + done.stderr
    assert "exceeds a size limit" in done.stdout, done.stdout
    assert not [n for n in os.listdir(tmp_path) if n.startswith("limited")], os.listdir(tmp_path)

