"""'Bake Normal Map' through pymeshlab 2025.7, mirroring tests/integration/test_bake_normal_map.sh
and test_bake_refusals.sh.

The scan (source layer) is a fine icosphere stretched into the ellipsoid x^2/a^2 + y^2/b^2 + z^2/c^2 = 1
(a, b, c = 1.06, 1, 0.95) with its exact normals; the target is a coarse unit icosphere without texture
coordinates (the per-triangle atlas is made). An ellipsoid rather than a sphere: on a unit sphere with
radial vertex normals, the ray from a target point along its interpolated normal is radial, so the
"exact" normal there equals the target's own interpolated normal and a bake that ignored the source
would pass. Here they differ by ~4 degrees on average, and the expected normal at every texel is
computed in numpy from the ellipsoid (the ray from the surface point along the interpolated target
normal, both directions, the nearer intersection, the gradient there). PNGs are decoded by
tests/integration/png_reader.py. The tangent frames follow docs/normal-map-baking.md: the old
per-face frame (T = the face's dP/du made orthogonal to the interpolated normal N, B = s N x T,
s = -1 for mirrored UVs) and MikkTSpace (Mikkelsen 2008), the default, computed here for the
per-triangle atlas where it has a closed form (every corner its own vertex, see
mikktspace_corner_tangents).
"""
import os
import shutil

import numpy as np
import pymeshlab
import pytest

from pymeshlab_radiance import rply

import pymeshlab_test_helpers as h

AXES = np.array([1.06, 1.0, 0.95])


def colour_of(points):
    """The scan's vertex colour as a function of position (set by MeshLab's per-vertex colour function)."""
    return 127.5 + 100.0 * points


@pytest.fixture(scope="module")
def meshes(scenes, tmp_path_factory):
    folder = tmp_path_factory.mktemp("bake")
    sphere = rply.read_rply(scenes("sphere", level=5))
    positions = sphere.positions.astype(float) * AXES
    normals = h.normalized(positions / AXES ** 2)
    scan = h.write_binary_ply(folder / "scan.ply", positions, sphere.faces, normals)
    shutil.copy(scenes("sphere", level=2), folder / "coarse.ply")
    return folder, scan, str(folder / "coarse.ply")


def bake_parameters(**overrides):
    """Every parameter, as scripts/bake_normal_map_filter.sh lists them."""
    p = dict(sourcemesh=0, texturesize=256, space=0, tangentframe=0, bits=0, maxdistance=pymeshlab.PureValue(0.0), gutter=4,
             newatlas=False, diffuse=True, lean=True, gltf=False, gltfroughness=0.5, assign=0, outputfile="")
    p.update(overrides)
    return p


def scan_and_target(meshes, target=None):
    folder, scan, coarse = meshes
    ms = h.load(scan)
    ms.apply_filter("compute_color_by_function_per_vertex", x="127.5+100*x", y="127.5+100*y", z="127.5+100*z")
    ms.load_new_mesh(os.path.abspath(target or coarse))
    return ms


def exact_on_ellipsoid(points, directions):
    """Nearest intersection (either direction) of p + s d with the ellipsoid, and its unit normal."""
    a = ((directions / AXES) ** 2).sum(1)
    b = 2 * ((points * directions) / AXES ** 2).sum(1)
    c = ((points / AXES) ** 2).sum(1) - 1
    root = np.sqrt(np.maximum(b * b - 4 * a * c, 0))
    s1, s2 = (-b + root) / (2 * a), (-b - root) / (2 * a)
    s = np.where(np.abs(s1) < np.abs(s2), s1, s2)
    q = points + s[:, None] * directions
    return q, h.normalized(q / AXES ** 2)


