#!/usr/bin/env python3
"""A capture made of every k-th view of another capture written by render_capture.py: copies
mesh.ply, the chosen photographs and masks (and noise twins), and writes project.mlp,
project_with_mesh.mlp, cameras.json and capture.json for them (cameras unchanged, copied from the
source's cameras.json and rewritten as VCGCamera elements exactly as render_capture.py does).

    subset_capture.py SOURCE_DIR --every 2 --out DIR
"""
import argparse
import json
import os
import shutil
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from render_capture import write_mlp  # noqa: E402


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("source")
    p.add_argument("--every", type=int, required=True, help="keep views 0, k, 2k, ...")
    p.add_argument("--out", required=True)
    args = p.parse_args(argv)
    src, out = os.path.abspath(args.source), os.path.abspath(args.out)
    cams = json.load(open(os.path.join(src, "cameras.json")))
    total = len(cams["views"])
    info = json.load(open(os.path.join(src, "capture.json")))
    keep = list(range(0, len(cams["views"]), args.every))
    for sub in ("photos", "masks", "photos_twin"):
        if os.path.isdir(os.path.join(src, sub)):
            os.makedirs(os.path.join(out, sub), exist_ok=True)
    shutil.copy2(os.path.join(src, "mesh.ply"), os.path.join(out, "mesh.ply"))
    views = [cams["views"][i] for i in keep]
    names = [os.path.basename(v["image"]) for v in views]
    twin_names = []
    for name in names:
        for sub in ("photos", "masks", "photos_twin"):
            f = os.path.join(src, sub, name)
            if os.path.isfile(f):
                shutil.copy2(f, os.path.join(out, sub, name))
                if sub == "photos_twin":
                    twin_names.append(name)
    cameras = [dict(R=np.array(v["R"]), t=np.array(v["t"]), centre=np.array(v["centre"]), fx=v["fx"], fy=v["fy"],
                    cx=v["cx"], cy=v["cy"], width=v["width"], height=v["height"]) for v in views]
    labels = [n[:-4] for n in names]
    write_mlp(os.path.join(out, "project.mlp"), cameras, [f"photos/{n}" for n in names], labels)
    write_mlp(os.path.join(out, "project_with_mesh.mlp"), cameras, [f"photos/{n}" for n in names], labels,
              mesh_file="mesh.ply")
    if twin_names:
        tw = [i for i, n in enumerate(names) if n in twin_names]
        write_mlp(os.path.join(out, "project_twin.mlp"), [cameras[i] for i in tw],
                  [f"photos_twin/{names[i]}" for i in tw], [labels[i] for i in tw])
    cams["views"] = views
    json.dump(cams, open(os.path.join(out, "cameras.json"), "w"), indent=1)
    info["subset"] = dict(source=os.path.basename(src), every=args.every, views=labels)
    info["sensors"] = [info["sensors"][i] for i in keep]
    json.dump(info, open(os.path.join(out, "capture.json"), "w"), indent=1)
    print(f"wrote {out}: {len(keep)} of {total} views")
    return 0


if __name__ == "__main__":
    sys.exit(main())
