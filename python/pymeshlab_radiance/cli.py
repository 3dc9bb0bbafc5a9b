"""``meshlab-radiance``: the command line over pymeshlab and our filters (also ``python -m pymeshlab_radiance``).

    meshlab-radiance import-cameras scan.ply colmap/sparse/0 --images colmap/images -o scan.mlp
    meshlab-radiance fit mesh.ply project.mlp -o fit.rply --degree 4
    meshlab-radiance simplify fit.rply -o fit_25.rply --percentage 0.25
    meshlab-radiance bake scan.ply coarse.ply -o coarse_baked.ply --size 1024
    meshlab-radiance splats mesh.ply point_cloud.ply -o mesh.rply
    meshlab-radiance info fit_25.rply
    meshlab-radiance export fit_25.rply -o fit_25.glb
    meshlab-radiance view fit_25.glb --screenshot fit_25.png
    meshlab-radiance filters
    meshlab-radiance batch recipe.toml scans/ out/ --workers 2

Every filter runs in a separate process (``batch_job``): pymeshlab prints its filters' progress
callback as log lines when the MeshSet is verbose, and the command turns them into a progress bar
(pymeshlab 2025.7 has no progress callback in its Python API). A refused filter's message (what is
wrong and how to fix it) goes to stderr and the exit status is 1; a command used wrongly exits with 2.
"""

import argparse
import os
import sys

try:
    import tomllib
except ImportError:  # Python 3.10
    import tomli as tomllib

PROG = "meshlab-radiance"

FIT = "radiance_fit_radiance_functions_from_rasters"
SIMPLIFY = "radiance_radiance_aware_simplification"
BAKE = "bake_normal_map"
EXPORT_GLTF = "radiance_export_gltf"
SPLATS = "radiance_transfer_gaussian_splats"
IMPORT_CAMERAS = "radiance_import_cameras_as_rasters"