def tangent_frames(positions, faces, wedge_uv, f, normals):
    p = positions[faces[f]]
    uv = wedge_uv[3 * f:3 * f + 3]
    e1, e2 = p[1] - p[0], p[2] - p[0]
    (du1, dv1), (du2, dv2) = uv[1] - uv[0], uv[2] - uv[0]
    det = du1 * dv2 - du2 * dv1
    dpdu = (e1 * dv2 - e2 * dv1) / det
    dpdv = (e2 * du1 - e1 * du2) / det
    s = np.sign(np.dot(np.cross(dpdu, dpdv), np.cross(e1, e2)))
    t = h.normalized(dpdu[None, :] - (normals @ dpdu)[:, None] * normals)
    return t, s * np.cross(normals, t)


def test_object_space_map_matches_the_ellipsoid(meshes):
    folder, _, _ = meshes
    ms = scan_and_target(meshes)
    ms.apply_filter(h.BAKE, **bake_parameters())
    for name in ("coarse_normal.png", "coarse_diffuse.png", "coarse_lean.exr", "coarse_bake.txt"):
        assert (folder / name).stat().st_size > 0, f"missing {name} beside the target mesh"
    assert not list(folder.glob("*.part*")), "temporary files left behind"
    description = (folder / "coarse_bake.txt").read_text().splitlines()
    for line in ("space = object", "bits = 16", "diffuse_map = coarse_diffuse.png", "lean_moments = coarse_lean.exr",
                 "uv = per-triangle atlas"):
        assert line in description, f"the description lacks '{line}'"
    target = ms.current_mesh()
    assert target.has_wedge_tex_coord(), "the layer got no texture coordinates"
    assert [os.path.basename(t) for t in target.textures()] == ["coarse_normal.png"], "the map is not the layer's texture"
    uv = target.wedge_tex_coord_matrix()
    assert uv.min() >= 0 and uv.max() <= 1

    normal_map, depth = h.read_png(folder / "coarse_normal.png")
    assert depth == 16 and normal_map.shape == (256, 256, 3)
    diffuse_map, _ = h.read_png(folder / "coarse_diffuse.png")
    baked_error, target_error, colour_error = [], [], []
    positions, faces, normals = target.vertex_matrix(), target.face_matrix(), target.vertex_normal_matrix()
    for f, col, row, point, normal in h.texels_inside_faces(positions, faces, uv, normals, 256, 256):
        d = h.normalized(normal)
        q, exact = exact_on_ellipsoid(point, d)
        baked_error.append(h.angle_degrees(exact, normal_map[row, col] * 2 - 1))
        target_error.append(h.angle_degrees(exact, d))
        colour_error.append(np.abs(diffuse_map[row, col, :3] * 255 - colour_of(q)))
    baked_error, target_error = np.concatenate(baked_error), np.concatenate(target_error)
    print(f"object space: {baked_error.size} texels, mean {baked_error.mean():.4f}, max {baked_error.max():.4f} "
          f"degrees (the target's own normals: mean {target_error.mean():.2f})")
    assert baked_error.size > 10000
    # The test discriminates: the target's own normals are degrees away from the scan's.
    assert target_error.mean() > 2.0
    assert baked_error.mean() <= 0.5 and baked_error.max() <= 2.0, \
        f"mean {baked_error.mean():.3f}, max {baked_error.max():.3f} degrees from the ellipsoid's normals"
    colour_error = np.concatenate(colour_error)
    assert colour_error.mean() <= 1.5 and colour_error.max() <= 4.0, \
        f"diffuse map off the scan's colours: mean {colour_error.mean():.2f}, max {colour_error.max():.2f}"
    # No texel left empty anywhere (charts, gutters, background): every texel decodes to a unit vector.
    length = np.linalg.norm(normal_map * 2 - 1, axis=2)
    assert np.abs(length - 1).max() <= 0.02, f"{int((np.abs(length - 1) > 0.02).sum())} texels are not unit normals"


