"""The installed binary wheel, checked from inside the fresh venv that tests/wheel/check_wheel.sh made
(pymeshlab 2025.7.post1 and the wheel, nothing from the repository, LD_LIBRARY_PATH unset):

1. the package and its plugins come from the venv's site-packages;
2. every shared library that loading our plugins adds to the process lies in the wheel
   (pymeshlab_radiance.libs), in pymeshlab's lib folder, or is one of the manylinux policy's system
   libraries (libc, libstdc++, libz, libexpat, ...): nothing from Debian's Embree, TBB or OpenEXR
   packages, although this machine has them;
3. ldd (the system's loader, no LD_LIBRARY_PATH) resolves every dependency of every plugin and bundled
   library: pymeshlab's own (libmeshlab-common, Qt, libgomp) into pymeshlab's lib folder, the bundled
   ones into the wheel, the rest only to the manylinux policy's system libraries;
4. pymeshlab lists all our filters; two run: the analytic material (its .rply read back with rply, the
   positions those of the MeshSet) and the PRT transfer on a sphere (Embree and TBB from the wheel: a
   convex object sees its whole hemisphere, so band 0 of every vertex is Y00 = 1 / (2 sqrt(pi))).

Usage: python installed_wheel_check.py   (prints what it checked; exit status 1 with the reason on failure)
"""

import importlib.machinery
import math
import os
import re
import subprocess
import sys
import sysconfig
import tempfile

# The plugins the wheel ships (one per plugin folder of the repository, MeshLab 2025.07 builds).
WHEEL_PLUGINS = ("libio_radiance.so", "libfilter_radiance_fit.so", "libfilter_radiance_simplify.so",
                 "libfilter_prt_subdivide.so", "libfilter_normal_bake.so", "libfilter_out_of_core.so",
                 "libfilter_level_of_detail.so", "libfilter_irradiance_grid.so")

# The manylinux_2_35 policy's system libraries (auditwheel's policy file): a wheel may rely on them.
MANYLINUX_SYSTEM = {
    "libatomic.so.1", "libgcc_s.so.1", "libstdc++.so.6", "libm.so.6", "libmvec.so.1", "libanl.so.1",
    "libdl.so.2", "librt.so.1", "libc.so.6", "libnsl.so.1", "libutil.so.1", "libpthread.so.0",
    "libX11.so.6", "libXext.so.6", "libXrender.so.1", "libICE.so.6", "libSM.so.6", "libGL.so.1",
    "libgobject-2.0.so.0", "libgthread-2.0.so.0", "libglib-2.0.so.0", "libresolv.so.2", "libexpat.so.1",
    "libz.so.1", "ld-linux-x86-64.so.2",
}
Y00 = 0.5 / math.sqrt(math.pi)


def fail(message):
    print(f"[wheel-check] FAILED: {message}", file=sys.stderr)
    sys.exit(1)


def mapped_libraries():
    """Paths of the shared libraries mapped into this process (Python's own extension modules, which
    importing the package's Python code brings, left out)."""
    paths = set()
    with open("/proc/self/maps") as maps:
        for line in maps:
            fields = line.split(maxsplit=5)
            if len(fields) == 6 and ".so" in os.path.basename(fields[5]):
                path = os.path.realpath(fields[5].strip())
                if not path.endswith(tuple(importlib.machinery.EXTENSION_SUFFIXES)):
                    paths.add(path)
    return paths


def soname_of(path):
    """The file's name as the loader asks for it: a bundled copy's hash removed (libtbb-4d79fbbd.so.12.8
    -> libtbb.so.12), the version cut to the soname's first number."""
    name = re.sub(r"-[0-9a-f]{8}(?=\.so)", "", os.path.basename(path))
    match = re.match(r"^(.*?\.so)(\.\d+)?", name)
    return match.group(1) + (match.group(2) or "") if match else name


def direct_dependencies(path):
    """DT_NEEDED entries of an ELF64 little-endian shared object (read here: the venv has no binutils)."""
    import struct

    with open(path, "rb") as f:
        data = f.read()
    if data[:4] != b"\x7fELF" or data[4] != 2 or data[5] != 1:
        fail(f"{path} is not a 64-bit little-endian ELF file")
    shoff, = struct.unpack_from("<Q", data, 0x28)
    shentsize, shnum = struct.unpack_from("<HH", data, 0x3A)
    sections = [struct.unpack_from("<IIQQQQIIQQ", data, shoff + i * shentsize) for i in range(shnum)]
    for kind, offset, size, link in ((s[1], s[4], s[5], s[6]) for s in sections):
        if kind != 6:  # SHT_DYNAMIC
            continue
        strtab = sections[link][4]
        names = []
        for i in range(0, size, 16):
            tag, value = struct.unpack_from("<qQ", data, offset + i)
            if tag == 1:  # DT_NEEDED
                names.append(data[strtab + value:data.index(b"\0", strtab + value)].decode())
        return names
    return []


def needed_names(paths):
    return {name for path in paths for name in direct_dependencies(path)}