EXAMPLES = {
    "fit": f"""example (photographs of a sphere made by the repository's tool, then the fit):
  build/tools/virtual_acquisition sphere.ply -o photos --views 16 --size 320x240
  {PROG} fit photos/mesh.ply photos/project.mlp -o fit.rply --degree 4 --regularization 0.02
The project (.mlp) gives the calibrated photographs as raster layers; any other parameter of
{FIT} is passed with -p NAME=VALUE (e.g. -p grazingangle=70 -p basis=1 for SH).""",
    "import-cameras": f"""example (a scan and its COLMAP reconstruction: sparse model and photographs):
  {PROG} import-cameras scan.ply colmap/sparse/0 --images colmap/images -o scan.mlp
  {PROG} fit scan.ply scan.mlp -o fit.rply
adds one raster layer per calibrated photograph of the camera file (a COLMAP model folder or one of its
.bin/.txt files, a Metashape camera XML, a nerfstudio transforms.json), undistorts the photographs that
have lens distortion once into --cache (default: <images>/undistorted; a rerun with the same
calibration reuses them), and writes a MeshLab project with the mesh and the rasters, which fit (or
MeshLab's File > Open Project) reads. Filter: {IMPORT_CAMERAS}; docs/camera-import.md.""",
    "simplify": f"""example:
  {PROG} simplify fit.rply -o fit_25.rply --percentage 0.25 --lod "0.5 0.1" --progressive fit.rpm
keeps 25 % of the faces of the radiance mesh (radiance-aware edge collapse), writes levels of detail
at 50 % and 10 % into the progressive file; -p NAME=VALUE passes any other parameter of
{SIMPLIFY} (e.g. -p metric=2 -p preserveboundary=false).""",
    "bake": f"""example (the full scan's normals and colours into a texture of its simplified copy):
  {PROG} simplify scan.ply -o coarse.ply --faces 2000 -p metric=3
  {PROG} bake scan.ply coarse.ply -o coarse_baked.ply --size 1024 --new-atlas --gltf
writes coarse_baked.ply with its texture coordinates, coarse_baked_normal.png, the diffuse map (when
the scan has vertex colours), the LEAN moments (coarse_baked_lean.exr) and coarse_baked.glb; -p NAME=VALUE passes any other parameter of {BAKE}
(e.g. -p space=1 for tangent space, -p bits=1 for 8 bit).""",
    "splats": f"""example (a 3D Gaussian Splatting scene's view-dependent colour onto a mesh in its frame):
  {PROG} splats mesh.ply output/point_cloud/iteration_30000/point_cloud.ply -o mesh.rply
gives every vertex an SH radiance function of the splats' degree and its mean colour; -p NAME=VALUE
passes any other parameter of {SPLATS} (e.g. -p maxsplatsize=5 -p fronttolerance=2); see
docs/gaussian-splats.md.""",
    "info": f"""example:
  {PROG} info fit_25.rply scan.ply
prints vertices, faces, bounding box and vertex colours as pymeshlab loads them, and for .rply
files the radiance basis and its coefficients (read with pymeshlab_radiance.rply).""",
    "export": f"""example:
  {PROG} export fit.rply -o fit.glb
writes the radiance mesh as glTF 2.0 (docs/gltf-radiance.md): every glTF viewer shows the mean colour
(COLOR_0); {PROG} view fit.glb shows the view-dependent radiance.""",
    "view": f"""examples:
  {PROG} view fit.glb                       serve the viewer on 127.0.0.1 and open a browser
  {PROG} view fit.glb --output fit.html     one standalone page, the model inside
  {PROG} view fit.glb --screenshot fit.png --look-at 0,0,3,0,0,0,0,1,0 --fov 40 --size 640x480
the same as python -m pymeshlab_radiance.view.""",
    "filters": f"""example:
  {PROG} filters --ours
lists the Python names pymeshlab knows once our plugins are loaded (the names recipes use).""",
    "batch": f"""example recipe (recipe.toml):
  [[step]]
  filter = "radiance_create_radiance_data_from_analytic_material"
  [[step]]
  filter = "radiance_radiance_aware_simplification"
  params = {{ targetpercentage = 0.25 }}
  [output]
  format = "rply"
then:
  {PROG} batch recipe.toml scans/ out/ --workers 2 --memory-limit 2GiB
runs the recipe on every mesh of scans/ (a .mlp project beside a mesh loads its photographs), each
object in its own process on a Dask cluster, and writes out/<name>.rply, out/thumbnails/,
out/manifest.jsonl (a rerun skips what is done), out/report.html and out/report.csv. The exit
status is 0 only if every object succeeded. On a cluster: --scheduler tcp://host:8786 (see
docs/batch.md for Slurm with dask-jobqueue).""",
}


class _Formatter(argparse.RawDescriptionHelpFormatter, argparse.ArgumentDefaultsHelpFormatter):
    pass


def _value(text):
    """A -p value as TOML reads it (numbers, true/false, strings in quotes), else the text itself."""
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def _params(pairs):
    params = {}
    for pair in pairs or []:
        name, sep, text = pair.partition("=")
        if not sep or not name.strip():
            raise SystemExit(f"{PROG}: -p wants NAME=VALUE, got '{pair}'")
        params[name.strip()] = _value(text.strip())
    return params


def _existing(path, what):
    if not os.path.isfile(path):
        print(f"{PROG}: {what} {path} does not exist", file=sys.stderr)
        raise SystemExit(2)
    return os.path.abspath(path)


def _size(text):
    from .batch_job import parse_size
    try:
        return parse_size(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e)) from None


def _add_job_options(parser):
    parser.add_argument("-p", "--param", action="append", metavar="NAME=VALUE",
                        help="any other parameter of the filter (Python name; TOML value: 3, 0.5, true, \"text\", \"0.5%%\")")
    parser.add_argument("--timeout", type=float, default=3600, help="seconds the job may run")
    parser.add_argument("--memory-limit", default="0", type=_size,
                        help="address-space limit of the job process (e.g. 4GiB; 0: none)")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def _report_job(args, result):
    """A failed job's message on stderr (False), or the filters' log lines on stdout (True)."""
    if result["status"] != "done":
        print(f"{PROG} {args.command}: {result.get('message', 'failed')}", file=sys.stderr)
        return False
    for step in result.get("steps", []):
        for line in step.get("log", []):
            print(f"{step['filter']}: {line}")
    return True


