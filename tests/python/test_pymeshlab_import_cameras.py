"""Import Cameras as Raster Layers (issue 29) through the real pymeshlab, with COLMAP models written
by the real pycolmap (binary and text).

The photographs are drawn here: black, with small Gaussian spots (in linear light) centred where
pycolmap's own camera model (Camera.img_from_cam) puts known 3D points, so the distorted images are
exactly what a real lens of that calibration would record. After the import, MeshLab's project file
(save_project) gives each raster's vcg camera; projecting the points with vcg's formula
(docs/design-notes.md, "Importing cameras"; written out below) must land on the spots' centroids in
the undistorted images within 0.1 pixel, and, for a pinhole camera whose photograph is used as it
is, within 1e-3 pixel of pycolmap's projection (the +0.5 pixel-centre convention).
"""
import math
import os
import shutil
import xml.etree.ElementTree as ET

import numpy as np
import pycolmap
import pymeshlab
import pymeshlab_radiance  # noqa: F401  (loads our plugins into pymeshlab)
import pytest

import pymeshlab_test_helpers as h

SIGMA = 1.4      # spot radius (pixels, Gaussian sigma)
WIDTH, HEIGHT = 240, 180

# Camera models and parameters (COLMAP's order), as a lab's calibration might give them.
CAMERAS = {
    1: ("OPENCV", [220.0, 215.0, 121.5, 88.25, -0.18, 0.04, 0.0015, -0.001]),
    2: ("PINHOLE", [230.0, 228.0, 118.75, 91.5]),
    3: ("OPENCV_FISHEYE", [170.0, 170.0, 119.5, 90.5, 0.03, -0.01, 0.002, 0.0]),
    4: ("FULL_OPENCV", [225.0, 222.0, 122.0, 89.0, 0.08, -0.02, 0.0008, 0.0006, 0.003, 0.02, -0.005, 0.001]),
}


def scene_points():
    """A grid of 3D points on a tilted plane in front of the cameras."""
    pts = []
    for i in np.linspace(-0.9, 0.9, 10):
        for j in np.linspace(-0.7, 0.7, 8):
            pts.append([i, j, 0.15 * i - 0.1 * j])
    return np.array(pts)


def camera_poses():
    """Four cameras about 3 units from the origin, looking at it (cam_from_world)."""
    poses = []
    for k, (yaw, pitch) in enumerate([(0.0, 0.0), (0.25, -0.1), (-0.2, 0.15), (0.1, 0.2)]):
        rotation = pycolmap.Rotation3d(np.array([pitch, yaw, 0.05 * k]).reshape(3, 1))
        poses.append(pycolmap.Rigid3d(rotation, np.array([0.05 * k, -0.03, 3.0]).reshape(3, 1)))
    return poses


def spots(centres, u, v):
    """Linear-light intensity of Gaussian spots at pixel coordinates (u, v) (arrays)."""
    linear = np.zeros(np.shape(u))
    for cu, cv in centres:
        linear += 0.9 * np.exp(-((u - cu) ** 2 + (v - cv) ** 2) / (2 * SIGMA ** 2))
    return np.clip(linear, 0, 1)


def draw_spots(centres):
    """8-bit sRGB image (H, W, 3): the spots sampled at the pixel centres (origin at the image's
    top-left corner, pixel centres at +0.5)."""
    v, u = np.mgrid[0:HEIGHT, 0:WIDTH] + 0.5
    code = np.round(h.srgb_encode(spots(centres, u, v))).astype(np.uint8)
    return np.repeat(code[:, :, None], 3, axis=2)


