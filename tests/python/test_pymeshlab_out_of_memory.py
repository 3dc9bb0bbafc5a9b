"""Running out of memory through pymeshlab 2025.7: a refusal that names the cause, and the document as
it was (no layer left from a filter that failed half way, no file written).

Each case runs in a child Python whose address space is limited (RLIMIT_AS, as `ulimit -v` and batch
schedulers set it) to what it uses after loading the mesh plus a margin, so that the filter's
allocations fail where they would on a smaller machine, and the rest of the suite is unaffected.
The child reports what it saw as one JSON line; the assertions are made here.
"""
import json
import subprocess
import sys

import pymeshlab_test_helpers as h

# What every child does first: load pymeshlab and our plugins, and define its helpers. A case that
# starts OpenMP threads under the limit runs its filter once on a small input before setting it: a
# thread that cannot be created under the limit aborts the process inside libgomp, which no filter
# can catch.
CHILD_PROLOGUE = """
import json, resource, sys
import numpy as np
import pymeshlab
import pymeshlab_radiance

def virtual_bytes():
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmSize:"):
                return int(line.split()[1]) * 1024

def limit_address_space(margin_mb):
    used = virtual_bytes()
    resource.setrlimit(resource.RLIMIT_AS, (used + margin_mb * 2**20, resource.RLIM_INFINITY))

def state(ms):
    return {"layers": ms.mesh_number(), "current": ms.current_mesh_id(),
            "faces": int(ms.current_mesh().face_number()), "vertices": int(ms.current_mesh().vertex_number())}

def report(**fields):
    print("RESULT " + json.dumps(fields))
    sys.stdout.flush()

def apply_and_report(ms, before, name, **parameters):
    try:
        ms.apply_filter(name, **parameters)
        report(refused=False, before=before, after=state(ms), message="")
    except pymeshlab.PyMeshLabException as e:
        report(refused=True, before=before, after=state(ms), message=str(e))
"""


def run_child(body, timeout=600, output=None):
    done = subprocess.run([sys.executable, "-c", CHILD_PROLOGUE + body], capture_output=True, text=True,
                          timeout=timeout, env=h.python_env(OMP_NUM_THREADS="2"))
    lines = [line for line in done.stdout.splitlines() if line.startswith("RESULT ")]
    assert done.returncode == 0 and lines, \
        f"the child Python failed (status {done.returncode}):\n{done.stdout[-3000:]}\n{done.stderr[-3000:]}"
    if output is not None:
        output.append(done.stdout + done.stderr)  # pymeshlab writes its verbose log to stderr
    return json.loads(lines[-1][len("RESULT "):])


def refusal_message(result, why_it_should_not_fit=""):
    """The refusal's message, once it is checked that the filter refused and left the document as it
    was (layers, current layer, their sizes)."""
    assert result["refused"], f"{why_it_should_not_fit} {result}"
    assert "The layers are unchanged." in result["message"], result["message"]
    assert result["after"] == result["before"], result
    return result["message"]


def grid_mesh_code(cells):
    """A flat grid of `cells` x `cells` squares, two triangles each, built in the child (too large for
    a command line as literals)."""
    return f"""
n = {cells}
xs, ys = np.meshgrid(np.arange(n + 1) * 0.01, np.arange(n + 1) * 0.01)
vertices = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
a = (np.arange(n)[None, :] + (n + 1) * np.arange(n)[:, None]).ravel()
faces = np.concatenate([np.stack([a, a + 1, a + n + 2], 1), np.stack([a, a + n + 2, a + n + 1], 1)]).astype(np.int32)
"""


def test_pop_buffer_levels_out_of_memory_leave_no_layer_behind():
    """16 levels of a 180k-face mesh need several hundred MB; under a 120 MB margin the filter runs out
    of memory (the campaign saw up to 16 layers left, the last empty). runFilter removes what it
    added: the document keeps its layers (the plane and the warm-up's level), unchanged."""
    body = grid_mesh_code(300) + f"""
ms = pymeshlab.MeshSet()
ms.add_mesh(pymeshlab.Mesh(vertex_matrix=vertices, face_matrix=faces), "plane")
ms.apply_filter({h.POP_LEVELS!r}, levels="2", correction=False)   # OpenMP's threads, once
ms.set_current_mesh(0)
before = state(ms)
limit_address_space(120)
apply_and_report(ms, before, {h.POP_LEVELS!r}, levels="1-16", correction=False)
"""
    message = refusal_message(run_child(body), "16 levels fitted in 120 MB?")
    assert "Out of memory" in message, message


