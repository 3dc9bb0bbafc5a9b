"""Test captures rendered by a second, independent path tracer: Blender's Cycles (CPU), in exactly the
layout and conventions of render_capture.py (Mitsuba 3), so that bench_fit_capture,
meshlab_projection_capture.sh and check_capture.py read either unchanged.

    blender --background --factory-startup --python bench/capture/render_capture_cycles.py -- \
        --mesh data-cache/meshes/bunny00.off --material glaze --views 40 --noise-twin --out CAPTURES/bunny_glaze_40_cycles

Everything that does not need a renderer (mesh cleaning, normals, the albedo field, the golden-spiral
cameras, the OpenCV and MeshLab camera conventions, the .mlp writer, the sRGB encoding) is imported
from render_capture.py; this file only builds and renders the Blender scene. The output directory
(mesh.ply, truth/albedo.ply, photos/, masks/, photos_twin/, project*.mlp, cameras.json, capture.json)
is described in render_capture.py's docstring.

What differs from the Mitsuba captures, on purpose (a second renderer should not share the first
one's choices): Cycles' Principled BSDF (Blender 3.4: Disney/Burley with GGX, clear coat available),
point lights with a radius instead of spherical area lights, Cycles' default Blackman-Harris pixel
filter (1.5 px wide) instead of a box filter, Cycles' sampler. The scene is the same: same mesh and
vertex normals (set as custom normals, so Cycles shades with the normals mesh.ply carries), same
albedo, same light directions, distances, sizes and power ratios, same faint sky, same cameras.

Conventions:
  * Blender cameras look down their local -Z with local +Y up: matrix_world's columns are
    (right, up, -forward, origin). Mitsuba's look_at (what rc.opencv_camera expects) has columns
    (left, up, forward, origin) = (-right, up, forward, origin): both are built here from one
    (origin, target, up) triple. The horizontal field of view is set (sensor fit HORIZONTAL), so
    fx = fy = (W/2) / tan(fov_x/2) with square pixels and no lens shift; the principal point is the
    image centre, as in the Mitsuba captures.
  * Cycles writes linear, premultiplied RGBA; it is rendered to a 32-bit float OpenEXR (no view
    transform is applied to EXR files) and read back. Blender's pixel rows start at the BOTTOM, so
    the image is flipped to the top-down order of PNGs and of OpenCV's v axis.
  * With film_transparent, pixels that miss the object have alpha 0 and no background radiance,
    as Mitsuba's hide_emitters with an RGBA film.
  * --max-depth is Cycles' max_bounces: 0 = direct light only (Mitsuba's max_depth 2), 1 = one
    indirect bounce (Mitsuba's 3). Cycles' shortcuts that bias the image (indirect sample clamping,
    glossy blur) are switched off.
Self-checks printed in the log (and in capture.json["self_check"]): Blender's own projection
(bpy_extras world_to_camera_view) against the OpenCV camera written to the project, and, for every
rendered view, the fraction of clearly front-facing vertices whose OpenCV projection lands on a pixel
the object covers (alpha >= 1/2), which must exceed 0.97 (exit status 1 otherwise).
"""
import argparse
import contextlib
import ctypes
import json
import math
import os
import shutil
import struct
import sys
import tempfile
import time
import traceback
import zlib

import numpy as np

import bpy
from bpy_extras.object_utils import world_to_camera_view
from mathutils import Matrix, Vector

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import render_capture as rc  # noqa: E402


# ---------------------------------------------------------------------------------------------------
# Materials: Cycles' Principled BSDF (Blender 3.4 input names); Base Color is the per-vertex albedo.
# Every material sets all five inputs, so that Blender's defaults never decide the look.

