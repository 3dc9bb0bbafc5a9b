#!/usr/bin/env python3
"""Checks a capture written by render_capture.py: that the cameras of its project.mlp, read here
independently of the writer (xml.etree + the VCGCamera projection of MeshLab's vcglib Shot), are the
cameras Mitsuba rendered the photographs with.

    check_capture.py CAPTURE_DIR [--aov-views 2] [--fit-python PYTHON [--held-out-every 5]]

Checks, each printed with its figure and asserted:
 1. every view: each mesh vertex in front of the camera projects onto a pixel the object covers in
    the photograph's own coverage mask (masks/, the path tracer's alpha), or one of its 8 neighbours
    (a vertex on the silhouette may fall on a pixel none of whose samples hit): >= 99 %;
 2. every view: the silhouette of the mesh rasterised here with the .mlp camera (pixel centres
    inside a projected triangle) against the mask (coverage > 1/2): IoU >= 0.97;
 3. a few views re-rendered with Mitsuba's `aov` integrator (position), rebuilt from the Mitsuba
    look_at values in capture.json (not from the .mlp): each fully covered pixel's mean hit position
    projected with the .mlp camera must land on that pixel's centre: mean offset < 0.05 px in u and v,
    median distance < 0.2 px. A half-pixel error in the principal point, a flipped axis or a wrong
    focal length fails this;
 4. the same views: the vertices whose projection hits a pixel whose mean hit position lies within
    1.5 pixel footprints of the vertex (visible, unoccluded) are >= 20 % of the front-facing ones
    (they are the ones the fit samples);
 5. with --fit-python (an interpreter with pymeshlab and our plugins: set PYTHONPATH and
    PYMESHLAB_RADIANCE_PLUGIN_DIR as tests/python/conftest.py describes): loads mesh.ply and
    project.mlp through pymeshlab, runs 'Fit Radiance Functions from Rasters' holding out every k-th
    raster, prints MeshLab's log lines and the held-out RMS (fitted / constant / colour projection)
    beside the photographs' own noise (capture.json, from the noise twin), and asserts the fit
    predicts held-out views no worse than the constant colour and, when the noise is known, within
    3 x the noise (misplaced cameras give errors of tens of levels). Writes check.json["fit"] and
    fit_check.log.
Exit status 1 when a check fails.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

import numpy as np


def read_ply(path):
    """Binary little-endian PLY with float vertex properties and a uchar/int face list."""
    with open(path, "rb") as f:
        header = []
        while True:
            line = f.readline().decode("ascii").strip()
            header.append(line)
            if line == "end_header":
                break
        assert "format binary_little_endian 1.0" in header, "expected a binary little-endian PLY"
        nv = nf = 0
        props = []
        element = None
        for line in header:
            t = line.split()
            if t[0] == "element":
                element = t[1]
                if element == "vertex":
                    nv = int(t[2])
                elif element == "face":
                    nf = int(t[2])
            elif t[0] == "property" and element == "vertex":
                assert t[1] == "float", line
                props.append(t[2])
        vert = np.frombuffer(f.read(4 * len(props) * nv), dtype="<f4").reshape(nv, len(props))
        face = np.frombuffer(f.read(13 * nf), dtype=[("n", "u1"), ("i", "<i4", (3,))])
        assert np.all(face["n"] == 3)
    V = vert[:, [props.index(k) for k in "xyz"]].astype(np.float64)
    N = vert[:, [props.index(k) for k in ("nx", "ny", "nz")]].astype(np.float64)
    return V, N, face["i"].astype(np.int64)


def read_mlp(path):
    """MeshLab's camera model (vcg::Shot): cp = R (X - C), cp.z = -cp.z, px = cp.x f / cp.z / s.x + c.x,
    py likewise, px from the left edge, py from the BOTTOM edge; R's rows = right, up, backwards;
    TranslationVector = -C."""
    views = []
    for raster in ET.parse(path).getroot().iter("MLRaster"):
        cam = raster[0]
        assert cam.tag == "VCGCamera", "VCGCamera must be the raster's first child"
        nums = lambda key: np.array([float(x) for x in cam.get(key).split()])  # noqa: E731
        assert cam.get("CameraType") == "0" and np.all(nums("LensDistortion") == 0)
        views.append(dict(label=raster.get("label"), rows=nums("RotationMatrix").reshape(4, 4)[:3, :3],
                          C=-nums("TranslationVector")[:3], focal=float(cam.get("FocalMm")),
                          pixel=nums("PixelSizeMm"), centre_px=nums("CenterPx"),
                          size=nums("ViewportPx").astype(int), image=raster.find("Plane").get("fileName")))
    return views


def project(view, X):
    """Image coordinates (u from the left, v from the TOP, continuous: pixel (c, r) covers
    [c, c+1) x [r, r+1)) and depth, with MeshLab's formula."""
    cp = (X - view["C"]) @ view["rows"].T
    depth = -cp[:, 2]
    safe = np.where(depth > 0, depth, 1.0)
    px = cp[:, 0] * view["focal"] / safe / view["pixel"][0] + view["centre_px"][0]
    py = cp[:, 1] * view["focal"] / safe / view["pixel"][1] + view["centre_px"][1]
    return px, view["size"][1] - py, depth


