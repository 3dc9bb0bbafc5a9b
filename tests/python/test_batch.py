"""`meshlab-radiance batch` on a real Dask LocalCluster of 2 workers over a dozen small scans:
a worker SIGKILLed mid-job, a broken file in the collection, reruns, a recipe refused before any job
runs, and a collection whose objects carry photographs (MeshLab project) or cameras of another tool.

Expected values come from the recipe itself (25 % of a 1280-face sphere is 320 faces; PB4 is the
create filter's default basis), from the files the test wrote, and from independent readers
(tests/integration/png_reader.py for the thumbnails)."""

import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import pymeshlab_test_helpers as h
from pymeshlab_radiance import batch_job, rply
from pymeshlab_radiance.recipe import EXAMPLE as RECIPE

SCANS = [f"scan{i:02d}.ply" for i in range(12)]
SPHERE_FACES = 1280  # create_sphere(subdiv=3): 20 * 4^3


def cli_environment():
    return h.python_env()


def start_batch(*args):
    return subprocess.Popen([sys.executable, "-m", "pymeshlab_radiance", "batch", *map(str, args), "--no-progress"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=cli_environment())


def run_batch(*args, timeout=180):
    process = start_batch(*args)
    out, err = process.communicate(timeout=timeout)
    return process.returncode, out, err


def manifest_lines(output):
    with open(output / "manifest.jsonl") as f:
        return [json.loads(line) for line in f]


def make_collection(folder):
    """Twelve spheres of different sizes and positions (binary PLY, as pymeshlab writes scans) and one
    file that is not a PLY at all."""
    import pymeshlab

    folder.mkdir(parents=True, exist_ok=True)
    for i, name in enumerate(SCANS):
        ms = pymeshlab.MeshSet()
        ms.create_sphere(subdiv=3, radius=1.0 + 0.1 * i)
        ms.compute_matrix_from_translation(axisx=float(i), freeze=True)
        ms.save_current_mesh(str(folder / name))
    (folder / "broken.ply").write_bytes(b"ply\nformat binary_little_endian 1.0\nelement vertex 99\n\x00\x17garbage")
    return folder


def job_processes():
    """Running job processes: {job pid: (worker pid, object key)}."""
    import psutil

    found = {}
    for process in psutil.process_iter(["pid", "ppid", "cmdline"]):
        cmd = process.info["cmdline"] or []
        if "pymeshlab_radiance.batch_job" in cmd and "run" in cmd:
            found[process.info["pid"]] = (process.info["ppid"], cmd[-1])
    return found


@pytest.fixture(scope="module")
def first_run(tmp_path_factory):
    """The first run over the collection, with the worker of one running job SIGKILLed."""
    root = tmp_path_factory.mktemp("batch")
    scans = make_collection(root / "scans")
    recipe = root / "recipe.toml"
    recipe.write_text(RECIPE)
    output = root / "out"
    mine = set(job_processes())
    process = start_batch(recipe, scans, output, "--workers", 2)
    killed = None
    deadline = time.time() + 120
    while killed is None and process.poll() is None and time.time() < deadline:
        for pid, (worker, key) in job_processes().items():
            if pid not in mine and key in SCANS:
                os.kill(worker, signal.SIGKILL)
                killed = {"job_pid": pid, "worker_pid": worker, "key": key}
                break
        time.sleep(0.02)
    out, err = process.communicate(timeout=180)
    return {"root": root, "scans": scans, "recipe": recipe, "output": output, "killed": killed,
            "returncode": process.returncode, "stderr": err}


def test_worker_killed_mid_job_and_broken_file(first_run):
    import psutil

    output, killed = first_run["output"], first_run["killed"]
    assert killed is not None, f"no job process was seen to kill:\n{first_run['stderr']}"
    # The broken file fails its own row; the exit status says not everything succeeded.
    assert first_run["returncode"] == 1, first_run["stderr"]
    rows = {row["key"]: row for row in manifest_lines(output)}
    assert set(rows) == set(SCANS) | {"broken.ply"}
    assert rows["broken.ply"]["status"] == "failed"
    assert "broken.ply" in rows["broken.ply"]["message"] and rows["broken.ply"]["message"].startswith("load:")
    assert "FAILED broken.ply" in first_run["stderr"]
    # The killed worker's job ran again (another process) and its output, like every other, is complete.
    again = rows[killed["key"]]
    assert again["status"] == "done" and again["pid"] != killed["job_pid"], again
    assert not psutil.pid_exists(killed["job_pid"]) or psutil.Process(killed["job_pid"]).status() == "zombie"
    for name in SCANS:
        assert rows[name]["status"] == "done", rows[name]
        mesh = rply.read_rply(str(output / name.replace(".ply", ".rply")))
        assert mesh.face_count == SPHERE_FACES // 4 and mesh.basis == "PB4"
        assert rows[name]["faces_before"] == SPHERE_FACES and rows[name]["faces_after"] == SPHERE_FACES // 4
        logs = " ".join(line for step in rows[name]["steps"] for line in step.get("log", []))
        assert f"Simplified {SPHERE_FACES} -> {SPHERE_FACES // 4} faces" in logs
    assert not [f for f in os.listdir(output) if f.startswith(".partial")], "a temporary was left behind"


def test_report_has_a_row_and_a_thumbnail_per_object(first_run):
    output = first_run["output"]
    with open(output / "report.csv") as f:
        records = {r["object"]: r for r in csv.DictReader(f)}
    assert set(records) == set(SCANS) | {"broken.ply"}
    assert records["broken.ply"]["status"] == "failed" and "broken.ply" in records["broken.ply"]["message"]
    page = (output / "report.html").read_text()
    for name in SCANS:
        record = records[name]
        assert (record["faces_before"], record["faces_after"], record["face_ratio"]) == ("1280", "320", "0.2500")
        assert record["thumbnail"] in page
        png = h.png_reader.read_png(str(output / record["thumbnail"]))
        alpha = np.array([[png.sample(x, y, 3) for x in range(png.width)] for y in range(png.height)])
        # A sphere fills a disc: drawn pixels in the centre, none in the corners.
        assert alpha[png.height // 2, png.width // 2] == 255 and alpha[0, 0] == 0
        assert 0.3 < (alpha == 255).mean() < 0.9


def test_rerun_skips_what_is_done_and_retries_what_failed(first_run, tmp_path):
    scans, output = tmp_path / "scans", tmp_path / "out"
    shutil.copytree(first_run["scans"], scans)
    shutil.copytree(first_run["output"], output)
    stamps = {f: os.stat(output / f).st_mtime_ns for f in os.listdir(output) if f.endswith(".rply")}
    before = len(manifest_lines(output))

    code, _, err = run_batch(first_run["recipe"], scans, output, "--workers", 2)
    assert code == 1 and "12 done already, 1 to run" in err, err
    lines = manifest_lines(output)
    assert len(lines) == before + 1 and lines[-1]["key"] == "broken.ply" and lines[-1]["status"] == "failed"

    shutil.copy(scans / SCANS[0], scans / "broken.ply")  # the broken scan replaced by a good one
    code, _, err = run_batch(first_run["recipe"], scans, output, "--workers", 2)
    assert code == 0 and "1 to run" in err, err
    assert manifest_lines(output)[-1]["status"] == "done"

    manifest = (output / "manifest.jsonl").read_bytes()
    code, _, err = run_batch(first_run["recipe"], scans, output, "--workers", 2)
    assert code == 0 and "13 done already, 0 to run" in err, err
    assert (output / "manifest.jsonl").read_bytes() == manifest
    assert {f: os.stat(output / f).st_mtime_ns for f in stamps} == stamps


def test_recipe_with_unknown_filter_is_refused_before_any_job(first_run, tmp_path):
    recipe = tmp_path / "typo.toml"
    recipe.write_text(RECIPE.replace("radiance_radiance_aware_simplification", "radiance_radiance_aware_simplificaton")
                      .replace("[output]", '[[step]]\nfilter = "meshing_decimation_quadric_edge_collapse"\n'
                               'params = { targetfacenumber = 10 }\n[output]'))
    output = tmp_path / "out"
    code, _, err = run_batch(recipe, first_run["scans"], output, "--workers", 2)
    assert code == 2, err
    assert "unknown filter 'radiance_radiance_aware_simplificaton'" in err
    assert "did you mean radiance_radiance_aware_simplification" in err
    assert "has no parameter targetfacenumber" in err and "targetfacenum" in err
    assert "nothing was started" in err and not output.exists()


def test_objects_with_photographs_are_fitted_and_foreign_cameras_refused(scenes, tmp_path):
    """A manifest: a mesh with its MeshLab project (fitted from its photographs) and a mesh with an
    incomplete COLMAP model beside it (cameras.txt without images.txt): the camera importer refuses
    it, and that row fails with the importer's reason while the other finishes."""
    photos = tmp_path / "photos"
    h.run_tool("virtual_acquisition", scenes("sphere", level=2), "-o", photos, "--views", 6, "--size", "96x72",
               "--no-variation", "--supersampling", 1)
    colmap = tmp_path / "colmap"
    (colmap / "sparse").mkdir(parents=True)
    shutil.copy(photos / "mesh.ply", colmap / "object.ply")
    (colmap / "sparse" / "cameras.txt").write_text("# Camera list with one line of data per camera:\n")
    manifest = tmp_path / "objects.txt"
    manifest.write_text("# mesh<TAB>project\nphotos/mesh.ply\tphotos/project.mlp\ncolmap/object.ply\tcolmap/sparse/cameras.txt\n")
    recipe = tmp_path / "fit.toml"
    recipe.write_text('[[step]]\nfilter = "radiance_fit_radiance_functions_from_rasters"\n'
                      'params = { degree = 2, depthtolerance = "0.5%", heldoutevery = 3 }\n[output]\nformat = "rply"\n')
    output = tmp_path / "out"
    code, _, err = run_batch(recipe, manifest, output, "--workers", 1)
    assert code == 1, err
    rows = {row["key"]: row for row in manifest_lines(output)}
    fitted = rows["photos/mesh.ply"]
    assert fitted["status"] == "done" and fitted["rasters"] == 6, fitted
    assert rply.read_rply(str(output / "photos__mesh.rply")).basis == "PB2"
    # Every 3rd photograph held out of the fit: the report's image error is the fit's held-out figure.
    summary = [line for step in fitted["steps"] for line in step["log"] if line.startswith("Held-out summary: 2 views")]
    assert len(summary) == 1, fitted["steps"]
    with open(output / "report.csv") as f:
        record = {r["object"]: r for r in csv.DictReader(f)}["photos/mesh.ply"]
    rms = summary[0].split("mean RMS fitted ")[1].split(",")[0]
    assert record["image_error"] == f"held-out photographs: RMS {rms} sRGB levels"
    refused = rows["colmap/object.ply"]
    assert refused["status"] == "failed"
    assert "COLMAP" in refused["message"] and "images.txt" in refused["message"], refused["message"]


def test_job_over_its_memory_limit_fails_its_row_with_the_remedy(first_run, tmp_path):
    """300 MiB of address space is less than pymeshlab and its plugins already hold (about 0.5 GiB):
    the job's first allocation fails, and the job says so instead of dying."""
    job = {"key": "scan00.ply", "meshes": [str(first_run["scans"] / "scan00.ply")], "steps": [
        {"filter": "meshing_surface_subdivision_midpoint", "params": {"iterations": 3}}],
        "output": {"format": "ply", "params": {}}, "output_path": str(tmp_path / "scan00.ply"),
        "thumbnail_path": None, "names": {}, "memory_limit": 300 * 2**20}
    result = batch_job.run_job(job, timeout=120)
    assert result["status"] == "failed" and result["returncode"] == 1, result
    # Where the first allocation fails (loading pymeshlab, the input, or the filter) depends on what
    # the interpreter has mapped already; the message names the cause, the limit and the remedy.
    message = result["message"]
    assert "out of memory" in message and "0.29 GiB per job" in message and "raise --memory-limit" in message, message
    assert not (tmp_path / "scan00.ply").exists()


def test_job_over_its_time_limit_is_stopped_and_says_so(first_run, tmp_path):
    job = {"key": "scan00.ply", "meshes": [str(first_run["scans"] / "scan00.ply")], "steps": [],
           "output": {"format": "ply", "params": {}}, "output_path": str(tmp_path / "scan00.ply"),
           "thumbnail_path": None, "names": {}, "memory_limit": 0}
    result = batch_job.run_job(job, timeout=0.05)  # far less than starting Python and pymeshlab takes
    assert result["status"] == "failed" and result["returncode"] == -signal.SIGKILL, result
    assert result["message"].startswith("the job ran longer than 0.05 s") and "raise --timeout" in result["message"]
    assert not (tmp_path / "scan00.ply").exists()