def _run_steps(args, meshes, steps, output, project=None, save_params=None):
    """One job (load, filters, atomic save) in a fresh process with a progress bar fed by the log."""
    from .batch_job import run_job
    from .progress import FilterProgress, bar

    output = os.path.abspath(output)
    stem = os.path.splitext(os.path.basename(output))[0]
    job = {"key": os.path.basename(output), "meshes": meshes, "project": project, "cameras": None, "steps": steps,
           "output": {"format": os.path.splitext(output)[1].lstrip("."), "params": save_params or {}},
           "output_path": output, "thumbnail_path": None,
           "names": {"stem": stem, "output_dir": os.path.dirname(output), "input_dir": os.path.dirname(meshes[0])},
           "memory_limit": args.memory_limit}
    with bar(total=100 * len(steps), unit="%", desc="loading", enabled=not args.no_progress) as progress:
        result = run_job(job, timeout=args.timeout, on_line=FilterProgress(progress, [s["filter"] for s in steps]))
    if not _report_job(args, result):
        return 1, result
    print(f"{result['faces_before']} -> {result['faces_after']} faces, {result['vertices_after']} vertices; "
          f"wrote {output} ({result['seconds_total']:.2f} s)")
    return 0, result


# ---------------------------------------------------------------------------------------------------
# Subcommands

def cmd_fit(args):
    params = {"degree": args.degree, "basis": {"pb": 0, "sh": 1}[args.basis], "regularization": args.regularization}
    params.update(_params(args.param))
    mesh, project = _existing(args.mesh, "the mesh"), _existing(args.project, "the project")
    return _run_steps(args, [mesh], [{"filter": FIT, "params": params}], args.output, project=project)[0]


def cmd_import_cameras(args):
    mesh = _existing(args.mesh, "the mesh")
    camerafile = os.path.abspath(args.camerafile)
    if not os.path.exists(camerafile):
        print(f"{PROG}: the camera file {args.camerafile} does not exist", file=sys.stderr)
        return 2
    if not args.output.lower().endswith(".mlp"):
        print(f"{PROG} import-cameras: the output {args.output} must be a MeshLab project (.mlp), which holds the "
              f"raster layers", file=sys.stderr)
        return 2
    params = {"camerafile": camerafile, "imagefolder": os.path.abspath(args.images) if args.images else "",
              "cachefolder": os.path.abspath(args.cache) if args.cache else ""}
    params.update(_params(args.param))
    status, result = _run_steps(args, [mesh], [{"filter": IMPORT_CAMERAS, "params": params}], args.output)
    if status == 0:
        print(f"{result['rasters_after']} raster layers in {args.output}")
    return status


def cmd_simplify(args):
    params = {"targetfaces": args.faces} if args.faces else {"targetpercentage": args.percentage}
    if args.lod:
        params["lodlevels"] = args.lod
    if args.progressive:
        params["progressivefile"] = os.path.abspath(args.progressive)
    params.update(_params(args.param))
    return _run_steps(args, [_existing(args.input, "the input")], [{"filter": SIMPLIFY, "params": params}],
                      args.output)[0]


def cmd_bake(args):
    output = os.path.abspath(args.output)
    normal_map = os.path.abspath(args.map) if args.map else os.path.splitext(output)[0] + "_normal.png"
    params = {"sourcemesh": 0, "texturesize": args.size, "newatlas": args.new_atlas, "gltf": args.gltf,
              "outputfile": normal_map}
    params.update(_params(args.param))
    meshes = [_existing(args.scan, "the scan"), _existing(args.target, "the target")]
    return _run_steps(args, meshes, [{"filter": BAKE, "params": params}], output)[0]


def cmd_splats(args):
    params = {"splatfile": _existing(args.splats, "the splat file")}
    params.update(_params(args.param))
    return _run_steps(args, [_existing(args.mesh, "the mesh")], [{"filter": SPLATS, "params": params}],
                      args.output)[0]