def rasterise(u, v, F, W, H):
    """Pixels whose centre lies inside (or on) a projected triangle."""
    mask = np.zeros((H, W), bool)
    tu, tv = u[F], v[F]
    x0 = np.clip(np.ceil(tu.min(1) - 0.5), 0, W).astype(int)
    x1 = np.clip(np.floor(tu.max(1) - 0.5), -1, W - 1).astype(int)
    y0 = np.clip(np.ceil(tv.min(1) - 0.5), 0, H).astype(int)
    y1 = np.clip(np.floor(tv.max(1) - 0.5), -1, H - 1).astype(int)
    w, h = x1 - x0, y1 - y0
    ok = (w >= 0) & (h >= 0)
    small = ok & (w < 12) & (h < 12)

    def inside(px, py, a, b):
        # same-side test against the three edges, either orientation
        e = []
        for i in range(3):
            j = (i + 1) % 3
            e.append((a[:, j] - a[:, i]) * (py - b[:, i]) - (b[:, j] - b[:, i]) * (px - a[:, i]))
        e = np.stack(e)
        return np.all(e >= 0, axis=0) | np.all(e <= 0, axis=0)

    idx = np.nonzero(small)[0]
    for dy in range(12):
        for dx in range(12):
            sel = idx[(w[idx] >= dx) & (h[idx] >= dy)]
            if len(sel) == 0:
                continue
            cx, cy = x0[sel] + dx, y0[sel] + dy
            hit = inside(cx + 0.5, cy + 0.5, tu[sel], tv[sel])
            mask[cy[hit], cx[hit]] = True
    for t in np.nonzero(ok & ~small)[0]:
        ys, xs = np.mgrid[y0[t]:y1[t] + 1, x0[t]:x1[t] + 1]
        xs, ys = xs.ravel(), ys.ravel()
        hit = inside(xs + 0.5, ys + 0.5, np.repeat(tu[t:t + 1], len(xs), 0), np.repeat(tv[t:t + 1], len(xs), 0))
        mask[ys[hit], xs[hit]] = True
    return mask


