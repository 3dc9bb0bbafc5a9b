"""The main job's plot (scripts/plot_error_vs_memory.py): PNG and SVG with matplotlib, and a plain SVG
with a message when matplotlib is missing. The table is written here in the layout
compare_radiance_meshes prints (a header row, the original with '-' errors, one row per mesh)."""
import os
import subprocess
import sys
import xml.etree.ElementTree as ET

_REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_SCRIPT = os.path.join(_REPO, "scripts", "plot_error_vs_memory.py")

_TABLE = """error over the pixels covered by either mesh
mesh                          vertices     faces basis  memory MB  % mem  RMSE lin  PSNR lin  RMSE 8b   PSNR 8b  mean pixels
bunny_radiance                   37706     75408   PB4     11.222  100.0          -         -         -         -       100000
radiance_500                     18853     37704   PB4      5.611   50.0    0.01000     40.00     2.000     42.11       100000
radiance_100                      3771      7540   PB4      1.122   10.0    0.03000     30.46     6.000     32.57       100000
color_500                        18853     37704   PB0      0.905    8.1    0.02000     33.98     4.000     36.09       100000
color_100                         3771      7540   PB0      0.181    1.6    0.05000     26.02     9.000     29.05       100000
"""


def _run(tmp_path, *prelude):
    """Runs the script (after `prelude` statements) on the table; returns (process, svg, png)."""
    table = tmp_path / "errors.txt"
    table.write_text(_TABLE)
    out = tmp_path / "plot.svg"
    code = "; ".join(prelude + (f"import sys, runpy; sys.argv = {[_SCRIPT, str(table), str(out), 'T']!r}",
                                f"runpy.run_path({_SCRIPT!r}, run_name='__main__')"))
    process = subprocess.run([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, timeout=120)
    return process, tmp_path / "plot.svg", tmp_path / "plot.png"


def _svg_text(path):
    return " ".join(t for t in ET.parse(path).getroot().itertext())


def test_matplotlib_writes_png_and_svg_with_every_series(tmp_path):
    import matplotlib  # noqa: F401  -- scripts/setup.sh installs it; the test fails without it

    process, svg, png = _run(tmp_path)
    assert process.returncode == 0, process.stderr
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert png.stat().st_size > 5000
    text = _svg_text(svg)
    for label in ("radiance", "color", "memory (MB)", "mean image RMSE (linear)", "T"):
        assert label in text, label
    assert "bunny_radiance" not in text  # the original has no error: not plotted


def test_without_matplotlib_a_plain_svg_and_a_message(tmp_path):
    process, svg, png = _run(tmp_path, "import sys", "sys.modules['matplotlib'] = None")
    assert process.returncode == 0, process.stderr
    assert "matplotlib is missing" in process.stderr and "pip install" in process.stderr
    assert not png.exists()
    root = ET.parse(svg).getroot()
    polylines = [e for e in root.iter() if e.tag.endswith("polyline")]
    assert len(polylines) == 2  # the two series
    assert all(len(p.get("points").split()) == 2 for p in polylines)  # two meshes each
    assert "radiance" in _svg_text(svg) and "color" in _svg_text(svg)
