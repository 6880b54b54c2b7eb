"""The report's shared ground (tools/report/make_report.py): the paper's values, the errors, atomic
output and the figure workers, the readers of the run directory's CSV and JSON, number formats
and the unit labels."""
import csv
import gc
import hashlib
import io
import json
import math
import os
import re
import sys

import matplotlib
import numpy as np
import matplotlib.pyplot as plt


PAPER = {
    "N": 1000, "T": 10000,
    "iqi_arm2": {"full": 1.05, "low": 2.17, "central": 0.42, "high": 0.79},
    "pqi_arm2_saddle": {"full": 5.66, "low": 10.81, "central": 3.11, "high": 4.69},
    "pqi_arm2_approx": {"full": 5.64, "low": 10.79, "central": 3.11, "high": 4.63},
    "pqi_arm2_upright": {"full": 5.52, "low": 10.84, "central": 3.05, "high": 4.05},
    "iqi_arm1": {"full": 1.12},
    "pqi_arm1_saddle": {"full": 6.96, "low": 11.16, "high": 4.61},
    "rms_approx_saddle": 0.36, "rms_upright_saddle": 13.46,
    "critical_points": [("(0, 0)", 0, "minimum"), ("(0, π)", 2, "index-one saddle"),
                        ("(π, 0)", 4, "index-one saddle"), ("(π, π)", 6, "maximum")],
}


REGIME_LABELS = {
    2: {"full": "full chaotic (2 < E < 6)", "low": "low chaotic (2 < E < 2.8)",
        "central": "central chaotic (2.8 ≤ E < 5)", "high": "high chaotic (5 ≤ E < 6)"},
    1: {"full": "full chaotic (4 < E < 6)", "low": "low chaotic (4 < E < 4.6)",
        "high": "high chaotic (4.6 ≤ E < 6)"},
}


CRITERIA = ("upright", "approx", "saddle")


COLORS = {"upright": "tab:blue", "approx": "tab:green", "saddle": "tab:red"}


class InputError(Exception):
    """A missing or malformed input: one line per problem."""


class RenderError(Exception):
    """A figure's worker process failed (its traceback is on stderr)."""


_KEPT = {}  # what a worker (start_rendering) would have written, by path: it writes figures only


def write_text(path, text):
    if not _writes():
        _KEPT[path] = text
        return
    tmp = "%s.tmp%d" % (path, os.getpid())
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


_CLIP_PATH = re.compile(r'  <clipPath id="(p[0-9a-f]+)">\n(.*?)  </clipPath>\n', re.S)


def canonical_clip_paths(svg):
    """The SVG with its clip paths named by their content and each defined once. Matplotlib names
    a clip path given as a path by the Python object's address, which differs from run to run
    and from one worker process to another; a rectangle is named by its content already."""
    names = {}
    defined = set()

    def rename(m):
        name = "p" + hashlib.sha1(m.group(2).encode()).hexdigest()[:10]
        names[m.group(1)] = name
        if name in defined:
            return ""
        defined.add(name)
        return '  <clipPath id="%s">\n%s  </clipPath>\n' % (name, m.group(2))

    svg = _CLIP_PATH.sub(rename, svg)
    return re.sub(r"url\(#(p[0-9a-f]+)\)", lambda m: "url(#%s)" % names.get(m.group(1), m.group(1)),
                  svg)


def _fresh_text_state():
    """Empties matplotlib's caches of fonts and text extents, so that every figure is drawn from
    the same state whichever figures its process drew before (each process of --jobs draws a
    different share): the output is the serial run's, byte for byte (tests/report)."""
    matplotlib.font_manager._get_font.cache_clear()
    matplotlib.text._get_text_metrics_with_cache_impl.cache_clear()


def _render_figure(fig, report_dir, name):
    _fresh_text_state()
    gc.collect()  # no collection while drawing: when it happens depends on the history too
    gc.disable()
    try:
        _render_formats(fig, report_dir, name)
    finally:
        gc.enable()


def _render_formats(fig, report_dir, name):
    for ext in ("png", "svg"):
        path = os.path.join(report_dir, "figures/%s.%s" % (name, ext))
        tmp = "%s.tmp%d" % (path, os.getpid())
        if ext == "svg":
            buf = io.StringIO()
            fig.savefig(buf, format=ext, dpi=120, bbox_inches="tight", metadata={"Date": None})
            with open(tmp, "w", encoding="utf-8") as f:
                f.write(canonical_clip_paths(buf.getvalue()))
        else:
            fig.savefig(tmp, format=ext, dpi=120, bbox_inches="tight")
        os.replace(tmp, path)


# Drawing (savefig: layout and rendering, ~90 % of the report's time) is shared by --jobs
# processes: after the inputs are read, jobs - 1 workers are forked, every process builds the whole
# report, and process r draws the figures k with k mod jobs = r; this process alone writes the
# tables and README.md, after the workers are done (finish_rendering). Each figure is drawn from
# the objects that built it, as in a serial run. A figure drawn from a pickle in another process
# was, now and then, laid out a few pixels off (about one figure in 50 per run). The likely cause:
# matplotlib keys the links between its transforms by object addresses, and the pickle carries
# them over into the other process.
_share = (0, 1)  # (rank, jobs)
_workers = []  # their process ids