def read_gray(mi, path):
    return np.array(mi.Bitmap(path), dtype=np.float64).reshape(mi.Bitmap(path).height(), -1)


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("capture")
    p.add_argument("--project", default="project.mlp")
    p.add_argument("--aov-views", type=int, default=2, help="views re-rendered with positions (0: none)")
    p.add_argument("--aov-spp", type=int, default=16)
    p.add_argument("--fit-python", default=None, help="python with pymeshlab + pymeshlab_radiance")
    p.add_argument("--held-out-every", type=int, default=5)
    p.add_argument("--threads", type=int, default=2)
    args = p.parse_args(argv)

    import drjit as dr
    import mitsuba as mi
    mi.set_variant("scalar_rgb")
    dr.set_thread_count(args.threads)

    folder = os.path.abspath(args.capture)
    info = json.load(open(os.path.join(folder, "capture.json")))
    V, Nrm, F = read_ply(os.path.join(folder, "mesh.ply"))
    views = read_mlp(os.path.join(folder, args.project))
    failures = []
    report = {}

    def check(ok, text):
        print(("ok   " if ok else "FAIL ") + text, flush=True)
        if not ok:
            failures.append(text)

    # 1 and 2: every view against the photograph's own coverage mask.
    on_mask, strict_on_mask, ious, mirrored = [], [], [], []
    for view in views:
        W, H = view["size"]
        mask = read_gray(mi, os.path.join(folder, "masks", os.path.basename(view["image"]))) / 255.0
        assert mask.shape == (H, W)
        u, v, depth = project(view, V)
        front = (depth > 0) & (u >= 0) & (v >= 0) & (u < W) & (v < H)
        covered = mask > 0
        near = covered.copy()  # a covered pixel or one of its 8 neighbours: the pixel of a vertex ON
        for dy in (-1, 0, 1):  # the silhouette may get no sample of its own
            for dx in (-1, 0, 1):
                near[max(dy, 0):H + min(dy, 0), max(dx, 0):W + min(dx, 0)] |= \
                    covered[max(-dy, 0):H + min(-dy, 0), max(-dx, 0):W + min(-dx, 0)]
        r_, c_ = v[front].astype(int), u[front].astype(int)
        on_mask.append(np.mean(near[r_, c_]))
        strict_on_mask.append(np.mean(covered[r_, c_]))
        sil = rasterise(u, v, F, W, H)
        obj = mask > 0.5
        ious.append(np.sum(sil & obj) / np.sum(sil | obj))
        flipped = sil[:, ::-1]
        mirrored.append(np.sum(flipped & obj) / np.sum(flipped | obj))
    on_mask, ious = np.array(on_mask), np.array(ious)
    check(on_mask.min() >= 0.99, f"vertices projected onto covered pixels or their neighbours: min "
          f"{100 * on_mask.min():.3f} %, mean {100 * on_mask.mean():.3f} % over {len(views)} views (onto covered "
          f"pixels themselves: min {100 * min(strict_on_mask):.3f} %, mean {100 * np.mean(strict_on_mask):.3f} %)")
    check(ious.min() >= 0.97, f"silhouette IoU (.mlp camera rasterised vs Mitsuba coverage): min {ious.min():.4f}, "
          f"mean {ious.mean():.4f} (mirrored camera would give mean {np.mean(mirrored):.3f})")
    report.update(vertices_on_mask_min=float(on_mask.min()), vertices_on_covered_pixel_min=float(min(strict_on_mask)), iou_min=float(ious.min()), iou_mean=float(ious.mean()),
                  iou_mirrored_mean=float(np.mean(mirrored)))

    # 3 and 4: positions rendered by Mitsuba from capture.json's look_at values.
    if args.aov_views > 0:
        chosen = np.linspace(0, len(views) - 1, args.aov_views).round().astype(int)
        scene = {"type": "scene", "object": {"type": "ply", "filename": os.path.join(folder, "mesh.ply")}}
        film = info["film"]
        radius = info["mesh"]["bounding_radius"]
        for k, i in enumerate(chosen):
            s = info["sensors"][i]
            scene[f"s{k}"] = {"type": "perspective", "fov": info["fov_x_degrees"], "fov_axis": "x",
                              "near_clip": 0.01 * radius, "far_clip": 100.0 * radius,
                              "to_world": mi.ScalarTransform4f().look_at(origin=s["origin"], target=s["target"], up=s["up"]),
                              "film": {"type": "hdrfilm", "width": film["width"], "height": film["height"],
                                       "rfilter": {"type": "box"}},
                              "sampler": {"type": "independent", "sample_count": args.aov_spp}}
        scene = mi.load_dict(scene)
        aov = mi.load_dict({"type": "aov", "aovs": "pos:position,dd:depth"})
        offsets, visible_fraction = [], []
        for k, i in enumerate(chosen):
            view = views[i]
            W, H = view["size"]
            img = np.array(mi.render(scene, sensor=k, integrator=aov, seed=7 + k), dtype=np.float64)
            pos, depth_aov = img[..., :3], img[..., 3]
            mask = read_gray(mi, os.path.join(folder, "masks", os.path.basename(view["image"]))) / 255.0
            # fully covered pixels whose 8 neighbours are fully covered too (no silhouette mixing)
            full = mask >= 1.0
            inner = full.copy()
            for dy in (-1, 0, 1):
                for dx in (-1, 0, 1):
                    inner[1:-1, 1:-1] &= full[1 + dy:H - 1 + dy, 1 + dx:W - 1 + dx]
            inner[[0, -1], :] = False
            inner[:, [0, -1]] = False
            rr, cc = np.nonzero(inner)
            u, v, _ = project(view, pos[rr, cc])
            du, dv = u - (cc + 0.5), v - (rr + 0.5)
            offsets.append(np.stack([du, dv], 1))
            print(f"     view {view['label']}: {len(rr)} inner pixels, mean offset ({du.mean():+.4f}, {dv.mean():+.4f}) px, "
                  f"median |offset| {np.median(np.hypot(du, dv)):.3f} px")
            # 4: visible vertices = those whose pixel's mean hit position is the vertex (within 1.5 px footprints)
            uu, vv, dd = project(view, V)
            facing = np.sum(Nrm * (view["C"][None, :] - V), 1) > 0
            inimg = facing & (dd > 0) & (uu >= 1) & (vv >= 1) & (uu < W - 1) & (vv < H - 1)
            ci, ri = uu[inimg].astype(int), vv[inimg].astype(int)
            footprint = dd[inimg] * view["pixel"][0] / view["focal"]
            near = np.linalg.norm(pos[ri, ci] - V[inimg], axis=1) < 1.5 * footprint
            visible_fraction.append(near.mean())
        o = np.concatenate(offsets)
        mean_off = np.abs(o.mean(0))
        med = float(np.median(np.hypot(o[:, 0], o[:, 1])))
        check(mean_off.max() < 0.05 and med < 0.2,
              f"Mitsuba hit positions reprojected with the .mlp camera: mean offset ({o[:, 0].mean():+.4f}, "
              f"{o[:, 1].mean():+.4f}) px, median distance to the pixel centre {med:.3f} px over {len(o)} pixels "
              f"of {len(chosen)} views")
        check(min(visible_fraction) >= 0.2, "front-facing vertices whose pixel shows them (unoccluded): "
              + ", ".join(f"{100 * f:.1f} %" for f in visible_fraction))
        report.update(aov_views=[views[i]["label"] for i in chosen], reprojection_mean_offset_px=o.mean(0).tolist(),
                      reprojection_median_px=med, visible_vertex_fraction=[float(f) for f in visible_fraction])

    # 5: the real MeshLab (pymeshlab) with our fit filter.
    if args.fit_python:
        code = f"""
import time, pymeshlab, pymeshlab_radiance
ms = pymeshlab.MeshSet()
ms.set_verbosity(True)
ms.load_new_mesh({os.path.join(folder, 'mesh.ply')!r})
ms.load_project({os.path.join(folder, args.project)!r})
print('LOADED meshes', ms.mesh_number(), 'rasters', ms.raster_number(), flush=True)
t = time.time()
ms.apply_filter('radiance_fit_radiance_functions_from_rasters', heldoutevery={args.held_out_every})
print('FIT SECONDS %.1f' % (time.time() - t), flush=True)
"""
        t = time.time()
        run = subprocess.run([args.fit_python, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                             text=True, timeout=3600)
        log = run.stdout
        with open(os.path.join(folder, "fit_check.log"), "w") as f:
            f.write(log)
        for line in log.splitlines():
            if re.search(r"LOADED|Fitted|Of the|Held-out|gains|FIT SECONDS|median|Robust", line):
                print("     " + line.strip()[:400])
        check(run.returncode == 0, f"pymeshlab fit ran (exit {run.returncode}, {time.time() - t:.0f} s)")
        loaded = re.search(r"LOADED meshes (\d+) rasters (\d+)", log)
        check(bool(loaded) and int(loaded.group(2)) == len(views),
              f"pymeshlab loaded {loaded.group(2) if loaded else '?'} rasters of {len(views)}")
        rows = re.findall(r"Held-out raster (\S+): (\d+) vertices, RMS error in sRGB levels: fitted ([\d.]+), "
                          r"constant mean colour ([\d.]+), colour projection ([\d.]+)", log)
        summary = re.search(r"Held-out summary: .*", log)
        if rows:
            r = np.array([[float(x) for x in row[1:]] for row in rows])
            noise = (info.get("noise_twin") or {}).get("per_photo_rms_noise_srgb_levels")
            fit = dict(held_out_views=len(rows), vertices_mean=float(r[:, 0].mean()), fitted_mean=float(r[:, 1].mean()),
                       constant_mean=float(r[:, 2].mean()), projection_mean=float(r[:, 3].mean()),
                       photo_noise=noise, summary=summary.group(0) if summary else None)
            report["fit"] = fit
            print(f"     held-out mean RMS (sRGB levels): fitted {fit['fitted_mean']:.2f}, constant {fit['constant_mean']:.2f}, "
                  f"projection {fit['projection_mean']:.2f}; photographs' own noise {noise if noise is None else round(noise, 2)}")
            check(fit["fitted_mean"] <= fit["constant_mean"], "held-out: fitted functions no worse than the constant colour")
            if noise:  # wrong cameras give tens of levels; right ones the held-out photograph's noise and a bit
                check(fit["fitted_mean"] < 3 * noise, f"held-out fitted RMS {fit['fitted_mean']:.2f} < 3 x the "
                      f"photographs' own noise {noise:.2f}")
        else:
            check(False, "no held-out lines in the log (see fit_check.log)")

    report["failures"] = failures
    with open(os.path.join(folder, "check.json"), "w") as f:
        json.dump(report, f, indent=1)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