def test_tangent_space_map_on_existing_coordinates(meshes, tmp_path):
    ms = scan_and_target(meshes)
    ms.apply_filter(h.BAKE, **bake_parameters(outputfile=str(tmp_path / "first_normal.png")))
    uv = ms.current_mesh().wedge_tex_coord_matrix().copy()
    out = tmp_path / "tangent"
    out.mkdir()
    ms.apply_filter(h.BAKE, **bake_parameters(space=1, tangentframe=1, bits=1, diffuse=False,
                                              outputfile=str(out / "sphere_normal.png")))
    assert np.array_equal(ms.current_mesh().wedge_tex_coord_matrix(), uv), "the existing coordinates were replaced"
    description = (out / "sphere_bake.txt").read_text().splitlines()
    assert "space = tangent" in description and "bits = 8" in description
    assert "tangent_frame = per-face-dpdu" in description
    assert "uv = target's wedge coordinates" in description
    assert not (out / "sphere_lean.exr").exists(), "a LEAN file for a tangent-space map"
    tangent_map, depth = h.read_png(out / "sphere_normal.png")
    assert depth == 8
    target = ms.current_mesh()
    positions, faces, normals = target.vertex_matrix(), target.face_matrix(), target.vertex_normal_matrix()
    errors = []
    for f, col, row, point, normal in h.texels_inside_faces(positions, faces, uv, normals, 256, 256):
        n = h.normalized(normal)
        _, exact = exact_on_ellipsoid(point, n)
        t, b = tangent_frames(positions, faces, uv, f, n)
        expected = np.stack([(exact * t).sum(1), (exact * b).sum(1), (exact * n).sum(1)], axis=1)
        errors.append(h.angle_degrees(expected, tangent_map[row, col] * 2 - 1))
    errors = np.concatenate(errors)
    print(f"tangent space: {errors.size} texels, mean {errors.mean():.3f}, max {errors.max():.3f} degrees")
    # 8 bit: one level is 0.45 degrees of the encoding.
    assert errors.mean() <= 1.0 and errors.max() <= 3.0, f"mean {errors.mean():.3f}, max {errors.max():.3f} degrees"
    length = np.linalg.norm(tangent_map * 2 - 1, axis=2)
    assert np.abs(length - 1).max() <= 0.03


def mikktspace_corner_tangents(positions, faces, wedge_uv, f, normals):
    """MikkTSpace (Mikkelsen 2008) tangents and sign of face f's corners when no corner is shared
    with another face (a per-triangle atlas gives every corner UVs of its own): each corner's
    group is the face alone, so its tangent is the face's dP/du projected on the plane of the
    corner's unit normal and made unit, and the sign is that of the UV triangle's area."""
    p = positions[faces[f]]
    uv = wedge_uv[3 * f:3 * f + 3]
    e1, e2 = p[1] - p[0], p[2] - p[0]
    (du1, dv1), (du2, dv2) = uv[1] - uv[0], uv[2] - uv[0]
    det = du1 * dv2 - du2 * dv1
    dpdu = (e1 * dv2 - e2 * dv1) / det
    n = h.normalized(normals[faces[f]])
    return h.normalized(dpdu[None, :] - (n @ dpdu)[:, None] * n), (1.0 if det > 0 else -1.0)


