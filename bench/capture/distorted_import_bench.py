"""Issue 29's target: a capture rendered by an independent path tracer (bench/capture/render_capture.py,
Mitsuba 3), distorted here by a known lens, written as a COLMAP binary model, a COLMAP text model
(both by the real pycolmap) and an Agisoft Metashape camera XML, imported by
"Import Cameras as Raster Layers" and fitted; the fit is compared with the fit from the exact
pinhole project. Prints, per format, the mean |difference| of the fitted colours in 8-bit sRGB levels
over the vertices both fits see (the vertices' mean colours, and the radiance evaluated toward the
first camera), and the import time.

The distorted photographs: for every pixel centre of the distorted image, the lens is inverted
(Newton's method, to 1e-12) to the ideal pinhole ray, and the capture's photograph is sampled there
(Keys cubic by default, or bilinear, on linear light). The import then resamples once more through
the forward model: the figures include both resamplings' blur, as a real lens's photographs would not.

  --large N: also times the import of N synthetic 24 MP photographs with distortion (and prints the
  process's peak memory; give no capture to time only that, in a fresh process).

Run with the Python that has pymeshlab, pycolmap and our plugins:
  PYTHONPATH=<checkout>/python PYMESHLAB_RADIANCE_PLUGIN_DIR=<build>/pymeshlab_plugins \\
    <build>/python-venv/bin/python bench/capture/distorted_import_bench.py CAPTURES/bunny_plastic_40 --work /tmp/d
"""
import argparse
import os
import shutil
import resource
import struct
import sys
import time
import xml.etree.ElementTree as ET
import zlib

import numpy as np
import pycolmap
import pymeshlab
import pymeshlab_radiance  # noqa: F401  (loads our plugins)
from pymeshlab_radiance.thumbnail import write_png

IMPORT = "radiance_import_cameras_as_rasters"
FIT = "radiance_fit_radiance_functions_from_rasters"
EVALUATE = "radiance_evaluate_radiance_toward_a_viewpoint_as_vertex_color"
# The known lens (OpenCV's order; focal lengths and principal point from each camera).
K1, K2, P1, P2 = -0.12, 0.03, 0.0008, -0.0005


def srgb_decode(code):
    s = np.asarray(code, dtype=float) / 255.0
    return np.where(s <= 0.04045, s / 12.92, ((s + 0.055) / 1.055) ** 2.4)


def srgb_encode(x):
    x = np.clip(x, 0.0, 1.0)
    return np.round(255.0 * np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)).astype(np.uint8)


def read_png_rgb(path):
    """8-bit RGB/RGBA PNG -> (H, W, 3) uint8 (filters 0-4, no interlace)."""
    data = open(path, "rb").read()
    pos, idat, width = 8, b"", 0
    while pos < len(data):
        length, tag = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if tag == b"IHDR":
            width, height, depth, colour = struct.unpack(">IIBB", body[:10])
            assert depth == 8 and colour in (2, 6), (path, depth, colour)
            channels = 3 if colour == 2 else 4
        elif tag == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    stride = width * channels
    out = np.zeros((height, stride), dtype=np.int32)
    previous = np.zeros(stride, dtype=np.int32)
    for r in range(height):
        f = raw[r * (stride + 1)]
        line = np.frombuffer(raw, dtype=np.uint8, count=stride, offset=r * (stride + 1) + 1).astype(np.int32)
        if f == 0:
            cur = line
        elif f == 2:
            cur = (line + previous) & 255
        else:
            cur = np.zeros(stride, dtype=np.int32)
            for i in range(stride):
                a = cur[i - channels] if i >= channels else 0
                b = previous[i]
                c = previous[i - channels] if i >= channels else 0
                if f == 1:
                    pred = a
                elif f == 3:
                    pred = (a + b) // 2
                else:
                    p = a + b - c
                    pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                    pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                cur[i] = (line[i] + pred) & 255
        out[r] = cur
        previous = cur
    return out.reshape(height, width, channels)[:, :, :3].astype(np.uint8)


