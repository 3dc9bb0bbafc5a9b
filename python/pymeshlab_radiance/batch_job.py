"""One object's job in a process of its own, and the launcher that runs it.

pymeshlab is not thread-safe, its loaders change the process's working directory, long series of
loads leak, and a crash (or the kernel's out-of-memory kill) takes the whole process down. So every
object is processed by a fresh Python process:

    python -m pymeshlab_radiance.batch_job run KEY < job.json     (result: one JSON line on stdout)
    python -m pymeshlab_radiance.batch_job probe   < query.json   (which filters/parameters exist)

``run_job(job, timeout=..., on_line=...)`` starts that process, feeds it the job, follows its stderr
(pymeshlab's verbose log: ``LOG: <level> <text> [ <percent>% ]`` lines, our ``@@step <i>`` markers)
and returns the result; ``on_line`` receives (step, percent, text) for a progress bar. The parent
never imports pymeshlab for that, so a Dask worker or the command line stays small and alive
whatever the job does.

The job process loads pymeshlab and our plugins, then limits its own address space (RLIMIT_AS:
pymeshlab with its libraries takes about 0.5 GB of address space before any mesh), asks the kernel to kill it when its parent dies
(PR_SET_PDEATHSIG: a killed Dask worker leaves no orphan writing files), writes its output into a
private temporary folder beside the destination and renames it into place, so an output file is
either complete or absent.
"""

import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time
import uuid

IMPORT_CAMERAS = "radiance_import_cameras_as_rasters"
_LOG = re.compile(r"^LOG: \d+ (.*?)(?:\s+\[\s*(\d+)%\s*\])?\s*$")
_STEP = re.compile(r"^@@step (\d+)$")
_PACKAGE_PARENT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


# ---------------------------------------------------------------------------------------------------
# The parent's side: launch, follow, collect.

def parse_size(text):
    """A memory size as the options take it: 4GiB, 500MB, 2e9, 0 (no limit) -> bytes."""
    text = str(text).strip().lower().replace(" ", "")
    if text in ("", "0", "none"):
        return 0
    units = (("kib", 2**10), ("mib", 2**20), ("gib", 2**30), ("tib", 2**40), ("kb", 10**3), ("mb", 10**6),
             ("gb", 10**9), ("tb", 10**12), ("k", 2**10), ("m", 2**20), ("g", 2**30), ("b", 1))
    for unit, factor in units:
        if text.endswith(unit):
            number = text[:-len(unit)]
            break
    else:
        number, factor = text, 1
    try:
        return int(float(number) * factor)
    except ValueError:
        raise ValueError(f"'{text}' is not a memory size: write it as 4GiB, 500MB or a number of bytes") from None


def child_environment():
    """The environment of a job process: this package importable from the same place."""
    env = dict(os.environ)
    paths = [_PACKAGE_PARENT] + [p for p in env.get("PYTHONPATH", "").split(os.pathsep) if p]
    env["PYTHONPATH"] = os.pathsep.join(dict.fromkeys(paths))
    env.setdefault("OMP_NUM_THREADS", "1")  # one job = one core; Dask runs as many jobs as cores
    return env


def run_job(job, timeout=3600, on_line=None, mode="run"):
    """Runs one job (or a probe) in a fresh process; returns its result dict. Never raises for
    what the job does: a crash, a kill or a timeout is a result with status 'failed' and the reason."""
    started = time.time()
    job = dict(job, parent_pid=os.getpid())
    # The object's key on the command line only names the process for ps/top (the job comes on stdin).
    process = subprocess.Popen([sys.executable, "-m", "pymeshlab_radiance.batch_job", mode, str(job.get("key", ""))],
                               stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                               env=child_environment(), text=True, errors="replace")
    stopped = threading.Event()
    timer = threading.Timer(timeout, lambda: (stopped.set(), _kill(process)))
    timer.start()
    stdout = []
    reader = threading.Thread(target=lambda: stdout.append(process.stdout.read()), daemon=True)
    reader.start()
    try:
        process.stdin.write(json.dumps(job))
        process.stdin.close()
    except BrokenPipeError:
        pass
    follow = _Follower(on_line)
    for line in process.stderr:
        follow.line(line.rstrip("\n"))
    process.wait()
    reader.join()
    timer.cancel()
    timed_out = stopped.is_set()
    result = _parse_result("".join(stdout))
    if result is None:
        result = {"status": "failed", "message": _death_message(process.returncode, follow, job, timeout, timed_out)}
    result["returncode"] = process.returncode
    result["seconds_process"] = round(time.time() - started, 3)
    for index, lines in follow.logs.items():
        if index < len(result.get("steps", [])):
            result["steps"][index]["log"] = lines[-20:]
    return result