def _writes():
    return _share[0] == 0


def start_rendering(jobs):
    """Forks the workers; returns in each process, the workers with their rank set."""
    global _share
    for rank in range(1, jobs):
        sys.stdout.flush()
        sys.stderr.flush()
        pid = os.fork()
        if pid == 0:
            _workers.clear()
            _share = (rank, jobs)
            return
        _workers.append(pid)
    _share = (0, jobs)


def finish_rendering():
    """In a worker: ends it (exit status 0). Else waits for every worker; raises RenderError when
    one failed (its traceback is on stderr)."""
    if not _writes():
        os._exit(0)
    failed = []
    while _workers:
        pid = _workers.pop(0)
        code = os.waitstatus_to_exitcode(os.waitpid(pid, 0)[1])
        if code != 0:
            failed.append("a worker drawing figures failed (exit status %d)" % code)
    if failed:
        raise RenderError("; ".join(failed))


def save_figure(fig, report_dir, name):
    """Writes figures/<name>.png and .svg atomically (in the process whose share it is); returns
    the relative PNG and SVG paths."""
    rank, jobs = _share
    if save_figure.count % jobs == rank:
        _render_figure(fig, report_dir, name)
    save_figure.count += 1
    plt.close(fig)
    return ["figures/%s.%s" % (name, ext) for ext in ("png", "svg")]


save_figure.count = 0


def write_table(report_dir, name, header, rows):
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(header)
    for r in rows:
        w.writerow(r)
    rel = "tables/%s.csv" % name
    write_text(os.path.join(report_dir, rel), buf.getvalue())
    return rel


def markdown_table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for r in rows:
        lines.append("| " + " | ".join(str(c) for c in r) + " |")
    return "\n".join(lines)


def read_csv(path, problems):
    try:
        with open(path, newline="", encoding="utf-8") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        problems.append("%s: cannot read (%s)" % (path, e.strerror))
        return None
    return rows


def columns(rows, path, names, problems):
    """The named columns as float arrays; records a problem for a missing column or a bad number."""
    if rows is None:
        return None
    out = {}
    for n in names:
        if rows and n not in rows[0]:
            problems.append("%s: missing column '%s'" % (path, n))
            return None
        try:
            out[n] = np.array([float(r[n]) if r[n] not in ("", "null") else np.nan for r in rows])
        except ValueError as e:
            problems.append("%s: column '%s': %s" % (path, n, e))
            return None
    return out


def read_json(path, problems):
    try:
        with open(path, encoding="utf-8") as f:
            return json.load(f)
    except OSError as e:
        problems.append("%s: cannot read (%s)" % (path, e.strerror))
    except ValueError as e:
        problems.append("%s: malformed JSON (%s)" % (path, e))
    return None


def num(x):
    return float("nan") if x is None else float(x)


def as_written(text):
    """A number as its shortest decimal (the text a scene or the paper wrote): '0.05' for
    0.050000000000000003, the double nearest 0.05; non-numbers unchanged."""
    try:
        x = float(text)
    except (TypeError, ValueError):
        return str(text)
    return repr(x) if x != int(x) or abs(x) >= 1e16 else "%d" % int(x)


def pi_label(k):
    """The label of k pi / 2: '−π', '−π/2', '0', 'π/2', 'π', '3π/2', '2π'."""
    if k == 0:
        return "0"
    sign = "−" if k < 0 else ""
    k = abs(k)
    if k % 2 == 0:
        return sign + ("π" if k == 2 else "%dπ" % (k // 2))
    return sign + ("π/2" if k == 1 else "%dπ/2" % k)


def pi_ticks(ax, axis, lo, hi):
    """Ticks of an angle axis at the multiples of π/2 in [lo, hi], labelled as such."""
    ks = range(int(math.ceil(lo / (math.pi / 2) - 1e-9)), int(math.floor(hi / (math.pi / 2) + 1e-9)) + 1)
    ticks, labels = [k * math.pi / 2 for k in ks], [pi_label(k) for k in ks]
    if axis == "x":
        ax.set_xticks(ticks, labels)
    else:
        ax.set_yticks(ticks, labels)


def units(model):
    """Axis labels with units: the paper's pendulum (every parameter 1) is in natural units (energy
    in m g L, time in sqrt(L / g)); any other model in SI units (J, s), as its parameters are."""
    natural = all(as_written(v) == "1" for k, v in model["parameters"].items()
                  if k in ("m1", "m2", "L1", "L2", "g"))
    if natural:
        return {"E": "E [m g L]", "rate": "[flips per √(L/g)]", "time": "[√(L/g)]",
                "natural": True, "action": "[m L² √(g/L)]"}
    return {"E": "E [J]", "rate": "[flips per s]", "time": "[s]", "natural": False,
            "action": "[J s]"}


def positive(values):
    """values with the non-positive ones as NaN (a zero flux is no point on a log axis, not a drop
    to the axis' floor)."""
    v = np.array(values, dtype=float)
    v[~(v > 0)] = np.nan
    return v


def figure_md(paths, caption):
    png, svg = paths
    name = os.path.splitext(os.path.basename(png))[0]
    return "![%s](%s)\n\n*%s* ([SVG](%s))\n" % (name, png, caption, svg)