def project_cameras(project):
    """(label, image path, R (world->camera, OpenCV axes), C, fx, fy, cx, cy, W, H) from a .mlp."""
    out = []
    for raster in ET.parse(project).getroot().iter("MLRaster"):
        c = raster.find("VCGCamera")
        get = lambda k: np.array([float(x) for x in c.get(k).split()])
        rows = get("RotationMatrix").reshape(4, 4)[:3, :3]
        R = np.array([rows[0], -rows[1], -rows[2]])
        W, H = get("ViewportPx").astype(int)
        fx = get("FocalMm")[0] / get("PixelSizeMm")[0]
        fy = get("FocalMm")[0] / get("PixelSizeMm")[1]
        out.append((raster.get("label"), os.path.join(os.path.dirname(project), raster.find("Plane").get("fileName")),
                    R, -get("TranslationVector")[:3], fx, fy, get("CenterPx")[0], H - get("CenterPx")[1], W, H))
    return out


def distort(x, y):
    r2 = x * x + y * y
    radial = 1 + K1 * r2 + K2 * r2 * r2
    return (x * radial + 2 * P1 * x * y + P2 * (r2 + 2 * x * x), y * radial + P1 * (r2 + 2 * y * y) + 2 * P2 * x * y)


def undistort(xd, yd):
    """Newton's method on the 2D map (numerical Jacobian), from the distorted point."""
    x, y = xd.copy(), yd.copy()
    for _ in range(30):
        fx, fy = distort(x, y)
        ex, ey = fx - xd, fy - yd
        h = 1e-7
        ax, ay = distort(x + h, y)
        bx, by = distort(x, y + h)
        j11, j21, j12, j22 = (ax - fx) / h, (ay - fy) / h, (bx - fx) / h, (by - fy) / h
        det = j11 * j22 - j12 * j21
        x -= (j22 * ex - j12 * ey) / det
        y -= (-j21 * ex + j11 * ey) / det
        if max(np.abs(ex).max(), np.abs(ey).max()) < 1e-12:
            break
    return x, y


def bilinear(linear, u, v):
    H, W = linear.shape[:2]
    fu, fv = np.clip(u - 0.5, 0, W - 1), np.clip(v - 0.5, 0, H - 1)
    c0, r0 = np.minimum(np.floor(fu).astype(int), W - 2), np.minimum(np.floor(fv).astype(int), H - 2)
    a, b = (fu - c0)[..., None], (fv - r0)[..., None]
    return ((1 - a) * (1 - b) * linear[r0, c0] + a * (1 - b) * linear[r0, c0 + 1] + (1 - a) * b * linear[r0 + 1, c0]
            + a * b * linear[r0 + 1, c0 + 1])


def keys_weights(t):
    """Keys (1981) cubic convolution weights (a = -0.5) of the 4 taps around fraction t."""
    a = -0.5
    d = np.stack([1 + t, t, 1 - t, 2 - t], axis=-1)
    near = ((a + 2) * d - (a + 3)) * d * d + 1
    far = ((a * d - 5 * a) * d + 8 * a) * d - 4 * a
    return np.where(d <= 1, near, far)


def bicubic(linear, u, v):
    """Keys cubic interpolation (sharper than bilinear: the bench's own resampling should blur as
    little as it can, so that the figures measure the import's), clamped to [0, 1]."""
    H, W = linear.shape[:2]
    fu, fv = np.clip(u - 0.5, 0, W - 1), np.clip(v - 0.5, 0, H - 1)
    c0, r0 = np.floor(fu).astype(int), np.floor(fv).astype(int)
    wu, wv = keys_weights(fu - c0), keys_weights(fv - r0)
    out = np.zeros(u.shape + (3,))
    for i in range(4):
        rows = np.clip(r0 - 1 + i, 0, H - 1)
        for j in range(4):
            cols = np.clip(c0 - 1 + j, 0, W - 1)
            out += (wv[..., i] * wu[..., j])[..., None] * linear[rows, cols]
    return np.clip(out, 0.0, 1.0)


def distorted_photograph(rgb, fx, fy, cx, cy, interpolation):
    H, W = rgb.shape[:2]
    v, u = np.mgrid[0:H, 0:W] + 0.5
    x, y = undistort((u - cx) / fx, (v - cy) / fy)
    sample = bicubic if interpolation == "cubic" else bilinear
    return srgb_encode(sample(srgb_decode(rgb), fx * x + cx, fy * y + cy))


