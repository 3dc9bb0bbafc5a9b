"""Helpers of the pymeshlab tests (tests/python/test_pymeshlab_*.py, test_hosts_agree.py).

Everything that computes an expected value here is written from the specifications (the papers,
docs/*.md, the filters' help texts), independently of the C++ code under test: sRGB, the PB basis,
mesh topology checks, PLY writers for hand-made inputs. Input meshes and photographs come from the
built C++ tools (make_scene, make_radiance_mesh, virtual_acquisition); a missing tool FAILS the test
with the command that builds it.
"""

import math
import os
import subprocess
import sys

import numpy as np
import pytest

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
BUILD = os.path.abspath(os.environ.get("RADIANCE_BUILD_DIR", os.path.join(REPO, "build")))
INTEGRATION = os.path.join(REPO, "tests", "integration")

if INTEGRATION not in sys.path:
    sys.path.insert(0, INTEGRATION)
import png_reader  # noqa: E402  (tests/integration: independent pure-Python PNG decoder)

# The MeshLab names of our filters and their Python names (MeshLab's rule: lower case, spaces and
# '-' '/' -> '_', "().,'\":+" removed), written out here rather than derived from the package.
FILTERS = {
    "Radiance: Fit Radiance Functions from Rasters": "radiance_fit_radiance_functions_from_rasters",
    "Radiance: Create Radiance Data from Analytic Material": "radiance_create_radiance_data_from_analytic_material",
    "Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color":
        "radiance_evaluate_radiance_toward_a_viewpoint_as_vertex_color",
    "Radiance: Radiance-Aware Simplification": "radiance_radiance_aware_simplification",
    "Radiance: Compute PRT Transfer": "radiance_compute_prt_transfer",
    "Radiance: Adaptive PRT Subdivision": "radiance_adaptive_prt_subdivision",
    "Radiance: Uniform PRT Subdivision": "radiance_uniform_prt_subdivision",
    "Radiance: PRT Relighting as Vertex Color": "radiance_prt_relighting_as_vertex_color",
    "Bake Normal Map": "bake_normal_map",
    "Extract Level of Detail (POP Buffer)": "extract_level_of_detail_pop_buffer",
    "Out-of-Core Simplification and Normal Map": "out_of_core_simplification_and_normal_map",
    "Compute Irradiance Vector Grid": "compute_irradiance_vector_grid",
    # Named by issue 29 (the plugin overrides pythonFilterName): not MeshLab's derived name.
    "Import Cameras as Raster Layers": "radiance_import_cameras_as_rasters",
    # Named by issue 30 (pythonFilterName overrides).
    "Radiance: Export Radiance Functions as glTF (.glb)": "radiance_export_gltf",
    "Radiance: Transfer Radiance from Gaussian Splats": "radiance_transfer_gaussian_splats",
}
CREATE = FILTERS["Radiance: Create Radiance Data from Analytic Material"]
EVALUATE = FILTERS["Radiance: Evaluate Radiance toward a Viewpoint as Vertex Color"]
FIT = FILTERS["Radiance: Fit Radiance Functions from Rasters"]
SIMPLIFY = FILTERS["Radiance: Radiance-Aware Simplification"]
TRANSFER = FILTERS["Radiance: Compute PRT Transfer"]
ADAPTIVE = FILTERS["Radiance: Adaptive PRT Subdivision"]
UNIFORM = FILTERS["Radiance: Uniform PRT Subdivision"]
RELIGHT = FILTERS["Radiance: PRT Relighting as Vertex Color"]
BAKE = FILTERS["Bake Normal Map"]
POP_LEVELS = FILTERS["Extract Level of Detail (POP Buffer)"]
OUT_OF_CORE = FILTERS["Out-of-Core Simplification and Normal Map"]
IRRADIANCE_GRID = FILTERS["Compute Irradiance Vector Grid"]
IMPORT_CAMERAS = FILTERS["Import Cameras as Raster Layers"]
EXPORT_GLTF = FILTERS["Radiance: Export Radiance Functions as glTF (.glb)"]
SPLATS = FILTERS["Radiance: Transfer Radiance from Gaussian Splats"]

# The plugin files the package must load (the 2025 builds of build/pymeshlab_plugins).
PLUGIN_FILES = ("libio_radiance.so", "libfilter_radiance_fit.so", "libfilter_radiance_simplify.so",
                "libfilter_prt_subdivide.so", "libfilter_normal_bake.so", "libfilter_level_of_detail.so",
                "libfilter_irradiance_grid.so", "libfilter_out_of_core.so")