def make_capture(folder, models=CAMERAS):
    """A pycolmap reconstruction (one image per camera), its photographs, written as binary
    (folder/sparse_bin) and text (folder/sparse_txt) models. Returns (reconstruction, expected), where
    expected[name] = list of (3D point, pixel in the distorted photograph)."""
    images = folder / "images"
    images.mkdir(parents=True, exist_ok=True)
    rec = pycolmap.Reconstruction()
    expected = {}
    points = scene_points()
    for (camera_id, (model, params)), pose in zip(sorted(models.items()), camera_poses()):
        camera = pycolmap.Camera.create_from_model_name(camera_id, model, params[0], WIDTH, HEIGHT)
        camera.params = params
        rec.add_camera_with_trivial_rig(camera)
        name = f"view_{camera_id}.png"
        rec.add_image_with_trivial_frame(pycolmap.Image(name=name, camera_id=camera_id, image_id=camera_id), pose)
        seen = []
        for X in points:
            pc = pose * X
            if pc[2] <= 0:
                continue
            uv = rec.cameras[camera_id].img_from_cam(pc)
            if uv is not None and 14 < uv[0] < WIDTH - 14 and 14 < uv[1] < HEIGHT - 14:
                seen.append((X, np.asarray(uv, dtype=float)))
        assert len(seen) >= 20, f"camera {camera_id} sees only {len(seen)} points"
        h.write_png(images / name, draw_spots([uv for _, uv in seen]))
        expected[name] = seen
    for kind in ("bin", "txt"):
        (folder / f"sparse_{kind}").mkdir(exist_ok=True)
    rec.write_binary(str(folder / "sparse_bin"))
    rec.write_text(str(folder / "sparse_txt"))
    return rec, expected


def read_project_cameras(project):
    """Raster label -> (vcg camera attributes as floats, image path) from a MeshLab project."""
    out = {}
    root = ET.parse(str(project)).getroot()
    for raster in root.iter("MLRaster"):
        cam = raster.find("VCGCamera")
        plane = raster.find("Plane")
        values = {k: np.array([float(x) for x in cam.get(k).split()]) for k in
                  ("TranslationVector", "RotationMatrix", "FocalMm", "PixelSizeMm", "CenterPx", "ViewportPx",
                   "LensDistortion")}
        path = plane.get("fileName")
        if not os.path.isabs(path):
            path = os.path.join(os.path.dirname(str(project)), path)
        out[raster.get("label")] = (values, path)
    return out


def vcg_project(values, X):
    """vcg::Shot's projection (meshlab-platform notes): rows of RotationMatrix are the camera's right,
    up and backward axes, TranslationVector is minus the centre; returns (u, v) with v from the top."""
    R = values["RotationMatrix"].reshape(4, 4)[:3, :3]
    C = -values["TranslationVector"][:3]
    cp = R @ (X - C)
    depth = -cp[2]
    f = values["FocalMm"][0]
    px = cp[0] * f / depth / values["PixelSizeMm"][0] + values["CenterPx"][0]
    py = cp[1] * f / depth / values["PixelSizeMm"][1] + values["CenterPx"][1]
    return np.array([px, values["ViewportPx"][1] - py])


def window_centroid(linear, rows, cols):
    total = linear.sum()
    return np.array([(linear.sum(axis=0) * (cols + 0.5)).sum() / total, (linear.sum(axis=1) * (rows + 0.5)).sum() / total])


def spot_centroids(image, values, camera, centres, u, v, radius=6):
    """Centroids (pixel coordinates, centres at +0.5) of the linear-light intensity in the window
    around (u, v): in the imported raster's image, and in the pinhole image pycolmap's own model
    predicts (each window pixel's ray through the raster's pinhole intrinsics, read from the
    project, imaged by pycolmap's Camera.img_from_cam, the spots evaluated there). A warp that is
    not the lens's moves the first away from the second; the spots' shape, stretched by the
    undistortion, moves both alike."""
    c0, r0 = int(math.floor(u)), int(math.floor(v))
    rows = np.arange(r0 - radius, r0 + radius + 1)
    cols = np.arange(c0 - radius, c0 + radius + 1)
    observed = h.srgb_decode(np.round(image[:, :, 1] * 255.0))[np.ix_(rows, cols)]
    fx = values["FocalMm"][0] / values["PixelSizeMm"][0]
    fy = values["FocalMm"][0] / values["PixelSizeMm"][1]
    cx, cy = values["CenterPx"][0], values["ViewportPx"][1] - values["CenterPx"][1]
    pv, pu = np.meshgrid(rows + 0.5, cols + 0.5, indexing="ij")
    rays = np.stack([(pu - cx) / fx, (pv - cy) / fy, np.ones_like(pu)], axis=-1).reshape(-1, 3)
    source = np.asarray(camera.img_from_cam(rays))
    predicted = spots(centres, source[:, 0], source[:, 1]).reshape(pu.shape)
    return window_centroid(observed, rows, cols), window_centroid(predicted, rows, cols)