def _kill(process):
    try:
        process.kill()
    except OSError:
        pass


def _parse_result(text):
    for line in reversed(text.splitlines()):
        if line.startswith("{"):
            try:
                return json.loads(line)
            except json.JSONDecodeError:
                return None
    return None


def _death_message(returncode, follow, job, timeout, timed_out):
    steps = job.get("steps", [])
    where = "while loading the input"
    if follow.step is not None and follow.step < len(steps):
        where = f"in step {follow.step + 1} ({steps[follow.step]['filter']})"
    if timed_out:
        return f"the job ran longer than {timeout:g} s {where} and was stopped: raise --timeout, or simplify the recipe"
    if returncode is not None and returncode < 0:
        name = signal.Signals(-returncode).name if -returncode in signal.Signals._value2member_map_ else str(-returncode)
        hint = {"SIGKILL": "killed from outside or by the kernel's out-of-memory killer: raise --memory-limit or use "
                           "fewer workers per machine",
                "SIGSEGV": "a crash in pymeshlab or a plugin: the input may be malformed",
                "SIGABRT": "an abort in pymeshlab or a plugin (often out of memory: raise --memory-limit)"}.get(name, "")
        return f"the job process died of {name} {where}" + (f" ({hint})" if hint else "")
    tail = " | ".join(follow.other[-6:])
    if "MemoryError" in tail or "bad_alloc" in tail:
        return (f"the job ran out of memory {where} (memory limit {job.get('memory_limit', 0) / 2**30:.2f} GiB per "
                f"job): raise --memory-limit")
    return f"the job process exited with status {returncode} {where}: {tail or 'no message'}"


class _Follower:
    """Reads the job's stderr: step markers, pymeshlab's LOG lines (progress and figures), the rest."""

    def __init__(self, on_line):
        self.on_line, self.step, self.logs, self.other = on_line, None, {}, []

    def line(self, text):
        marker = _STEP.match(text)
        if marker:
            self.step = int(marker.group(1))
            if self.on_line:
                self.on_line(self.step, 0, "")
            return
        log = _LOG.match(text)
        if log:
            message, percent = log.group(1).strip(), log.group(2)
            if percent is None and self.step is not None:
                self.logs.setdefault(self.step, []).append(message)
            if self.on_line and self.step is not None:
                self.on_line(self.step, None if percent is None else int(percent), message)
            return
        if text.strip():
            self.other = (self.other + [text.strip()])[-40:]


# ---------------------------------------------------------------------------------------------------
# The job process's side.

def _child_setup(job):
    """Memory limit, death with the parent, stdout kept for the result only."""
    _limit_memory(job)
    _die_with_parent(job.get("parent_pid"))
    result_out = os.fdopen(os.dup(1), "w")
    os.dup2(2, 1)  # pymeshlab's own prints (C++ and Python) go to stderr with its log
    sys.stdout = sys.stderr
    return result_out


def _load_pymeshlab():
    """pymeshlab and our plugins, loaded before the memory limit (the package loads its plugins lazily,
    and the limit is meant for the job's meshes); the ImportError's text on failure, else None."""
    try:
        import pymeshlab_radiance

        pymeshlab_radiance.load()
        # The modules the eager package import brought before the limit, in its order: the limit counts
        # what is mapped already, so a job keeps the headroom it had.
        from pymeshlab_radiance import rply  # noqa: F401
        return None
    except ImportError as e:
        return str(e)