SH_BASIS = "Spherical harmonics SH(d), global frame"


# ---------------------------------------------------------------------------------------------------
# Tools and processes

def tool(name):
    path = os.path.join(BUILD, "tools", name)
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        pytest.fail(f"the C++ tool {path} is missing: build it ('cmake --build {BUILD} --target {name}', or "
                    f"scripts/setup.sh), or point RADIANCE_BUILD_DIR at a build folder")
    return path


def run_tool(name, *args, timeout=300):
    result = subprocess.run([tool(name)] + [str(a) for a in args], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True, timeout=timeout)
    if result.returncode != 0:
        pytest.fail(f"{name} {' '.join(map(str, args))} failed ({result.returncode}):\n{result.stdout}")
    return result.stdout


def meshlabserver():
    path = os.path.join(BUILD, "meshlab-prefix", "bin", "meshlabserver")
    if not os.access(path, os.X_OK):
        pytest.fail(f"{path} is missing: scripts/setup.sh makes the private MeshLab 2020.09 prefix")
    return path


def run_meshlabserver(work, *args, timeout=300):
    """Debian's meshlabserver 2020.09 from the private prefix under Xvfb, with private settings
    (as tests/integration/lib.sh); returns (exit status, output). A crash fails the test."""
    import shutil

    if shutil.which("xvfb-run") is None:
        pytest.fail("xvfb-run is missing (apt-get install xvfb): meshlabserver 2020.09 needs a display")
    home = os.path.join(str(work), "meshlab-home")
    os.makedirs(home, exist_ok=True)
    env = dict(os.environ, HOME=home, XDG_CONFIG_HOME=home)
    result = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", meshlabserver()] +
                            [str(a) for a in args], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                            text=True, errors="replace", timeout=timeout, env=env)
    if 128 < result.returncode < 255:
        pytest.fail(f"meshlabserver crashed (status {result.returncode}) with {args}:\n{result.stdout[-3000:]}")
    return result.returncode, result.stdout


def python_env(**extra):
    """The environment for a child Python process that imports what this one imports: this process's
    sys.path as PYTHONPATH, so the child finds the same package (the repository's python/ or, in the
    wheel check, the installed wheel) and the same plugins, never a different copy first."""
    return dict(os.environ, PYTHONPATH=os.pathsep.join(p for p in sys.path if p), **extra)


