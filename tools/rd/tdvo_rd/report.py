"""Outputs from cached results: the CSV of all rows, BD-rate tables, RD plots, a Markdown page.

Nothing here encodes: everything is made from the result JSON files, so plots and tables can be
redrawn (`3dvo-rd report`) without rerunning a job.

[report] keys of the sweep file (all optional):
    title = "..."                  # page title
    description = "..."            # Markdown paragraph under the title
    anchors = ["intra"]            # modes the others are compared against (default: the first)
    distortion = ["D_A"]           # metrics for BD figures and plots (first = main)
    rate = "kbit_s"                # or "bits_per_vertex_frame": plot axis and BD rate
    method = "pchip"               # or "cubic" (bdrate.py)

Texture sweeps have their own columns, distortions (object and frame PSNR) and rates
(texture_report.py); the kind of the sweep ([sweep] kind) chooses.
"""

import csv
import io
import math
import os

from . import bdrate
from . import texture_report
from .job import write_atomic, write_text_atomic
from .sweep import PAGE_MARKER, SweepError, check_page

# CSV columns, in order. Metric columns hold the text 3dvo-metrics printed (10 significant
# digits); D_A is its summary `vertex_mean_error`; sted_s, sted_t and sted are STED's spatial and
# temporal parts and STED itself (docs/metrics.md, "STED").
_METRIC_COLUMNS = ["D_A", "vertex_rmse", "kg_error", "sted_s", "sted_t", "sted", "hausdorff_max",
                   "hausdorff_mean", "reference_to_test_max", "reference_to_test_mean",
                   "test_to_reference_max", "test_to_reference_mean", "diagonal"]
_TIME_COLUMNS = ["encode_s", "decode_s", "metrics_s"]
CSV_COLUMNS = (["sequence", "mode", "point", "setting", "frames", "vertices", "frame_rate",
                "bytes", "kbit_s", "bits_per_vertex_frame"] + _METRIC_COLUMNS + _TIME_COLUMNS +
               ["key"])
# Columns that differ between two runs of the same sweep (wall-clock times).
TIMING_COLUMNS = _TIME_COLUMNS

# Distortions usable for BD figures, with what their PSNR-like quality divides by: the reference
# diagonal for distances, 100 for the KG error (a percentage), 1 for STED (a ratio of lengths).
DISTORTIONS = {
    "D_A": "diagonal", "vertex_rmse": "diagonal", "hausdorff_max": "diagonal",
    "hausdorff_mean": "diagonal", "kg_error": 100.0, "sted": 1.0, "sted_s": 1.0, "sted_t": 1.0,
}
DISTORTION_NAMES = {
    "D_A": "D_A", "vertex_rmse": "vertex RMSE", "hausdorff_max": "Hausdorff max",
    "hausdorff_mean": "Hausdorff mean", "kg_error": "KG error", "sted": "STED",
    "sted_s": "STED_s", "sted_t": "STED_t",
}
RATES = {"kbit_s": "kbit/s", "bits_per_vertex_frame": "bits/vertex/frame"}


class GeometryKind:
    """What a geometry sweep's CSV, BD tables, plots and page show (the texture counterpart is
    texture_report.TextureKind)."""
    columns = CSV_COLUMNS
    distortion_names = DISTORTION_NAMES
    default_distortion = ["D_A"]
    rates = RATES
    quality_text = ("quality = 20·log10(peak / distortion) dB with the reference diagonal as the "
                    "peak of distances, 100 for the KG error and 1 for STED")

    @staticmethod
    def row_of(result):
        return row_of(result)

    @staticmethod
    def quality(row, distortion):
        return quality(row, distortion)

    @staticmethod
    def axis_label(distortion):
        peak = DISTORTIONS[distortion]
        if peak != "diagonal":
            peak = "100 %" if peak == 100.0 else "%g" % peak
        return "20·log10(%s / %s) [dB]" % (peak, DISTORTION_NAMES[distortion])

    @staticmethod
    def sequence_section(sweep, rows):
        out = ["| sequence | input | frames | vertices/frame | frame rate |",
               "|---|---|---|---|---|"]
        for s in sweep.sequences:
            vertices = next((int(r["vertices"]) // int(r["frames"]) for r in rows
                             if r["sequence"] == s.name), None)
            out.append("| %s | `%s` | %d from %d | %s | %g |" % (
                s.name, os.path.relpath(s.pattern, sweep.root), s.frame_count, s.first_frame,
                vertices if vertices is not None else "n/a", s.frame_rate))
        return out

    @staticmethod
    def points_section(sequence, rows, labels):
        out = ["| mode | setting | kbit/s | bits/vertex/frame | D_A | vertex RMSE | "
               "Hausdorff max | Hausdorff mean | KG % | STED | STED_s | STED_t |",
               "|---|---|---|---|---|---|---|---|---|---|---|---|"]
        for r in rows:
            if r["sequence"] != sequence.name:
                continue
            out.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                labels[r["mode"]], r["setting"], _fmt(r["kbit_s"], 6),
                _fmt(r["bits_per_vertex_frame"]), _fmt(r["D_A"]), _fmt(r["vertex_rmse"]),
                _fmt(r["hausdorff_max"]), _fmt(r["hausdorff_mean"]), _fmt(r["kg_error"]),
                _fmt(r["sted"]), _fmt(r["sted_s"]), _fmt(r["sted_t"])))
        out.append("")
        diagonal = next((r["diagonal"] for r in rows if r["sequence"] == sequence.name), "")
        out += ["Distances in OBJ units; reference bounding-box diagonal %s. KG in percent; STED "
                "and its parts are ratios of lengths (docs/metrics.md)." % _fmt(diagonal, 6)]
        return out