def write_models(cameras, work):
    rec = pycolmap.Reconstruction()
    sensors, metashape = [], []
    for i, (label, _, R, C, fx, fy, cx, cy, W, H) in enumerate(cameras, start=1):
        fx, fy, cx, cy, W, H = float(fx), float(fy), float(cx), float(cy), int(W), int(H)
        camera = pycolmap.Camera.create_from_model_name(i, "OPENCV", fx, int(W), int(H))
        camera.params = [fx, fy, cx, cy, K1, K2, P1, P2]
        rec.add_camera_with_trivial_rig(camera)
        pose = pycolmap.Rigid3d(pycolmap.Rotation3d(R), (-R @ C).reshape(3, 1))
        rec.add_image_with_trivial_frame(pycolmap.Image(name=label + ".png", camera_id=i, image_id=i), pose)
        sensors.append(f'<sensor id="{i}" label="s{i}" type="frame"><resolution width="{W}" height="{H}"/>'
                       f'<calibration type="frame" class="adjusted"><resolution width="{W}" height="{H}"/>'
                       f'<f>{fy!r}</f><cx>{cx - W / 2!r}</cx><cy>{cy - H / 2!r}</cy><b1>{fx - fy!r}</b1>'
                       f'<k1>{K1!r}</k1><k2>{K2!r}</k2><p1>{P2!r}</p1><p2>{P1!r}</p2></calibration></sensor>')
        m = np.eye(4)
        m[:3, :3], m[:3, 3] = R.T, C
        metashape.append(f'<camera id="{i}" sensor_id="{i}" label="{label}"><transform>'
                         f'{" ".join(repr(float(x)) for x in m.ravel())}</transform></camera>')
    for kind in ("bin", "txt"):
        os.makedirs(os.path.join(work, "sparse_" + kind), exist_ok=True)
    rec.write_binary(os.path.join(work, "sparse_bin"))
    rec.write_text(os.path.join(work, "sparse_txt"))
    with open(os.path.join(work, "cameras.xml"), "w") as f:
        f.write('<?xml version="1.0" encoding="UTF-8"?>\n<document version="1.5.0"><chunk label="c">'
                f'<sensors>{"".join(sensors)}</sensors><cameras>{"".join(metashape)}</cameras></chunk></document>\n')


def fit(mesh, viewpoint, project=None, camerafile=None, imagefolder=None, cache=None):
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(mesh)
    start = time.time()
    if project:
        ms.load_project(project)
    else:
        ms.apply_filter(IMPORT, camerafile=camerafile, imagefolder=imagefolder, cachefolder=cache)
    seconds = time.time() - start
    ms.apply_filter(FIT)
    m = ms.current_mesh()
    mean = m.vertex_color_matrix()[:, :3].copy()
    seen = m.vertex_scalar_array().copy() > 0
    ms.apply_filter(EVALUATE, viewpoint=viewpoint)
    return mean, ms.current_mesh().vertex_color_matrix()[:, :3].copy(), seen, seconds


def peak_rss_reset():
    """Resets the process's peak resident memory (Linux: clear_refs 5), so VmHWM then measures what follows."""
    with open("/proc/self/clear_refs", "w") as f:
        f.write("5")


def peak_rss_mib():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 1024.0
    return float("nan")


