"""The batch report: OUTPUT/report.csv (one row per object) and OUTPUT/report.html (the same with a
thumbnail per object and the run's figures), both written atomically."""

import csv
import html
import io
import os
import re
import time

from .thumbnail import write_atomically

COLUMNS = ("object", "status", "faces_before", "faces_after", "face_ratio", "image_error", "seconds",
           "output", "thumbnail", "message")
# Image error figures as the fit logs them: photographs held out of the fit (heldoutevery > 0), or
# the left-out rasters on which it chose its model.
_ERRORS = (
    (re.compile(r"Held-out summary: .*?mean RMS fitted ([\d.]+)"), "held-out photographs: RMS {0} sRGB levels"),
    (re.compile(r"RMS error in sRGB levels on them: per-vertex ([\d.]+), shared diffuse \+ reflected lobe ([\d.]+)"),
     "left-out rasters: RMS {0} (per vertex), {1} (shared) sRGB levels"),
)


def image_error(row):
    """The image error the recipe's filters logged, as text ('' if none measured it): the last
    held-out summary, else the last model-choice figure."""
    for pattern, text in _ERRORS:
        found = ""
        for step in row.get("steps", []):
            for line in step.get("log", []):
                match = pattern.search(line)
                if match:
                    found = text.format(*match.groups())
        if found:
            return found
    return ""


def table(rows):
    out = []
    for row in rows:
        before, after = row.get("faces_before"), row.get("faces_after")
        out.append({
            "object": row["key"], "status": row["status"],
            "faces_before": "" if before is None else before, "faces_after": "" if after is None else after,
            "face_ratio": f"{after / before:.4f}" if before and after is not None else "",
            "image_error": image_error(row),
            "seconds": row.get("seconds_process", row.get("seconds_total", "")),
            "output": row.get("output", ""), "thumbnail": row.get("thumbnail", ""),
            "message": row.get("message", ""),
        })
    return out


def write_report(output_dir, rows, recipe, run):
    records = table(rows)
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    writer.writerows(records)
    write_atomically(os.path.join(output_dir, "report.csv"), text.getvalue().encode())
    write_atomically(os.path.join(output_dir, "report.html"), _html(records, rows, recipe, run).encode())


def _html(records, rows, recipe, run):
    e = html.escape
    done = sum(r["status"] == "done" for r in records)
    speed = run.get("objects_per_minute")
    figures = (f"{done}/{len(records)} objects done, {len(records) - done} failed; this run: {run['ran']} jobs in "
               f"{run['seconds']:.1f} s on {run['workers']} workers"
               + (f" ({speed:.1f} objects per minute)" if speed else "") + f", {run['skipped']} already done")
    steps = "".join(f"<li><code>{e(s['filter'])}</code> {e(str(s['params']))}</li>" for s in recipe.steps)
    body = []
    for record, row in zip(records, rows):
        picture = (f'<img src="{e(record["thumbnail"])}" width="160" height="160" alt="{e(record["object"])}">'
                   if record["thumbnail"] else "")
        logs = "<br>".join(e(line) for step in row.get("steps", []) for line in step.get("log", [])[-2:])
        cells = [picture, e(record["object"]), f'<span class="{e(record["status"])}">{e(record["status"])}</span>',
                 e(str(record["faces_before"])), e(str(record["faces_after"])), e(record["face_ratio"]),
                 e(record["image_error"]), e(str(record["seconds"])),
                 f'<a href="{e(record["output"])}">{e(record["output"])}</a>' if record["output"] else "",
                 e(record["message"]) + (f'<div class="log">{logs}</div>' if logs else "")]
        body.append("<tr>" + "".join(f"<td>{c}</td>" for c in cells) + "</tr>")
    return f"""<!DOCTYPE html>
<html><head><meta charset="utf-8"><title>Batch report</title>
<style>body{{font-family:sans-serif}} table{{border-collapse:collapse}} td,th{{border:1px solid #ccc;padding:4px;
vertical-align:top}} .failed{{color:#b00;font-weight:bold}} .done{{color:#070}} .log{{color:#555;font-size:80%}}</style>
</head><body>
<h1>Batch report</h1>
<p>{e(figures)}. Written {e(time.strftime('%Y-%m-%d %H:%M:%S'))}.</p>
<p>Recipe <code>{e(str(recipe.source))}</code> (sha256 {e(recipe.sha256()[:16])}), output format
<code>{e(recipe.output['format'])}</code>:</p><ol>{steps}</ol>
<table><tr><th>thumbnail</th><th>object</th><th>status</th><th>faces before</th><th>faces after</th><th>ratio</th>
<th>image error</th><th>time (s)</th><th>output</th><th>message / filters' log</th></tr>
{''.join(body)}
</table></body></html>
"""
