"""``meshlab-radiance batch RECIPE.toml INPUT OUTPUT``: one recipe over a collection, on Dask.

Steps of a run:
1. read the recipe (``recipe.py``) and the collection (``collection.py``);
2. ask pymeshlab, in a separate process, whether every filter, parameter and the output format exist
   (a recipe that cannot run is refused before any job starts);
3. read OUTPUT/manifest.jsonl and keep only the objects not yet done with this input and this recipe
   (same hashes, output present): a rerun does no work, a failed row runs again;
4. start a Dask ``LocalCluster`` (processes, one thread each, a memory limit each) or connect to
   ``--scheduler``; each object is one task, and each task runs its job in a fresh process
   (``batch_job.run_job``), so a job that crashes fails its row only, and a worker that dies
   mid-job has its task run again on another worker by the scheduler;
5. append one manifest line per finished job (hashes, status, timings, faces, the filters' log
   lines, the refusal message), with a progress bar over the collection;
6. write OUTPUT/report.html and OUTPUT/report.csv (``report.py``) and exit 0 only if every object of
   the collection is done.
"""

import difflib
import hashlib
import json
import os
import socket
import sys
import time

from . import batch_job
from .collection import CollectionError, discover
from .recipe import RecipeError, default_output_name, load_recipe

MANIFEST = "manifest.jsonl"
THUMBNAILS = "thumbnails"


class BatchError(Exception):
    """A run that cannot start: printed on stderr, exit status 2."""


# ---------------------------------------------------------------------------------------------------
# The task each Dask worker runs.

def run_row(job, timeout):
    """Runs one object's job in its own process; always returns a manifest row."""
    started = time.time()
    result = batch_job.run_job(job, timeout=timeout)
    try:
        from distributed import get_worker
        worker = get_worker().address
    except (ImportError, ValueError):
        worker = None
    row = {key: job[key] for key in ("key", "input", "input_sha256", "recipe_sha256")}
    row.update(result)
    row.update(worker=worker, host=socket.gethostname(), started=round(started, 3), finished=round(time.time(), 3))
    if row["status"] == "done":
        row["output"] = os.path.basename(job["output_path"])
        row["thumbnail"] = f"{THUMBNAILS}/{os.path.basename(job['thumbnail_path'])}"
    return row


# ---------------------------------------------------------------------------------------------------
# The manifest: JSON lines, appended, the last line of an object wins.

def read_manifest(path):
    rows = {}
    if not os.path.isfile(path):
        return rows
    with open(path, encoding="utf-8") as f:
        for line in f:
            try:
                row = json.loads(line)
            except json.JSONDecodeError:
                continue  # a line cut by a crash of the client: that object simply runs again
            if isinstance(row, dict) and "key" in row:
                rows[row["key"]] = row
    return rows


def append_manifest(path, row):
    with open(path, "a", encoding="utf-8") as f:
        f.write(json.dumps(row, sort_keys=True) + "\n")
        f.flush()
        os.fsync(f.fileno())


# ---------------------------------------------------------------------------------------------------
# Checking the recipe against pymeshlab before anything runs.

def check_recipe(recipe, timeout=300):
    query = {"steps": recipe.steps, "format": recipe.output["format"], "save_params": recipe.output["params"]}
    answer = batch_job.run_job(query, timeout=timeout, mode="probe")
    if answer.get("status") != "done":
        raise BatchError(f"could not ask pymeshlab which filters exist: {answer.get('message')}")
    problems = []
    known = answer["known"]
    for name in answer["unknown_filters"]:
        close = difflib.get_close_matches(name, known, n=3, cutoff=0.6)
        hint = f" (did you mean {', '.join(close)}?)" if close else ""
        problems.append(f"unknown filter '{name}'{hint}")
    for name, wrong in answer["unknown_params"].items():
        problems.append(f"filter '{name}' has no parameter {', '.join(wrong['wrong'])} "
                        f"(its parameters: {', '.join(wrong['allowed'])})")
    if answer["format_error"]:
        problems.append(f"[output] format '{recipe.output['format']}' cannot be saved by pymeshlab: "
                        f"{answer['format_error']} (use rply, ply, obj, off or stl; for glTF add a bake_normal_map "
                        f"step with gltf = true)")
    if problems:
        ours = [n for n in known if n.startswith(("radiance_", "bake_normal", "extract_level", "out_of_core",
                                                   "compute_irradiance"))]
        raise BatchError(f"the recipe {recipe.source} cannot run, nothing was started:\n  - " + "\n  - ".join(problems)
                         + f"\npymeshlab knows {len(known)} filters with our plugins loaded, ours: {', '.join(ours)}; "
                         f"'meshlab-radiance filters' lists them all.")
    return known