KINDS = {"geometry": GeometryKind, "texture": texture_report.TextureKind}


class ReportOptions:
    def __init__(self, sweep):
        table = sweep.report_table()
        self.kind = KINDS[sweep.kind]
        mode_names = [m.name for m in sweep.modes]
        self.title = table.get("title", str, "Rate-distortion results: " + sweep.name)
        self.description = table.get("description", str, "")
        self.anchors = table.get("anchors", list, mode_names[:1])
        for a in self.anchors:
            if a not in mode_names:
                table._fail("anchors: no mode named '%s'" % a)
        names = self.kind.distortion_names
        self.distortion = table.get("distortion", list, self.kind.default_distortion)
        for d in self.distortion:
            if d not in names:
                table._fail("distortion: '%s' is not one of %s" % (d, ", ".join(names)))
        self.rate = table.get("rate", str, "kbit_s")
        if self.rate not in self.kind.rates:
            table._fail("rate must be one of %s" % ", ".join(self.kind.rates))
        self.method = table.get("method", str, "pchip")
        if self.method not in bdrate.METHODS:
            table._fail("method must be one of %s" % ", ".join(bdrate.METHODS))
        table.finish()


def row_of(result):
    """One CSV row (dict of text) from a job result."""
    job = result["job"]
    metrics = dict(result["metrics_text"])
    metrics["D_A"] = metrics.pop("vertex_mean_error", "")
    row = {
        "sequence": job["sequence"], "mode": job["mode"], "point": str(job["point"]),
        "setting": job["setting_label"], "frames": str(result["frames"]),
        "vertices": str(result["vertices"]), "frame_rate": "%.10g" % result["frame_rate"],
        "bytes": str(result["bytes"]), "kbit_s": "%.10g" % result["kbit_s"],
        "bits_per_vertex_frame": "%.10g" % result["bits_per_vertex_frame"],
        "key": result["key"],
    }
    for name in _METRIC_COLUMNS:
        row[name] = metrics.get(name, "")
    for name in _TIME_COLUMNS:
        row[name] = "%.3f" % result["time"][name]
    return row


def csv_text(rows, columns=CSV_COLUMNS):
    out = io.StringIO()
    writer = csv.DictWriter(out, fieldnames=columns, lineterminator="\n")
    writer.writeheader()
    for row in rows:
        writer.writerow(row)
    return out.getvalue()


def _float(text):
    return float(text) if text not in ("", None) else None


def quality(row, distortion):
    """PSNR-like quality in dB of a row's distortion (bdrate.quality_db)."""
    peak = DISTORTIONS[distortion]
    peak = _float(row["diagonal"]) if peak == "diagonal" else peak
    return bdrate.quality_db(_float(row[distortion]), peak)


def curves(rows, options, distortion):
    """{sequence: {mode: [(rate, quality), ...]}} in sweep order, points with a finite quality."""
    out = {}
    for row in rows:
        q = options.kind.quality(row, distortion)
        if q is None or math.isinf(q):
            continue
        out.setdefault(row["sequence"], {}).setdefault(row["mode"], []).append(
            (float(row[options.rate]), q))
    return out