MATERIALS = {
    "plastic": {"Roughness": 0.3, "Specular": 0.5, "Metallic": 0.0, "Clearcoat": 0.0, "Clearcoat Roughness": 0.03},
    # a glazed ceramic: a rough-ish base under a smooth clear coat (two highlights, one sharp)
    "glaze": {"Roughness": 0.35, "Specular": 0.5, "Metallic": 0.0, "Clearcoat": 0.5, "Clearcoat Roughness": 0.1},
    "metal": {"Roughness": 0.35, "Specular": 0.5, "Metallic": 0.85, "Clearcoat": 0.0, "Clearcoat Roughness": 0.03},
    "matte": {"Roughness": 0.8, "Specular": 0.1, "Metallic": 0.0, "Clearcoat": 0.0, "Clearcoat Roughness": 0.03},
}
ALBEDO_ATTRIBUTE = "albedo"


# ---------------------------------------------------------------------------------------------------
# Meshes: OFF through render_capture.py; PLY and OBJ read here (Blender's importers would rotate
# axes and may split vertices).

PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "i2", "int16": "i2",
             "ushort": "u2", "uint16": "u2", "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
             "float": "f4", "float32": "f4", "double": "f8", "float64": "f8"}


def read_ply(path):
    """Positions and triangles of an ASCII or binary PLY with 'vertex' and 'face' elements only."""
    with open(path, "rb") as f:
        if f.readline().strip() != b"ply":
            raise ValueError(f"{path}: not a PLY file")
        fmt, elements = None, []
        while True:
            line = f.readline()
            if not line:
                raise ValueError(f"{path}: no end_header")
            t = line.decode("ascii").split()
            if not t or t[0] in ("comment", "obj_info"):
                continue
            if t[0] == "end_header":
                break
            if t[0] == "format":
                fmt = t[1]
            elif t[0] == "element":
                elements.append((t[1], int(t[2]), []))
            elif t[0] == "property":
                elements[-1][2].append((t[-1], t[2:4] if t[1] == "list" else t[1]))
        body = f.read()
    if [e[0] for e in elements] != ["vertex", "face"]:
        raise ValueError(f"{path}: only PLY files with exactly a vertex and a face element are supported")
    (_, nv, vprops), (_, nf, fprops) = elements
    if any(isinstance(t, list) for _, t in vprops) or [isinstance(t, list) for _, t in fprops] != [True]:
        raise ValueError(f"{path}: expected scalar vertex properties and one face list property")
    vnames = [n for n, _ in vprops]
    count_type, index_type = (PLY_TYPES[x] for x in fprops[0][1])
    if fmt == "ascii":
        lines = body.decode("ascii").split("\n")
        V = np.array([lines[i].split()[:len(vprops)] for i in range(nv)], dtype=np.float64)
        V = V[:, [vnames.index(k) for k in "xyz"]]
        polys = [[int(x) for x in lines[nv + i].split()[1:]] for i in range(nf)]
        return V, rc.triangulate(polys)
    endian = {"binary_little_endian": "<", "binary_big_endian": ">"}.get(fmt)
    if endian is None:
        raise ValueError(f"{path}: unknown PLY format {fmt}")
    vdtype = np.dtype([(n, endian + PLY_TYPES[t]) for n, t in vprops])
    vert = np.frombuffer(body, dtype=vdtype, count=nv)
    V = np.stack([vert[k].astype(np.float64) for k in "xyz"], axis=1)
    pos = nv * vdtype.itemsize
    # Fast path: every face a triangle (a fixed-size record); otherwise face by face.
    tri = np.dtype([("n", endian + count_type), ("i", endian + index_type, (3,))])
    if len(body) - pos >= nf * tri.itemsize:
        faces = np.frombuffer(body, dtype=tri, count=nf, offset=pos)
        if np.all(faces["n"] == 3):
            return V, faces["i"].astype(np.int64)
    cdt, idt = np.dtype(endian + count_type), np.dtype(endian + index_type)
    polys = []
    for _ in range(nf):
        k = int(np.frombuffer(body, cdt, 1, pos)[0])
        polys.append(np.frombuffer(body, idt, k, pos + cdt.itemsize).tolist())
        pos += cdt.itemsize + k * idt.itemsize
    return V, rc.triangulate(polys)