def test_tangent_space_default_is_mikktspace(meshes, tmp_path):
    """The default tangent frame: a MikkTSpace renderer (T, N interpolated from the corners, not
    renormalised, B = s N x T, n = normalize(x T + y B + z N)) gets the ellipsoid's normal back."""
    ms = scan_and_target(meshes)
    ms.apply_filter(h.BAKE, **bake_parameters(space=1, diffuse=False, outputfile=str(tmp_path / "mikk_normal.png"),
                                              tangentframe=0))
    description = (tmp_path / "mikk_bake.txt").read_text().splitlines()
    assert "tangent_frame = mikktspace" in description
    assert any(line.startswith("green_channel = +Y up") for line in description)
    tangent_map, depth = h.read_png(tmp_path / "mikk_normal.png")
    assert depth == 16
    target = ms.current_mesh()
    positions, faces, normals = target.vertex_matrix(), target.face_matrix(), target.vertex_normal_matrix()
    uv = target.wedge_tex_coord_matrix()
    errors, old_frame_errors = [], []
    for f, col, row, point, normal, weights in h.texels_inside_faces(positions, faces, uv, normals, 256, 256,
                                                                     with_weights=True):
        _, exact = exact_on_ellipsoid(point, h.normalized(normal))
        corner_t, sign = mikktspace_corner_tangents(positions, faces, uv, f, normals)
        t = weights @ corner_t
        b = sign * np.cross(normal, t)
        code = tangent_map[row, col] * 2 - 1
        decoded = code[:, :1] * t + code[:, 1:2] * b + code[:, 2:3] * normal
        errors.append(h.angle_degrees(decoded, exact))
        # The same texels decoded in the old per-face frame: what a map of the old kind would need.
        t_old, b_old = tangent_frames(positions, faces, uv, f, h.normalized(normal))
        old = code[:, :1] * t_old + code[:, 1:2] * b_old + code[:, 2:3] * h.normalized(normal)
        old_frame_errors.append(h.angle_degrees(old, exact))
    errors, old_frame_errors = np.concatenate(errors), np.concatenate(old_frame_errors)
    print(f"MikkTSpace: {errors.size} texels, mean {errors.mean():.4f}, max {errors.max():.4f} degrees; decoded in "
          f"the per-face frame: mean {old_frame_errors.mean():.4f}")
    assert errors.size > 10000
    # Measured at 16 bit: mean 0.0010, max 0.0026 degrees; decoded in the per-face frame 0.025.
    assert errors.mean() <= 0.01 and errors.max() <= 0.05, f"mean {errors.mean():.3f}, max {errors.max():.3f} degrees"
    # The frames really differ (the check above would not tell MikkTSpace from the old frame otherwise).
    assert old_frame_errors.mean() > 5 * errors.mean()


def test_baked_layer_saves_with_its_texture_elsewhere(meshes, tmp_path):
    """A map written to an absolute path elsewhere: the layer's texture is named by the file name, so
    save_current_mesh(save_textures=True) in a third folder writes the mesh, refers to the bare name
    and copies the image beside it (a path as the name made pymeshlab fail)."""
    maps, saved = tmp_path / "maps", tmp_path / "saved"
    maps.mkdir()
    saved.mkdir()
    ms = scan_and_target(meshes)
    ms.apply_filter(h.BAKE, **bake_parameters(outputfile=str(maps / "coarse_normal.png")))
    assert list(ms.current_mesh().textures()) == ["coarse_normal.png"], "the texture is not named by the file name"
    ms.save_current_mesh(str(saved / "lowpoly.obj"), save_textures=True, save_wedge_texcoord=True)
    assert (saved / "lowpoly.obj").stat().st_size > 0
    copy, _ = h.read_png(saved / "coarse_normal.png")
    original, _ = h.read_png(maps / "coarse_normal.png")
    assert copy.shape == original.shape
    # The copy is the same picture (MeshLab may store it with another bit depth: compare in [0, 1]).
    assert np.abs(copy - original).max() <= 1.0 / 255 + 1e-6
    material = (saved / "lowpoly.obj.mtl").read_text() if (saved / "lowpoly.obj.mtl").exists() else \
        (saved / "lowpoly.mtl").read_text()
    assert "map_Kd coarse_normal.png" in material, material