# ---------------------------------------------------------------------------------------------------
# Planning: which objects need a job.

def plan(items, recipe, output_dir, memory_limit):
    """(jobs to run, rows already done, rows failed before any job: unreadable inputs)."""
    manifest = read_manifest(os.path.join(output_dir, MANIFEST))
    recipe_hash = recipe.sha256()
    jobs, done, failed = [], [], []
    for item in items:
        try:
            input_hash = item.sha256()
        except OSError as e:
            failed.append({"key": item.key, "input": item.mesh, "status": "failed", "recipe_sha256": recipe_hash,
                           "message": f"cannot read the input: {e.strerror}: {e.filename}"})
            continue
        name = default_output_name(item.key, recipe.output["format"])
        previous = manifest.get(item.key)
        if (previous and previous.get("status") == "done" and previous.get("input_sha256") == input_hash
                and previous.get("recipe_sha256") == recipe_hash and os.path.isfile(os.path.join(output_dir, name))):
            done.append(previous)
            continue
        stem = os.path.splitext(name)[0]
        jobs.append({
            "key": item.key, "input": item.mesh, "input_sha256": input_hash, "recipe_sha256": recipe_hash,
            "meshes": [item.mesh], "project": item.project, "cameras": item.cameras,
            "steps": recipe.steps, "output": recipe.output,
            "output_path": os.path.join(output_dir, name),
            "thumbnail_path": os.path.join(output_dir, THUMBNAILS, stem + ".png"),
            "names": {"stem": stem, "output_dir": output_dir, "input_dir": os.path.dirname(item.mesh)},
            "memory_limit": memory_limit,
        })
    return jobs, done, failed


# ---------------------------------------------------------------------------------------------------
# Running on Dask.

def _start_client(workers, scheduler, memory_limit):
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        raise BatchError("the batch command needs Dask: pip install 'dask[distributed]' tqdm "
                         "(or pip install 'pymeshlab-radiance[batch]')") from None
    if scheduler:
        return Client(scheduler, timeout="60s"), None
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           memory_limit=memory_limit or "auto", dashboard_address=":0")  # any free port: several runs may share a machine
    return Client(cluster), cluster


def run_jobs(jobs, manifest_path, workers, scheduler, memory_limit, timeout, retries, progress):
    from distributed import as_completed

    from .progress import bar

    client, cluster = _start_client(workers, scheduler, memory_limit)
    rows = []
    try:
        futures = {}
        for job in jobs:
            key = "radiance-job-" + hashlib.sha1((job["key"] + job["input_sha256"] + str(time.time())).encode()).hexdigest()
            futures[client.submit(run_row, job, timeout, key=key, retries=retries, pure=False)] = job
        with bar(total=len(jobs), unit="object", desc="batch", enabled=progress) as pbar:
            for future in as_completed(futures):
                job = futures[future]
                try:
                    row = future.result()
                except Exception as e:  # the scheduler gave up (e.g. KilledWorker: the job killed each worker)
                    row = {key: job[key] for key in ("key", "input", "input_sha256", "recipe_sha256")}
                    row.update(status="failed", message=f"the task failed on the cluster: {type(e).__name__}: {e}")
                append_manifest(manifest_path, row)
                rows.append(row)
                pbar.update(1)
                failed = sum(r["status"] != "done" for r in rows)
                pbar.set_postfix_str(f"{failed} failed" if failed else job["key"][-30:])
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return rows


# ---------------------------------------------------------------------------------------------------
# The command.