def read_obj(path):
    """Positions and triangles of a Wavefront OBJ ('v' and 'f' lines; other lines ignored)."""
    V, polys = [], []
    with open(path, "r") as f:
        for line in f:
            t = line.split()
            if not t:
                continue
            if t[0] == "v":
                V.append([float(x) for x in t[1:4]])
            elif t[0] == "f":
                idx = [int(x.split("/")[0]) for x in t[1:]]
                polys.append([i - 1 if i > 0 else len(V) + i for i in idx])  # 1-based, or relative
    return np.array(V, dtype=np.float64), rc.triangulate(polys)


def read_mesh(path):
    ext = os.path.splitext(path)[1].lower()
    readers = {".off": rc.read_off, ".ply": read_ply, ".obj": read_obj}
    if ext not in readers:
        raise SystemExit(f"{path}: unsupported mesh format (OFF, PLY or OBJ)")
    return readers[ext](path)


# ---------------------------------------------------------------------------------------------------
# PNG (Blender's Python has no Pillow): 8-bit grey or RGB, no interlace, filter type 0 on every row.

def write_png(path, array_u8):
    a = np.ascontiguousarray(array_u8, dtype=np.uint8)
    height, width = a.shape[:2]
    colour_type = 0 if a.ndim == 2 else 2
    rows = np.zeros((height, 1 + a[0].size), np.uint8)  # leading 0 of each row: filter type None
    rows[:, 1:] = a.reshape(height, -1)

    def chunk(tag, data):
        return struct.pack(">I", len(data)) + tag + data + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF)
    with open(path, "wb") as f:
        f.write(b"\x89PNG\r\n\x1a\n"
                + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, colour_type, 0, 0, 0))
                + chunk(b"IDAT", zlib.compress(rows.tobytes(), 6))
                + chunk(b"IEND", b""))


def filmic_encode8(scene, linear_rgb, exposure, tmp):
    """8-bit RGB of exposure * linear_rgb through Blender's own colour management with the Filmic
    view transform (no look): the float image is saved with the scene's view settings applied
    (Image.save_render), read back as bytes."""
    height, width = linear_rgb.shape[:2]
    image = bpy.data.images.new("tone", width, height, alpha=True, float_buffer=True)
    rgba = np.ones((height, width, 4), np.float32)
    rgba[..., :3] = linear_rgb
    image.pixels.foreach_set(rgba[::-1].ravel())  # Blender's rows start at the bottom
    view, settings = scene.view_settings, scene.render.image_settings
    saved = (view.view_transform, view.look, view.exposure, settings.file_format, settings.color_mode,
             settings.color_depth)
    view.view_transform, view.look, view.exposure = "Filmic", "None", math.log2(exposure)
    settings.file_format, settings.color_mode, settings.color_depth = "PNG", "RGB", "8"
    path = os.path.join(tmp, "tone.png")
    try:
        image.save_render(path, scene=scene)
    finally:
        (view.view_transform, view.look, view.exposure, settings.file_format, settings.color_mode,
         settings.color_depth) = saved
        bpy.data.images.remove(image)
    png = bpy.data.images.load(path, check_existing=False)
    values = np.empty(width * height * 4, np.float32)
    png.pixels.foreach_get(values)  # a byte image's pixels are its stored values / 255
    bpy.data.images.remove(png)
    return np.round(values.reshape(height, width, 4)[::-1, :, :3] * 255.0).astype(np.uint8)


# ---------------------------------------------------------------------------------------------------
# Scene

def reset_scene():
    """The factory startup scene without its cube, light and camera."""
    for obj in list(bpy.data.objects):
        bpy.data.objects.remove(obj, do_unlink=True)
    for block in (bpy.data.meshes, bpy.data.lights, bpy.data.cameras, bpy.data.materials):
        for item in list(block):
            block.remove(item)
    return bpy.context.scene