def run_python(code, timeout=300):
    """Runs `code` in a fresh Python process with this environment (same interpreter, same plugins)."""
    return subprocess.run([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                          text=True, timeout=timeout, env=python_env())


def filter_script(path, *filters):
    """Writes a meshlabserver 2020.09 script with every parameter each filter declares (from the
    filter itself: scripts/filter_script.sh), its defaults but for the values given. `filters`: pairs
    (filter name, {parameter: value}); booleans become true/false, sequences x,y,z or r,g,b,a."""
    def word(value):
        if isinstance(value, bool):
            return "true" if value else "false"
        if isinstance(value, (list, tuple)):
            return ",".join(str(v) for v in value)
        return str(value)
    args = ["bash", os.path.join(REPO, "scripts", "filter_script.sh"), "--out", str(path)]
    for name, values in filters:
        args += ["--filter", name] + [f"{key}={word(value)}" for key, value in values.items()]
    subprocess.run(args, check=True, env=dict(os.environ, RADIANCE_BUILD_DIR=BUILD))
    return path


def create_mlx(path, case):
    """A meshlabserver script running the create filter (as lib.sh's create_radiance_mlx); `case`
    gives basis, degree, reflected, specular, stripes, lighttype, light."""
    return filter_script(path, ("Radiance: Create Radiance Data from Analytic Material", dict(
        basis=case["basis"], degree=case["degree"], reflected=bool(case["reflected"]), albedo=(230, 60, 40, 255),
        specularColor=(255, 255, 255, 255), specular=case["specular"], shininess=40, stripes=case["stripes"],
        stripeAxis=1, lightType=case["lighttype"], light=case["light"], lightIntensity=3, ambient=0.05,
        setColor=True)))


# ---------------------------------------------------------------------------------------------------
# pymeshlab

_KEPT_ALIVE = []


def reset_pymeshlab_logger():
    """See conftest._reset_pymeshlab_static_logger: a successful filter clears pymeshlab's static
    logger pointer (pymeshlab 2025.7 leaves it at the log of a MeshSet whose filter raised)."""
    import pymeshlab

    scratch = pymeshlab.MeshSet()
    scratch.add_mesh(pymeshlab.Mesh(vertex_matrix=np.eye(3), face_matrix=np.array([[0, 1, 2]], dtype=np.int32)))
    scratch.apply_filter("set_selection_none")


def keep_alive(ms):
    """Keeps a MeshSet whose filter raised alive for the whole session (pymeshlab bug, see conftest)."""
    _KEPT_ALIVE.append(ms)
    return ms


def snapshot(ms):
    """What a refused filter must leave unchanged: the layers, their vertices, colours and faces."""
    state = {"count": ms.mesh_number(), "current": ms.current_mesh_id(), "meshes": []}
    for mid in range(64):
        if not ms.mesh_id_exists(mid):
            continue
        m = ms.mesh(mid)
        entry = {"id": mid, "label": m.label(), "vertices": m.vertex_matrix().copy(),
                 "faces": m.face_matrix().copy()}
        entry["colors"] = m.vertex_color_matrix().copy() if m.has_vertex_color() else None
        entry["wedge_uv"] = m.wedge_tex_coord_matrix().copy() if m.has_wedge_tex_coord() else None
        state["meshes"].append(entry)
    return state


def assert_unchanged(before, after, what):
    assert after["count"] == before["count"], f"{what}: {before['count']} layers before, {after['count']} after"
    assert after["current"] == before["current"], f"{what}: the current layer changed"
    for a, b in zip(before["meshes"], after["meshes"]):
        assert a["id"] == b["id"] and a["label"] == b["label"], f"{what}: layers renamed or replaced"
        for key in ("vertices", "faces", "colors", "wedge_uv"):
            if a[key] is None:
                assert b[key] is None, f"{what}: layer {a['id']} gained {key}"
            else:
                assert b[key] is not None and np.array_equal(a[key], b[key]), \
                    f"{what}: layer {a['id']}'s {key} changed"


def expect_refusal(ms, filter_name, message, **parameters):
    """The filter raises pymeshlab.PyMeshLabException whose text contains `message`, and the MeshSet
    is as before (layers, vertices, faces, colours, texture coordinates). Returns the message."""
    import pymeshlab

    keep_alive(ms)
    before = snapshot(ms)
    with pytest.raises(pymeshlab.PyMeshLabException) as caught:
        ms.apply_filter(filter_name, **parameters)
    text = str(caught.value)
    assert message in text, f"{filter_name} {parameters}: expected '{message}' in the refusal, got:\n{text}"
    assert_unchanged(before, snapshot(ms), f"{filter_name} refused")
    return text


def load(*paths):
    import pymeshlab

    ms = pymeshlab.MeshSet()
    for p in paths:
        ms.load_new_mesh(os.path.abspath(str(p)))
    return ms


# ---------------------------------------------------------------------------------------------------
# Colour and radiance functions (from the definitions)

def srgb_decode(code):
    s = np.asarray(code, dtype=float) / 255.0
    return np.where(s <= 0.04045, s / 12.92, ((s + 0.055) / 1.055) ** 2.4)


def srgb_encode(x):
    """Linear -> sRGB code 0..255 (not rounded)."""
    x = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    return 255.0 * np.where(x <= 0.0031308, 12.92 * x, 1.055 * x ** (1 / 2.4) - 0.055)


def pb_exponents(degree):
    """PB(d) basis u^i v^j ordered by total degree, then by j (docs/radiance-ply-format.md)."""
    return [(total - j, j) for total in range(degree + 1) for j in range(total + 1)]


def evaluate_pb(mesh, directions):
    """RF of every vertex of a numpy-read .rply mesh (plain PB) toward unit `directions` (N, 3):
    u, v = the direction in the tangent frame (t, n x t); returns linear RGB (N, 3)."""
    n = mesh.normals.astype(float)
    t = mesh.tangents.astype(float)
    b = np.cross(n, t)
    u = (t * directions).sum(1)
    v = (b * directions).sum(1)
    degree = int(mesh.basis[2:])
    basis = np.stack([u ** i * v ** j for i, j in pb_exponents(degree)], axis=1)
    return np.einsum("nck,nk->nc", mesh.coefficients.astype(float), basis)


def normalized(v):
    v = np.asarray(v, dtype=float)
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


# ---------------------------------------------------------------------------------------------------
# Hand-made input files

def write_ascii_ply(path, vertices, faces=(), normals=None, texcoords=None):
    """ASCII PLY with x y z [nx ny nz] and triangles [with a per-face texcoord list]."""
    with open(path, "w") as f:
        f.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\n"
                % len(vertices))
        if normals is not None:
            f.write("property float nx\nproperty float ny\nproperty float nz\n")
        f.write("element face %d\nproperty list uchar int vertex_indices\n" % len(faces))
        if texcoords is not None:
            f.write("property list uchar float texcoord\n")
        f.write("end_header\n")
        for i, v in enumerate(vertices):
            extra = "" if normals is None else " %r %r %r" % tuple(float(x) for x in normals[i])
            f.write("%r %r %r%s\n" % (tuple(float(x) for x in v) + (extra,)))
        for k, t in enumerate(faces):
            extra = "" if texcoords is None else " 6 " + " ".join(repr(float(x)) for x in texcoords[k])
            f.write("3 %d %d %d%s\n" % (tuple(t) + (extra,)))
    return str(path)