def large_import(work, count):
    W, H = 6000, 4000
    folder = os.path.join(work, "large")
    os.makedirs(folder, exist_ok=True)
    names = [f"large_{i:03d}.png" for i in range(1, count + 1)]
    if not all(os.path.exists(os.path.join(folder, n)) for n in names):
        v, u = np.mgrid[0:H, 0:W].astype(np.int32)
        rgb = np.stack([(u * 7 + v * 3) % 256, (u // 3 + v // 5) % 256, (u ^ v) % 256], axis=-1).astype(np.uint8)
        del u, v
        # One encoding, copied: every photograph is still a file of its own, decoded on import.
        first = os.path.join(folder, names[0])
        if not os.path.exists(first):
            write_png(first, rgb)
        for n in names[1:]:
            if not os.path.exists(os.path.join(folder, n)):
                shutil.copyfile(first, os.path.join(folder, n))
        del rgb
    for model, params in (("PINHOLE", [5000.0, 5000.0, W / 2, H / 2]), ("OPENCV", [5000.0, 5000.0, W / 2, H / 2, K1, K2, P1, P2])):
        rec = pycolmap.Reconstruction()
        camera = pycolmap.Camera.create_from_model_name(1, model, 5000.0, W, H)
        camera.params = params
        rec.add_camera_with_trivial_rig(camera)
        for i, name in enumerate(names, start=1):
            rec.add_image_with_trivial_frame(pycolmap.Image(name=name, camera_id=1, image_id=i),
                                             pycolmap.Rigid3d(pycolmap.Rotation3d(np.eye(3)), np.array([[0.0], [0.0], [3.0]])))
        sparse = os.path.join(folder, "sparse_" + model.lower())
        os.makedirs(sparse, exist_ok=True)
        rec.write_binary(sparse)
        cache = os.path.join(folder, "cache")
        if os.path.isdir(cache):
            for f in os.listdir(cache):
                os.remove(os.path.join(cache, f))
        ms = pymeshlab.MeshSet()
        peak_rss_reset()
        before = peak_rss_mib()
        start = time.time()
        ms.apply_filter(IMPORT, camerafile=sparse, imagefolder=folder, cachefolder=cache)
        seconds = time.time() - start
        what = "decoded only (PINHOLE: used as they are)" if model == "PINHOLE" else "decoded, undistorted, written to the cache (OPENCV)"
        print(f"{count} photographs of 24 MP (6000x4000) {what}: {seconds:.1f} s, {seconds / count:.2f} s per photograph; "
              f"peak resident memory {peak_rss_mib():.0f} MiB (at the start {before:.0f} MiB)")
        del ms


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("capture", nargs="?", help="a capture folder (mesh.ply, project.mlp, photos/)")
    parser.add_argument("--work", required=True, help="folder for the distorted photographs and the models")
    parser.add_argument("--interpolation", choices=("cubic", "linear"), default="cubic",
                        help="how the bench resamples the capture's photographs into distorted ones")
    parser.add_argument("--large", type=int, default=0, help="also time the import of N synthetic 24 MP photographs")
    args = parser.parse_args()
    work = os.path.abspath(args.work)
    if args.capture is None:  # only the timing of large photographs (a fresh process: its peak memory is the import's)
        large_import(work, args.large)
        return 0
    images = os.path.join(work, "images_" + args.interpolation)
    os.makedirs(images, exist_ok=True)
    capture = os.path.abspath(args.capture)
    cameras = project_cameras(os.path.join(capture, "project.mlp"))
    start = time.time()
    for label, path, R, C, fx, fy, cx, cy, W, H in cameras:
        out = os.path.join(images, label + ".png")
        if not os.path.exists(out):
            write_png(out, distorted_photograph(read_png_rgb(path), fx, fy, cx, cy, args.interpolation))
    print(f"{len(cameras)} photographs distorted (k1 {K1}, k2 {K2}, p1 {P1}, p2 {P2}; {args.interpolation} "
          f"resampling) in {time.time() - start:.1f} s")
    write_models(cameras, work)
    mesh = os.path.join(capture, "mesh.ply")
    viewpoint = cameras[0][3]
    reference_mean, reference_view, reference_seen, t = fit(mesh, viewpoint, project=os.path.join(capture, "project.mlp"))
    print(f"{'format':<22} {'import s':>8} {'vertices':>9} {'mean colour':>12} {'toward view 0':>14}   (mean |difference|, 8-bit levels)")
    print(f"{'pinhole project':<22} {t:8.2f} {int(reference_seen.sum()):9d} {0:12.3f} {0:14.3f}")
    for name, camerafile in (("COLMAP binary", os.path.join(work, "sparse_bin")),
                             ("COLMAP text", os.path.join(work, "sparse_txt")),
                             ("Metashape XML", os.path.join(work, "cameras.xml"))):
        mean, view, seen, t = fit(mesh, viewpoint, camerafile=camerafile, imagefolder=images,
                                  cache=os.path.join(work, f"cache_{args.interpolation}_" + name.split()[-1].lower()))
        both = seen & reference_seen
        d_mean = np.abs(mean[both] - reference_mean[both]).mean() * 255.0
        d_view = np.abs(view[both] - reference_view[both]).mean() * 255.0
        print(f"{name:<22} {t:8.2f} {int(both.sum()):9d} {d_mean:12.3f} {d_view:14.3f}")
    if args.large:
        large_import(work, args.large)


if __name__ == "__main__":
    sys.exit(main())
