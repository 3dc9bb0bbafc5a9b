#!/usr/bin/env python3
"""What the splat transfer keeps of the view dependence, at one vertex: the colour a viewer sees
toward directions on a great circle of the vertex's hemisphere, from the splats (the reference
rasteriser's colour of the field at the vertex: eval_sh at the camera-to-splat direction, + 0.5,
sRGB-decoded) and from the transferred radiance function (our SH, read back from the saved .rply).

    python3 bench/plot_splat_transfer.py OUT.png

Runs the filter through pymeshlab on tests/integration/splat_writer.py's SH1 field on the unit
sphere (UV-sphere mesh), writes OUT.png and OUT.svg and prints the largest difference in 8-bit
levels along the curve. Needs matplotlib (scripts/setup.sh installs it into build/python-venv) and
the plugins (PYMESHLAB_RADIANCE_PLUGIN_DIR or an installed package).
"""
import math
import os
import sys
import tempfile

import numpy as np

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, os.path.join(REPO, "tests", "integration"))
import splat_writer  # noqa: E402

import matplotlib  # noqa: E402

matplotlib.use("Agg")
matplotlib.rcParams["svg.fonttype"] = "none"
import matplotlib.pyplot as plt  # noqa: E402


def our_sh1(coefficients, w):
    """Our SH of bands 0-1 (no Condon-Shortley phase): Y00, c y, c z, c x."""
    c = 0.4886025119029199
    basis = np.stack([np.full(len(w), 0.28209479177387814), c * w[:, 1], c * w[:, 2], c * w[:, 0]], axis=1)
    return basis @ coefficients.T  # (directions, channels)


def main(out):
    import pymeshlab
    import pymeshlab_radiance  # noqa: F401
    from pymeshlab_radiance import rply

    work = tempfile.mkdtemp(prefix="plot_splats_")
    mesh, splats, saved = (os.path.join(work, n) for n in ("sphere.ply", "splats.ply", "sphere.rply"))
    splat_writer.write_scenario("sphere_mesh", mesh)
    splat_writer.write_scenario("sphere_splats", splats)
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(mesh)
    ms.apply_filter("radiance_transfer_gaussian_splats", splatfile=splats)
    ms.save_current_mesh(saved)
    result = rply.read_rply(saved)
    # The vertex nearest to (0, 0.6, 0.8): its hemisphere sees the x-dependent lobe edge-on.
    target = np.array([0.0, 0.6, 0.8])
    v = int(np.argmin(np.linalg.norm(result.positions - target, axis=1)))
    p = result.positions[v].astype(float)
    n = p / np.linalg.norm(p)
    t = np.array([1.0, 0.0, 0.0])
    t -= t.dot(n) * n
    t /= np.linalg.norm(t)
    angles = np.linspace(-90.0, 90.0, 181)  # from grazing -x side to grazing +x side, through the normal
    w = np.cos(np.radians(angles))[:, None] * n + np.sin(np.radians(angles))[:, None] * t
    sh = np.repeat(splat_writer.field_coefficients(p[None, :]), len(w), axis=0)
    splat_linear = splat_writer.srgb_decode(np.maximum(splat_writer.eval_sh_band1(sh, -w) + 0.5, 0.0))
    rf_linear = our_sh1(result.coefficients[v].astype(float), w)
    splat8, rf8 = splat_writer.srgb_encode8(splat_linear), splat_writer.srgb_encode8(rf_linear)
    print(f"vertex {v} at {np.round(p, 3)}: largest difference {np.abs(splat8 - rf8).max():.0f} levels, "
          f"mean {np.abs(splat8 - rf8).mean():.2f}")

    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    for c, (name, colour) in enumerate(zip(("red", "green", "blue"), ("tab:red", "tab:green", "tab:blue"))):
        ax.plot(angles, splat8[:, c], color=colour, lw=3, alpha=0.35, label=f"splats, {name}")
        ax.plot(angles, rf8[:, c], color=colour, lw=1.2, ls="--", label=f"transferred RF, {name}")
    ax.set_xlabel("viewing angle from the normal toward +x (degrees)")
    ax.set_ylabel("8-bit sRGB level")
    ax.set_title(f"one vertex of the sphere: splat colour vs transferred SH1 ({result.vertex_count} vertices)")
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    fig.savefig(os.path.splitext(out)[0] + ".svg")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        raise SystemExit(__doc__)
    main(sys.argv[1])