def test_output_that_is_a_folder_receives_the_maps(meshes, tmp_path):
    """An existing folder as the output: the maps go inside it, named after the target (they used to
    be written beside the folder, named after it)."""
    folder = tmp_path / "maps"
    folder.mkdir()
    ms = scan_and_target(meshes)
    ms.apply_filter(h.BAKE, **bake_parameters(outputfile=str(folder)))
    assert sorted(p.name for p in folder.iterdir()) == ["coarse_bake.txt", "coarse_diffuse.png", "coarse_lean.exr",
                                                       "coarse_normal.png"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["maps"], "files written beside the folder"


# ---------------------------------------------------------------------------------------------------
# Refusals: our message ending with "The layers are unchanged", the MeshSet as it was, no file.

def bake_refusal(ms, folder, message, **parameters):
    folder.mkdir(exist_ok=True)
    text = h.expect_refusal(ms, h.BAKE, message, **bake_parameters(outputfile=str(folder / "baked_normal.png"),
                                                                   **parameters))
    assert "The layers are unchanged" in text
    assert not list(folder.iterdir()), f"files written by a refused bake: {list(folder.iterdir())}"


def test_refuses_a_size_not_a_power_of_two(meshes, tmp_path):
    bake_refusal(scan_and_target(meshes), tmp_path / "npot", "Texture size 1000 is not a power of two",
                 texturesize=1000)


def test_refuses_an_absurd_size(meshes, tmp_path):
    bake_refusal(scan_and_target(meshes), tmp_path / "huge", "16384", texturesize=65536)


def test_refuses_the_source_equal_to_the_target(meshes, tmp_path):
    bake_refusal(scan_and_target(meshes), tmp_path / "same", "are the same", sourcemesh=1)


def test_refuses_a_target_without_faces(meshes, tmp_path):
    points = tmp_path / "points.ply"
    points.write_text("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                      "property float z\nelement face 0\nproperty list uchar int vertex_indices\nend_header\n"
                      "0 0 0\n1 0 0\n0 1 0\n")
    bake_refusal(scan_and_target(meshes, points), tmp_path / "points", "has no faces")


def test_refuses_overlapping_texture_coordinates(meshes, tmp_path):
    overlap = h.write_ascii_ply(tmp_path / "overlap.ply", [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)],
                                [(0, 1, 2), (0, 3, 1)],
                                texcoords=[(0.1, 0.1, 0.9, 0.1, 0.1, 0.9), (0.2, 0.2, 0.8, 0.2, 0.2, 0.8)])
    ms = scan_and_target(meshes, overlap)
    assert ms.current_mesh().has_wedge_tex_coord()
    bake_refusal(ms, tmp_path / "overlap", "lie inside two or more faces (overlapping charts)")


def test_refuses_a_negative_ray_distance(meshes, tmp_path):
    bake_refusal(scan_and_target(meshes), tmp_path / "negative", "must be 0 (automatic) or a positive distance",
                 maxdistance=pymeshlab.PureValue(-1.0))


def test_refuses_a_source_that_no_ray_meets(meshes, tmp_path):
    """The scan moved far away: rays find nothing within the distance. It used to be baked from closest
    points 1000 units off (or written as a constant map); now it is refused with the fix."""
    ms = scan_and_target(meshes)
    ms.set_current_mesh(0)
    ms.apply_filter("compute_matrix_from_translation", axisx=1000.0, freeze=True)
    ms.set_current_mesh(1)
    bake_refusal(ms, tmp_path / "far", "the two layers do not overlap", maxdistance=pymeshlab.PureValue(0.5))