def configure_render(scene, args, exr_path):
    scene.render.engine = "CYCLES"
    c = scene.cycles
    c.device = "CPU"
    scene.render.threads_mode = "FIXED"
    scene.render.threads = args.threads
    c.samples = args.spp
    c.use_adaptive_sampling = False  # every pixel gets --spp samples, as in Mitsuba
    c.use_denoising = False  # the photographs keep their Monte Carlo noise (the twins measure it)
    c.max_bounces = args.max_depth
    c.sample_clamp_direct = 0.0  # no clamping, no glossy blur: unbiased, as Mitsuba
    c.sample_clamp_indirect = 0.0
    c.blur_glossy = 0.0
    c.use_animated_seed = False
    # Pixel filter left at Cycles' default (Blackman-Harris, 1.5 px): a different reconstruction
    # from the Mitsuba captures' box filter, on purpose.
    scene.render.film_transparent = True  # alpha = coverage; the sky lights the object, unseen
    scene.render.use_persistent_data = True  # keep the BVH between the views
    scene.render.resolution_x, scene.render.resolution_y = args.width, args.height
    scene.render.resolution_percentage = 100
    scene.render.pixel_aspect_x = scene.render.pixel_aspect_y = 1.0
    scene.render.use_border = False
    # Linear float output; the view transform would not touch an EXR, set neutral all the same.
    scene.view_settings.view_transform = "Standard"
    scene.view_settings.look = "None"
    scene.view_settings.exposure = 0.0
    scene.view_settings.gamma = 1.0
    settings = scene.render.image_settings
    settings.file_format = "OPEN_EXR"
    settings.color_mode = "RGBA"
    settings.color_depth = "32"
    settings.exr_codec = "ZIP"
    scene.render.filepath = exr_path
    scene.render.use_file_extension = False


def add_object(scene, V, F, N, albedo):
    """The mesh, smooth shaded with its area-weighted vertex normals (those of mesh.ply: Blender
    would otherwise compute angle-weighted ones), albedo as a linear float point colour attribute."""
    mesh = bpy.data.meshes.new("object")
    mesh.vertices.add(len(V))
    mesh.vertices.foreach_set("co", V.astype(np.float32).ravel())
    mesh.loops.add(3 * len(F))
    mesh.loops.foreach_set("vertex_index", F.astype(np.int32).ravel())
    mesh.polygons.add(len(F))
    mesh.polygons.foreach_set("loop_start", np.arange(0, 3 * len(F), 3, dtype=np.int32))
    mesh.polygons.foreach_set("loop_total", np.full(len(F), 3, np.int32))
    mesh.polygons.foreach_set("use_smooth", np.ones(len(F), bool))
    mesh.update(calc_edges=True)
    if mesh.validate(verbose=False) or len(mesh.vertices) != len(V) or len(mesh.polygons) != len(F):
        raise SystemExit(f"Blender changed the mesh while validating it: {len(V)} -> {len(mesh.vertices)} vertices, "
                         f"{len(F)} -> {len(mesh.polygons)} triangles")
    mesh.use_auto_smooth = True  # needed for custom normals; 180 degrees: no edge is split
    mesh.auto_smooth_angle = math.pi
    mesh.normals_split_custom_set_from_vertices([tuple(n) for n in N])
    colours = mesh.color_attributes.new(ALBEDO_ATTRIBUTE, "FLOAT_COLOR", "POINT")
    rgba = np.concatenate([albedo, np.ones((len(V), 1))], axis=1).astype(np.float32)
    colours.data.foreach_set("color", rgba.ravel())
    obj = bpy.data.objects.new("object", mesh)
    scene.collection.objects.link(obj)
    return obj


def add_material(obj, name):
    """Principled BSDF with MATERIALS[name]; Base Color from the albedo attribute."""
    material = bpy.data.materials.new(name)
    material.use_nodes = True
    nodes, links = material.node_tree.nodes, material.node_tree.links
    bsdf = nodes["Principled BSDF"]
    bsdf.distribution = "GGX"
    for key, value in MATERIALS[name].items():
        bsdf.inputs[key].default_value = value
    attribute = nodes.new("ShaderNodeAttribute")
    attribute.attribute_type = "GEOMETRY"
    attribute.attribute_name = ALBEDO_ATTRIBUTE
    links.new(attribute.outputs["Color"], bsdf.inputs["Base Color"])
    obj.data.materials.append(material)
    return dict(type="Cycles Principled BSDF", distribution=bsdf.distribution,
                base_color=f"per-vertex albedo (truth/albedo.ply, r g b; colour attribute '{ALBEDO_ATTRIBUTE}')",
                **{key.lower().replace(" ", "_"): value for key, value in MATERIALS[name].items()})