def _limit_memory(job):
    limit = int(job.get("memory_limit") or 0)
    if limit > 0:
        import resource
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))


def _die_with_parent(parent_pid):
    try:
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):
        return
    if parent_pid and os.getppid() != parent_pid:  # the parent died before prctl
        os._exit(1)


def _marker(index):
    sys.stderr.write(f"@@step {index}\n")
    sys.stderr.flush()


def _load_inputs(ms, job, pymeshlab):
    for path in job["meshes"]:
        ms.load_new_mesh(path)
    main_id = ms.current_mesh_id()
    if job.get("project"):
        ms.load_project(job["project"])
        ms.set_current_mesh(main_id)
    cameras = job.get("cameras")
    if cameras:
        if IMPORT_CAMERAS not in pymeshlab.filter_list():
            raise _Refusal(
                f"{cameras['camerafile']} holds cameras ({cameras['kind']}) but this pymeshlab_radiance has no filter "
                f"{IMPORT_CAMERAS}: export the cameras as a MeshLab project (.mlp, same name as the mesh) beside the "
                f"mesh, or use a version of the package with the camera importer")
        ms.apply_filter(IMPORT_CAMERAS, camerafile=cameras["camerafile"], imagefolder=cameras["imagefolder"])
        ms.set_current_mesh(main_id)


class _Refusal(Exception):
    pass


def _run(job):
    import numpy as np
    import pymeshlab
    import pymeshlab_radiance  # noqa: F401  (loads our plugins)
    from pymeshlab_radiance.recipe import expand_value
    from pymeshlab_radiance.thumbnail import render_thumbnail, write_png

    result = {"status": "failed", "steps": [], "pid": os.getpid()}
    ms = pymeshlab.MeshSet(verbose=True)
    t0 = time.time()
    stage = "load"
    try:
        _load_inputs(ms, job, pymeshlab)
        mesh = ms.current_mesh()
        result.update(faces_before=mesh.face_number(), vertices_before=mesh.vertex_number(),
                      rasters=ms.raster_number(), seconds_load=round(time.time() - t0, 3))
        for index, step in enumerate(job["steps"]):
            stage = f"step {index + 1} ({step['filter']})"
            _marker(index)
            params = {k: expand_value(v, job.get("names", {})) for k, v in step["params"].items()}
            t = time.time()
            ms.apply_filter(step["filter"], **params)
            mesh = ms.current_mesh()
            result["steps"].append({"filter": step["filter"], "seconds": round(time.time() - t, 3),
                                    "faces": mesh.face_number(), "vertices": mesh.vertex_number()})
        _marker(len(job["steps"]))
        stage = "save"
        t = time.time()
        mesh = ms.current_mesh()
        result.update(faces_after=mesh.face_number(), vertices_after=mesh.vertex_number())
        box = mesh.bounding_box()
        result.update(bbox_min=[float(x) for x in box.min()], bbox_max=[float(x) for x in box.max()],
                      vertex_color=bool(mesh.has_vertex_color()), layers=ms.mesh_number(),
                      rasters_after=ms.raster_number())
        if (job.get("output_path") or "").lower().endswith(".mlp"):  # a MeshLab project: layers and rasters
            _save_project_atomically(ms, job["output_path"])
            result["seconds_save"] = round(time.time() - t, 3)
        elif job.get("output_path"):  # none for 'info'
            save = {k: expand_value(v, job["names"]) for k, v in job["output"].get("params", {}).items()}
            _save_atomically(ms, job["output_path"], save)
            result["seconds_save"] = round(time.time() - t, 3)
        if job.get("thumbnail_path"):
            stage = "thumbnail"
            colors = mesh.vertex_color_matrix()[:, :3] if mesh.has_vertex_color() else None
            faces = mesh.face_matrix() if mesh.face_number() else np.zeros((0, 3), dtype=np.int32)
            write_png(job["thumbnail_path"], render_thumbnail(mesh.vertex_matrix(), faces, colors))
        result["status"] = "done"
    except (pymeshlab.PyMeshLabException, _Refusal, TypeError, ValueError, OSError, MemoryError) as e:
        text = " ".join(str(e).split()) or type(e).__name__
        text = re.sub(r"^Failed to apply filter: \S+ Details: ", "", text)  # the filter is named in `stage`
        if isinstance(e, MemoryError) or "bad_alloc" in text:
            text = f"out of memory (limit {int(job.get('memory_limit') or 0) / 2**30:.2f} GiB per job): raise --memory-limit"
        result["message"] = f"{stage}: {text}"
        if stage.startswith("step"):
            result["failed_step"] = len(result["steps"])
    result["seconds_total"] = round(time.time() - t0, 3)
    return result


