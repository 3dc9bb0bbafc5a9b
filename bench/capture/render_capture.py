#!/usr/bin/env python3
"""Test captures rendered by an independent physically based path tracer (Mitsuba 3, scalar_rgb
variant, CPU): calibrated 8-bit photographs of a scanned mesh with a glossy, spatially varying
material, written as a MeshLab project that MeshLab and our fit filter load.

    render_capture.py --mesh bunny00.off --material plastic --lights keyfill --views 40 \
        --noise-twin --out captures/bunny_plastic_40

writes in --out
    mesh.ply               the mesh as rendered (binary PLY: positions, unit per-vertex normals, faces);
                           NOT its albedo
    photos/view_XXX.png    8-bit sRGB photographs (linear radiance times one exposure per capture,
                           clamped, sRGB-encoded)
    masks/view_XXX.png     the object's coverage of each pixel (path tracer alpha), 8-bit
    photos_twin/...        with --noise-twin: every view again with other sampler seeds, same exposure
    project.mlp            MeshLab project: the photographs as rasters with their cameras, EMPTY
                           MeshGroup (load mesh.ply first: pymeshlab load_new_mesh + load_project,
                           meshlabserver -i mesh.ply -p project.mlp)
    project_with_mesh.mlp  the same rasters plus mesh.ply in the MeshGroup (MeshLab File > Open Project)
    cameras.json           per view: OpenCV intrinsics/extrinsics (x_cam = R X + t, pixel centres at
                           integer coordinates), image size, camera centre
    capture.json           every parameter, the material, Mitsuba's version, the exact Mitsuba look_at
                           of each sensor, exposure, render times, the photographs' own noise
    truth/albedo.ply       the per-vertex base colour that was rendered (ground truth; not for the fit)

Cameras: a golden-spiral (Fibonacci) set of directions on the sphere (by default the upper 3/4 of it
around --up), distance jittered, each looking at the centre of the bounding box, the bounding sphere
filling the frame's height. Mitsuba's perspective look_at camera has camera axes x = left, y = up,
z = forward; in OpenCV's convention R's rows are (-left, -up, forward); fx = fy = (W/2) / tan(fov_x/2);
the principal point is the image centre: (W/2, H/2) in continuous image coordinates (pixel (c, r)
covers [c, c+1) x [r, r+1)), i.e. (W/2 - 0.5, H/2 - 0.5) in OpenCV's integer-centre convention.
MeshLab's VCGCamera (vcglib's Shot): RotationMatrix rows = (right, up, backwards) = diag(1,-1,-1) R,
TranslationVector = -C (minus the camera centre), FocalMm / PixelSizeMm = focal in pixels,
CenterPx = (W/2, H - H/2) with y from the image's bottom edge. check_capture.py verifies all this
against Mitsuba's own position/coverage output.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np


# ---------------------------------------------------------------------------------------------------
# Meshes

def read_off(path):
    with open(path, "r") as f:
        tokens = []
        for line in f:
            line = line.split("#", 1)[0].strip()
            if line:
                tokens.extend(line.split())
    if not tokens[0].upper().endswith("OFF"):
        raise ValueError(f"{path}: not an OFF file")
    pos = 1
    if tokens[0].upper() != "OFF":
        raise ValueError(f"{path}: only plain OFF is supported (got {tokens[0]})")
    nv, nf = int(tokens[pos]), int(tokens[pos + 1])
    pos += 3
    V = np.array(tokens[pos:pos + 3 * nv], dtype=np.float64).reshape(nv, 3)
    pos += 3 * nv
    polygons = []
    for _ in range(nf):
        k = int(tokens[pos])
        polygons.append([int(t) for t in tokens[pos + 1:pos + 1 + k]])
        pos += 1 + k
    return V, triangulate(polygons)


def triangulate(polygons):
    """Fan triangulation of a list of index lists: (n, 3) int64."""
    return np.array([(p[0], p[j], p[j + 1]) for p in polygons for j in range(1, len(p) - 1)],
                    dtype=np.int64).reshape(-1, 3)


def read_mesh(path, mi):
    """Positions (float64) and triangles of an OFF (read here), PLY or OBJ (read by Mitsuba)."""
    ext = os.path.splitext(path)[1].lower()
    if ext == ".off":
        return read_off(path)
    if ext not in (".ply", ".obj"):
        raise ValueError(f"{path}: unsupported mesh format (OFF, PLY or OBJ)")
    shape = mi.load_dict({"type": ext[1:], "filename": os.path.abspath(path), "face_normals": True})
    V = np.array(shape.vertex_positions_buffer(), dtype=np.float64).reshape(-1, 3)
    F = np.array(shape.faces_buffer(), dtype=np.int64).reshape(-1, 3)
    return V, F


def clean_mesh(V, F):
    """Drops degenerate triangles and unreferenced vertices (the fit sees exactly what was rendered)."""
    ok = (F[:, 0] != F[:, 1]) & (F[:, 1] != F[:, 2]) & (F[:, 0] != F[:, 2])
    area2 = np.linalg.norm(np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]), axis=1)
    F = F[ok & (area2 > 0)]
    used = np.zeros(len(V), bool)
    used[F.ravel()] = True
    remap = -np.ones(len(V), np.int64)
    remap[used] = np.arange(used.sum())
    return V[used], remap[F]


def vertex_normals(V, F):
    """Area-weighted unit vertex normals."""
    fn = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])  # length = 2 area
    N = np.zeros_like(V)
    for k in range(3):
        np.add.at(N, F[:, k], fn)
    length = np.linalg.norm(N, axis=1, keepdims=True)
    return N / np.where(length > 0, length, 1.0)


def write_ply(path, V, F, normals=None, colors=None, gloss=None):
    """Binary little-endian PLY: float x y z [nx ny nz] [float r g b] [float gloss], uchar-count int faces."""
    fields = [("x", "<f4"), ("y", "<f4"), ("z", "<f4")]
    if normals is not None:
        fields += [("nx", "<f4"), ("ny", "<f4"), ("nz", "<f4")]
    if colors is not None:
        fields += [("r", "<f4"), ("g", "<f4"), ("b", "<f4")]
    if gloss is not None:
        fields += [("gloss_x", "<f4")]  # Mitsuba groups attributes by postfix: "gloss_x" loads as vertex_gloss
    vert = np.empty(len(V), dtype=fields)
    vert["x"], vert["y"], vert["z"] = V.T
    if normals is not None:
        vert["nx"], vert["ny"], vert["nz"] = normals.T
    if colors is not None:
        vert["r"], vert["g"], vert["b"] = colors.T
    if gloss is not None:
        vert["gloss_x"] = gloss
    face = np.empty(len(F), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    face["n"] = 3
    face["i"] = F
    header = ["ply", "format binary_little_endian 1.0", f"element vertex {len(V)}"]
    header += [f"property float {name}" for name, _ in fields]
    header += [f"element face {len(F)}", "property list uchar int vertex_indices", "end_header"]
    with open(path, "wb") as f:
        f.write(("\n".join(header) + "\n").encode("ascii"))
        f.write(vert.tobytes())
        f.write(face.tobytes())


# ---------------------------------------------------------------------------------------------------
# Material, lights, cameras

MATERIALS = {
    # Mitsuba's principled BSDF (Burley 2012, 2015); base_color is the per-vertex albedo.
    "plastic": dict(roughness=0.28, specular=0.5, metallic=0.0),
    "metal": dict(roughness=0.3, specular=0.5, metallic=0.9),
    "matte": dict(roughness=0.8, specular=0.1, metallic=0.0),
}
# "mixed": the plastic where a smooth per-vertex gloss field is 1, the matte where it is 0 (Mitsuba's
# blendbsdf, weight = the gloss): a glossy object with matte regions, the case the shared fit's
# per-vertex guard is there for.
MIXED = ("matte", "plastic")


# The "keyfill" lights, shared by both renderers: (name, direction as weights of (a, u, b) of
# up_frame, distance / bounding radius, light radius / bounding radius, irradiance at the centre / pi),
# and the faint sky's radiance. The studio setup uses the key alone.
KEYFILL_LIGHTS = (("key", (0.55, 0.75, 0.35), 4.0, 0.25, 1.0),
                  ("fill", (-0.6, 0.2, 0.75), 4.0, 0.4, 0.35))
SKY_RADIANCE = (0.08, 0.08, 0.09)


def light_direction(weights, up):
    """Unit direction of a KEYFILL_LIGHTS entry for the mesh's up axis."""
    u, a, b = up_frame(up)
    wa, wu, wb = weights
    direction = wa * a + wu * u + wb * b
    return direction / np.linalg.norm(direction)