def main():
    if os.environ.get("LD_LIBRARY_PATH") or os.environ.get("PYMESHLAB_RADIANCE_PLUGIN_DIR"):
        fail("run with LD_LIBRARY_PATH and PYMESHLAB_RADIANCE_PLUGIN_DIR unset")
    site = os.path.realpath(sysconfig.get_paths()["platlib"])
    inside = (os.path.join(site, "pymeshlab_radiance"), os.path.join(site, "pymeshlab_radiance.libs"),
              os.path.join(site, "pymeshlab", "lib"))

    import pymeshlab  # first alone: what pymeshlab itself maps is not ours to check
    before = mapped_libraries()
    import pymeshlab_radiance
    from pymeshlab_radiance import rply

    # 1. Where the package and its plugins come from.
    if not os.path.realpath(pymeshlab_radiance.__file__).startswith(site + os.sep):
        fail(f"pymeshlab_radiance imported from {pymeshlab_radiance.__file__}, not from {site}")
    plugins = pymeshlab_radiance.load()
    if sorted(os.path.basename(p) for p in plugins) != sorted(WHEEL_PLUGINS) or \
            not all(os.path.realpath(p).startswith(inside[0]) for p in plugins):
        fail(f"expected the wheel's {len(WHEEL_PLUGINS)} plugins {sorted(WHEEL_PLUGINS)}, loaded {plugins}")

    # 2. What loading them added to the process.
    added = sorted(mapped_libraries() - before)
    foreign = [p for p in added if not p.startswith(inside) and soname_of(p) not in MANYLINUX_SYSTEM]
    if foreign:
        fail(f"loading the plugins mapped libraries from outside the wheel and pymeshlab: {foreign}")
    bundled = [p for p in added if p.startswith(inside[1])]
    for wanted in ("libembree3", "libtbb", "libOpenEXR-3_1", "libImath-3_1"):
        if not any(os.path.basename(p).startswith(wanted + "-") for p in bundled):
            fail(f"{wanted} was not loaded from the wheel's pymeshlab_radiance.libs (loaded: {added})")
    print(f"[wheel-check] loading the plugins added {len(added)} libraries, all from the wheel, pymeshlab or "
          f"the manylinux system set: " + ", ".join(os.path.basename(p) for p in added))

    # 3. ldd of every plugin and bundled library (the system's loader, no LD_LIBRARY_PATH): each direct
    #    dependency resolves into pymeshlab's lib folder when pymeshlab ships it, into the wheel when the
    #    wheel bundles it, else it is one of the manylinux system libraries; nothing is "not found".
    from_pymeshlab = set(os.listdir(inside[2]))
    bundled_files = [os.path.join(inside[1], f) for f in os.listdir(inside[1])]
    for library in list(plugins) + bundled_files:
        resolved = {}
        out = subprocess.run(["ldd", library], capture_output=True, text=True, env={"PATH": os.environ["PATH"]}).stdout
        for line in out.splitlines():
            if "not found" in line:
                fail(f"ldd {os.path.basename(library)}: {line.strip()}")
            match = re.match(r"\s*(\S+) => (/\S+)", line)
            if match:
                resolved[match.group(1)] = os.path.realpath(match.group(2))
        for needed in direct_dependencies(library):
            where = resolved.get(needed, needed)
            if needed in from_pymeshlab:
                ok = where.startswith(inside[2] + os.sep)
            elif re.search(r"-[0-9a-f]{8}\.so", needed):
                ok = where.startswith(inside[1] + os.sep)
            else:
                ok = needed in MANYLINUX_SYSTEM
            if not ok:
                fail(f"ldd {os.path.basename(library)}: its dependency {needed} resolves to {where}, outside the "
                     f"wheel and pymeshlab, and is not a manylinux system library")
    print(f"[wheel-check] ldd: the direct dependencies of the {len(plugins)} plugins and {len(bundled_files)} bundled "
          f"libraries resolve into pymeshlab ({', '.join(sorted(from_pymeshlab & needed_names(plugins)))}), "
          f"the wheel, or the manylinux system set")

    # 4. The filters: listed, and two of them run.
    known = set(pymeshlab.filter_list())
    missing = [f for f in pymeshlab_radiance.filter_names() if f not in known]
    if missing:
        fail(f"pymeshlab does not list {missing}")
    print(f"[wheel-check] pymeshlab lists {len(known)} filters, our {len(pymeshlab_radiance.filter_names())} among them")
    with tempfile.TemporaryDirectory() as folder:
        ms = pymeshlab.MeshSet()
        ms.create_sphere(subdiv=2)
        ms.apply_filter("radiance_create_radiance_data_from_analytic_material", degree=4)
        path = os.path.join(folder, "sphere.rply")
        ms.save_current_mesh(path)
        mesh = rply.read_rply(path)
        positions = ms.current_mesh().vertex_matrix()
        if mesh.basis != "PB4" or mesh.positions.shape != positions.shape or mesh.coefficients.shape != (len(positions), 3, 15):
            fail(f"the .rply holds {mesh.basis} {mesh.positions.shape} {mesh.coefficients.shape}, "
                 f"expected PB4 ({len(positions)}, 3) ({len(positions)}, 3, 15)")
        if abs(mesh.positions - positions).max() > 1e-6 or not (abs(mesh.coefficients).max() > 0):
            fail("the .rply's positions differ from the MeshSet's, or its coefficients are all zero")
        print(f"[wheel-check] analytic material: {path} read back with rply, {mesh.basis}, {len(positions)} vertices")

        ms.apply_filter("radiance_compute_prt_transfer", order=2, rays=64, occluders=0, albedo=False, rayoffset=0.0001)
        ms.save_current_mesh(path)
        transfer = rply.read_rply(path).blocks["prt"].values
        error = abs(transfer[:, 0] - Y00).max()
        if not error < 1e-3 * Y00:
            fail(f"PRT transfer of a convex sphere: band 0 is off Y00 by up to {error:.3g}")
        print(f"[wheel-check] PRT transfer (Embree, TBB from the wheel): band 0 = Y00 within {error:.2g}")
    print("[wheel-check] OK")


if __name__ == "__main__":
    main()