def test_simplification_out_of_memory_while_adding_lod_layers_leaves_the_document_and_folder_as_they_were(tmp_path):
    """The campaign's case: memory ran out while the filter added its levels of detail, and the current
    layer was already simplified, partial LOD layers and the .rpm files were left. 60 levels of a
    180k-face mesh under an 800 MB margin: the simplification itself fits, the layers do not (the log
    shows the levels added before the failure). After the refusal: one layer, unsimplified, and no
    file in the folder (the .rpm and its base are staged and committed only on success)."""
    rpm = tmp_path / "plane.rpm"
    body = grid_mesh_code(300) + f"""
vertices[:, 2] = np.random.default_rng(1).uniform(0, 0.002, len(vertices))   # not flat: collapses cost
ms = pymeshlab.MeshSet(verbose=True)
ms.add_mesh(pymeshlab.Mesh(vertex_matrix=vertices, face_matrix=faces), "plane")
before = state(ms)
levels = ",".join(str(round(0.99 - 0.01 * i, 2)) for i in range(60))
limit_address_space(800)
apply_and_report(ms, before, {h.SIMPLIFY!r}, metric=3, targetfaces=1000, lodlevels=levels, progressivefile={str(rpm)!r})
"""
    output = []
    message = refusal_message(run_child(body, output=output), "60 levels of detail fitted in 800 MB?")
    assert "Out of memory" in message, message
    added = output[0].count("Level of detail")
    assert added >= 1, "memory ran out before the layers were added: the case is not the one tested\n" + output[0][-2000:]
    assert list(tmp_path.iterdir()) == [], list(tmp_path.iterdir())


def test_irradiance_grid_larger_than_the_address_space_limit_is_refused_up_front(tmp_path):
    """A resolution-400 grid (about 64 million vertices of 216 bytes: 14 GB) under a 400 MB margin: the
    filter's memory check (memory/available_memory.h, which counts the address-space limit as well as
    the machine's free memory) refuses it before allocating, with the figures and the parameter to
    lower; without the limit in the check, the allocation itself fails and only 'Out of memory' is
    said (or, with overcommit, the process is killed later)."""
    out = tmp_path / "grid.ivg"
    body = grid_mesh_code(20) + f"""
ms = pymeshlab.MeshSet()
ms.add_mesh(pymeshlab.Mesh(vertex_matrix=vertices, face_matrix=faces), "floor")
ms.apply_filter({h.IRRADIANCE_GRID!r}, resolution=2, rays=8, lightsource=1, outputfile={str(tmp_path / 'small.ivg')!r})
before = state(ms)
limit_address_space(400)
apply_and_report(ms, before, {h.IRRADIANCE_GRID!r}, resolution=400, rays=8, lightsource=1, outputfile={str(out)!r})
"""
    message = refusal_message(run_child(body))
    assert "A grid of resolution 400 needs about" in message and "choose a lower resolution" in message, message
    assert not out.exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["small.ivg"]


def test_radiance_simplification_larger_than_the_memory_is_refused_up_front_with_the_figures():
    """A 90k-vertex plane with PB(4) radiance needs about 240 MB to simplify with the radiance quadric
    (simplify/radiance_simplification.h's estimate: the quadric holds 75 float attributes per vertex);
    under a 120 MB margin the filter refuses it before building anything, saying how much it needs and
    how much there is; without the check, an allocation half way fails with only 'Out of memory'.
    The document is as it was."""
    body = grid_mesh_code(300) + f"""
vertices[:, 2] = np.random.default_rng(2).uniform(0, 0.002, len(vertices))
ms = pymeshlab.MeshSet()
ms.add_mesh(pymeshlab.Mesh(vertex_matrix=vertices, face_matrix=faces), "plane")
ms.compute_normal_per_vertex()
ms.apply_filter({h.CREATE!r}, basis=0, degree=4, reflected=False)
warm = pymeshlab.MeshSet()
warm.add_mesh(pymeshlab.Mesh(vertex_matrix=vertices[:2500], face_matrix=faces[(faces < 2500).all(axis=1)]), "warm")
warm.compute_normal_per_vertex()
warm.apply_filter({h.CREATE!r}, basis=0, degree=4, reflected=False)
warm.apply_filter({h.SIMPLIFY!r}, targetpercentage=0.5, lodlevels="")   # OpenMP's threads, once
before = state(ms)
limit_address_space(120)
apply_and_report(ms, before, {h.SIMPLIFY!r}, targetpercentage=0.1, lodlevels="")
"""
    message = refusal_message(run_child(body))
    assert "simplifying this mesh of 90601 vertices needs about" in message and "are available" in message, message
    assert "Out of memory" not in message, message