def up_frame(up):
    u = np.zeros(3)
    u["xyz".index(up)] = 1.0
    a = np.roll(u, 1)
    b = np.cross(u, a)
    return u, a, b


def albedo_field(V, seed):
    """A smooth, spatially varying RGB albedo in [0.12, 0.85] from positions: three random
    sinusoids per channel plus a few soft coloured patches, deterministic from the seed."""
    rng = np.random.default_rng(seed)
    lo, hi = V.min(0), V.max(0)
    scale = float(np.linalg.norm(hi - lo))
    X = (V - 0.5 * (lo + hi)) / scale  # ~[-0.5, 0.5]
    base = np.array([0.55, 0.45, 0.35]) + 0.1 * rng.uniform(-1, 1, 3)
    col = np.tile(base, (len(V), 1))
    for c in range(3):
        for _ in range(3):
            k = rng.normal(size=3)
            k *= rng.uniform(4.0, 9.0) / np.linalg.norm(k)
            col[:, c] += 0.08 * np.sin(X @ k * 2 * np.pi / 3 + rng.uniform(0, 2 * np.pi))
    for _ in range(5):  # soft patches of another colour
        centre = X[rng.integers(len(X))]
        radius = rng.uniform(0.08, 0.18)
        w = np.exp(-np.sum((X - centre) ** 2, axis=1) / (2 * radius ** 2))[:, None]
        col = col * (1 - w) + w * rng.uniform(0.1, 0.85, 3)[None, :]
    return np.clip(col, 0.12, 0.85)