def bd_table(rows, options, modes):
    """Rows of the BD table: each sequence x distortion x anchor x other mode, then the average
    over sequences (only when every sequence has a figure)."""
    table = []
    for distortion in options.distortion:
        per_sequence = curves(rows, options, distortion)
        for anchor in options.anchors:
            for mode in modes:
                if mode == anchor:
                    continue
                figures = []
                for sequence, by_mode in per_sequence.items():
                    if anchor not in by_mode or mode not in by_mode:
                        continue
                    a, t = by_mode[anchor], by_mode[mode]
                    entry = {"sequence": sequence, "distortion": distortion, "anchor": anchor,
                             "mode": mode, "method": options.method, "bd_rate_percent": "",
                             "bd_quality_db": "", "note": ""}
                    curve = ([p[0] for p in a], [p[1] for p in a], [p[0] for p in t],
                             [p[1] for p in t], options.method)
                    notes = []
                    for field, function, text in (("bd_rate_percent", bdrate.bd_rate, "%.2f"),
                                                  ("bd_quality_db", bdrate.bd_quality, "%.3f")):
                        try:
                            entry[field] = text % function(*curve)
                        except bdrate.BdError as e:
                            notes.append("%s: %s" % ("BD-rate" if field == "bd_rate_percent"
                                                     else "BD-quality", e))
                    entry["note"] = "; ".join(notes)
                    figures.append(entry)
                    table.append(entry)
                table += _averages(figures, len(per_sequence), distortion, anchor, mode,
                                   options.method)
    return table


def _averages(entries, sequences, distortion, anchor, mode, method):
    """The row averaging each BD figure over the sequences, when every sequence has it."""
    average = {"sequence": "average", "distortion": distortion, "anchor": anchor, "mode": mode,
               "method": method, "bd_rate_percent": "", "bd_quality_db": "", "note": ""}
    for field, text in (("bd_rate_percent", "%.2f"), ("bd_quality_db", "%.3f")):
        values = [float(e[field]) for e in entries if e[field]]
        if values and len(values) == sequences:
            average[field] = text % (sum(values) / len(values))
    if not (average["bd_rate_percent"] or average["bd_quality_db"]):
        return []
    average["note"] = "mean over %d sequences" % sequences
    return [average]


def bd_csv_text(table):
    out = io.StringIO()
    fields = ["sequence", "distortion", "anchor", "mode", "method", "bd_rate_percent",
              "bd_quality_db", "note"]
    writer = csv.DictWriter(out, fieldnames=fields, lineterminator="\n")
    writer.writeheader()
    for entry in table:
        writer.writerow(entry)
    return out.getvalue()