def import_cameras(ms, camerafile, imagefolder, **extra):
    ms.apply_filter(h.IMPORT_CAMERAS, camerafile=str(camerafile), imagefolder=str(imagefolder), **extra)


@pytest.fixture(scope="module")
def capture(tmp_path_factory):
    folder = tmp_path_factory.mktemp("colmap_capture")
    rec, expected = make_capture(folder)
    return folder, rec, expected


@pytest.mark.parametrize("kind", ["bin", "txt"])
def test_pycolmap_model_projects_onto_the_photographs_spots(capture, kind, tmp_path):
    folder, rec, expected = capture
    cache = tmp_path / "cache"
    ms = pymeshlab.MeshSet()
    import_cameras(ms, folder / f"sparse_{kind}", folder / "images", cachefolder=str(cache))
    assert ms.raster_number() == len(CAMERAS)
    # A project needs a mesh layer to be saved with the rasters.
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=scene_points()))
    project = tmp_path / "project.mlp"
    ms.save_project(str(project))
    cameras = read_project_cameras(project)
    assert sorted(cameras) == sorted(expected)
    worst = 0.0
    for name, seen in expected.items():
        values, image_path = cameras[name]
        assert values["ViewportPx"].tolist() == [WIDTH, HEIGHT]
        assert not values["LensDistortion"].any(), "the rasters must be exact pinhole cameras"
        image, _ = h.read_png(image_path)
        model = CAMERAS[int(name[5])][0]
        if model == "PINHOLE":
            # Used as it is: vcg's projection is pycolmap's, to float precision.
            assert os.path.samefile(image_path, folder / "images" / name)
            for X, uv in seen:
                assert np.abs(vcg_project(values, X) - uv).max() < 2e-3, (name, X)
        else:
            assert os.path.dirname(image_path) == str(cache), image_path
        for X, uv in seen:
            pinhole_uv = vcg_project(values, X)
            if not (8 < pinhole_uv[0] < WIDTH - 8 and 8 < pinhole_uv[1] < HEIGHT - 8):
                continue  # cropped by the undistortion's zoom
            observed, predicted = spot_centroids(image, values, rec.cameras[int(name[5])], [c for _, c in seen],
                                                 *pinhole_uv)
            error = np.abs(observed - predicted).max()
            worst = max(worst, error)
            assert error < 0.1, f"{name} ({model}): spot of {X} is {error:.3f} px from where pycolmap's lens puts it"
        # The raster's pose is pycolmap's: X in pycolmap's camera frame, through the raster's pinhole
        # intrinsics, lands where vcg's projection puts it.
        pose = rec.images[int(name[5])].cam_from_world()
        fx = values["FocalMm"][0] / values["PixelSizeMm"][0]
        fy = values["FocalMm"][0] / values["PixelSizeMm"][1]
        cx, cy = values["CenterPx"][0], values["ViewportPx"][1] - values["CenterPx"][1]
        for X, _ in seen:
            pc = pose * X
            assert np.abs(vcg_project(values, X) - [fx * pc[0] / pc[2] + cx, fy * pc[1] / pc[2] + cy]).max() < 2e-3
    assert worst > 0.0
    print(f"{kind}: spots within {worst:.3f} px of pycolmap's prediction")