def gloss_field(V, seed):
    """A smooth per-vertex weight in [0, 1] from positions: a random plane wave through the object,
    sharpened, so that about half of the surface is glossy and half matte with soft borders."""
    rng = np.random.default_rng(seed + 104729)
    lo, hi = V.min(0), V.max(0)
    X = (V - 0.5 * (lo + hi)) / float(np.linalg.norm(hi - lo))
    k = rng.normal(size=3)
    k *= 3.0 / np.linalg.norm(k)
    wave = np.sin(2 * np.pi * (X @ k) + rng.uniform(0, 2 * np.pi))
    return np.clip(0.5 + 2.0 * wave, 0.0, 1.0)


def camera_views(n, centre, radius, up, seed, fov_y_deg, whole_sphere, distance_jitter=0.12):
    """Golden-spiral directions (on the upper 3/4 of the sphere around `up`, or all of it), each at
    a distance where the bounding sphere fills the image height (times 1 .. 1+distance_jitter).
    Returns [(origin, target, up_vector)]."""
    rng = np.random.default_rng(seed + 7919)
    u, a, b = up_frame(up)
    zmin = -1.0 if whole_sphere else -0.5
    golden = math.pi * (3.0 - math.sqrt(5.0))
    base_distance = radius / math.sin(math.radians(fov_y_deg) / 2)
    views = []
    for i in range(n):
        z = 1.0 - (i + 0.5) / n * (1.0 - zmin)  # uniform in height = uniform in area
        z = min(z, 0.985)  # keep away from the pole, where the up vector degenerates
        r = math.sqrt(max(0.0, 1 - z * z))
        phi = i * golden
        d = z * u + r * (math.cos(phi) * a + math.sin(phi) * b)
        dist = base_distance * (1.0 + distance_jitter * rng.uniform())
        views.append((centre + dist * d, centre.copy(), u.copy()))
    return views


def fov_x_from_y(fov_y_deg, width, height):
    return math.degrees(2 * math.atan(math.tan(math.radians(fov_y_deg) / 2) * width / height))


# ---------------------------------------------------------------------------------------------------
# Camera conventions

def opencv_camera(to_world, fov_x_deg, width, height):
    """OpenCV camera (x_cam = R X + t; x right, y down, z forward; pixel centres at integers) of a
    Mitsuba perspective sensor with to_world matrix M (columns: left, up, forward, origin)."""
    M = np.asarray(to_world, dtype=np.float64)
    left, upv, fwd, C = M[:3, 0], M[:3, 1], M[:3, 2], M[:3, 3]
    R = np.stack([-left, -upv, fwd])
    fx = (width / 2) / math.tan(math.radians(fov_x_deg) / 2)
    return dict(R=R, t=-R @ C, centre=C, fx=fx, fy=fx, cx=width / 2 - 0.5, cy=height / 2 - 0.5,
                width=width, height=height)