def add_lights(scene, centre, radius, up):
    """Key and fill point lights with a radius (soft shadows) at rc.KEYFILL_LIGHTS, as
    rc.build_scene's keyfill spheres.
    A Cycles point light of power P gives an irradiance P / (4 pi d^2) at distance d; P is chosen
    so that it is pi * weight at the centre, as the Mitsuba lights' radiance is."""
    lights = []
    for name, weights, distance, size, weight in rc.KEYFILL_LIGHTS:
        position = centre + distance * radius * rc.light_direction(weights, up)
        d = distance * radius
        power = weight * math.pi * 4 * math.pi * d * d
        light = bpy.data.lights.new(name, "POINT")
        light.energy = power
        light.color = (1.0, 1.0, 1.0)
        light.shadow_soft_size = size * radius
        obj = bpy.data.objects.new(name, light)
        obj.location = position.tolist()
        obj.visible_camera = False  # as Mitsuba's hide_emitters: seen in reflections, not directly
        scene.collection.objects.link(obj)
        lights.append(dict(name=name, kind="Cycles point light with radius", position=position.tolist(),
                           radius=size * radius, power_watts=power, irradiance_at_centre=weight * math.pi))
    world = bpy.data.worlds.new("sky")
    world.use_nodes = True
    background = world.node_tree.nodes["Background"]
    background.inputs["Color"].default_value = (*rc.SKY_RADIANCE, 1.0)
    background.inputs["Strength"].default_value = 1.0
    scene.world = world
    lights.append(dict(name="sky", kind="constant world background, hidden from the camera (film_transparent)",
                       radiance=list(rc.SKY_RADIANCE)))
    return lights


def look_at(origin, target, up):
    """4x4 camera-to-world matrices of one look-at: Blender's (columns right, up, -forward, origin)
    and Mitsuba's (columns left, up, forward, origin), which rc.opencv_camera takes."""
    forward = target - origin
    forward /= np.linalg.norm(forward)
    right = np.cross(forward, up)
    right /= np.linalg.norm(right)
    up_cam = np.cross(right, forward)
    blender, mitsuba = np.eye(4), np.eye(4)
    blender[:3, :4] = np.stack([right, up_cam, -forward, origin], axis=1)
    mitsuba[:3, :4] = np.stack([-right, up_cam, forward, origin], axis=1)
    return blender, mitsuba


def add_cameras(scene, views, fov_x, radius, width, height):
    """One Blender camera per view; returns the camera objects, the OpenCV cameras and the matrices."""
    objects, cameras, matrices = [], [], []
    for i, (origin, target, up) in enumerate(views):
        blender_m, mitsuba_m = look_at(origin, target, up)
        cam = bpy.data.cameras.new(f"view_{i:03d}")
        cam.type = "PERSP"
        cam.sensor_fit = "HORIZONTAL"
        cam.lens_unit = "FOV"
        cam.angle_x = math.radians(fov_x)
        cam.shift_x = cam.shift_y = 0.0
        cam.clip_start, cam.clip_end = 0.01 * radius, 100.0 * radius
        obj = bpy.data.objects.new(f"view_{i:03d}", cam)
        obj.matrix_world = Matrix(blender_m.tolist())
        scene.collection.objects.link(obj)
        objects.append(obj)
        cameras.append(rc.opencv_camera(mitsuba_m, fov_x, width, height))
        matrices.append(blender_m)
    return objects, cameras, matrices


# ---------------------------------------------------------------------------------------------------
# Rendering

@contextlib.contextmanager
def stdout_to(path):
    """Sends the process's stdout (Cycles' per-tile progress lines, printed from C) to a file."""
    libc = ctypes.CDLL(None)
    sys.stdout.flush()
    libc.fflush(None)
    saved = os.dup(1)
    with open(path, "a") as log:
        os.dup2(log.fileno(), 1)
        try:
            yield
        finally:
            libc.fflush(None)
            os.dup2(saved, 1)
            os.close(saved)