def _lock(output_dir):
    """One run per output folder at a time: the manifest has one writer."""
    import fcntl

    handle = open(os.path.join(output_dir, ".batch.lock"), "w")
    try:
        fcntl.flock(handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError:
        raise BatchError(f"another batch run is writing into {output_dir}: wait for it to end, or choose "
                         f"another output folder") from None
    return handle


def _remove_partials(output_dir):
    """Temporary folders of jobs killed while saving in an earlier run (never a finished output)."""
    import shutil

    for folder in (output_dir, os.path.join(output_dir, THUMBNAILS)):
        for name in os.listdir(folder):
            if name.startswith(".partial-"):
                path = os.path.join(folder, name)
                shutil.rmtree(path, ignore_errors=True) if os.path.isdir(path) else os.unlink(path)


def add_arguments(parser):
    parser.add_argument("recipe", help="the recipe (TOML): [[step]] filter/params, [output] format/params")
    parser.add_argument("input", help="a folder of meshes (with .mlp projects or cameras beside them) or a manifest file")
    parser.add_argument("output", help="the output folder: outputs, thumbnails/, manifest.jsonl, report.html, report.csv")
    where = parser.add_mutually_exclusive_group()
    where.add_argument("--workers", type=int, default=None,
                       help="Dask workers of the local cluster (processes, one job each; default: the CPU count)")
    where.add_argument("--scheduler", metavar="ADDRESS",
                       help="a running Dask scheduler (tcp://host:8786, e.g. from dask-jobqueue) instead of a local cluster")
    parser.add_argument("--memory-limit", default="4GiB",
                        help="memory per worker and per job (address-space limit of the job process), e.g. 2GiB "
                             "[%(default)s]; pymeshlab itself takes about 0.5 GiB of address space")
    parser.add_argument("--timeout", type=float, default=3600, help="seconds one job may run [%(default)s]")
    parser.add_argument("--retries", type=int, default=1,
                        help="extra tries of a task whose worker failed it [%(default)s]; a worker that dies has "
                             "its task rerun by the scheduler anyway")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


def run(args):
    started = time.time()
    from .report import write_report

    recipe = load_recipe(args.recipe)
    output_dir = os.path.abspath(args.output)
    items = discover(args.input, exclude=output_dir)
    try:
        memory_limit = batch_job.parse_size(args.memory_limit)
    except ValueError as e:
        raise BatchError(f"--memory-limit: {e}") from None
    check_recipe(recipe)
    os.makedirs(os.path.join(output_dir, THUMBNAILS), exist_ok=True)
    lock = _lock(output_dir)  # noqa: F841  (held until the process ends)
    _remove_partials(output_dir)
    manifest_path = os.path.join(output_dir, MANIFEST)
    jobs, done, unreadable = plan(items, recipe, output_dir, memory_limit)
    for row in unreadable:
        append_manifest(manifest_path, row)
    workers = args.workers or os.cpu_count() or 1
    print(f"{len(items)} objects: {len(done)} done already, {len(jobs)} to run"
          + (f", {len(unreadable)} unreadable" if unreadable else "")
          + ("" if not jobs else f" on {args.scheduler or f'{workers} local workers'}"), file=sys.stderr)
    rows = []
    t_jobs = time.time()
    if jobs:
        rows = run_jobs(jobs, manifest_path, workers, args.scheduler, memory_limit, args.timeout, args.retries,
                        not args.no_progress)
    seconds = time.time() - t_jobs
    final = {row["key"]: row for row in done + unreadable + rows}
    ordered = [final[item.key] for item in items if item.key in final]
    throughput = len(rows) / seconds * 60 if rows and seconds > 0 else None
    write_report(output_dir, ordered, recipe, {"ran": len(rows), "skipped": len(done), "seconds": seconds,
                                               "workers": args.scheduler or workers, "objects_per_minute": throughput})
    failures = [row for row in ordered if row["status"] != "done"]
    for row in failures:
        print(f"FAILED {row['key']}: {row.get('message', '')}", file=sys.stderr)
    summary = f"{len(ordered) - len(failures)}/{len(ordered)} done, {len(failures)} failed"
    if rows:
        summary += f"; {len(rows)} jobs in {seconds:.1f} s ({throughput:.1f} objects per minute)"
    print(f"{summary}; total {time.time() - started:.1f} s; report: {os.path.join(output_dir, 'report.html')}",
          file=sys.stderr)
    return 0 if not failures else 1


def main(args):
    try:
        return run(args)
    except (RecipeError, CollectionError, BatchError) as e:
        print(f"meshlab-radiance batch: {e}", file=sys.stderr)
        return 2