def cmd_info(args):
    from .batch_job import run_job

    status = 0
    for path in args.meshes:
        path = _existing(path, "the mesh")
        result = run_job({"meshes": [path], "steps": [], "output_path": None}, timeout=args.timeout)
        if result["status"] != "done":
            print(f"{PROG} info: {path}: {result.get('message')}", file=sys.stderr)
            status = 1
            continue
        lo, hi = result["bbox_min"], result["bbox_max"]
        print(f"{path}: {result['vertices_after']} vertices, {result['faces_after']} faces, "
              f"bounding box ({', '.join(f'{x:g}' for x in lo)}) .. ({', '.join(f'{x:g}' for x in hi)}), "
              f"{'with' if result['vertex_color'] else 'without'} vertex colours")
        if path.lower().endswith(".rply"):
            from . import rply
            try:
                mesh = rply.read_rply(path)
            except rply.RadianceFileError as e:
                print(f"{PROG} info: {path}: {e}", file=sys.stderr)
                status = 1
                continue
            radiance = (f"radiance {mesh.basis}{' reflected' if mesh.reflected else ''}, {mesh.coefficient_count} "
                        f"coefficients per channel" if mesh.basis else "no radiance functions")
            blocks = ", ".join(f"{name} ({block.width} floats)" for name, block in mesh.blocks.items())
            print(f"  {radiance}" + (f"; blocks: {blocks}" if blocks else ""))
    return status


def cmd_export(args):
    from .batch_job import run_job

    output = os.path.abspath(args.output)
    job = {"meshes": [_existing(args.input, "the input")], "steps": [{"filter": EXPORT_GLTF, "params": {"outputfile": output}}],
           "output_path": None}
    return 0 if _report_job(args, run_job(job, timeout=args.timeout)) else 1


def cmd_view(args):
    from . import view
    try:
        return view.run(args)
    except view.ViewerError as e:
        print(f"{PROG} view: {e}", file=sys.stderr)
        return 1


def cmd_filters(args):
    from .batch_job import run_job

    answer = run_job({"steps": []}, timeout=300, mode="probe")
    if answer.get("status") != "done":
        print(f"{PROG} filters: {answer.get('message')}", file=sys.stderr)
        return 1
    from . import filter_names
    ours = set(filter_names())
    for name in answer["known"]:
        if not args.ours or name in ours:
            print(name)
    return 0


def cmd_batch(args):
    from . import batch
    return batch.main(args)