def render_view(scene, camera, seed, exr_path, log_path):
    """Linear premultiplied RGBA, float32 (H, W, 4), first row = top of the image."""
    scene.camera = camera
    scene.cycles.seed = seed
    if os.path.exists(exr_path):
        os.remove(exr_path)
    with stdout_to(log_path):
        bpy.ops.render.render(write_still=True)
    if not os.path.exists(exr_path):
        raise SystemExit(f"Cycles wrote no image (see {log_path})")
    image = bpy.data.images.load(exr_path, check_existing=False)
    width, height = image.size
    pixels = np.empty(width * height * 4, np.float32)
    image.pixels.foreach_get(pixels)  # the EXR's values: linear (colour space 'Linear'), premultiplied
    bpy.data.images.remove(image)
    return pixels.reshape(height, width, 4)[::-1].copy()  # Blender's rows start at the bottom


# ---------------------------------------------------------------------------------------------------
# Self-checks of the camera conventions

def blender_projection_error(scene, objects, cameras, V, count=200):
    """Max distance in pixels between Blender's own projection of some vertices
    (world_to_camera_view: x, y in [0, 1] from the bottom-left corner) and the OpenCV camera's."""
    idx = np.linspace(0, len(V) - 1, min(count, len(V))).round().astype(int)
    W, H = scene.render.resolution_x, scene.render.resolution_y
    worst = 0.0
    for obj, cam in zip(objects, cameras):
        x = (V[idx] @ cam["R"].T) + cam["t"]
        u = cam["fx"] * x[:, 0] / x[:, 2] + cam["cx"]
        v = cam["fy"] * x[:, 1] / x[:, 2] + cam["cy"]
        ndc = np.array([tuple(world_to_camera_view(scene, obj, Vector(p.tolist()))) for p in V[idx]])
        ub, vb = ndc[:, 0] * W - 0.5, (1.0 - ndc[:, 1]) * H - 0.5  # continuous -> integer-centre pixels
        worst = max(worst, float(np.max(np.hypot(u - ub, v - vb))))
    return worst


def covered_fraction(cam, V, N, alpha):
    """Fraction of the clearly front-facing vertices (angle between normal and view direction below
    ~73 degrees) whose OpenCV projection falls on a pixel at least half covered (alpha >= 1/2: at
    low sample counts alpha is a multiple of 1/spp, often exactly 1/2). Occluded ones count too:
    they project inside the silhouette all the same. Grazing vertices are left out because they lie
    on the silhouette, where the 1.5 px pixel filter leaves alpha below 1/2 on small images."""
    H, W = alpha.shape
    x = V @ cam["R"].T + cam["t"]
    to_camera = cam["centre"][None, :] - V
    facing = np.sum(N * to_camera, axis=1) > 0.3 * np.linalg.norm(to_camera, axis=1)
    col = np.floor(cam["fx"] * x[:, 0] / x[:, 2] + cam["cx"] + 0.5).astype(int)
    row = np.floor(cam["fy"] * x[:, 1] / x[:, 2] + cam["cy"] + 0.5).astype(int)
    ok = facing & (x[:, 2] > 0) & (col >= 0) & (col < W) & (row >= 0) & (row < H)
    return float(np.mean(alpha[row[ok], col[ok]] >= 0.5))


# ---------------------------------------------------------------------------------------------------

