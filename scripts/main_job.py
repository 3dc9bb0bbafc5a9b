#!/usr/bin/env python3
"""The main job as a pymeshlab batch script (what `bash scripts/run_main_job.sh` runs).

A real scan (the CGAL bunny, 37,706 vertices) is photographed virtually (40 calibrated photographs of
a glossy, spatially varying material with cast shadows, written as a MeshLab project). pymeshlab then
opens the scan and the photographs (raster layers) and our filters fit PB(4) radiance functions,
simplify them with levels of detail, bake the scan's normals onto a decimated copy, and compute PRT
transfer on a column scene, subdivide it adaptively and relight it. The repository's command-line
tools (build/tools) photograph, render and measure around the filters (called with subprocess).

    python scripts/main_job.py [--build-dir build] [--out-dir out] [--data-dir data-cache] [--quick]

Needs pymeshlab==2025.7.post1 and this repository's package (`pip install .`), or, for a development
build, PYMESHLAB_RADIANCE_PLUGIN_DIR=build/pymeshlab_plugins and PYTHONPATH=python.
Python names of the filters' parameters are the MeshLab names in lower case:
pymeshlab.print_filter_parameter_list('radiance_fit_radiance_functions_from_rasters').
"""
import argparse
import glob
import os
import subprocess
import sys
import time

import pymeshlab
import pymeshlab_radiance  # loads our plugins (the filters and the .rply format) into pymeshlab

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TIMINGS = []  # (step, seconds) for the summary at the end


def log(message):
    print(f"[main] {message}", flush=True)


def timed(name, start):
    """Records the wall time of a step since `start` (time.perf_counter()) and returns it."""
    seconds = time.perf_counter() - start
    TIMINGS.append((name, seconds))
    return seconds