def test_cache_is_reused_and_keyed_by_the_calibration(tmp_path):
    _, expected = make_capture(tmp_path, {1: CAMERAS[1]})
    cache = tmp_path / "cache"
    ms = pymeshlab.MeshSet()
    import_cameras(ms, tmp_path / "sparse_bin", tmp_path / "images", cachefolder=str(cache))
    first = sorted(os.listdir(cache))
    assert len(first) == 1
    stamp = os.stat(cache / first[0]).st_mtime_ns
    import_cameras(ms, tmp_path / "sparse_txt", tmp_path / "images", cachefolder=str(cache))
    assert sorted(os.listdir(cache)) == first, "the same calibration must reuse its undistorted image"
    assert os.stat(cache / first[0]).st_mtime_ns == stamp
    assert ms.raster_number() == 2
    # A changed k1: a new image, the old one is not served.
    text = (tmp_path / "sparse_txt" / "cameras.txt").read_text().replace(" -0.17999999999999999 ", " -0.17 ")
    assert " -0.17 " in text
    (tmp_path / "sparse_txt" / "cameras.txt").write_text(text)
    import_cameras(ms, tmp_path / "sparse_txt", tmp_path / "images", cachefolder=str(cache))
    assert len(os.listdir(cache)) == 2


def test_default_cache_is_beside_the_images_and_resized_photographs_scale_the_camera(tmp_path):
    """A PINHOLE model whose photographs are copies at half the size: the camera is scaled."""
    _, expected = make_capture(tmp_path, {2: CAMERAS[2]})
    half = tmp_path / "half"
    half.mkdir()
    image, _ = h.read_png(tmp_path / "images" / "view_2.png")
    code = np.round(image * 255).astype(np.uint8)
    h.write_png(half / "view_2.png", code[::2, ::2].copy())
    ms = pymeshlab.MeshSet()
    import_cameras(ms, tmp_path / "sparse_bin", half)
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=scene_points()))
    ms.save_project(str(tmp_path / "p.mlp"))
    values, path = read_project_cameras(tmp_path / "p.mlp")["view_2.png"]
    assert values["ViewportPx"].tolist() == [WIDTH // 2, HEIGHT // 2]
    for X, uv in expected["view_2.png"]:
        assert np.abs(vcg_project(values, X) - uv / 2).max() < 2e-3


def refuse(ms, message, camerafile, imagefolder):
    before = ms.raster_number()
    text = h.expect_refusal(ms, h.IMPORT_CAMERAS, message, camerafile=str(camerafile), imagefolder=str(imagefolder))
    assert ms.raster_number() == before, f"refusal '{message}' changed the rasters"
    return text


def test_bad_input_is_refused_and_nothing_is_added(tmp_path):
    _, expected = make_capture(tmp_path, {1: CAMERAS[1], 2: CAMERAS[2]})
    images = tmp_path / "images"
    ms = h.load()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=scene_points()))
    import_cameras(ms, tmp_path / "sparse_bin", images)
    assert ms.raster_number() == 2

    # A camera model COLMAP has but the import does not read.
    bad = tmp_path / "unsupported"
    bad.mkdir()
    shutil.copy(tmp_path / "sparse_txt" / "images.txt", bad)
    (bad / "cameras.txt").write_text(f"1 RAD_TAN_THIN_PRISM_FISHEYE {WIDTH} {HEIGHT} " + " ".join(["0.1"] * 16) +
                                     f"\n2 PINHOLE {WIDTH} {HEIGHT} 230 228 118.75 91.5\n")
    refuse(ms, "RAD_TAN_THIN_PRISM_FISHEYE", bad, images)

    # A photograph missing, and a model naming a photograph the folder lacks.
    lacking = tmp_path / "lacking"
    lacking.mkdir()
    shutil.copy(images / "view_1.png", lacking)
    refuse(ms, "view_2.png' is not in the image folder", tmp_path / "sparse_bin", lacking)
    renamed = tmp_path / "renamed"
    renamed.mkdir()
    shutil.copy(tmp_path / "sparse_txt" / "cameras.txt", renamed)
    (renamed / "images.txt").write_text((tmp_path / "sparse_txt" / "images.txt").read_text().replace("view_1.png", "other.jpg"))
    refuse(ms, "other.jpg", renamed, images)

    # A photograph of the wrong size (another shape than the calibration's).
    wrong = tmp_path / "wrong"
    wrong.mkdir()
    shutil.copy(images / "view_1.png", wrong)
    h.write_png(wrong / "view_2.png", np.zeros((HEIGHT, WIDTH + 40, 3), dtype=np.uint8))
    refuse(ms, f"{WIDTH + 40} x {HEIGHT} pixels", tmp_path / "sparse_bin", wrong)

    # A pose that is not a rotation (a quaternion of norm 2), and a NaN focal length.
    scaled = tmp_path / "scaled"
    scaled.mkdir()
    shutil.copy(tmp_path / "sparse_txt" / "cameras.txt", scaled)
    lines = (tmp_path / "sparse_txt" / "images.txt").read_text().splitlines()
    for i, line in enumerate(lines):
        fields = line.split()
        if fields and not line.startswith("#") and fields[-1].endswith(".png"):
            fields[1:5] = [str(2 * float(x)) for x in fields[1:5]]
            lines[i] = " ".join(fields)
            break
    (scaled / "images.txt").write_text("\n".join(lines) + "\n")
    refuse(ms, "not a rotation", scaled, images)
    nan = tmp_path / "nan"
    nan.mkdir()
    shutil.copy(tmp_path / "sparse_txt" / "images.txt", nan)
    (nan / "cameras.txt").write_text(f"1 OPENCV {WIDTH} {HEIGHT} nan 215 121.5 88.25 -0.18 0.04 0.0015 -0.001\n"
                                     f"2 PINHOLE {WIDTH} {HEIGHT} 230 228 118.75 91.5\n")
    refuse(ms, "not a finite number", nan, images)

    # A file of another format, and a camera file that does not exist.
    h.write_ascii_ply(tmp_path / "scan.ply", [[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[0, 1, 2]])
    refuse(ms, "is not a camera file this import reads", tmp_path / "scan.ply", images)
    refuse(ms, "does not exist", tmp_path / "none.xml", images)
    assert ms.raster_number() == 2


def rotation_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def write_metashape_xml(path, rec, chunk_rotation, chunk_translation, chunk_scale):
    """The reconstruction's OPENCV / PINHOLE cameras as Metashape would export them: cx, cy as
    offsets from the image centre, P1 = OpenCV's p2 and P2 = OpenCV's p1, camera-to-chunk
    transforms, the chunk placed in the world by (rotation, translation, scale). The chunk's
    coordinates are COLMAP's world coordinates."""
    sensors, cameras = [], []
    for camera_id, camera in sorted(rec.cameras.items()):
        p = [float(x) for x in camera.params]
        fx, fy, cx, cy = (p[0], p[1], p[2], p[3]) if camera.model_name != "SIMPLE_PINHOLE" else (p[0], p[0], p[1], p[2])
        k1, k2, p1, p2 = (p[4:8] if camera.model_name == "OPENCV" else [0.0] * 4)
        sensors.append(
            f'<sensor id="{camera_id}" label="s{camera_id}" type="frame"><resolution width="{WIDTH}" height="{HEIGHT}"/>'
            f'<calibration type="frame" class="adjusted"><resolution width="{WIDTH}" height="{HEIGHT}"/>'
            f'<f>{fy!r}</f><cx>{cx - WIDTH / 2!r}</cx><cy>{cy - HEIGHT / 2!r}</cy><b1>{fx - fy!r}</b1>'
            f'<k1>{k1!r}</k1><k2>{k2!r}</k2><p1>{p2!r}</p1><p2>{p1!r}</p2></calibration></sensor>')
    for image_id, image in sorted(rec.images.items()):
        pose = image.cam_from_world()
        R = pose.rotation.matrix()
        C = -R.T @ np.asarray(pose.translation).reshape(3)
        m = np.eye(4)
        m[:3, :3] = R.T
        m[:3, 3] = C
        label = os.path.splitext(image.name)[0]  # Metashape's labels drop the extension
        cameras.append(f'<camera id="{image_id}" sensor_id="{image.camera_id}" label="{label}">'
                       f'<transform>{" ".join(repr(float(x)) for x in m.ravel())}</transform></camera>')
    cameras.append('<camera id="90" sensor_id="1" label="disabled_one" enabled="false">'
                   '<transform>1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1</transform></camera>')
    cameras.append('<camera id="91" sensor_id="1" label="not_aligned"/>')
    rotation = " ".join(repr(float(x)) for x in chunk_rotation.ravel())
    translation = " ".join(repr(float(x)) for x in chunk_translation)
    path.write_text(
        '<?xml version="1.0" encoding="UTF-8"?>\n<document version="1.5.0"><chunk label="c" enabled="true">'
        f'<sensors>{"".join(sensors)}</sensors><cameras>{"".join(cameras)}</cameras>'
        f'<transform><rotation>{rotation}</rotation><translation>{translation}</translation>'
        f'<scale>{chunk_scale!r}</scale></transform></chunk></document>\n')


def opengl_camera_to_world(pose):
    """nerfstudio's transform_matrix of a pycolmap cam_from_world pose: camera to world, with OpenGL's
    camera axes (columns 2 and 3 of OpenCV's negated)."""
    R = pose.rotation.matrix()
    m = np.eye(4)
    m[:3, :3] = R.T @ np.diag([1.0, -1.0, -1.0])
    m[:3, 3] = -R.T @ np.asarray(pose.translation).reshape(3)
    return m


def write_nerfstudio(path, rec):
    """The reconstruction as nerfstudio's transforms.json: per-frame intrinsics, camera-to-world
    matrices with OpenGL's axes (columns 2 and 3 of OpenCV's negated)."""
    import json

    frames = []
    for image_id, image in sorted(rec.images.items()):
        camera = rec.cameras[image.camera_id]
        p = [float(x) for x in camera.params]
        m = opengl_camera_to_world(image.cam_from_world())
        frame = {"file_path": "images/" + image.name, "transform_matrix": m.tolist(), "w": WIDTH, "h": HEIGHT,
                 "fl_x": p[0], "fl_y": p[1], "cx": p[2], "cy": p[3], "camera_model": "OPENCV"}
        if camera.model_name == "OPENCV":
            frame.update(k1=p[4], k2=p[5], p1=p[6], p2=p[7])
        frames.append(frame)
    path.write_text(json.dumps({"frames": frames}, indent=1))


def saved_cameras(ms, folder, name):
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=scene_points()))
    ms.save_project(str(folder / name))
    return read_project_cameras(folder / name)