def parse_args(argv):
    p = argparse.ArgumentParser(prog="blender --background --factory-startup --python render_capture_cycles.py --",
                                description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--mesh", required=True, help="OFF, PLY or OBJ")
    p.add_argument("--material", choices=sorted(MATERIALS), default="plastic")
    p.add_argument("--views", type=int, default=40)
    p.add_argument("--width", type=int, default=512)
    p.add_argument("--height", type=int, default=384)
    p.add_argument("--spp", type=int, default=64)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--up", choices=["x", "y", "z"], default="y", help="the mesh's up axis")
    p.add_argument("--whole-sphere", action="store_true", help="cameras on the whole sphere, not its upper 3/4")
    p.add_argument("--fov-y", type=float, default=38.0, help="vertical field of view in degrees")
    p.add_argument("--max-depth", type=int, default=3,
                   help="Cycles' max bounces (0 = direct light only, i.e. Mitsuba's max_depth 2)")
    p.add_argument("--noise-twin", action="store_true", help="render every view again with other seeds into photos_twin/")
    p.add_argument("--twin-views", type=int, default=0,
                   help="with --noise-twin: re-render only this many views, evenly spaced (0: all)")
    p.add_argument("--tone", choices=["standard", "filmic"], default="standard",
                   help="standard: 8-bit sRGB of the exposed linear radiance (as render_capture.py); filmic: "
                        "Blender's Filmic view transform (Blender 3.x's default) at the same exposure, a tone "
                        "curve that is not sRGB, as a camera's is not")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--out", required=True)
    return p.parse_args(argv)


def main(argv):
    args = parse_args(argv)
    out = os.path.abspath(args.out)
    for sub in ("photos", "masks", "truth") + (("photos_twin",) if args.noise_twin else ()):
        os.makedirs(os.path.join(out, sub), exist_ok=True)

    V, F = rc.clean_mesh(*read_mesh(args.mesh))
    N = rc.vertex_normals(V, F)
    albedo = rc.albedo_field(V, args.seed)
    rc.write_ply(os.path.join(out, "mesh.ply"), V, F, normals=N)
    rc.write_ply(os.path.join(out, "truth", "albedo.ply"), V, F, normals=N, colors=albedo)

    lo, hi = V.min(0), V.max(0)
    centre = 0.5 * (lo + hi)
    radius = float(np.linalg.norm(V - centre, axis=1).max())
    fov_x = rc.fov_x_from_y(args.fov_y, args.width, args.height)
    views = rc.camera_views(args.views, centre, radius, args.up, args.seed, args.fov_y, args.whole_sphere)

    tmp = tempfile.mkdtemp(prefix="cycles_capture_")
    exr_path, log_path = os.path.join(tmp, "render.exr"), os.path.join(tmp, "blender.log")
    try:
        t0 = time.time()
        scene = reset_scene()
        configure_render(scene, args, exr_path)
        obj = add_object(scene, V, F, N, albedo)
        material = add_material(obj, args.material)
        lights = add_lights(scene, centre, radius, args.up)
        cam_objects, cameras, blender_matrices = add_cameras(scene, views, fov_x, radius, args.width, args.height)
        setup_s = time.time() - t0
        projection_error = blender_projection_error(scene, cam_objects, cameras, V)
        print(f"self-check: Blender's projection vs the OpenCV cameras: max {projection_error:.2e} px", flush=True)

        images, times, twin_ids, twins, twin_times = rc.render_photos_and_twins(
            lambda i, seed: render_view(scene, cam_objects[i], seed, exr_path, log_path), args)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise

    fractions = np.array([covered_fraction(cam, V, N, img[..., 3]) for cam, img in zip(cameras, images)])
    coverage_ok = bool(fractions.min() > 0.97) and projection_error < 0.01
    print(f"self-check: front-facing vertices projected onto alpha >= 0.5 pixels: min {fractions.min():.4f} "
          f"(view {int(fractions.argmin())}), mean {fractions.mean():.4f} over {args.views} views: "
          + ("ok" if coverage_ok else "FAIL (camera conventions wrong?)"), flush=True)

    # From here on render_capture.py's post-processing.
    exposure, clipped = rc.capture_exposure(images)

    def encode8(img):
        if args.tone == "filmic":
            return filmic_encode8(scene, img[..., :3], exposure, tmp)
        return rc.srgb_encode8(img[..., :3] * exposure)

    names, labels, noise = rc.write_photographs(out, images, twin_ids, twins, encode8, write_png)

    rc.write_projects_and_cameras(out, cameras, names, labels, twin_ids if args.noise_twin else None)

    cyc = scene.cycles
    info = dict(
        tool="bench/capture/render_capture_cycles.py", renderer="Blender Cycles",
        blender_version=bpy.app.version_string, device="CPU", threads=args.threads,
        arguments={k: v for k, v in vars(args).items()},
        mesh=dict(source=os.path.basename(args.mesh), vertices=int(len(V)), faces=int(len(F)),
                  bbox_min=lo.tolist(), bbox_max=hi.tolist(), bounding_radius=radius,
                  normals="mesh.ply's area-weighted vertex normals, as Blender custom normals"),
        material=material,
        albedo="smooth field of positions: 3 sinusoids per channel + 5 soft patches, seeded; clamp [0.12, 0.85]",
        lights=lights,
        integrator=dict(type="Cycles path tracing", max_bounces=cyc.max_bounces, diffuse_bounces=cyc.diffuse_bounces,
                        glossy_bounces=cyc.glossy_bounces, sample_clamp_direct=cyc.sample_clamp_direct,
                        sample_clamp_indirect=cyc.sample_clamp_indirect, blur_glossy=cyc.blur_glossy,
                        caustics_reflective=cyc.caustics_reflective, sampling_pattern=cyc.sampling_pattern,
                        adaptive_sampling=cyc.use_adaptive_sampling, denoising=cyc.use_denoising,
                        film_transparent=scene.render.film_transparent),
        # "film": width and height as in the Mitsuba captures (check_capture.py reads them)
        film=dict(width=args.width, height=args.height, pixel_filter=cyc.pixel_filter_type,
                  pixel_filter_width_px=cyc.filter_width, spp=args.spp,
                  output="32-bit float OpenEXR, linear, premultiplied RGBA, rows flipped to top-down"),
        fov_x_degrees=fov_x, fov_y_degrees=args.fov_y,
        # origin/target/up as the Mitsuba captures' sensors (check_capture.py rebuilds Mitsuba look_ats
        # from them), plus the Blender camera's matrix_world
        sensors=[dict(origin=o.tolist(), target=t.tolist(), up=u.tolist(), blender_matrix_world=m.tolist())
                 for (o, t, u), m in zip(views, blender_matrices)],
        tone=dict(exposure=exposure,
                  mapping=("8-bit sRGB of clamp(exposure * linear radiance, 0, 1)" if args.tone == "standard" else
                           "8-bit Blender Filmic view transform (look None) of exposure * linear radiance "
                           "(view exposure log2(exposure) stops)"),
                  fraction_of_covered_pixels_clipped=clipped),
        noise_twin=noise,
        seeds=dict(rule="scene.cycles.seed per render", photos=f"{args.seed * 100003} + view",
                   twin=f"{args.seed * 100003 + 50021} + view"),
        self_check=dict(blender_vs_opencv_projection_max_px=projection_error,
                        front_facing_vertices_on_alpha_min=float(fractions.min()),
                        front_facing_vertices_on_alpha_mean=float(fractions.mean()), ok=coverage_ok),
        render_seconds=dict(scene_setup=setup_s, photos_total=float(sum(times)),
                            photos_per_view_median=float(np.median(times)), twin_total=float(sum(twin_times))),
    )
    shutil.rmtree(tmp, ignore_errors=True)
    with open(os.path.join(out, "capture.json"), "w") as f:
        json.dump(info, f, indent=1)
    print(f"wrote {out}: {args.views} views {args.width}x{args.height} at {args.spp} spp (Cycles), "
          f"render {sum(times):.0f} s (+ twin {sum(twin_times):.0f} s), exposure {exposure:.4g}, "
          f"clipped {100 * clipped:.2f} % of covered pixels"
          + (f", per-photo noise {noise['per_photo_rms_noise_srgb_levels']:.2f} sRGB levels" if noise else ""),
          flush=True)
    return 0 if coverage_ok else 1


if __name__ == "__main__":
    # Blender reports an uncaught exception in a --python script and still exits with status 0.
    try:
        status = main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
    except Exception:
        traceback.print_exc()
        status = 1
    sys.exit(status)