def f32(v):
    """Shortest decimal that reads back as the float32 nearest to v (as MeshLab stores values)."""
    s = np.format_float_positional(np.float32(v), unique=True, trim="-")
    return "0" if s in ("-0", "0") else s


def vcg_camera_element(cam, pixel_size_mm=0.01):
    """<VCGCamera .../> of an OpenCV camera (see meshlab-platform.md 'Cameras in MeshLab projects')."""
    rows = np.diag([1.0, -1.0, -1.0]) @ cam["R"]  # right, up, backwards
    focal_mm = cam["fx"] * pixel_size_mm
    pixel = (pixel_size_mm, focal_mm / cam["fy"])
    centre_px = (cam["cx"] + 0.5, cam["height"] - 0.5 - cam["cy"])
    T = -cam["centre"]
    rot = " ".join(f32(rows[i, j]) if i < 3 and j < 3 else ("1" if i == j else "0")
                   for i in range(4) for j in range(4)) + " "
    return (f'<VCGCamera TranslationVector="{f32(T[0])} {f32(T[1])} {f32(T[2])} 1" LensDistortion="0 0" '
            f'ViewportPx="{cam["width"]} {cam["height"]}" PixelSizeMm="{f32(pixel[0])} {f32(pixel[1])}" '
            f'CenterPx="{f32(centre_px[0])} {f32(centre_px[1])}" FocalMm="{f32(focal_mm)}" '
            f'RotationMatrix="{rot}" CameraType="0" BinaryData="0"/>')


def write_mlp(path, cameras, image_files, labels, mesh_file=None):
    lines = ["<!DOCTYPE MeshLabDocument>", "<MeshLabProject>"]
    if mesh_file is None:
        lines.append(" <MeshGroup/>")
    else:
        lines += [" <MeshGroup>", f'  <MLMesh label="{mesh_file}" filename="{mesh_file}" visible="1">',
                  "   <MLMatrix44>", "1 0 0 0 ", "0 1 0 0 ", "0 0 1 0 ", "0 0 0 1 ", "</MLMatrix44>",
                  "  </MLMesh>", " </MeshGroup>"]
    lines.append(" <RasterGroup>")
    for cam, image, label in zip(cameras, image_files, labels):
        lines += [f'  <MLRaster label="{label}">', "   " + vcg_camera_element(cam),
                  f'   <Plane semantic="1" fileName="{image}"/>', "  </MLRaster>"]
    lines += [" </RasterGroup>", "</MeshLabProject>", ""]
    with open(path, "w") as f:
        f.write("\n".join(lines))


def render_photos_and_twins(render_view, args):
    """Every view rendered (render_view(i, seed) -> float RGBA image), then with --noise-twin the
    twin views (all, or --twin-views of them evenly spaced) with other seeds. Returns (images,
    seconds per image, twin view indices, twin images, their seconds)."""
    def render_all(seed_base, label, which):
        images, times = [], []
        for i in which:
            t = time.time()
            images.append(render_view(i, seed_base + i))
            times.append(time.time() - t)
            print(f"{label} view {i + 1}/{args.views}: {times[-1]:.1f} s", flush=True)
        return images, times

    images, times = render_all(args.seed * 100003, "photo", range(args.views))
    twin_ids = list(range(args.views))
    if args.twin_views and args.twin_views < args.views:
        twin_ids = sorted(set(np.linspace(0, args.views - 1, args.twin_views).round().astype(int).tolist()))
    twins, twin_times = (render_all(args.seed * 100003 + 50021, "twin", twin_ids) if args.noise_twin else ([], []))
    return images, times, twin_ids, twins, twin_times


def capture_exposure(images):
    """One exposure per capture: the 99.7th percentile of the brightest channel over covered pixels
    maps to 1. Returns (exposure, fraction of covered pixels clipped)."""
    covered = np.concatenate([img[..., :3][img[..., 3] > 0.999].max(axis=1) for img in images])
    exposure = 1.0 / float(np.percentile(covered, 99.7))
    return exposure, float(np.mean(covered * exposure >= 1.0))