def run(command, stdout=None, tee=None, stderr_too=False, check=True):
    """Runs a command-line tool; stdout: a file for its output; tee: print its output and write it
    to that file too (stderr as well with stderr_too)."""
    command = [str(c) for c in command]
    if tee is None:
        return subprocess.run(command, stdout=stdout, check=check).returncode
    with open(tee, "w") as copy, subprocess.Popen(
            command, stdout=subprocess.PIPE, text=True,
            stderr=subprocess.STDOUT if stderr_too else None) as process:
        for line in process.stdout:
            sys.stdout.write(line)
            copy.write(line)
    sys.stdout.flush()
    if check and process.returncode != 0:
        raise subprocess.CalledProcessError(process.returncode, command)
    return process.returncode


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build-dir", default=os.environ.get("BUILD_DIR", os.path.join(REPO, "build")),
                        help="the CMake build tree (its tools/ folder) [build]")
    parser.add_argument("--out-dir", default=os.environ.get("OUT_DIR", os.path.join(REPO, "out")),
                        help="where the outputs go [out]")
    parser.add_argument("--data-dir", default=os.environ.get("RADIANCE_DATA_CACHE", os.path.join(REPO, "data-cache")),
                        help="the fetched sample data (samples/fetch_data.sh) [data-cache]")
    parser.add_argument("--quick", action="store_true",
                        help="a small acquisition (12 photographs of 320x240) for trying the script")
    parser.add_argument("--verbose", action="store_true", help="print MeshLab's log of every filter")
    args = parser.parse_args()
    build, out, data = (os.path.abspath(d) for d in (args.build_dir, args.out_dir, args.data_dir))
    tools = os.path.join(build, "tools")
    os.makedirs(out, exist_ok=True)
    scan = os.path.join(data, "meshes", "bunny00.off")
    if not os.path.isfile(scan):
        sys.exit(f"missing {scan}: run samples/fetch_data.sh")
    job_start = time.perf_counter()
    log(f"pymeshlab {pymeshlab_version()}, our plugins from {pymeshlab_radiance.plugin_dir()}")

    # 1. Photographs: the scan rendered from calibrated cameras (a MeshLab project whose raster
    #    layers are the photographs; its MeshGroup is empty, mesh.ply beside it is the scan).
    photos = os.path.join(out, "bunny_photos")
    views, size = (12, "320x240") if args.quick else (40, "1024x768")
    log(f"photographing {os.path.basename(scan)} virtually: {views} views of {size}")
    start = time.perf_counter()
    with open(os.path.join(out, "acquisition.log"), "w") as acquisition_log:
        run([f"{tools}/virtual_acquisition", scan, "-o", photos, "--views", views, "--size", size,
             "--material", "glossy"], stdout=acquisition_log)
    timed("acquisition", start)
    print("".join(open(os.path.join(out, "acquisition.log")).readlines()[-3:]), end="", flush=True)

    # 2. Photographs -> radiance functions: the scan as the current mesh, the photographs as raster
    #    layers (load_project adds the project's rasters to the MeshSet), then our fit.
    log("fitting PB(4) radiance functions in pymeshlab")
    start = time.perf_counter()
    ms = pymeshlab.MeshSet()
    ms.set_verbosity(args.verbose)
    ms.load_new_mesh(os.path.join(photos, "mesh.ply"))
    ms.load_project(os.path.join(photos, "project.mlp"))
    if ms.raster_number() != views:
        sys.exit(f"load_project gave {ms.raster_number()} raster layers, expected {views}")
    filter_start = time.perf_counter()
    ms.apply_filter("radiance_fit_radiance_functions_from_rasters",
                    visibleonly=False,                                 # all rasters, not only visible ones
                    basis="Hemispherical polynomials PB(d), local frame",
                    degree=4,
                    regularization=0.001,
                    depthtolerance=pymeshlab.PureValue(0.0002),        # absolute, in scene units
                    grazingangle=80,
                    bordermargin=2,
                    minsamples=3,
                    reflected=False,
                    quality="Sample count",                            # vertex quality := samples used
                    setcolor=True)                                     # vertex colour := mean colour
    filter_seconds = time.perf_counter() - filter_start
    fitted = ms.current_mesh()
    samples = int(fitted.vertex_scalar_array().sum())
    fit_rply = os.path.join(out, "bunny_radiance.rply")
    ms.save_current_mesh(fit_rply, save_vertex_color=True, save_vertex_quality=True, save_vertex_normal=True)
    seconds = timed("fit", start)
    log(f"fitted PB(4) on {fitted.vertex_number():,} vertices from {ms.raster_number()} raster layers, "
        f"{samples:,} samples, in {filter_seconds:.2f} s (load + fit + save {seconds:.1f} s)")

    # The fitted radiance rendered from the camera of photograph 7: photograph | fit | 4x difference.
    log("rendering the fitted radiance from the camera of photograph 7")
    start = time.perf_counter()
    run([f"{tools}/render_radiance", fit_rply, "--project", os.path.join(photos, "project.mlp"),
         "--view", 7, "--mode", "fragment", "-o", os.path.join(out, "bunny_fit_view07.png"),
         "--compare", "raster", "--side-by-side", os.path.join(out, "bunny_photo_vs_fit_view07.png")])
    run([f"{tools}/radiance_info", fit_rply])
    timed("picture", start)

    # 3. Radiance-aware simplification to 25 % of the faces, with levels of detail at 50, 10 and 5 %
    #    (extra layers) and the whole collapse sequence recorded as a progressive mesh (.rpm).
    #    The fitted mesh is still the current mesh of the MeshSet.
    log("radiance-aware simplification of the fitted mesh in pymeshlab (25 %, progressive)")
    simp = os.path.join(out, "simplification")
    os.makedirs(simp, exist_ok=True)
    start = time.perf_counter()
    faces_before = ms.current_mesh().face_number()
    ms.apply_filter("radiance_radiance_aware_simplification",
                    targetpercentage=0.25,
                    lodlevels="0.5 0.1 0.05",
                    progressivefile=os.path.join(simp, "bunny.rpm"))
    filter_seconds = time.perf_counter() - start
    simplified = ms.current_mesh()                                     # the 25 % layer stays current
    ms.save_current_mesh(os.path.join(out, "bunny_radiance_25.rply"))
    timed("simplification (filter)", start)
    levels = ", ".join(f"'{m.label()}' {m.face_number():,}" for m in ms if m.id() != simplified.id())
    log(f"simplified {faces_before:,} -> {simplified.face_number():,} faces ({simplified.vertex_number():,} "
        f"vertices) in {filter_seconds:.2f} s; level-of-detail layers (faces): {levels}")

    # Levels of detail replayed from the recording, the baselines (colour QEM on the mean colour,
    # geometry only) and directional reduction (PB3..PB0), all rendered from 16 views against the
    # fitted original (per-fragment eq. 8): table, heat maps, plot.
    start = time.perf_counter()
    ratios = "0.5,0.25,0.1,0.05"
    run([f"{tools}/simplify_radiance", os.path.join(simp, "bunny.rpm"), "-o", os.path.join(simp, "radiance"),
         "--ratios", ratios], stdout=subprocess.DEVNULL)
    # Garland-Heckbert's 6D quadric holds the geometric distance itself: no extra geometry term.
    run([f"{tools}/simplify_radiance", fit_rply, "-o", os.path.join(simp, "color"), "--metric", "color",
         "--geometry-weight", 0, "--attribute-weight", 1, "--ratios", ratios], stdout=subprocess.DEVNULL)
    run([f"{tools}/simplify_radiance", fit_rply, "-o", os.path.join(simp, "geometry"), "--metric", "geometry",
         "--ratios", ratios], stdout=subprocess.DEVNULL)
    for basis in ("PB3", "PB2", "PB1", "PB0"):
        run([f"{tools}/simplify_radiance", fit_rply, "-o", os.path.join(simp, "directional"), "--reduce", basis],
            stdout=subprocess.DEVNULL)
    log("image-space comparison (16 views, 512x512, per-fragment shading)")
    others = [f for series in ("radiance", "color", "geometry", "directional")
              for f in sorted(glob.glob(os.path.join(simp, f"{series}_*.rply")))]
    errors = os.path.join(out, "simplification_errors.txt")
    run([f"{tools}/compare_radiance_meshes", fit_rply, *others, "--up", "0,1,0",
         "--heatmaps", os.path.join(simp, "heatmaps")], tee=errors)
    # The plot as PNG and SVG (matplotlib, extra `plots`); without matplotlib a plain SVG and a message.
    run([sys.executable, os.path.join(REPO, "scripts", "plot_error_vs_memory.py"), errors,
         os.path.join(out, "simplification_error_vs_memory.svg"), "Fitted bunny: image error against memory"])
    timed("simplification (baselines, comparison)", start)

    # 4. Normal map: a copy of the fitted scan decimated by MeshLab's own quadric edge collapse to
    #    1,508 faces (2 %), its vertex normals recomputed, then the full scan's normals and colours
    #    baked onto it (per-triangle atlas, 2048^2, object space, 16 bit, LEAN moments).
    log("normal map: bunny scan simplified to 2 % (1,508 faces), scan normals and colours baked onto it")
    bake = os.path.join(out, "bake")
    os.makedirs(bake, exist_ok=True)
    start = time.perf_counter()
    ms = pymeshlab.MeshSet()
    ms.set_verbosity(args.verbose)
    ms.load_new_mesh(fit_rply)
    scan_id = ms.current_mesh_id()
    ms.generate_copy_of_current_mesh()                                 # the copy becomes the current mesh
    ms.meshing_decimation_quadric_edge_collapse(targetfacenum=1508, preservenormal=True,
                                                preservetopology=False)  # others: MeshLab's defaults
    ms.compute_normal_per_vertex(weightmode="By Area")
    filter_start = time.perf_counter()
    ms.apply_filter("bake_normal_map",
                    sourcemesh=scan_id,                                # the full scan's layer
                    texturesize=2048,
                    space="Object space",
                    bits="16 bit",
                    maxdistance=pymeshlab.PureValue(0),                # 0: automatic ray distance
                    gutter=4,
                    newatlas=True,                                     # per-triangle atlas
                    diffuse=True,                                      # the scan's colours: _diffuse.png
                    lean=True,                                         # LEAN moments: _lean.exr
                    assign="Normal map",
                    outputfile=os.path.join(bake, "bunny_2pct_normal.png"))
    filter_seconds = time.perf_counter() - filter_start
    target = ms.current_mesh()
    # The decimated mesh with its texture coordinates, saved beside the maps. save_textures=False: the
    # filter has written the 16-bit map already, and MeshLab would write the layer's copy of the image
    # over it under the same name (elsewhere, save_textures=True copies the map beside the mesh).
    for extension in ("ply", "obj"):
        ms.save_current_mesh(os.path.join(bake, f"bunny_2pct.{extension}"), save_textures=False,
                             save_vertex_color=False, save_vertex_normal=True, save_wedge_texcoord=True)
    seconds = timed("normal map (decimation, bake)", start)
    log(f"baked a 2048x2048 object-space normal map (16 bit, LEAN) from {ms.mesh(scan_id).face_number():,} "
        f"onto {target.face_number():,} faces ({target.vertex_number():,} vertices) in {filter_seconds:.2f} s "
        f"(with loading, decimation and saving {seconds:.1f} s)")
    start = time.perf_counter()
    run([f"{tools}/normal_map_error", fit_rply, os.path.join(bake, "bunny_2pct.obj"),
         os.path.join(bake, "bunny_2pct_normal.png")],
        tee=os.path.join(out, "normal_map_error.txt"), stderr_too=True, check=False)
    timed("normal map (error)", start)

    # 5. Precomputed radiance transfer: the column on a plane (Křivánek et al. 2004 Fig. 1) through
    #    our filters: transfer, adaptive subdivision (face colour/quality := the error estimate),
    #    relighting under a directional light as vertex colour.
    log("PRT: column on a plane through pymeshlab (transfer, adaptive subdivision, relighting)")
    prt = os.path.join(out, "prt")
    os.makedirs(prt, exist_ok=True)
    start = time.perf_counter()
    run([f"{tools}/make_scene", "column", "-o", os.path.join(prt, "column.ply")])
    ms = pymeshlab.MeshSet()
    ms.set_verbosity(args.verbose)
    ms.load_new_mesh(os.path.join(prt, "column.ply"))
    column_faces = ms.current_mesh().face_number()
    log(f"column: {ms.current_mesh().vertex_number():,} vertices, {column_faces:,} faces")
    filter_start = time.perf_counter()
    ms.apply_filter("radiance_compute_prt_transfer",
                    order=6, rays=256, occluders="The current mesh", albedo=False, rayoffset=0.0001)
    log(f"computed PRT transfer (SH order 6, 36 coefficients, 256 rays per vertex) on "
        f"{ms.current_mesh().vertex_number():,} vertices in {time.perf_counter() - filter_start:.2f} s")
    filter_start = time.perf_counter()
    ms.apply_filter("radiance_adaptive_prt_subdivision",
                    budget=0, budgetfactor=4,                          # 4 x the face count
                    measure="Probed: midpoint interpolation error, relative", alpha=4, threshold=0)
    subdivided = ms.current_mesh()
    log(f"adaptive PRT subdivision: {column_faces:,} -> {subdivided.face_number():,} faces, "
        f"{subdivided.vertex_number():,} vertices, in {time.perf_counter() - filter_start:.2f} s")
    filter_start = time.perf_counter()
    ms.apply_filter("radiance_prt_relighting_as_vertex_color",
                    lighting="Directional light", environmentmap="", rotation=0, upaxis="+Z",
                    lightdirection=[1, 0.3, 0.8], lightintensity=3, exposure=1)
    log(f"relit {ms.current_mesh().vertex_number():,} vertices under the directional light toward "
        f"(1, 0.3, 0.8), intensity 3, in {time.perf_counter() - filter_start:.2f} s")
    # The relit mesh with its transfer (.rply block 'prt'), and the error estimate per face.
    ms.save_current_mesh(os.path.join(prt, "column_adaptive.rply"),
                         save_vertex_color=True, save_vertex_normal=True, save_vertex_quality=False)
    ms.save_current_mesh(os.path.join(prt, "column_adaptive_error.ply"),
                         save_vertex_color=False, save_vertex_normal=False, save_vertex_quality=False,
                         save_face_color=True, save_face_quality=True)
    timed("PRT (filters)", start)

    # Adaptive against uniform subdivision at the same triangle count, on the column and on the
    # (simplified) bunny scan standing on a plane: relighting error over 32 directional lights and
    # four HDR maps in four rotations each, pictures against a per-pixel ray-cast reference.
    start = time.perf_counter()
    hdrs = [a for name in ("city", "courtyard", "forest", "studio")
            for a in ("--hdr", os.path.join(data, "hdr", f"{name}.exr"))]
    log("PRT: adaptive vs uniform subdivision, column scene (Křivánek et al. 2004 Fig. 1)")
    run([f"{tools}/evaluate_prt", "--scene", "column", "--levels", 2, *hdrs, "--out", os.path.join(prt, "column")],
        tee=os.path.join(out, "prt_column_errors.txt"))
    log("PRT: adaptive vs uniform subdivision, bunny scan (simplified to 2000 faces) on a plane")
    run([f"{tools}/evaluate_prt", "--mesh", scan, "--up", "y", "--simplify-to", 2000, "--levels", 2, *hdrs,
         "--out", os.path.join(prt, "bunny")], tee=os.path.join(out, "prt_bunny_errors.txt"))
    timed("PRT (evaluation)", start)

    # Summary.
    meshlab = os.path.join(build, "meshlab-prefix", "bin", "meshlab")
    log("outputs:")
    for pattern in ("*.rply", "*.png", "*.svg"):
        for f in sorted(glob.glob(os.path.join(out, pattern))):
            print(f"  {os.path.getsize(f):>10,}  {f}")
    log(f"picture (photograph | fitted radiance | 4x difference): {out}/bunny_photo_vs_fit_view07.png")
    log(f"simplification: {out}/simplification_errors.txt, {out}/simplification_error_vs_memory.{{png,svg}},")
    print(f"       heat maps in {simp}/heatmaps (radiance_100 vs color_100: 10 % of the faces)")
    log(f"normal map: {bake}/bunny_2pct_{{normal,diffuse}}.png, _lean.exr; error in {out}/normal_map_error.txt; "
        f"see it with")
    print(f"       {meshlab} {bake}/bunny_2pct.ply, then Ctrl+Alt+N (Baked Normal Map decoration)")
    log(f"PRT: {out}/prt_column_errors.txt, {out}/prt_bunny_errors.txt; pictures in {prt}/column and")
    print(f"       {prt}/bunny (reference.png = per-pixel transfer; input/uniform/adaptive.png = interpolated)")
    log(f"open the fit with: {meshlab} {fit_rply}")
    total = time.perf_counter() - job_start
    log("timings: " + ", ".join(f"{name} {seconds:.1f} s" for name, seconds in TIMINGS) + f"; total {total:.1f} s")


def pymeshlab_version():
    try:
        from importlib.metadata import version
        return version("pymeshlab")
    except Exception:
        return "(unknown version)"


if __name__ == "__main__":
    main()