def test_per_vertex_texture_coordinates_are_kept(meshes, tmp_path):
    """A target whose UVs are per-vertex (texture_u / texture_v, as photogrammetry tools write) keeps
    its layout: the bake writes into it, and the layer's wedge coordinates equal the per-vertex ones
    (a per-triangle atlas was made instead, and the user's layout lost)."""
    vertices, faces = h.grid(4, 4)
    uv = np.array([(0.05 + 0.9 * x / 4, 0.05 + 0.9 * y / 4) for x, y, _ in vertices])
    target = tmp_path / "uv_grid.ply"
    with open(target, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                "property float nx\nproperty float ny\nproperty float nz\nproperty float texture_u\n"
                "property float texture_v\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
                % (len(vertices), len(faces)))
        for (x, y, z), (u, v) in zip(vertices, uv):
            f.write(f"{x / 4 - 0.5} {y / 4 - 0.5} 0 0 0 1 {u} {v}\n")
        for t in faces:
            f.write("3 %d %d %d\n" % t)
    ms = scan_and_target(meshes, target)
    assert ms.current_mesh().has_vertex_tex_coord() and not ms.current_mesh().has_wedge_tex_coord()
    out = tmp_path / "out"
    out.mkdir()
    ms.apply_filter(h.BAKE, **bake_parameters(outputfile=str(out / "grid_normal.png"), diffuse=False))
    assert "uv = target's wedge coordinates" in (out / "grid_bake.txt").read_text().splitlines()
    mesh = ms.current_mesh()
    expected = uv[mesh.face_matrix()].reshape(-1, 2)
    assert np.allclose(mesh.wedge_tex_coord_matrix(), expected, atol=1e-6), "the per-vertex layout was not kept"


def test_a_chart_atlas_made_by_meshlab_is_baked_into(meshes, tmp_path):
    """The help text's advice for a layout with charts: MeshLab's own 'Parametrization: Voronoi
    Atlas' first, then the bake keeps those charts (no per-triangle atlas) and fills them with the
    ellipsoid's normals."""
    ms = scan_and_target(meshes)
    ms.apply_filter("generate_voronoi_atlas_parametrization", regionnum=8, overlapflag=False)
    ms.set_current_mesh(ms.mesh_number() - 1)  # MeshLab puts the parametrized copy in a new layer
    atlas = ms.current_mesh()
    assert atlas.has_wedge_tex_coord(), "MeshLab's atlas gave the layer no wedge coordinates"
    before = atlas.wedge_tex_coord_matrix().copy()
    out = tmp_path / "voronoi"
    out.mkdir()
    ms.apply_filter(h.BAKE, **bake_parameters(outputfile=str(out / "atlas_normal.png"), diffuse=False, lean=False,
                                               texturesize=512))
    assert "uv = target's wedge coordinates" in (out / "atlas_bake.txt").read_text().splitlines()
    mesh = ms.current_mesh()
    uv = mesh.wedge_tex_coord_matrix()
    assert np.array_equal(uv, before), "the charts were replaced"
    normal_map, _ = h.read_png(out / "atlas_normal.png")
    errors = []
    positions, faces, normals = mesh.vertex_matrix(), mesh.face_matrix(), mesh.vertex_normal_matrix()
    for f, col, row, point, normal in h.texels_inside_faces(positions, faces, uv, normals, 512, 512):
        _, exact = exact_on_ellipsoid(point, h.normalized(normal))
        errors.append(h.angle_degrees(exact, normal_map[row, col] * 2 - 1))
    errors = np.concatenate(errors)
    assert errors.size > 10000
    assert errors.mean() <= 0.5, f"mean {errors.mean():.3f} degrees from the ellipsoid's normals"


def test_gltf_bake_commits_all_files_or_none(meshes, tmp_path):
    """Issue 28: the glTF bake put its files in place one by one; when the last rename failed (a folder
    named like the .glb) the new maps stayed, beside no .glb, under "The layers are unchanged". The
    files are one set now: the old map is kept, no new file appears."""
    folder = tmp_path / "gltf"
    folder.mkdir()
    (folder / "baked_normal.png").write_bytes(b"old map")
    (folder / "baked.glb").mkdir()
    ms = scan_and_target(meshes)
    text = h.expect_refusal(ms, h.BAKE, "baked.glb",
                            **bake_parameters(outputfile=str(folder / "baked_normal.png"), gltf=True))
    assert "The layers are unchanged" in text
    assert (folder / "baked_normal.png").read_bytes() == b"old map"
    assert sorted(p.name for p in folder.iterdir()) == ["baked.glb", "baked_normal.png"], list(folder.iterdir())