def write_binary_ply(path, vertices, faces, normals):
    """Binary little-endian PLY with x y z nx ny nz (float) and uchar/int triangles."""
    vertices = np.asarray(vertices, dtype="<f4")
    normals = np.asarray(normals, dtype="<f4")
    faces = np.asarray(faces, dtype="<i4")
    head = ("ply\nformat binary_little_endian 1.0\nelement vertex %d\n"
            "property float x\nproperty float y\nproperty float z\n"
            "property float nx\nproperty float ny\nproperty float nz\n"
            "element face %d\nproperty list uchar int vertex_indices\nend_header\n" % (len(vertices), len(faces)))
    records = np.concatenate([vertices, normals], axis=1).astype("<f4")
    face_records = np.zeros(len(faces), dtype=[("n", "u1"), ("i", "<i4", (3,))])
    face_records["n"] = 3
    face_records["i"] = faces
    with open(path, "wb") as f:
        f.write(head.encode("ascii"))
        f.write(records.tobytes())
        f.write(face_records.tobytes())
    return str(path)


def grid(nx, ny, z=0.0):
    """(nx+1) x (ny+1) vertices of a unit-spaced grid and its 2 nx ny counter-clockwise triangles."""
    vertices = [(float(x), float(y), z) for y in range(ny + 1) for x in range(nx + 1)]
    faces = []
    for y in range(ny):
        for x in range(nx):
            a = (nx + 1) * y + x
            b, c, d = a + 1, a + nx + 2, a + nx + 1
            faces += [(a, b, c), (a, c, d)]
    return vertices, faces


# ---------------------------------------------------------------------------------------------------
# Mesh checks

def face_triples(positions, faces):
    """Faces as position triples, rotated to start at the smallest (orientation kept)."""
    out = set()
    for f in faces:
        corners = [tuple(positions[i]) for i in f]
        k = corners.index(min(corners))
        out.add(tuple(corners[k:] + corners[:k]))
    return out


def check_closed_genus0_manifold(faces, what):
    """Every face a proper triangle, every directed edge once with its twin (closed, consistently
    oriented 2-manifold), Euler characteristic 2."""
    faces = np.asarray(faces)
    assert faces.ndim == 2 and faces.shape[1] == 3, f"{what}: not a triangle list"
    assert np.all((faces[:, 0] != faces[:, 1]) & (faces[:, 1] != faces[:, 2]) & (faces[:, 0] != faces[:, 2])), \
        f"{what}: a face repeats a vertex"
    directed = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]])
    keys = directed[:, 0].astype(np.int64) * (1 << 32) + directed[:, 1]
    unique, counts = np.unique(keys, return_counts=True)
    assert counts.max() == 1, f"{what}: a directed edge is used twice (non-manifold or flipped face)"
    twins = directed[:, 1].astype(np.int64) * (1 << 32) + directed[:, 0]
    assert np.isin(twins, unique).all(), f"{what}: an edge has one face only (the surface is not closed)"
    used = np.unique(faces).size
    euler = used - len(directed) // 2 + len(faces)
    assert euler == 2, f"{what}: Euler characteristic {euler}, expected 2"


def check_original_vertices_and_rows(original, simplified, what):
    """Half-edge collapses never move a vertex: every simplified vertex is an original one and
    carries that vertex's radiance row, bit for bit (numpy-read .rply meshes)."""
    where = {tuple(p): i for i, p in enumerate(original.positions.tolist())}
    for i, p in enumerate(simplified.positions.tolist()):
        j = where.get(tuple(p))
        assert j is not None, f"{what}: vertex {i} at {p} is not an original vertex"
        assert np.array_equal(simplified.coefficients[i], original.coefficients[j]), \
            f"{what}: vertex {i} carries another radiance row than original vertex {j}"
        assert np.array_equal(simplified.tangents[i], original.tangents[j]), \
            f"{what}: vertex {i} carries another frame than original vertex {j}"