def test_metashape_and_nerfstudio_files_give_the_colmap_rasters(tmp_path):
    """The same capture as COLMAP binary model, Metashape XML (with a chunk transform) and nerfstudio
    JSON: each imported raster projects points as the COLMAP one (the Metashape ones after the
    chunk's similarity), and the undistorted images agree."""
    rec, expected = make_capture(tmp_path, {1: CAMERAS[1], 2: CAMERAS[2]})
    reference = pymeshlab.MeshSet()
    import_cameras(reference, tmp_path / "sparse_bin", tmp_path / "images", cachefolder=str(tmp_path / "c0"))
    colmap = saved_cameras(reference, tmp_path, "colmap.mlp")

    R, T, s = rotation_z(0.7), np.array([5.0, -2.0, 1.5]), 2.5
    write_metashape_xml(tmp_path / "cameras.xml", rec, R, T, s)
    ms = pymeshlab.MeshSet()
    import_cameras(ms, tmp_path / "cameras.xml", tmp_path / "images", cachefolder=str(tmp_path / "c1"))
    assert ms.raster_number() == 2  # the disabled and the unaligned camera are skipped
    metashape = saved_cameras(ms, tmp_path, "metashape.mlp")

    write_nerfstudio(tmp_path / "transforms.json", rec)
    ns = pymeshlab.MeshSet()
    import_cameras(ns, tmp_path / "transforms.json", tmp_path, cachefolder=str(tmp_path / "c2"))
    nerf = saved_cameras(ns, tmp_path, "nerfstudio.mlp")

    for name in expected:
        label = os.path.splitext(name)[0]
        reference_values, reference_image = colmap[name]
        metashape_values, metashape_image = metashape[label]
        nerf_values, nerf_image = nerf["images/" + name]
        for X, _ in expected[name]:
            uv = vcg_project(reference_values, X)
            assert np.abs(vcg_project(metashape_values, s * R @ X + T) - uv).max() < 2e-3, (name, X)
            assert np.abs(vcg_project(nerf_values, X) - uv).max() < 2e-3, (name, X)
        a = h.read_png(reference_image)[0]
        for other in (metashape_image, nerf_image):
            assert np.abs(h.read_png(other)[0] - a).max() <= 1.5 / 255, other