def build_parser():
    parser = argparse.ArgumentParser(prog=PROG, formatter_class=argparse.RawDescriptionHelpFormatter,
                                     description="Radiance functions, radiance-aware simplification and normal-map "
                                                 "baking over pymeshlab, for one object or a collection.",
                                     epilog=__doc__.split("\n\n")[1])
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    sub.required = True

    def command(name, help_text):
        p = sub.add_parser(name, help=help_text, description=help_text, epilog=EXAMPLES[name], formatter_class=_Formatter)
        return p

    p = command("fit", "fit radiance functions to a mesh from its calibrated photographs (a MeshLab project)")
    p.add_argument("mesh", help="the mesh (.ply, .obj, ...)")
    p.add_argument("project", help="MeshLab project (.mlp) or Bundler .out with the photographs as rasters")
    p.add_argument("-o", "--output", required=True, help="the fitted mesh (.rply keeps the radiance functions)")
    p.add_argument("--degree", type=int, default=4, help="degree of the basis")
    p.add_argument("--basis", choices=("pb", "sh"), default="pb", help="hemispherical polynomials or spherical harmonics")
    p.add_argument("--regularization", type=float, default=0.001, help="regularisation weight of the least squares")
    _add_job_options(p)
    p.set_defaults(run=cmd_fit)

    p = command("import-cameras", "calibrated photographs (COLMAP, Metashape, nerfstudio) as raster layers of a "
                                  "MeshLab project, ready for fit")
    p.add_argument("mesh", help="the mesh the cameras photographed (.ply, .obj, ...)")
    p.add_argument("camerafile", help="COLMAP model folder or file (.bin, .txt), Metashape XML or nerfstudio "
                                      "transforms.json")
    p.add_argument("-o", "--output", required=True, help="the MeshLab project (.mlp) to write")
    p.add_argument("--images", "--imagefolder", dest="images",
                   help="folder the camera file's image names are relative to (default: the camera file's folder)")
    p.add_argument("--cache", "--cachefolder", dest="cache",
                   help="folder of the undistorted photographs (default: <images>/undistorted)")
    _add_job_options(p)
    p.set_defaults(run=cmd_import_cameras)

    p = command("simplify", "radiance-aware simplification (edge collapse) of a mesh")
    p.add_argument("input", help="the mesh (.rply with radiance functions, or any mesh)")
    p.add_argument("-o", "--output", required=True, help="the simplified mesh")
    size = p.add_mutually_exclusive_group()
    size.add_argument("--percentage", type=float, default=0.25, help="fraction of the faces to keep")
    size.add_argument("--faces", type=int, help="number of faces to keep (instead of --percentage)")
    p.add_argument("--lod", help="extra levels of detail as fractions, e.g. \"0.5 0.1\"")
    p.add_argument("--progressive", help="write the progressive mesh (.rpm) of the run")
    _add_job_options(p)
    p.set_defaults(run=cmd_simplify)

    p = command("bake", "bake a full scan's normals (and colours) into a normal map of a simplified mesh")
    p.add_argument("scan", help="the full-resolution scan (source)")
    p.add_argument("target", help="the simplified mesh (target; its texture coordinates, or --new-atlas)")
    p.add_argument("-o", "--output", required=True, help="the target saved with its texture")
    p.add_argument("--map", help="the normal map file (default: <output>_normal.png)")
    p.add_argument("--size", type=int, default=2048, help="texture size (power of two, 16..16384)")
    p.add_argument("--new-atlas", action="store_true", help="make a per-triangle atlas instead of the target's UVs")
    p.add_argument("--gltf", action="store_true", help="also write a glTF 2.0 .glb beside the map")
    _add_job_options(p)
    p.set_defaults(run=cmd_bake)

    p = command("splats", "transfer a 3D Gaussian Splatting scene's radiance onto a mesh's vertices")
    p.add_argument("mesh", help="the mesh, in the splats' coordinate frame")
    p.add_argument("splats", help="the 3DGS .ply (reference trainer's point_cloud.ply or SuperSplat's export)")
    p.add_argument("-o", "--output", required=True, help="the mesh with its radiance functions (.rply)")
    _add_job_options(p)
    p.set_defaults(run=cmd_splats)

    p = command("info", "what a mesh file holds: counts, bounding box, colours, radiance basis")
    p.add_argument("meshes", nargs="+", help="mesh files")
    p.add_argument("--timeout", type=float, default=600, help="seconds to load one file")
    p.set_defaults(run=cmd_info)

    p = command("export", "write a radiance mesh as glTF 2.0 (.glb) with its radiance functions")
    p.add_argument("input", help="the mesh with radiance functions (.rply)")
    p.add_argument("-o", "--output", required=True, help="the .glb to write")
    p.add_argument("--timeout", type=float, default=600, help="seconds the job may run")
    p.set_defaults(run=cmd_export)

    from .view import add_arguments as add_view_arguments
    p = command("view", "show a .glb's radiance functions in a browser (WebGL2), or render a screenshot")
    add_view_arguments(p)
    p.set_defaults(run=cmd_view)

    p = command("filters", "list the filters pymeshlab knows with our plugins loaded")
    p.add_argument("--ours", action="store_true", help="only this package's filters")
    p.set_defaults(run=cmd_filters)

    from .batch import add_arguments
    p = command("batch", "run a recipe over a collection of objects on Dask (a local cluster or a scheduler)")
    add_arguments(p)
    p.set_defaults(run=cmd_batch)
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except KeyboardInterrupt:
        print(f"{PROG}: interrupted", file=sys.stderr)
        return 130