def plot(rows, options, labels, distortion, sequence, stem):
    """Draws one RD plot (rate on a log axis, PSNR-like quality) as stem.png and stem.svg."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    matplotlib.rcParams["svg.hashsalt"] = "3dvo-rd"  # stable SVG ids: reruns give equal files
    figure, axes = plt.subplots(figsize=(6.4, 4.4))
    by_mode = curves(rows, options, distortion).get(sequence, {})
    markers = "osD^vP*X"
    for i, (mode, points) in enumerate(by_mode.items()):
        points = sorted(points)
        axes.plot([p[0] for p in points], [p[1] for p in points], marker=markers[i % 8],
                  label=labels.get(mode, mode))
    axes.set_xscale("log")
    # Plain numbers (200, 300, ...) rather than powers of ten on the log axis.
    axes.xaxis.set_major_locator(LogLocator(base=10, subs=(1.0, 2.0, 3.0, 5.0, 7.0)))
    axes.xaxis.set_major_formatter(FuncFormatter(lambda value, _: "%g" % value))
    axes.xaxis.set_minor_formatter(NullFormatter())
    axes.set_xlabel("rate [%s]" % options.kind.rates[options.rate])
    axes.set_ylabel(options.kind.axis_label(distortion))
    axes.set_title("%s: %s" % (sequence, options.kind.distortion_names[distortion]))
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    figure.tight_layout()
    write_atomic(stem + ".png", lambda f: figure.savefig(f, format="png", dpi=100,
                                                         metadata={"Software": None}),
                 binary=True)
    write_atomic(stem + ".svg", lambda f: figure.savefig(f, format="svg",
                                                         metadata={"Date": None, "Creator": None}),
                 binary=True)
    plt.close(figure)


def _fmt(text, digits=4):
    value = _float(text)
    return "n/a" if value is None else "%.*g" % (digits, value)


def markdown_page(sweep, options, rows, table, binary_hashes, files_dir_name, command):
    """The results page (deterministic: no dates, no timings)."""
    labels = {m.name: m.label for m in sweep.modes}
    out = ["# " + options.title, ""]
    out += ["%s%s; do not edit by hand. -->"
            % (PAGE_MARKER, os.path.relpath(sweep.path, sweep.root)), ""]
    if options.description:
        out += [options.description.strip(), ""]
    out += ["Produced by:", "", "```sh", command, "```", "",
            "Every figure below is made from the cached job results (see [rd.md](rd.md)). "
            "All rows: [%s/rd.csv](%s/rd.csv); BD figures: [%s/bd.csv](%s/bd.csv)." %
            ((files_dir_name,) * 4), ""]

    kind = options.kind
    names = kind.distortion_names
    out += ["## Sequences", ""] + kind.sequence_section(sweep, rows)
    out += ["", "## Coding modes", "", "| mode | cfg | fixed keys | rate points |",
            "|---|---|---|---|"]
    for m in sweep.modes:
        out.append("| %s | %s | %s | %s |" % (
            m.label, ", ".join("`%s`" % os.path.relpath(c, sweep.root) for c in m.cfg) or "-",
            ", ".join("`%s=%s`" % kv for kv in m.overrides) or "-",
            "; ".join(" ".join("%s=%s" % kv for kv in s) or "(base)" for s in m.settings)))

    out += ["", "## BD-rate", "",
            "Bjøntegaard delta rate of each mode against each anchor (negative: less rate at "
            "equal distortion) and delta quality (positive: better), %s interpolation, %s; "
            "definitions in [rd.md](rd.md#bd-rate)." % (options.method.upper(),
                                                        kind.quality_text), ""]
    for distortion in options.distortion:
        for anchor in options.anchors:
            entries = [e for e in table if e["distortion"] == distortion and
                       e["anchor"] == anchor]
            if not entries:
                continue
            out += ["### %s, against %s" % (names[distortion], labels[anchor]), "",
                    "| sequence | mode | BD-rate | BD-quality | note |", "|---|---|---|---|---|"]
            for e in entries:
                out.append("| %s | %s | %s | %s | %s |" % (
                    e["sequence"], labels[e["mode"]],
                    e["bd_rate_percent"] + " %" if e["bd_rate_percent"] else "n/a",
                    e["bd_quality_db"] + " dB" if e["bd_quality_db"] else "n/a", e["note"]))
            out.append("")

    for s in sweep.sequences:
        out += ["## " + s.name, ""]
        for distortion in options.distortion:
            stem = "%s/%s-%s" % (files_dir_name, s.name, distortion)
            out += ["![%s, %s](%s.svg)" % (s.name, names[distortion], stem), ""]
        out += kind.points_section(s, rows, labels) + [""]

    out += ["## Binaries", "", "SHA-256 of the programs that made these results (part of every "
            "job's cache key):", ""]
    for name, digest in sorted(binary_hashes.items()):
        out.append("- `%s`: `%s`" % (name, digest))
    out.append("")
    return "\n".join(out)


def write_outputs(sweep, results, binary_hashes, results_dir, page=None, command=None):
    """Writes <results_dir>/rd.csv and bd.csv, and with `page` also the Markdown page plus a
    folder beside it (page without .md) holding rd.csv, bd.csv and the plots.

    `results` is aligned with sweep.jobs(); None entries (missing or failed jobs) are left out."""
    options = ReportOptions(sweep)
    # A cached result may have been made for another job with the same cache key (e.g. a mode
    # renamed, or a setting moved between a mode's `set` and its rate points): the rows name
    # the jobs of this sweep, not the ones recorded in the cache.
    results = [None if r is None else dict(r, job=job.record())
               for job, r in zip(sweep.jobs(), results)]
    rows = [options.kind.row_of(r) for r in results if r is not None]
    table = bd_table(rows, options, [m.name for m in sweep.modes])
    rd_csv, bd_csv = csv_text(rows, options.kind.columns), bd_csv_text(table)
    write_text_atomic(os.path.join(results_dir, "rd.csv"), rd_csv)
    write_text_atomic(os.path.join(results_dir, "bd.csv"), bd_csv)
    if page is None:
        return rows, table
    check_page(page)  # again (the cli checked before the jobs): it may have appeared since
    files_dir = page[:-3]
    os.makedirs(files_dir, exist_ok=True)
    write_text_atomic(os.path.join(files_dir, "rd.csv"), rd_csv)
    write_text_atomic(os.path.join(files_dir, "bd.csv"), bd_csv)
    labels = {m.name: m.label for m in sweep.modes}
    for s in sweep.sequences:
        for distortion in options.distortion:
            plot(rows, options, labels, distortion, s.name,
                 os.path.join(files_dir, "%s-%s" % (s.name, distortion)))
    text = markdown_page(sweep, options, rows, table, binary_hashes,
                         os.path.basename(files_dir), command or "")
    write_text_atomic(page, text)
    return rows, table