def test_nerf_field_of_view_only_takes_the_photographs_size(tmp_path):
    """The original NeRF's transforms.json (Mildenhall et al. 2020): only camera_angle_x, file paths
    without an extension. Two pinhole cameras with square pixels and the principal point at the
    image centre, written that way, import as the COLMAP model of the same cameras: the points
    project to the same pixels (f = (W / 2) / tan(camera_angle_x / 2) with W the photograph's width)."""
    import json

    cx, cy = WIDTH / 2, HEIGHT / 2
    models = {1: ("PINHOLE", [230.0, 230.0, cx, cy]), 2: ("PINHOLE", [205.0, 205.0, cx, cy])}
    rec, expected = make_capture(tmp_path, models)
    reference = pymeshlab.MeshSet()
    import_cameras(reference, tmp_path / "sparse_bin", tmp_path / "images", cachefolder=str(tmp_path / "c0"))
    colmap = saved_cameras(reference, tmp_path, "colmap.mlp")

    for camera_id in models:
        image = rec.images[camera_id]
        m = opengl_camera_to_world(image.cam_from_world())
        angle = 2 * math.atan(cx / models[camera_id][1][0])
        frames = [{"file_path": "./images/" + os.path.splitext(image.name)[0], "transform_matrix": m.tolist()}]
        (tmp_path / f"transforms_{camera_id}.json").write_text(json.dumps({"camera_angle_x": angle, "frames": frames}))
        ms = pymeshlab.MeshSet()
        import_cameras(ms, tmp_path / f"transforms_{camera_id}.json", tmp_path, cachefolder=str(tmp_path / "c1"))
        assert ms.raster_number() == 1
        nerf = saved_cameras(ms, tmp_path, f"nerf_{camera_id}.mlp")
        reference_values, _ = colmap[image.name]
        nerf_values, _ = nerf["images/" + os.path.splitext(image.name)[0]]
        for X, uv in expected[image.name]:
            assert np.abs(vcg_project(nerf_values, X) - vcg_project(reference_values, X)).max() < 2e-3, (image.name, X)
            assert np.abs(vcg_project(nerf_values, X) - uv).max() < 2e-3, (image.name, X)