def _save_atomically(ms, path, save_params):
    """Saves into a private folder beside `path` (so side files such as .mtl or textures keep the final
    names they reference), then renames every file into place, the mesh last."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    partial = os.path.join(folder, f".partial-{uuid.uuid4().hex}")
    os.mkdir(partial)
    try:
        name = os.path.basename(path)
        ms.save_current_mesh(os.path.join(partial, name), **save_params)
        others = [f for f in os.listdir(partial) if f != name]
        for f in others + [name]:
            os.replace(os.path.join(partial, f), os.path.join(folder, f))
    finally:
        shutil.rmtree(partial, ignore_errors=True)


def _save_project_atomically(ms, path):
    """A MeshLab project names its mesh and photographs relative to its own folder: it is written in
    that folder under a unique temporary name, then renamed into place."""
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    partial = os.path.join(folder, f".partial-{uuid.uuid4().hex}.mlp")
    try:
        ms.save_project(partial)
        os.replace(partial, path)
    finally:
        if os.path.exists(partial):
            os.remove(partial)


def _probe(query):
    """Which of the query's filters and parameters pymeshlab knows (after loading our plugins), and
    whether it saves the output format."""
    import pymeshlab
    import pymeshlab_radiance  # noqa: F401

    known = sorted(pymeshlab.filter_list())
    answer = {"known": known, "unknown_filters": [], "unknown_params": {}, "format_error": None}
    ms = pymeshlab.MeshSet()
    ms.create_sphere(subdiv=1)
    for step in query.get("steps", []):
        name = step["filter"]
        if name not in known:
            answer["unknown_filters"].append(name)
            continue
        try:
            allowed = set(ms.filter_parameter_values(name))
        except pymeshlab.PyMeshLabException:
            continue  # defaults need more than a sphere (rasters, two layers): checked when it runs
        wrong = sorted(set(step.get("params", {})) - allowed)
        if wrong:
            answer["unknown_params"][name] = {"wrong": wrong, "allowed": sorted(allowed)}
    fmt = query.get("format")
    if fmt:
        folder = tempfile.mkdtemp(prefix="radiance-probe-")
        try:
            ms.save_current_mesh(os.path.join(folder, f"probe.{fmt}"), **query.get("save_params", {}))
        except (pymeshlab.PyMeshLabException, TypeError) as e:
            answer["format_error"] = " ".join(str(e).split())
        finally:
            shutil.rmtree(folder, ignore_errors=True)
    answer["status"] = "done"
    return answer


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    mode = argv[0] if argv else "run"
    load_error = _load_pymeshlab()  # first, as an import of the package did before loading became lazy
    job = json.loads(sys.stdin.read())
    result_out = _child_setup(job)
    try:
        if load_error:
            raise ImportError(load_error)
        result = _run(job) if mode == "run" else _probe(job)
    except ImportError as e:  # no usable pymeshlab or plugins, or a module the limit kept from loading
        result = {"status": "failed", "message": f"cannot load pymeshlab and the plugins: {e}"}
    result_out.write(json.dumps(result) + "\n")
    result_out.flush()
    # Leave without running pymeshlab's destructors: nothing remains to save, and a process that
    # saw a refused filter may crash while freeing (the dangling log pointer of pymeshlab 2025.7).
    os._exit(0 if result.get("status") == "done" else 1)


if __name__ == "__main__":
    main()
