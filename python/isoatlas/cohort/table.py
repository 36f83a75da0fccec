"""The cohort's results: OUT/cohort.csv (a row per subject) and OUT/index.html (a grid of thumbnails,
histograms of volumes and areas), each rewritten only when its content changes."""
import csv
import html
import io
import os

from .files import write_atomically

COLUMNS = ("id", "status", "error", "voxels", "volume_mm3", "area_mm2", "components", "genus", "iterations", "converged",
           "psnr_level0_db", "psnr_top_db", "top_level", "model_bytes", "seconds_segment", "seconds_extract", "seconds_build",
           "seconds_eval", "seconds_render", "seconds_total", "worker")


def row_of(report):
    """A report.json (or the runner's record of a subject that never reported) as a table row."""
    figures, seconds = report.get("figures", {}), report.get("seconds", {})
    row = {"id": report["id"], "status": report.get("status", "failed"), "error": report.get("error", ""), "worker": report.get("worker", "")}
    for key in COLUMNS:
        if key in figures:
            row[key] = figures[key]
        elif key.startswith("seconds_") and key[len("seconds_"):] in seconds:
            row[key] = round(seconds[key[len("seconds_"):]], 3)
    return row


def write_table(out_dir, rows):
    text = io.StringIO()
    writer = csv.DictWriter(text, fieldnames=COLUMNS, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow({k: row.get(k, "") for k in COLUMNS})
    write_atomically(os.path.join(out_dir, "cohort.csv"), text.getvalue(), if_changed=True)


def _histograms(out_dir, rows):
    """volumes.png: histograms of the done subjects' volumes and areas (matplotlib, no display)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    done = [r for r in rows if r["status"] == "done"]
    figure, axes = plt.subplots(1, 2, figsize=(9, 3.2), dpi=100)
    for axis, key, label in ((axes[0], "volume_mm3", "volume (cm^3)"), (axes[1], "area_mm2", "surface area (cm^2)")):
        values = [r[key] / (1000 if key == "volume_mm3" else 100) for r in done if key in r]
        axis.hist(values, bins=max(1, min(20, len(values))), color="#4a78a8", edgecolor="white")
        axis.set_xlabel(label)
        axis.set_ylabel("subjects")
        axis.yaxis.get_major_locator().set_params(integer=True)
    figure.suptitle(f"{len(done)} subjects segmented")
    figure.tight_layout()
    buffer = io.BytesIO()
    figure.savefig(buffer, format="png", metadata={"Software": None})  # no date inside: same rows, same bytes
    plt.close(figure)
    write_atomically(os.path.join(out_dir, "volumes.png"), buffer.getvalue(), if_changed=True)


def write_index(out_dir, rows):
    """index.html: the histograms, then each subject's thumbnail (or its error) and figures."""
    _histograms(out_dir, rows)
    failed = sum(r["status"] != "done" for r in rows)
    cells = []
    for r in rows:
        name = html.escape(r["id"])
        if r["status"] == "done":
            thumbnail = os.path.join(r["id"], "thumbnail.png")
            picture = (f'<img src="{html.escape(thumbnail)}" alt="{name}">' if os.path.isfile(os.path.join(out_dir, thumbnail))
                       else '<div class="none">no thumbnail</div>')
            figures = " ".join(f"{label} {r[key]:{fmt}}" for key, label, fmt in
                               (("volume_mm3", "vol", ".0f"), ("area_mm2", "area", ".0f"), ("genus", "genus", "d"),
                                ("psnr_top_db", "PSNR", ".1f")) if key in r and r[key] != "")
            cells.append(f'<figure>{picture}<figcaption><a href="{name}/report.json">{name}</a><br>{html.escape(figures)}</figcaption></figure>')
        else:
            cells.append(f'<figure class="failed"><div class="none">{html.escape(r.get("error", ""))}</div>'
                         f'<figcaption>{name}: failed</figcaption></figure>')
    page = f"""<!doctype html>
<html><head><meta charset="utf-8"><title>isoatlas cohort</title>
<style>body{{font-family:sans-serif;margin:1.5em}} figure{{display:inline-block;width:260px;margin:6px;vertical-align:top}}
img{{width:256px;background:#222}} .none{{width:256px;height:96px;background:#eee;font-size:12px;overflow:hidden}}
.failed figcaption{{color:#a00}} figcaption{{font-size:13px}}</style></head>
<body><h1>isoatlas cohort: {len(rows)} subjects, {failed} failed</h1>
<p>The table: <a href="cohort.csv">cohort.csv</a>.</p>
<img src="volumes.png" alt="histograms of volumes and areas" style="width:auto">
<div>{"".join(cells)}</div></body></html>
"""
    write_atomically(os.path.join(out_dir, "index.html"), page, if_changed=True)