def write_photographs(out, images, twin_ids, twins, encode8, save_png):
    """photos/ and masks/ of every view, photos_twin/ of the twins (encode8(image) -> 8-bit RGB,
    save_png(path, array)), and the photographs' own noise from the twins (None without them).
    Returns (file names, raster labels, noise)."""
    names = [f"view_{i:03d}.png" for i in range(len(images))]
    labels = [f"view_{i:03d}" for i in range(len(images))]
    for img, name in zip(images, names):
        save_png(os.path.join(out, "photos", name), encode8(img))
        save_png(os.path.join(out, "masks", name), np.round(np.clip(img[..., 3], 0, 1) * 255).astype(np.uint8))
    if not twins:
        return names, labels, None
    diffs = []
    for img, twin, name in zip([images[i] for i in twin_ids], twins, [names[i] for i in twin_ids]):
        a8, b8 = encode8(img), encode8(twin)
        save_png(os.path.join(out, "photos_twin", name), b8)
        both = (img[..., 3] > 0.999) & (twin[..., 3] > 0.999)
        diffs.append((a8[both].astype(float) - b8[both].astype(float)).ravel())
    d = np.concatenate(diffs)
    noise = dict(rms_difference_srgb_levels=float(np.sqrt(np.mean(d ** 2))),
                 per_photo_rms_noise_srgb_levels=float(np.sqrt(np.mean(d ** 2) / 2)),
                 views=[labels[i] for i in twin_ids] if len(twin_ids) < len(images) else "all",
                 over="covered pixels (alpha = 1 in both renders), every twin view, every channel")
    return names, labels, noise


def write_projects_and_cameras(out, cameras, names, labels, twin_ids=None):
    """project.mlp, project_with_mesh.mlp, project_twin.mlp (when twin_ids is given: the views
    rendered twice) and cameras.json of a capture whose photographs are photos/NAME."""
    write_mlp(os.path.join(out, "project.mlp"), cameras, [f"photos/{n}" for n in names], labels)
    write_mlp(os.path.join(out, "project_with_mesh.mlp"), cameras, [f"photos/{n}" for n in names], labels,
              mesh_file="mesh.ply")
    if twin_ids is not None:
        write_mlp(os.path.join(out, "project_twin.mlp"), [cameras[i] for i in twin_ids],
                  [f"photos_twin/{names[i]}" for i in twin_ids], [labels[i] for i in twin_ids])
    with open(os.path.join(out, "cameras.json"), "w") as f:
        json.dump(dict(
            convention="OpenCV: x_cam = R X + t (x right, y down, z forward), u = fx x/z + cx, v = fy y/z + cy, "
                       "pixel centres at integer (u, v), (0, 0) = centre of the top-left pixel; "
                       "centre = camera centre in world coordinates = -R^T t",
            views=[dict(image=f"photos/{n}", width=c["width"], height=c["height"], fx=c["fx"], fy=c["fy"],
                        cx=c["cx"], cy=c["cy"], R=c["R"].tolist(), t=c["t"].tolist(), centre=c["centre"].tolist())
                   for n, c in zip(names, cameras)]), f, indent=1)


# ---------------------------------------------------------------------------------------------------
# Images

def srgb_encode8(linear):
    x = np.clip(linear, 0.0, 1.0)
    s = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.round(s * 255.0).astype(np.uint8)


def write_png(mi, path, array_u8):
    bmp = mi.Bitmap(np.ascontiguousarray(array_u8),
                    pixel_format=mi.Bitmap.PixelFormat.Y if array_u8.ndim == 2 else mi.Bitmap.PixelFormat.RGB)
    bmp.write(path)


# ---------------------------------------------------------------------------------------------------