# ---------------------------------------------------------------------------------------------------
# Images

def read_png(path):
    """PNG (8 or 16 bit RGB/RGBA) -> float array (H, W, C) in [0, 1], row 0 at the top, decoded by
    the repository's independent reader (tests/integration/png_reader.py)."""
    png = png_reader.read_png(str(path))
    dtype = ">u2" if png.depth == 16 else "u1"
    rows = [np.frombuffer(bytes(r), dtype=dtype, count=png.width * png.channels) for r in png.rows]
    array = np.stack(rows).reshape(png.height, png.width, png.channels).astype(float)
    return array / (65535.0 if png.depth == 16 else 255.0), png.depth


def write_png(path, rgb):
    """An 8-bit RGB (H, W, 3) or RGBA PNG, by the package's writer (atomic; no imaging library)."""
    from pymeshlab_radiance.thumbnail import write_png as package_write_png

    package_write_png(str(path), rgb)


def texels_inside_faces(positions, faces, wedge_uv, normals, width, height, with_weights=False):
    """For every texel centre inside a face's UV triangle (v up, row 0 at the top): the face index,
    column, row, the surface point and the interpolated (unnormalised) vertex normal (and, with
    with_weights, the barycentric weights of the corners, one row per texel)."""
    out = []
    for f, face in enumerate(faces):
        p = positions[face]
        n = normals[face]
        uv = wedge_uv[3 * f:3 * f + 3]
        x = uv[:, 0] * width
        y = (1.0 - uv[:, 1]) * height
        area = (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])
        if abs(area) < 1e-9:
            continue
        cols = np.arange(max(0, int(x.min())), min(width, int(x.max()) + 1))
        rows = np.arange(max(0, int(y.min())), min(height, int(y.max()) + 1))
        c, r = np.meshgrid(cols, rows)
        c, r = c.ravel(), r.ravel()
        cx, cy = c + 0.5, r + 0.5
        b1 = ((cx - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (cy - y[0])) / area
        b2 = ((x[1] - x[0]) * (cy - y[0]) - (cx - x[0]) * (y[1] - y[0])) / area
        b0 = 1.0 - b1 - b2
        inside = (b0 >= 0) & (b1 >= 0) & (b2 >= 0)
        if not inside.any():
            continue
        b = np.stack([b0, b1, b2], axis=1)[inside]
        out.append((f, c[inside], r[inside], b @ p, b @ n) + ((b,) if with_weights else ()))
    return out


def angle_degrees(a, b):
    a, b = normalized(a), normalized(b)
    return np.degrees(np.arccos(np.clip((a * b).sum(-1), -1.0, 1.0)))


Y00 = 0.5 / math.sqrt(math.pi)


def blender_import_glb(glb_path, folder, report):
    """Imports the .glb with Debian's Blender (headless, factory settings) and returns Blender's log
    and the words of the line that `report` prints (Blender Python run after the import with the one
    imported mesh's data as `mesh`; the line must start with IMPORTED)."""
    import shutil

    blender = os.environ.get("BLENDER") or shutil.which("blender")
    assert blender, "Blender not found: install Debian's 'blender' package (scripts/setup.sh does) or set BLENDER"
    script = os.path.join(str(folder), "import_glb.py")
    # Debian 12's Blender 3.4 glTF add-on still uses numpy.bool, which Debian's numpy 1.24 no longer
    # has: every glTF import fails in set_poly_smoothing. The alias (the builtin bool, which is what
    # numpy.bool was) lets the add-on run; nothing else is changed.
    with open(script, "w") as f:
        f.write("import numpy\n"
                "if not hasattr(numpy, 'bool'):\n"
                "    numpy.bool = bool\n"
                "import bpy\n"
                "bpy.ops.wm.read_factory_settings(use_empty=True)\n"
                f"result = bpy.ops.import_scene.gltf(filepath={str(glb_path)!r})\n"
                "assert result == {'FINISHED'}, result\n"
                "meshes = [o for o in bpy.context.scene.objects if o.type == 'MESH']\n"
                "assert len(meshes) == 1, meshes\n"
                "mesh = meshes[0].data\n" + report)
    run = subprocess.run([blender, "-b", "--factory-startup", "-noaudio", "--python-exit-code", "1", "-P", script],
                         capture_output=True, text=True, timeout=300)
    log = run.stdout + run.stderr
    assert run.returncode == 0, log
    assert "Traceback" not in log, log
    return log, next(l for l in log.splitlines() if l.startswith("IMPORTED")).split()