def add_exif_orientation(jpeg, orientation):
    """The JPEG's bytes with an APP1 Exif segment holding only the orientation tag (TIFF 6.0, little
    endian: IFD0 with one SHORT entry 0x0112) inserted after the start-of-image marker."""
    import struct

    tiff = b"II*\x00" + struct.pack("<I", 8) + struct.pack("<H", 1) + struct.pack("<HHIHH", 0x0112, 3, 1, orientation, 0) \
        + struct.pack("<I", 0)
    payload = b"Exif\x00\x00" + tiff
    data = jpeg.read_bytes()
    assert data[:2] == b"\xff\xd8"
    jpeg.write_bytes(data[:2] + b"\xff\xe1" + struct.pack(">H", len(payload) + 2) + payload + data[2:])


def test_exif_orientation_is_honoured(tmp_path):
    """A JPEG (written by ImageMagick) stored turned counter-clockwise, with EXIF orientation 6
    (display turned clockwise): the raster shows the upright photograph at the calibration's size.
    Without the tag, the same file is refused (the wrong shape)."""
    import subprocess

    _, expected = make_capture(tmp_path, {2: CAMERAS[2]})
    upright = np.round(h.read_png(tmp_path / "images" / "view_2.png")[0] * 255).astype(np.uint8)
    h.write_png(tmp_path / "stored.png", np.ascontiguousarray(np.rot90(upright, 1)))  # counter-clockwise
    photos = tmp_path / "jpeg"
    photos.mkdir()
    subprocess.run(["convert", str(tmp_path / "stored.png"), "-quality", "98", str(photos / "view_2.jpg")], check=True)
    model = tmp_path / "jpeg_model"
    model.mkdir()
    shutil.copy(tmp_path / "sparse_txt" / "cameras.txt", model)
    (model / "images.txt").write_text((tmp_path / "sparse_txt" / "images.txt").read_text().replace("view_2.png", "view_2.jpg"))
    refused = h.load()
    refused.add_mesh(pymeshlab.Mesh(vertex_matrix=scene_points()))
    refuse(refused, f"{HEIGHT} x {WIDTH} pixels", model, photos)
    add_exif_orientation(photos / "view_2.jpg", 6)
    ms = pymeshlab.MeshSet()
    import_cameras(ms, model, photos)
    values, path = saved_cameras(ms, tmp_path, "jpeg.mlp")["view_2.jpg"]
    assert values["ViewportPx"].tolist() == [WIDTH, HEIGHT]
    shown = h.read_png(path)[0][:, :, :3]
    assert shown.shape == upright.shape, shown.shape
    assert np.abs(shown * 255 - upright).mean() < 2.0, "the raster is not the upright photograph"