def build_scene(mi, args, render_ply, centre, radius, views, fov_x, hdr_path):
    def principled(material):
        return {"type": "principled", "base_color": {"type": "mesh_attribute", "name": "vertex_color"},
                "roughness": material["roughness"], "specular": material["specular"],
                "metallic": material["metallic"]}
    if args.material == "mixed":
        bsdf = {"type": "blendbsdf", "weight": {"type": "mesh_attribute", "name": "vertex_gloss"},
                "matte": principled(MATERIALS[MIXED[0]]), "glossy": principled(MATERIALS[MIXED[1]])}
    else:
        bsdf = principled(MATERIALS[args.material])
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": args.max_depth, "hide_emitters": True},
        "object": {"type": "ply", "filename": render_ply, "face_normals": False, "bsdf": bsdf},
    }
    lights = []

    def add_sphere_light(name, weights, dist, rad, power):
        r_light = rad * radius
        # radiance such that the irradiance at the centre is ~ pi * power
        L = power * (dist / rad) ** 2
        pos = centre + dist * radius * light_direction(weights, args.up)
        scene[name] = {"type": "sphere", "center": pos.tolist(), "radius": r_light,
                       "emitter": {"type": "area", "radiance": {"type": "rgb", "value": [L, L, L]}}}
        lights.append(dict(name=name, kind="sphere area light", position=pos.tolist(), radius=r_light,
                           radiance=L))

    if args.lights == "keyfill":
        # Two small spherical area lights (soft-edged shadows, glossy highlights) and a faint sky.
        for light in KEYFILL_LIGHTS:
            add_sphere_light(*light)
        scene["sky"] = {"type": "constant", "radiance": {"type": "rgb", "value": list(SKY_RADIANCE)}}
        lights.append(dict(name="sky", kind="constant environment", radiance=list(SKY_RADIANCE)))
    else:
        if hdr_path is None:
            raise SystemExit("--lights studio needs an environment map: --hdr PATH")
        # Map's up axis is Mitsuba's +y: rotate it onto --up.
        to_world = mi.ScalarTransform4f()
        if args.up == "z":
            to_world = mi.ScalarTransform4f().rotate([1, 0, 0], 90)
        elif args.up == "x":
            to_world = mi.ScalarTransform4f().rotate([0, 0, 1], -90)
        scene["env"] = {"type": "envmap", "filename": hdr_path, "scale": 1.0, "to_world": to_world}
        lights.append(dict(name="env", kind="environment map", file=os.path.basename(hdr_path)))
        add_sphere_light(*KEYFILL_LIGHTS[0])
    for i, (origin, target, upv) in enumerate(views):
        scene[f"sensor_{i:03d}"] = {
            "type": "perspective", "fov": fov_x, "fov_axis": "x",
            "near_clip": 0.01 * radius, "far_clip": 100.0 * radius,
            "to_world": mi.ScalarTransform4f().look_at(origin=origin.tolist(), target=target.tolist(), up=upv.tolist()),
            "film": {"type": "hdrfilm", "width": args.width, "height": args.height, "pixel_format": "rgba",
                     "rfilter": {"type": "box"}},
            "sampler": {"type": args.sampler, "sample_count": args.spp},
        }
    return scene, lights


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--mesh", required=True, help="OFF, PLY or OBJ")
    p.add_argument("--material", choices=sorted(MATERIALS) + ["mixed"], default="plastic",
                   help="mixed: plastic and matte blended by a smooth per-vertex gloss field (truth/albedo.ply, gloss_x)")
    p.add_argument("--lights", choices=["keyfill", "studio"], default="keyfill")
    p.add_argument("--hdr", default=None, help="equirectangular environment map for --lights studio (EXR/HDR)")
    p.add_argument("--views", type=int, default=40)
    p.add_argument("--width", type=int, default=512)
    p.add_argument("--height", type=int, default=384)
    p.add_argument("--spp", type=int, default=32)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--sampler", default="ldsampler", choices=["independent", "stratified", "multijitter", "ldsampler"],
                   help="Mitsuba sampler (low-discrepancy ones give less noise per sample)")
    p.add_argument("--up", choices=["x", "y", "z"], default="y", help="the mesh's up axis")
    p.add_argument("--whole-sphere", action="store_true", help="cameras on the whole sphere, not its upper 3/4")
    p.add_argument("--fov-y", type=float, default=38.0, help="vertical field of view in degrees")
    p.add_argument("--max-depth", type=int, default=3, help="Mitsuba path depth (2 = direct light only)")
    p.add_argument("--noise-twin", action="store_true", help="render every view again with other seeds into photos_twin/")
    p.add_argument("--twin-views", type=int, default=0,
                   help="with --noise-twin: re-render only this many views, evenly spaced (0: all)")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--out", required=True)
    args = p.parse_args(argv)

    import drjit as dr
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    dr.set_thread_count(args.threads)

    out = os.path.abspath(args.out)
    for sub in ("photos", "masks", "truth") + (("photos_twin",) if args.noise_twin else ()):
        os.makedirs(os.path.join(out, sub), exist_ok=True)

    V, F = read_mesh(args.mesh, mi)
    V, F = clean_mesh(V, F)
    N = vertex_normals(V, F)
    albedo = albedo_field(V, args.seed)
    write_ply(os.path.join(out, "mesh.ply"), V, F, normals=N)
    render_ply = os.path.join(out, "truth", "albedo.ply")
    gloss = gloss_field(V, args.seed) if args.material == "mixed" else None
    write_ply(render_ply, V, F, normals=N, colors=albedo, gloss=gloss)

    lo, hi = V.min(0), V.max(0)
    centre = 0.5 * (lo + hi)
    radius = float(np.linalg.norm(V - centre, axis=1).max())
    fov_x = fov_x_from_y(args.fov_y, args.width, args.height)
    views = camera_views(args.views, centre, radius, args.up, args.seed, args.fov_y, args.whole_sphere)
    hdr = os.path.abspath(args.hdr) if args.hdr else None
    scene_dict, lights = build_scene(mi, args, render_ply, centre, radius, views, fov_x, hdr)
    t0 = time.time()
    scene = mi.load_dict(scene_dict)
    load_s = time.time() - t0
    sensors = scene.sensors()
    assert len(sensors) == args.views

    cameras = []
    for s in sensors:
        cameras.append(opencv_camera(np.array(s.world_transform().matrix, dtype=np.float64), fov_x,
                                     args.width, args.height))

    images, times, twin_ids, twins, twin_times = render_photos_and_twins(
        lambda i, seed: np.array(mi.render(scene, sensor=i, seed=seed), dtype=np.float32), args)
    exposure, clipped = capture_exposure(images)

    names, labels, noise = write_photographs(out, images, twin_ids, twins,
                                             lambda img: srgb_encode8(img[..., :3] * exposure),
                                             lambda path, array: write_png(mi, path, array))

    write_projects_and_cameras(out, cameras, names, labels, twin_ids if args.noise_twin else None)

    info = dict(
        tool="bench/capture/render_capture.py", renderer="Mitsuba 3", mitsuba_version=mi.__version__,
        drjit_version=dr.__version__, variant="scalar_rgb", threads=args.threads,
        arguments={k: v for k, v in vars(args).items()},
        mesh=dict(source=os.path.basename(args.mesh), vertices=int(len(V)), faces=int(len(F)),
                  bbox_min=lo.tolist(), bbox_max=hi.tolist(), bounding_radius=radius),
        material=(dict(type="principled", base_color="per-vertex albedo (truth/albedo.ply, r g b)",
                       **MATERIALS[args.material]) if args.material != "mixed" else
                  dict(type="blendbsdf", weight="per-vertex gloss (truth/albedo.ply, gloss_x)",
                       bsdf_weight_0=dict(type="principled", **MATERIALS[MIXED[0]]),
                       bsdf_weight_1=dict(type="principled", **MATERIALS[MIXED[1]]),
                       glossy_fraction=float(np.mean(gloss > 0.5)))),
        albedo="smooth field of positions: 3 sinusoids per channel + 5 soft patches, seeded; clamp [0.12, 0.85]",
        lights=lights,
        integrator=dict(type="path", max_depth=args.max_depth, hide_emitters=True),
        film=dict(width=args.width, height=args.height, rfilter="box", spp=args.spp, sampler=args.sampler),
        fov_x_degrees=fov_x, fov_y_degrees=args.fov_y,
        sensors=[dict(origin=o.tolist(), target=t.tolist(), up=u.tolist()) for o, t, u in views],
        tone=dict(exposure=exposure, mapping="8-bit sRGB of clamp(exposure * linear radiance, 0, 1)",
                  fraction_of_covered_pixels_clipped=clipped),
        noise_twin=noise,
        seeds=dict(photos=f"{args.seed * 100003} + view", twin=f"{args.seed * 100003 + 50021} + view"),
        render_seconds=dict(scene_load=load_s, photos_total=float(sum(times)),
                            photos_per_view_median=float(np.median(times)), twin_total=float(sum(twin_times))),
    )
    with open(os.path.join(out, "capture.json"), "w") as f:
        json.dump(info, f, indent=1)
    print(f"wrote {out}: {args.views} views {args.width}x{args.height} at {args.spp} spp, "
          f"render {sum(times):.0f} s (+ twin {sum(twin_times):.0f} s), exposure {exposure:.4g}, "
          f"clipped {100 * clipped:.2f} % of covered pixels" + (f", per-photo noise {noise['per_photo_rms_noise_srgb_levels']:.2f} sRGB levels" if noise else ""))
    return 0


if __name__ == "__main__":
    sys.exit(main())
