"""Throughput of `meshlab-radiance batch` (objects per minute) with 1 and 2 local Dask workers, and the
per-job figures the cluster estimate in docs/batch.md is reasoned from.

    python bench/batch_throughput.py [--objects 24] [--subdiv 5] [--workers 1 2] [--folder /tmp/bench]

Makes N spheres (create_sphere, 20 * 4^subdiv faces) with pymeshlab, runs the minimal recipe
(analytic radiance PB4, radiance-aware simplification to 25 %, .rply) into a fresh output folder for
each worker count, and prints: wall time, objects per minute, and per job the mean time of the whole
process (start, imports, plugins, load, filters, save, thumbnail), of the work inside it, and their
difference (the fixed cost of a fresh process). Needs pymeshlab_radiance importable with its plugins
(PYTHONPATH=python PYMESHLAB_RADIANCE_PLUGIN_DIR=build/pymeshlab_plugins from a source checkout).
"""

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

from pymeshlab_radiance.recipe import EXAMPLE as RECIPE


def make_collection(folder, count, subdiv):
    import pymeshlab

    os.makedirs(folder, exist_ok=True)
    for i in range(count):
        ms = pymeshlab.MeshSet()
        ms.create_sphere(subdiv=subdiv, radius=1.0 + 0.05 * i)
        ms.save_current_mesh(os.path.join(folder, f"object{i:03d}.ply"))


def run(recipe, scans, output, workers):
    shutil.rmtree(output, ignore_errors=True)
    started = time.time()
    result = subprocess.run([sys.executable, "-m", "pymeshlab_radiance", "batch", recipe, scans, output,
                             "--workers", str(workers), "--no-progress"], stderr=subprocess.PIPE, text=True)
    wall = time.time() - started
    if result.returncode != 0:
        sys.exit(f"batch failed ({result.returncode}):\n{result.stderr}")
    with open(os.path.join(output, "manifest.jsonl")) as f:
        rows = [json.loads(line) for line in f]
    return wall, rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--objects", type=int, default=24)
    parser.add_argument("--subdiv", type=int, default=5)
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--folder", default=None)
    args = parser.parse_args()
    folder = args.folder or tempfile.mkdtemp(prefix="batch-bench-")
    scans, recipe = os.path.join(folder, "scans"), os.path.join(folder, "recipe.toml")
    make_collection(scans, args.objects, args.subdiv)
    with open(recipe, "w") as f:
        f.write(RECIPE)
    print(f"{args.objects} spheres of {20 * 4 ** args.subdiv} faces, recipe: create PB4 + simplify to 25 %, "
          f"{os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} at start")
    print("workers | wall s | objects/min | job process s (mean) | work in job s (mean) | process overhead s")
    for workers in args.workers:
        wall, rows = run(recipe, scans, os.path.join(folder, f"out{workers}"), workers)
        process = sum(r["seconds_process"] for r in rows) / len(rows)
        work = sum(r["seconds_total"] for r in rows) / len(rows)
        print(f"{workers:7d} | {wall:6.1f} | {len(rows) / wall * 60:11.1f} | {process:20.3f} | {work:20.3f} | "
              f"{process - work:18.3f}")
    print(f"load average {os.getloadavg()[0]:.2f} at the end")


if __name__ == "__main__":
    main()
