#!/usr/bin/env python3
"""compare_readers.py RADIANCE_INFO FOLDER...: reads every file of the folders (e.g. the fuzzer's
corpus, build-fuzz/corpus) with the C++ reader (the radiance_info tool) and the numpy reader
(python/pymeshlab_radiance/rply.py), and lists the files on which they disagree: one loads and the
other refuses, or they refuse with different sentences. Both must follow the same rules
(docs/radiance-ply-format.md); the numpy reader's "update the plugin (pymeshlab_radiance)" is the
one intended difference. Exit status 1 when they disagree on any file."""
import collections
import importlib.util
import os
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
spec = importlib.util.spec_from_file_location("rply", os.path.join(ROOT, "python", "pymeshlab_radiance", "rply.py"))
rply = importlib.util.module_from_spec(spec)
sys.modules["rply"] = rply
spec.loader.exec_module(rply)


def verdicts(tool, path):
    r = subprocess.run([tool, path], capture_output=True, text=True, errors="replace")
    cpp = "" if r.returncode == 0 else r.stderr.strip().split("': ", 1)[-1]
    try:
        rply.read_rply(path)
        py = ""
    except rply.RadianceFileError as e:
        py = str(e).split("': ", 1)[-1].replace("update the plugin (pymeshlab_radiance)", "update the plugin")
    except Exception as e:  # noqa: BLE001 - anything but a refusal is a bug of the numpy reader
        py = f"unexpected {type(e).__name__}: {e}"
    return r.returncode == 0, cpp, py


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    tool, folders = sys.argv[1], sys.argv[2:]
    files = sorted(os.path.join(f, n) for f in folders for n in os.listdir(f))
    loaded, differing = 0, collections.OrderedDict()
    for path in files:
        ok, cpp, py = verdicts(tool, path)
        if cpp != py:
            differing[path] = (cpp or "loads", py or "loads")
        loaded += ok and not py
    print(f"{len(files)} files: {len(files) - len(differing)} read alike ({loaded} loaded by both), "
          f"{len(differing)} differ")
    for path, (cpp, py) in differing.items():
        print(f"{path}\n  C++:   {cpp}\n  numpy: {py}")
    sys.exit(1 if differing else 0)


if __name__ == "__main__":
    main()