def test_metashape_and_nerfstudio_bad_files_are_refused(tmp_path):
    """A Metashape chunk transform whose rotation holds a scale, a nerfstudio frame whose matrix holds
    one, and a Metashape XML naming a photograph the folder lacks: refused, no raster added."""
    rec, _ = make_capture(tmp_path, {1: CAMERAS[1], 2: CAMERAS[2]})
    ms = h.load()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=scene_points()))
    write_metashape_xml(tmp_path / "scaled.xml", rec, np.diag([2.0, 1.0, 1.0]), np.zeros(3), 1.0)
    refuse(ms, "not a rotation", tmp_path / "scaled.xml", tmp_path / "images")
    write_metashape_xml(tmp_path / "ok.xml", rec, np.eye(3), np.zeros(3), 1.0)
    lacking = tmp_path / "lacking"
    lacking.mkdir()
    shutil.copy(tmp_path / "images" / "view_1.png", lacking)
    refuse(ms, "'view_2' is not in the image folder", tmp_path / "ok.xml", lacking)
    write_nerfstudio(tmp_path / "transforms.json", rec)
    text = (tmp_path / "transforms.json").read_text()
    import json

    data = json.loads(text)
    data["frames"][1]["transform_matrix"][0][0] *= 3.0
    (tmp_path / "scaled.json").write_text(json.dumps(data))
    refuse(ms, "not a rotation", tmp_path / "scaled.json", tmp_path)
    assert ms.raster_number() == 0
