#!/usr/bin/env python3
"""The reproduction report: every figure and table of the paper regenerated from a scene's run
directory and compared with the paper's values.

    make_report.py --run-dir OUT --out REPORT_DIR [--other-run-dir OTHER ...] [--jobs N]

Inputs (written by `flipflux run SCENE` into the scene's output directory OUT):
    run.json                       scene, scene_file, precision, git_commit, seconds, model
    predictions.csv                quantity,arm,energy,value,error_estimate,method
    orbits-arm<a>.csv              energy,period,action,flux,curve_flux,... (a = 1, 2)
    orbit-curves-arm<a>.csv        energy,theta1,theta2 (the saddle orbits' curves)
    ensemble-<name>.json           the JSON of `flipflux simulate` (one per [[ensemble]])
    ensemble-<name>/               the CSVs of `flipflux simulate --csv-dir`
    trajectory-<name>.csv          optional: a scene's [[trajectory]] (states; -events.csv: flips);
                                   'typical' and 'recrossing' are drawn (paper Figs. typical
                                   trajectory, recrossing), their energies from run.json
Optional studies, recognised by content: arm-2 ensembles with the main arm-2 ensemble's seed (its
initial conditions) that count the saddle criterion and were integrated otherwise (method, rtol,
atol: the tolerance study, e.g. MATLAB ode45's defaults) or alike with their own chaos threshold
(the threshold study). --other-run-dir: another scene's output (another pendulum, e.g.
data/scenes/appendix-c.toml) drawn in the Appendix C section; a missing one is noted.
The report needs an arm-2 ensemble with the upright, approx and saddle criteria, an arm-1 ensemble
with the saddle criterion, residence times of arm 2 (upright and saddle) at E = 5 and per-trajectory
rates of arm 2 (saddle) at E = 5.3 (energies scaled with the model: see `special_energies`).

The report draws; flipflux computes. Every statistic in it comes from the C++ results: the quality
indices with their bootstrap errors, noise floors and reference-length PQI, chi^2 and worst z over
the energies, paired criterion differences, residence-time statistics, RMS differences of the
predicted rates (ensemble JSON; run.json for the prediction grid), and the chaotic regimes
(the ensemble JSON's "regimes"). What the report computes itself
is the verdict against the paper's published numbers (`compare`, with the paper's N and T), two
independent consistency checks of the inputs (dF/dE = T by quadrature, with the orbits' dT/dE; the
approximate curve's slope from the saddle's centre mode), and closed-form combinations of the
JSON's numbers derived in docs/theory.md ("What the report derives": Fano factor, Var(N_T)/T,
the island correction).

Outputs (REPORT_DIR): README.md (the report), figures/<name>.png and .svg, tables/<name>.csv.
Every file is written to a temporary name and renamed. A missing or malformed input is a one-line
error per problem on stderr and exit status 2; nothing is written then.

Only the standard library, numpy and matplotlib (Debian's python3-matplotlib) are used.
"""
import argparse
import csv
import gc
import glob
import hashlib
import importlib.util
import io
import json
import math
import os
import re
import sys
import time
import traceback

REQUIRED_PYTHON = "/usr/bin/python3"


def _ensure_matplotlib():
    """Checks for numpy and matplotlib; re-executes under Debian's python3 when the interpreter found
    first on PATH (e.g. a pyenv shim) lacks them."""
    if importlib.util.find_spec("matplotlib") is None or importlib.util.find_spec("numpy") is None:
        if os.path.realpath(sys.executable) != os.path.realpath(REQUIRED_PYTHON) and \
                os.path.exists(REQUIRED_PYTHON) and not os.environ.get("FLIPFLUX_REPORT_REEXEC"):
            os.environ["FLIPFLUX_REPORT_REEXEC"] = "1"
            os.execv(REQUIRED_PYTHON, [REQUIRED_PYTHON] + sys.argv)
        sys.stderr.write("make_report.py: error: numpy and matplotlib are required "
                         "(apt-get install python3-matplotlib)\n")
        sys.exit(2)


_ensure_matplotlib()

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import statistics_sections  # noqa: E402

matplotlib.rcParams.update({"svg.hashsalt": "flipflux", "figure.dpi": 100, "font.size": 9,
                            "axes.grid": True, "grid.alpha": 0.3,
                            "figure.constrained_layout.use": True})

# ---- the paper's values (flip-rate-double-pendulum.tex, Sec. Results) --------------------------

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


statistics_sections.bind(sys.modules[__name__])


class InputError(Exception):
    """A missing or malformed input: one line per problem."""


class RenderError(Exception):
    """A figure's worker process failed (its traceback is on stderr)."""


# ---- atomic output ------------------------------------------------------------------------------

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


# ---- reading the run directory ------------------------------------------------------------------

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


def load_model(run, path, problems):
    try:
        m = run["model"]
        c = {k: float(m["coefficients"][k]) for k in ("A", "B", "C", "alpha", "beta")}
        model = {"coefficients": c, "parameters": m.get("parameters", {}),
                 "saddle": {a: float(m["saddle_energy"][str(a)]) for a in (1, 2)},
                 "maximum": float(m["maximum_energy"]), "approx_slope": {}}
        for a in (1, 2):
            model["approx_slope"][a] = centre_mode_slope(c, a)
            given = m.get("approximate_curve", {}).get(str(a))
            if given is not None:
                model["approx_slope_run"] = model.get("approx_slope_run", {})
                model["approx_slope_run"][a] = float(given["slope"])
        return model
    except (KeyError, TypeError, ValueError) as e:
        problems.append("%s: model: missing or malformed entry %s" % (path, e))
        return None


def centre_mode_slope(c, a):
    """Slope of the centre (oscillatory) mode at the saddle of arm a, from K v = w^2 M v with
    K = diag(alpha cos th1, beta cos th2) and M = [[A, C cos(th1 - th2)], [C cos(th1 - th2), B]]
    (an independent route to the approximate curve's amplitude; egalitarian arm 2: 2 - sqrt 2)."""
    th = (0.0, math.pi) if a == 2 else (math.pi, 0.0)
    k = np.diag([c["alpha"] * math.cos(th[0]), c["beta"] * math.cos(th[1])])
    cc = c["C"] * math.cos(th[0] - th[1])
    m = np.array([[c["A"], cc], [cc, c["B"]]])
    w2, v = np.linalg.eig(np.linalg.solve(m, k))
    i = int(np.argmax(w2.real))
    d = v[:, i].real
    return d[1] / d[0] if a == 2 else d[0] / d[1]


def potential(model, th1, th2):
    c = model["coefficients"]
    return 2 * c["alpha"] * np.sin(th1 / 2) ** 2 + 2 * c["beta"] * np.sin(th2 / 2) ** 2


def load_predictions(path, problems):
    rows = read_csv(path, problems)
    if rows is None:
        return None
    table = {}
    for i, r in enumerate(rows, start=2):
        try:
            arm = int(r["arm"]) if r.get("arm") not in (None, "") else 0
            table.setdefault((r["quantity"], arm), []).append((float(r["energy"]),
                                                                float(r["value"])))
        except (KeyError, ValueError, TypeError) as e:
            problems.append("%s:%d: malformed row (%s)" % (path, i, e))
            return None
    return {k: np.array(sorted(v)) for k, v in table.items()}


def load_ensembles(run_dir, problems):
    """Every ensemble-<name>.json with its CSV directory, by arm."""
    ensembles = []
    for path in sorted(glob.glob(os.path.join(run_dir, "ensemble-*.json"))):
        d = read_json(path, problems)
        if d is None:
            continue
        try:
            e = {"name": os.path.basename(path)[len("ensemble-"):-len(".json")], "path": path,
                 "arm": int(d["arm"]), "trajectories": int(d["trajectories"]),
                 "time": float(d["time"]), "method": d.get("method", "?"),
                 "rtol": d.get("rtol", "?"), "atol": d.get("atol", "?"), "chaos": d.get("chaos"),
                 "seed": d.get("seed"), "json": d,
                 "quality": d.get("quality", {}), "agreement": d.get("agreement", {}),
                 "prediction_differences": d.get("prediction_differences", []), "energies": []}
            for en in d["energies"]:
                e["energies"].append({"energy": float(en["energy"]), "criteria": en["criteria"],
                                      "seconds": en.get("seconds"),
                                      "paired_differences": en.get("paired_differences", [])})
        except (KeyError, TypeError, ValueError) as ex:
            problems.append("%s: missing or malformed entry %s" % (path, ex))
            continue
        e["csv_dir"] = path[:-len(".json")]
        ensembles.append(e)
    return ensembles


def rate_series(ensemble, criterion, chaotic=False):
    """Arrays energy, predicted, mean, std, standard_error, count (NaN where missing)."""
    rows = []
    for en in ensemble["energies"]:
        c = en["criteria"].get(criterion)
        if c is None:
            continue
        s = c.get("chaotic") if chaotic else c
        if chaotic and s is None:
            continue
        n = s.get("trajectories", ensemble["trajectories"]) if chaotic else ensemble["trajectories"]
        r = statistics_sections.replicate_entry(c, chaotic) or {}
        rows.append((en["energy"], num(c.get("predicted_rate")), num(s.get("mean_rate")),
                     num(s.get("std")), num(s.get("standard_error")), float(n),
                     num(s.get("z_score")), num(r.get("standard_error")), num(r.get("z_score")),
                     num(r.get("error_ratio"))))
    a = np.array(rows, dtype=float).reshape(-1, 10)
    order = np.argsort(a[:, 0])
    a = a[order]
    return {"energy": a[:, 0], "predicted": a[:, 1], "mean": a[:, 2], "std": a[:, 3],
            "se": a[:, 4], "n": a[:, 5], "z": a[:, 6], "rse": a[:, 7], "rz": a[:, 8],
            "ratio": a[:, 9]}


def energy_label_files(directory, prefix, suffix):
    """{energy: path} of files <prefix><label><suffix> in directory (labels parsed as numbers)."""
    out = {}
    for path in glob.glob(os.path.join(directory, prefix + "*" + suffix)):
        label = os.path.basename(path)[len(prefix):-len(suffix)]
        try:
            out[float(label)] = path
        except ValueError:
            continue
    return out


def find_at_energy(files, energy):
    for e, p in files.items():
        if abs(e - energy) < 1e-9 * max(1.0, abs(energy)):
            return p
    return None


def special_energies(model):
    """The paper's E = 5 (residence times) and E = 5.3 (rate histogram) for arm 2, scaled with
    the model like the regimes: E_s + 0.75 D and E_s + 0.825 D (D = E_max - E_s)."""
    es, em = model["saddle"][2], model["maximum"]
    d = em - es
    return round(es + 0.75 * d, 12), round(es + 0.825 * d, 12)


def load_inputs(run_dir):
    problems = []
    if not os.path.isdir(run_dir):
        raise InputError("--run-dir: '%s' is not a directory" % run_dir)
    p = lambda name: os.path.join(run_dir, name)  # noqa: E731
    data = {"run_dir": run_dir}
    run = read_json(p("run.json"), problems)
    data["run"] = run
    data["model"] = load_model(run, p("run.json"), problems) if run is not None else None
    data["predictions"] = load_predictions(p("predictions.csv"), problems)
    data["orbits"], data["curves"] = {}, {}
    for a in (1, 2):
        path = p("orbits-arm%d.csv" % a)
        rows = read_csv(path, problems)
        optional = tuple(c for c in ("curve_flux", "period_derivative", "multiplier",
                                     "stability_index", "error_estimate_action")
                         if rows and c in rows[0])
        data["orbits"][a] = columns(rows, path, ("energy", "period", "action", "flux") + optional,
                                    problems)
        path = p("orbit-curves-arm%d.csv" % a)
        data["curves"][a] = columns(read_csv(path, problems), path,
                                    ("energy", "theta1", "theta2"), problems)
    ensembles = load_ensembles(run_dir, problems)
    data["ensembles"] = ensembles
    if data["predictions"] is not None:
        for q in ("omega", "flux-upright", "flux-approx", "flux-saddle", "rate-upright",
                  "rate-approx", "rate-saddle"):
            for a in ((0,) if q == "omega" else (1, 2)):
                if (q, a) not in data["predictions"]:
                    problems.append("%s: no rows for %s%s" % (p("predictions.csv"), q,
                                                              "" if a == 0 else " arm %d" % a))
    main = {}
    for a, needed in ((2, CRITERIA), (1, ("saddle",))):
        cands = [e for e in ensembles if e["arm"] == a and
                 not statistics_sections.is_census_or_check(e, run) and
                 all(c in e["energies"][0]["criteria"] for c in needed if e["energies"])]
        if not cands:
            problems.append("%s: no ensemble-<name>.json of arm %d with criteria %s" %
                            (run_dir, a, ", ".join(needed)))
        else:
            main[a] = max(cands, key=lambda e: (len(e["energies"]), e["trajectories"]))
            if (main[a].get("chaos") or {}).get("indicator", "none") == "none":
                problems.append("%s: no chaos classification (the chaotic-only figures and the "
                                "PQI tables need chaos = true)" % main[a]["path"])
    data["main"] = main
    if data["model"] is not None:
        e_res, e_hist = special_energies(data["model"])
        data["e_res"], data["e_hist"] = e_res, e_hist
        arm2 = [e for e in ensembles if e["arm"] == 2]
        # the scene's marks (run.json: residence_times, histogram) choose among arm 2's
        # ensembles; without any (an older run) the first one with the file serves
        listed = run.get("ensembles") if isinstance(run, dict) else None
        listed = [x for x in listed if isinstance(x, dict) and isinstance(x.get("name"), str)] \
            if isinstance(listed, list) else []

        def marked_or_all(key):
            names = {x["name"] for x in listed if x.get(key) is True}
            return [e for e in arm2 if e["name"] in names] if names else arm2
        data["residence"] = {}
        for c in ("upright", "saddle"):
            for e in marked_or_all("residence_times"):
                f = find_at_energy(energy_label_files(e["csv_dir"], "residence_E", "_%s.csv" % c),
                                   e_res)
                if f:
                    data["residence"][c] = (f, e)
                    break
            else:
                problems.append("%s: no ensemble-*/residence_E%g_%s.csv (arm 2, residence_times "
                                "= true at E = %g)" % (run_dir, e_res, c, e_res))
        data["histogram"] = None
        for e in marked_or_all("histogram"):
            f = find_at_energy(energy_label_files(e["csv_dir"], "trajectories_E", ".csv"), e_hist)
            if f:
                data["histogram"] = (f, e)
                break
        else:
            problems.append("%s: no ensemble-*/trajectories_E%g.csv (arm 2, per-trajectory rates "
                            "at E = %g)" % (run_dir, e_hist, e_hist))
    if problems:
        raise InputError("\n".join(problems))
    for c, (f, e) in data["residence"].items():
        cols = columns(read_csv(f, problems), f, ("trajectory", "residence_time"), problems)
        data["residence"][c] = (cols, e, f)
    f, e = data["histogram"]
    cols = columns(read_csv(f, problems), f, ("rate_saddle",), problems)
    chaotic = columns(read_csv(f, problems), f, ("chaotic",), [])
    data["histogram"] = (cols, chaotic, e, f)
    data["trajectories"] = load_trajectories(run_dir, run, problems)
    if problems:
        raise InputError("\n".join(problems))
    return data


# ---- statistics ---------------------------------------------------------------------------------

def regimes(data, a):
    """The chaotic regimes of arm a as flipflux defined them for its main ensemble (the JSON's
    "regimes": name, lower, upper; study/study_result.hpp), not recomputed here."""
    return [(r["regime"], num(r["lower"]), num(r["upper"]))
            for r in data["main"][a]["json"].get("regimes") or []]


def json_quality(ensemble, criterion, subset, regime):
    """flipflux's quality entry (IQI, PQI, their bootstrap sd, noise floor, RMS S, reference) of a
    regime, or None."""
    try:
        for q in ensemble["quality"][criterion][subset]:
            if q["regime"] == regime:
                return q
    except (KeyError, TypeError):
        pass
    return None


def compare(ours, se_ours, paper, ensemble, kind):
    """(difference in sigma, verdict) from our replicate error (the jackknife over independent
    replicates; None without replicates: no verdict). The paper states no error: its own is
    estimated as ours scaled to its ensemble (IQI error ~ 1/sqrt(N T), PQI error ~ 1/sqrt(N)), an
    assumption the verdict names; z against our error alone is printed beside it."""
    if se_ours is None or not math.isfinite(se_ours) or not se_ours > 0:
        return float("nan"), "no verdict (no replicates: a per-trajectory error alone is not " \
                             "trusted)"
    n, t = ensemble["trajectories"], ensemble["time"]
    scale = math.sqrt(n * t / (PAPER["N"] * PAPER["T"])) if kind == "IQI" else \
        math.sqrt(n / PAPER["N"])
    sigma = math.sqrt(se_ours ** 2 + (se_ours * scale) ** 2)
    z, z_ours = (ours - paper) / sigma, (ours - paper) / se_ours
    word = "agrees" if abs(z) <= 2 else "**differs**"
    return z, "%s (%.1fσ; %.1fσ by our error alone)" % (word, z, z_ours)


# ---- figures ------------------------------------------------------------------------------------

def critical_points(model):
    es1, es2, em = model["saddle"][1], model["saddle"][2], model["maximum"]
    return [((0.0, 0.0), 0.0, "minimum"), ((0.0, math.pi), es2, "index-one saddle"),
            ((math.pi, 0.0), es1, "index-one saddle"), ((math.pi, math.pi), em, "maximum")]


def fig_potential(data, out):
    model = data["model"]
    th = np.linspace(-math.pi, 2 * math.pi, 361)
    t1, t2 = np.meshgrid(th, th, indexing="xy")
    v = potential(model, t1, t2)
    fig, ax = plt.subplots(figsize=(5.5, 4.6))
    cs = ax.contourf(t1, t2, v, levels=24, cmap="viridis")
    ax.contour(t1, t2, v, levels=[model["saddle"][2], model["saddle"][1]], colors="w",
               linewidths=0.8, linestyles="--")
    fig.colorbar(cs, ax=ax, label="V(θ₁, θ₂)")
    marks = {"minimum": "o", "index-one saddle": "x", "maximum": "^"}
    for (x, y), e, kind in critical_points(model):
        ax.plot(x, y, marks[kind], color="w", ms=8, mew=2)
        ax.annotate("%s\nV = %.6g" % (kind, e), (x, y), textcoords="offset points", xytext=(6, 6),
                    color="w", fontsize=7)
    ax.set(xlabel="θ₁", ylabel="θ₂", title="Potential energy V(θ₁, θ₂) [%s] and its critical "
           "points" % units(model)["E"][4:-1], aspect="equal")
    pi_ticks(ax, "x", -math.pi, 2 * math.pi)
    pi_ticks(ax, "y", -math.pi, 2 * math.pi)
    ax.grid(False)
    return save_figure(fig, out, "potential")


def fig_allowed_region(data, out):
    model = data["model"]
    es = sorted(model["saddle"].values())
    em = model["maximum"]
    energies = [0.5 * es[0], 0.5 * (es[0] + es[1]), 0.5 * (es[1] + em), 1.1 * em]
    th = np.linspace(-math.pi, math.pi, 301)
    t1, t2 = np.meshgrid(th, th, indexing="xy")
    v = potential(model, t1, t2)
    fig, axes = plt.subplots(1, 4, figsize=(13, 3.4), sharey=True)
    for ax, e in zip(axes, energies):
        ax.contourf(t1, t2, (v > e).astype(float), levels=[0.5, 1.5], colors=["tab:red"], alpha=0.5)
        if e < em:
            ax.contour(t1, t2, v, levels=[e], colors="k", linewidths=0.8)
        ax.set(title="E = %.4g" % e, xlabel="θ₁", aspect="equal")
        pi_ticks(ax, "x", -math.pi, math.pi)
        pi_ticks(ax, "y", -math.pi, math.pi)
        ax.grid(False)
    axes[0].set_ylabel("θ₂")
    fig.suptitle("Allowed configuration region V ≤ E (forbidden region shaded)")
    return save_figure(fig, out, "allowed-region")


def orbit_curve(data, a, energy):
    c = data["curves"][a]
    sel = np.abs(c["energy"] - energy) < 1e-9
    return c["theta1"][sel], c["theta2"][sel]


def nearest(values, target):
    values = np.unique(values)
    return float(values[np.argmin(np.abs(values - target))])


def forbidden_region(ax, model, x, y, energy, **kw):
    """Shades V > energy over the grid x, y (θ₁ along x, θ₂ along y) as filled contour polygons
    of the continuous V (vector paths with interpolated, smooth edges; no raster)."""
    t1, t2 = np.meshgrid(x, y, indexing="xy")
    v = potential(model, t1, t2)
    if np.max(v) > energy:
        ax.contourf(t1, t2, v, levels=[energy, np.max(v) + 1], colors=[kw.get("color", "tab:red")],
                    alpha=kw.get("alpha", 0.3))
        ax.contour(t1, t2, v, levels=[energy], colors=[kw.get("color", "tab:red")], linewidths=0.8)


def flip_window(a):
    """Axis ranges (θ₁, θ₂) around the flip angle's upright position: arm 2 θ₂ ∈ [0, 2π],
    arm 1 θ₁ ∈ [0, 2π], the other angle in [−π, π] (one orientation for every figure)."""
    return ((-math.pi, math.pi), (0, 2 * math.pi)) if a == 2 else \
        ((0, 2 * math.pi), (-math.pi, math.pi))


def curve_in_window(th1, th2, a):
    """A curve's angles with the flip angle reduced to [0, 2π) (it stays near π)."""
    return (th1, np.mod(th2, 2 * math.pi)) if a == 2 else (np.mod(th1, 2 * math.pi), th2)


def fig_criteria(data, out):
    model = data["model"]
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.6))
    chosen = {}
    for ax, a in zip(axes, (2, 1)):
        em, e1 = model["maximum"], model["saddle"][1]
        e = nearest(data["curves"][a]["energy"], e1 + 0.5 * (em - e1))
        chosen[a] = e
        (x0, x1), (y0, y1) = flip_window(a)
        forbidden_region(ax, model, np.linspace(x0, x1, 401), np.linspace(y0, y1, 401), e)
        s = np.linspace(-math.pi, math.pi, 401)
        slope = model["approx_slope"][a]
        if a == 2:
            ax.axhline(math.pi, color=COLORS["upright"], ls=":", lw=1.5, label="upright arm θ₂ = π")
            ax.plot(s, math.pi + slope * np.sin(s), color=COLORS["approx"],
                    label="approximate saddle orbit θ₂ = π + A sin θ₁")
        else:
            ax.axvline(math.pi, color=COLORS["upright"], ls=":", lw=1.5, label="upright arm θ₁ = π")
            ax.plot(math.pi + slope * np.sin(s), s, color=COLORS["approx"],
                    label="approximate saddle orbit θ₁ = π + A sin θ₂")
        th1, th2 = curve_in_window(*orbit_curve(data, a, e), a)
        ax.plot(th1, th2, "-", color=COLORS["saddle"], lw=2, label="saddle orbit")
        ax.set(xlim=(x0, x1), ylim=(y0, y1), xlabel="θ₁", ylabel="θ₂", aspect="equal",
               title="Flip criteria of arm %d at E = %s" % (a, as_written(e)))
        pi_ticks(ax, "x", x0, x1)
        pi_ticks(ax, "y", y0, y1)
        ax.text(0.02, 0.02, "A = %.6g%s" % (slope, " (paper: 2 − √2)" if a == 2 and
                                            is_egalitarian(model) else ""),
                transform=ax.transAxes, fontsize=7)
        ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=2, fontsize=7,
                  title="shaded: forbidden region V > E", title_fontsize=7)
    return save_figure(fig, out, "criteria"), chosen


def fig_orbit_family(data, out, shown=10):
    """Every k-th orbit of each family (at most `shown`), thin, on equal axes, in the orientation
    of the criteria figure."""
    fig, axes = plt.subplots(1, 2, figsize=(11, 5.2))
    for ax, a in zip(axes, (2, 1)):
        c = data["curves"][a]
        es = np.unique(c["energy"])
        pick = es[np.unique(np.round(np.linspace(0, len(es) - 1, min(shown, len(es)))).astype(int))]
        cmap = plt.get_cmap("viridis")
        norm = matplotlib.colors.Normalize(es[0], es[-1])
        for e in pick:
            sel = c["energy"] == e
            th1, th2 = curve_in_window(c["theta1"][sel], c["theta2"][sel], a)
            ax.plot(th1, th2, color=cmap(norm(e)), lw=0.8)
        sm = matplotlib.cm.ScalarMappable(cmap=cmap, norm=norm)
        fig.colorbar(sm, ax=ax, label=units(data["model"])["E"], shrink=0.8)
        (x0, x1), (y0, y1) = flip_window(a)
        ax.set(xlabel="θ₁", ylabel="θ₂", xlim=(x0, x1), ylim=(y0, y1), aspect="equal",
               title="Saddle-orbit family of arm %d (%d of %d orbits)" % (a, len(pick), len(es)))
        pi_ticks(ax, "x", x0, x1)
        pi_ticks(ax, "y", y0, y1)
    return save_figure(fig, out, "orbit-family")


def cumulative_integral(x, y):
    """∫ y dx from x[0] by cubic (4-point Lagrange) interpolation on each interval (order h^4)."""
    out = np.zeros_like(x)
    g = np.array([-math.sqrt(3 / 5), 0, math.sqrt(3 / 5)])
    w = np.array([5 / 9, 8 / 9, 5 / 9])
    for i in range(len(x) - 1):
        j = min(max(i - 1, 0), max(len(x) - 4, 0))
        idx = np.arange(j, min(j + 4, len(x)))
        mid, half = 0.5 * (x[i] + x[i + 1]), 0.5 * (x[i + 1] - x[i])
        pts = mid + half * g
        val = np.zeros_like(pts)
        for k in idx:
            lk = np.ones_like(pts)
            for m in idx:
                if m != k:
                    lk *= (pts - x[m]) / (x[k] - x[m])
            val += y[k] * lk
        out[i + 1] = out[i] + half * np.sum(w * val)
    return out


def hermite_integral(x, y, dy):
    """∫ y dx from x[0] by the corrected trapezoid rule h/2 (y_i + y_i+1) + h²/12 (y'_i − y'_i+1)
    (the integral of the cubic Hermite interpolant of y, y'): local error h⁵ y⁗ / 720."""
    h = np.diff(x)
    return np.concatenate([[0.0], np.cumsum(h / 2 * (y[:-1] + y[1:]) +
                                            h * h / 12 * (dy[:-1] - dy[1:]))])


def fig_period_action(data, out, a):
    """T(E), F(E) and the check dF/dE = T: F reconstructed from T by quadrature over the orbit
    grid, with the orbits' own dT/dE (Hermite, when the run has it) and by 4-point interpolation
    of T alone, against the shooting's F."""
    o, u = data["orbits"][a], units(data["model"])
    order = np.argsort(o["energy"])
    e, t, f = o["energy"][order], o["period"][order], o["action"][order]
    through = o["curve_flux"][order] if "curve_flux" in o else None
    rec4 = f[0] + cumulative_integral(e, t)
    resid4 = rec4 / f - 1
    herm = "period_derivative" in o and np.all(np.isfinite(o["period_derivative"]))
    if herm:
        dt = o["period_derivative"][order]
        rec = f[0] + hermite_integral(e, t, dt)
        resid = rec / f - 1
        # Richardson: the Hermite rule's error is c h⁴ + O(h⁶) on a uniform grid, so on the even
        # nodes F_h + (F_h − F_2h) / 15 cancels the h⁴ term
        even = slice(0, None, 2)
        rec2 = f[0] + hermite_integral(e[even], t[even], dt[even])
        richardson = rec[even] + (rec[even] - rec2) / 15
        resid_r = richardson / f[even] - 1
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8))
    axes[0].plot(e, t, "o-", ms=3)
    axes[0].set(xlabel=u["E"], ylabel="period T " + u["time"], title="Saddle-orbit period, arm %d" % a)
    axes[1].plot(e, f, "o", ms=4, label="action F (shooting)")
    axes[1].plot(e, rec if herm else rec4, "-", label="F(E₀) + ∫ T dE")
    axes[1].set(xlabel=u["E"], ylabel="action F " + u["action"], title="Action, arm %d" % a)
    axes[1].legend(fontsize=7)
    axes[2].semilogy(e[1:], np.maximum(np.abs(resid4[1:]), 1e-18), "s-", ms=3, color="0.5",
                     label="4-point interpolation of T (O(h⁴))")
    if herm:
        axes[2].semilogy(e[1:], np.maximum(np.abs(resid[1:]), 1e-18), "o-", ms=3, color="k",
                         label="Hermite with the orbits' dT/dE (h⁵ T⁗/720 per step)")
        if len(e) > 4:
            axes[2].semilogy(e[even][1:], np.maximum(np.abs(resid_r[1:]), 1e-18), "^-", ms=3,
                             color="tab:blue", label="Hermite, Richardson-extrapolated (h, 2h)")
    if "error_estimate_action" in o:
        rel = o["error_estimate_action"][order] / f
        axes[2].semilogy(e, np.maximum(rel, 1e-18), ":", color="tab:red",
                         label="the orbits' own error estimate of F (relative)")
    axes[2].set(xlabel=u["E"], ylabel="|F_rec / F − 1|", title="dF/dE = T residual")
    axes[2].legend(fontsize=6)
    best = resid if herm else resid4
    stats = {"max_residual": float(np.max(np.abs(best[1:]))) if len(e) > 1 else float("nan"),
             "max_residual_4pt": float(np.max(np.abs(resid4[1:]))) if len(e) > 1 else float("nan"),
             "middle_residual": (float(np.max(np.abs(best[1:][
                 (e[1:] >= e[0] + 0.25 * (e[-1] - e[0])) & (e[1:] <= e[0] + 0.75 * (e[-1] - e[0]))])))
                 if len(e) > 4 else float("nan")),
             "hermite": bool(herm),
             "richardson": (float(np.max(np.abs(resid_r[1:][e[even][1:] <= e[0] + 0.75 *
                                                             (e[-1] - e[0])])))
                            if herm and len(e) > 4 else float("nan")),
             "flux_over_action": (float(np.max(np.abs(through / (2 * f) - 1)))
                                  if through is not None else None),
             "energies": int(len(e)), "step": float(np.min(np.diff(e))) if len(e) > 1 else 0}
    return save_figure(fig, out, "period-action-arm%d" % a), stats


def positive(values):
    """values with the non-positive ones as NaN (a zero flux is no point on a log axis, not a drop
    to the axis' floor)."""
    v = np.array(values, dtype=float)
    v[~(v > 0)] = np.nan
    return v


def fig_fluxes(data, out):
    p, u = data["predictions"], units(data["model"])
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.6))
    for ax, a in zip(axes, (2, 1)):
        om = p[("omega", 0)]
        ax.semilogy(om[:, 0], positive(om[:, 1]), "k-", label="phase volume Ω(E)")
        for c in CRITERIA:
            f = p[("flux-" + c, a)]
            ax.semilogy(f[:, 0], positive(f[:, 1]), "-" if c != "approx" else "--",
                        color=COLORS[c], label="flux, %s criterion" % c)
        ax.axvline(data["model"]["saddle"][a], color="0.5", lw=0.6, ls=":")
        ax.set(xlabel=u["E"], ylabel="Ω and flux f (both directions)",
               title="Phase volume and fluxes, arm %d (zero below E_s = %s)" %
               (a, as_written(data["model"]["saddle"][a])))
        ax.legend(fontsize=7, loc="lower right")
        fa, fs = p[("flux-approx", a)], p[("flux-saddle", a)]
        common = np.intersect1d(np.round(fa[:, 0], 9), np.round(fs[:, 0], 9))
        va = {round(x, 9): y for x, y in fa}
        vs = {round(x, 9): y for x, y in fs}
        ratio = np.array([va[x] / vs[x] - 1 if vs[x] > 0 else np.nan for x in common])
        ins = ax.inset_axes([0.45, 0.42, 0.35, 0.25])
        ins.plot(common, 100 * ratio, color=COLORS["approx"])
        ins.axhline(0, color="k", lw=0.5)
        ins.set_title("f_approx / f_saddle − 1 [%]", fontsize=6)
        ins.tick_params(labelsize=6)
    return save_figure(fig, out, "fluxes")


def _pred_line(ax, data, a, criterion, **kw):
    r = data["predictions"][("rate-" + criterion, a)]
    ax.plot(r[:, 0], r[:, 1], "-", color=COLORS[criterion], **kw)


def fig_rates(data, out, a, subset):
    """Predicted against simulated rates of the saddle criterion of arm a: left the mean with its
    standard error, middle with the trajectory-to-trajectory standard deviation, right R(E)."""
    ens = data["main"][a]
    s = rate_series(ens, "saddle", chaotic=(subset == "chaotic"))
    fig, axes = plt.subplots(1, 3, figsize=(14, 3.8))
    for ax, err, what in ((axes[0], s["se"], "standard error"),
                          (axes[1], s["std"], "trajectory-to-trajectory sd")):
        _pred_line(ax, data, a, "saddle", label="prediction (flux over a saddle)")
        ax.errorbar(s["energy"], s["mean"], yerr=err, fmt="o", ms=3, capsize=2, color="k",
                    label="simulation (%s), ± %s" % (subset, what))
        u = units(data["model"])
        ax.set(xlabel=u["E"], ylabel="flip rate of arm %d %s" % (a, u["rate"]),
               xlim=(s["energy"].min() - 0.1, s["energy"].max() + 0.1))
        ax.legend(fontsize=7)
    rel = s["mean"] / s["predicted"] - 1
    replicated = bool(np.isfinite(s["rse"]).any())
    err = s["rse"] if replicated else s["se"]
    axes[2].errorbar(s["energy"], 100 * rel, yerr=100 * err / s["predicted"], fmt="o", ms=3,
                     capsize=2, color="k")
    axes[2].axhline(0, color=COLORS["saddle"])
    if subset == "all" and a == 2:
        axes[2].axhspan(-1, 1, color="0.85", zorder=0, label="the paper: 'at the 1 % level'")
        axes[2].legend(fontsize=7)
    axes[2].set(xlabel=units(data["model"])["E"], ylabel="R_sim / R_pred − 1 [%]",
                title="relative deviation ± %s" % ("replicate error" if replicated else "SE"))
    fig.suptitle("Saddle-orbit criterion, arm %d, %s trajectories (N = %d, T = %g)" %
                 (a, subset, ens["trajectories"], ens["time"]))
    g = ((ens.get("agreement") or {}).get("saddle") or {}).get(
        "chaotic_trajectories" if subset == "chaotic" else "all_trajectories") or {}
    rg = g.get("replicates") if isinstance(g.get("replicates"), dict) else {}
    stats = {"max_rel": 100 * num(g.get("max_relative_deviation")), "chi2": num(g.get("chi2")),
             "dof": int(g.get("energies", 0)), "worst_z": num(g.get("worst_z")),
             "chi2_rep": num(rg.get("chi2")), "expected_rep": num(rg.get("expected_chi2")),
             "worst_z_rep": num(rg.get("worst_z")), "dof_rep": int(rg.get("energies", 0)),
             "mismatches": rg.get("error_mismatches"), "R": statistics_sections.replicates_of(ens)}
    return save_figure(fig, out, "rates-arm%d-%s" % (a, subset)), stats


def fig_rates_criteria(data, out):
    ens = data["main"][2]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    for c in CRITERIA:
        s = rate_series(ens, c, chaotic=True)
        _pred_line(axes[0], data, 2, c, label="prediction, %s" % c)
        axes[0].errorbar(s["energy"], s["mean"], yerr=s["std"], fmt="o", ms=3, capsize=2,
                         color=COLORS[c], mfc="none", label="simulation (chaotic), %s" % c)
        axes[1].errorbar(s["energy"], 100 * (s["mean"] / s["predicted"] - 1),
                         yerr=100 * s["se"] / s["predicted"], fmt="o-", ms=3, capsize=2,
                         color=COLORS[c], label=c)
    u = units(data["model"])
    axes[0].set(xlabel=u["E"], ylabel="flip rate of arm 2 " + u["rate"],
                title="Three criteria, chaotic ensemble (error bars: trajectory-to-trajectory sd)")
    axes[0].legend(fontsize=7)
    axes[1].axhline(0, color="k", lw=0.8)
    axes[1].set(xlabel=u["E"], ylabel="R_sim / R_pred − 1 [%]", title="relative deviation ± SE")
    axes[1].legend(fontsize=7)
    return save_figure(fig, out, "rates-criteria")


def fig_residence(data, out):
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    stats = {}
    for c in ("upright", "saddle"):  # the statistics flipflux computed (the ensemble JSON)
        _, ens, _ = data["residence"][c]
        rt = {}
        for en in ens["energies"]:
            if abs(en["energy"] - data["e_res"]) < 1e-9 * max(1.0, abs(data["e_res"])):
                rt = (en["criteria"].get(c) or {}).get("residence_times") or {}
        stats[c] = {"count": int(rt.get("count", 0)), "min": num(rt.get("min")),
                    "q001": num(rt.get("q0.001")), "mean": num(rt.get("mean"))}
    short = max(stats["saddle"]["min"] * 2, 1.0) if np.isfinite(stats["saddle"]["min"]) else 1.0
    for c in ("upright", "saddle"):
        r = data["residence"][c][0]["residence_time"]
        r = r[np.isfinite(r)]
        if len(r) == 0:
            continue
        for ax, bins in ((axes[0], np.linspace(0, np.quantile(r, 0.99), 80)),
                         (axes[1], np.linspace(0, short, 50))):
            ax.hist(r, bins=bins, density=True, histtype="step", color=COLORS[c], lw=1.3,
                    label="%s (%d residence times, min %.3g)" % (c, len(r), np.min(r)))
    u = units(data["model"])
    axes[0].set(xlabel="residence time " + u["time"], ylabel="density", yscale="log",
                title="Residence times of arm 2 at E = %s" % as_written(data["e_res"]))
    axes[1].set(xlabel="residence time " + u["time"], ylabel="density", xlim=(0, short),
                title="short times: the saddle criterion's gap")
    for ax in axes:
        ax.legend(fontsize=7)
    return save_figure(fig, out, "residence-E%g" % data["e_res"]), stats


def fig_rate_histogram(data, out):
    """Per-trajectory rates at the histogram energy: one binning for all and chaotic trajectories,
    a log count axis (the high-rate tail), separate lines for the means and the prediction."""
    cols, chaotic, ens, _ = data["histogram"]
    r = cols["rate_saddle"]
    keep = np.isfinite(r)
    pred, entry = None, {}
    for en in ens["energies"]:
        if abs(en["energy"] - data["e_hist"]) < 1e-9:
            entry = en["criteria"]["saddle"]
            pred = num(entry.get("predicted_rate"))
    u = units(data["model"])
    fig, ax = plt.subplots(figsize=(7, 4.2))
    edges = np.histogram_bin_edges(r[keep], bins=max(10, min(60, int(2 * math.sqrt(keep.sum())))))
    ax.hist(r[keep], bins=edges, color="0.75", label="all trajectories (%d)" % keep.sum())
    mean = num(entry.get("mean_rate"))
    chaotic_mean = num((entry.get("chaotic") or {}).get("mean_rate"))
    if chaotic is not None:
        c = (chaotic["chaotic"] > 0.5) & keep
        ax.hist(r[c], bins=edges, histtype="step", color="k", lw=1.2,
                label="chaotic trajectories (%d)" % c.sum())
    ax.axvline(mean, color="k", ls="--", lw=1.2, label="mean, all: %.5g" % mean)
    if np.isfinite(chaotic_mean):
        ax.axvline(chaotic_mean, color="tab:purple", ls="-.", lw=1.2,
                   label="mean, chaotic: %.5g" % chaotic_mean)
    if pred is not None and np.isfinite(pred):
        ax.axvline(pred, color=COLORS["saddle"], lw=1.2, label="prediction f₃/Ω: %.5g" % pred)
    ax.axvline(3 * mean, color="tab:orange", ls=":", lw=1.2,
               label="3 × mean (the paper: tail 'of order three times the mean')")
    ax.set_yscale("log")
    ax.set_ylim(0.5, None)
    ax.set(xlabel="per-trajectory flip rate N/T %s (saddle criterion, arm 2)" % u["rate"],
           ylabel="trajectories per bin",
           title="Per-trajectory rates at E = %s (N = %d, T = %s)" %
           (as_written(data["e_hist"]), keep.sum(), as_written(ens["time"])))
    ax.legend(fontsize=7)
    stats = {"n": int(keep.sum()), "max_over_mean": num(entry.get("max_rate")) / mean,
             "mean": mean, "pred": pred, "chaotic_mean": chaotic_mean}
    return save_figure(fig, out, "rate-histogram-E%g" % data["e_hist"]), stats


def paired_difference(ens, energy):
    """The standard error of the per-trajectory (approx - saddle) rate difference (paired: same
    trajectories) at an energy, from the ensemble JSON, or None."""
    for en in ens["energies"]:
        if abs(en["energy"] - energy) < 1e-9 * max(1.0, abs(energy)):
            for d in en.get("paired_differences") or []:
                if d["criteria"] == ["approx", "saddle"]:
                    return num(d["standard_error"])
                if d["criteria"] == ["saddle", "approx"]:
                    return num(d["standard_error"])
    return None


def fig_approx_vs_saddle(data, out):
    p = data["predictions"]
    ra, rs = p[("rate-approx", 2)], p[("rate-saddle", 2)]
    common = np.intersect1d(np.round(ra[:, 0], 9), np.round(rs[:, 0], 9))
    ea = {round(e, 9): v for e, v in ra}
    es = {round(e, 9): v for e, v in rs}
    pred_rel = np.array([ea[e] / es[e] - 1 for e in common])
    ens = data["main"][2]
    sa, ss = rate_series(ens, "approx"), rate_series(ens, "saddle")
    sim_rel = sa["mean"] / ss["mean"] - 1
    err = []
    for e, m in zip(ss["energy"], ss["mean"]):
        se = paired_difference(ens, e)
        err.append(se / m if se is not None and m > 0 else np.nan)
    err = np.array(err)
    fig, ax = plt.subplots(figsize=(7, 4))
    ax.plot(common, 100 * pred_rel, "-", color=COLORS["approx"], label="theory")
    ax.errorbar(ss["energy"], 100 * sim_rel, yerr=100 * np.nan_to_num(err), fmt="o", ms=3,
                capsize=2, color="k", label="simulation means (paired SE)")
    ax.axhline(0, color="k", lw=0.6)
    ax.axhline(1, color="tab:orange", ls=":", lw=1, label="1 % (the paper: theory below 1 %)")
    ax.set(xlabel=units(data["model"])["E"], ylabel="R_approx / R_saddle − 1 [%]",
           title="Approximate against exact saddle criterion, arm 2")
    ax.legend(fontsize=7)
    stats = {"pred_max": float(np.max(np.abs(pred_rel))) * 100 if len(pred_rel) else float("nan"),
             "sim_max": float(np.nanmax(np.abs(sim_rel))) * 100}
    return save_figure(fig, out, "approx-vs-saddle"), stats


# ---- figures the paper has beyond the rates, and what the run computes but the paper does not show

def lengths(model):
    p = model["parameters"]
    return float(p.get("L1", 1)), float(p.get("L2", 1))


def masses_xy(model, th1, th2):
    """Positions of the joint (mass A) and the tip (mass B), the pivot at the origin, y up."""
    l1, l2 = lengths(model)
    x1, y1 = l1 * np.sin(th1), -l1 * np.cos(th1)
    return x1, y1, x1 + l2 * np.sin(th2), y1 - l2 * np.cos(th2)


def fig_schematic(data, out):
    """The double pendulum: pivot, links L₁ and L₂, masses m₁ and m₂, angles θ₁ and θ₂ from the
    downward vertical, gravity (paper Fig. double pendulum system example). A drawing: no data."""
    model = data["model"]
    p = model["parameters"]
    th1, th2 = 0.55, 1.25
    x1, y1, x2, y2 = masses_xy({"parameters": {"L1": 1, "L2": 1}}, th1, th2)
    fig, ax = plt.subplots(figsize=(4.8, 4.8))
    ax.plot([-0.4, 0.4], [0, 0], color="k", lw=2)
    ax.plot([0, x1, x2], [0, y1, y2], color="k", lw=2)
    for (x, y), name, c in (((x1, y1), "m₁", "tab:blue"), ((x2, y2), "m₂", "tab:red")):
        ax.plot(x, y, "o", ms=16, color=c)
        ax.annotate(name, (x, y), xytext=(12, 0), textcoords="offset points", fontsize=11,
                    va="center")
    ax.plot([0, 0], [0, -1.1], ls="--", color="0.5", lw=1)
    ax.plot([x1, x1], [y1, y1 - 0.9], ls="--", color="0.5", lw=1)
    for (cx, cy), th, name in (((0, 0), th1, "θ₁"), ((x1, y1), th2, "θ₂")):
        a = np.linspace(-math.pi / 2, -math.pi / 2 + th, 40)
        ax.plot(cx + 0.35 * np.cos(a), cy + 0.35 * np.sin(a), color="tab:green")
        m = -math.pi / 2 + th / 2
        ax.text(cx + 0.45 * math.cos(m), cy + 0.45 * math.sin(m), name, color="tab:green",
                fontsize=11, ha="center", va="center")
    ax.text(x1 / 2 - 0.12, y1 / 2, "L₁", fontsize=11)
    ax.text((x1 + x2) / 2 + 0.04, (y1 + y2) / 2 + 0.08, "L₂", fontsize=11)
    ax.annotate("", xy=(-0.9, -1.5), xytext=(-0.9, -0.9),
                arrowprops={"arrowstyle": "->", "lw": 1.5})
    ax.text(-0.85, -1.25, "g", fontsize=11)
    ax.set(xlim=(-1.2, 2.2), ylim=(-2.0, 0.4), aspect="equal",
           title="The double pendulum (this run: m₁ = %s, m₂ = %s, L₁ = %s, L₂ = %s, g = %s)" %
           tuple(as_written(p.get(k, "?")) for k in ("m1", "m2", "L1", "L2", "g")))
    ax.title.set_fontsize(8)
    ax.axis("off")
    return save_figure(fig, out, "schematic")


def fig_energy_regimes(data, out):
    """The critical energies and which flips are possible where (paper Fig. energy regimes), with
    the paper's chaotic sub-regimes of each arm (scaled with the model like the quality tables)."""
    model, u = data["model"], units(data["model"])
    es2, es1, em = model["saddle"][2], model["saddle"][1], model["maximum"]
    top = 1.2 * em
    fig, ax = plt.subplots(figsize=(10, 3.8))
    rows = [("no flip possible", 0, min(es1, es2), "0.7"),
            ("arm 2 can flip (above E_max by the upright and approximate criteria only)", es2, top,
             "tab:red"),
            ("arm 1 can flip", es1, top, "tab:blue"),
            ("saddle orbits of arm 2 exist", es2, em, "tab:orange"),
            ("saddle orbits of arm 1 exist", es1, em, "tab:cyan")]
    for i, (label, lo, hi, c) in enumerate(rows):
        ax.barh(i, hi - lo, left=lo, height=0.6, color=c, alpha=0.6)
        ax.text(lo + 0.05, i, label, va="center", fontsize=7)
    for a, y in ((2, len(rows)), (1, len(rows) + 1)):
        for (reg, lo, hi), c in zip([r for r in regimes(data, a) if r[0] != "full"],
                                    ("#fdd", "#fbb", "#f99") if a == 2 else ("#ddf", "#aaf")):
            ax.barh(y, hi - lo, left=lo, height=0.6, color=c, edgecolor="k", lw=0.4)
            ax.text((lo + hi) / 2, y, reg, ha="center", va="center", fontsize=7)
        ax.text(em + 0.05, y, "the paper's chaotic regimes of arm %d" % a, va="center",
                fontsize=7)
    for e, name in ((es2, "E_s(arm 2) = V(0, π)"), (es1, "E_s(arm 1) = V(π, 0)"),
                    (em, "E_max = V(π, π)")):
        ax.axvline(e, color="k", ls="--", lw=0.8)
        ax.text(e, len(rows) + 1.7, "%s = %s" % (name, as_written(e)), rotation=0, fontsize=7,
                ha="center")
    ax.set(xlim=(0, top), ylim=(-0.6, len(rows) + 2.2), xlabel=u["E"], yticks=[],
           title="Energy regimes: critical energies and which flips are possible")
    ax.grid(False)
    return save_figure(fig, out, "energy-regimes")


def fig_keyframes(data, out):
    """Key frames of the down-up saddle orbit of arm 2 (paper Fig. key frames, E = 2.5 for the
    egalitarian pendulum: E_s + 0.125 (E_max − E_s)): the pendulum at the orbit's two turning
    points and midway, where it passes the saddle configuration; masses A (m₁) and B (m₂)."""
    model = data["model"]
    es, em = model["saddle"][2], model["maximum"]
    e = nearest(data["curves"][2]["energy"], es + 0.125 * (em - es))
    th1, th2 = orbit_curve(data, 2, e)
    mid = int(np.argmin(np.abs(th1)))
    frames = [(0, "1: turning point"), (mid, "2: midway (θ₁ = %.2g)" % th1[mid]),
              (len(th1) - 1, "3: other turning point")]
    xa, ya, xb, yb = masses_xy(model, th1, th2)
    xs, ys = np.concatenate([xa, xb, [0]]), np.concatenate([ya, yb, [0]])
    pad = 0.25 * sum(lengths(model))
    box = (xs.min() - pad, xs.max() + pad, ys.min() - pad, ys.max() + pad)
    fig, axes = plt.subplots(1, 3, figsize=(11, 4.2))
    for ax, (i, title) in zip(axes, frames):
        ax.plot(xa, ya, color="tab:blue", lw=0.8, alpha=0.5)
        ax.plot(xb, yb, color="tab:red", lw=0.8, alpha=0.5)
        ax.plot([0, xa[i], xb[i]], [0, ya[i], yb[i]], color="k", lw=2)
        ax.plot(0, 0, "ks", ms=5)
        ax.axvline(0, color="0.6", lw=0.6, ls=":")
        for x, y, name, c in ((xa[i], ya[i], "A", "tab:blue"), (xb[i], yb[i], "B", "tab:red")):
            ax.plot(x, y, "o", ms=12, color=c)
            ax.annotate(name, (x, y), xytext=(9, 4), textcoords="offset points", fontsize=10)
        ax.set(xlim=box[:2], ylim=box[2:], aspect="equal", title=title, xticks=[], yticks=[])
    fig.suptitle("Down-up saddle orbit of arm 2 at E = %s (θ₁, θ₂) = (%.3f, %.3f) → (%.3f, %.3f); "
                 "paths of A and B faint" % (as_written(e), th1[0], th2[0], th1[-1], th2[-1]),
                 fontsize=9)
    return save_figure(fig, out, "keyframes-E%s" % as_written(e)), e


def fig_multipliers(data, out):
    """The saddle orbits' Floquet multipliers and stability indices against E (orbits-arm<a>.csv;
    empty where the orbit is elliptic)."""
    u = units(data["model"])
    fig, axes = plt.subplots(1, 2, figsize=(12, 4))
    stats = {}
    for a, c in ((2, "tab:red"), (1, "tab:blue")):
        o = data["orbits"][a]
        if "multiplier" not in o:
            continue
        order = np.argsort(o["energy"])
        e, m = o["energy"][order], o["multiplier"][order]
        period = o["period"][order]
        axes[0].semilogy(e, positive(np.abs(m)), "o-", ms=3, color=c,
                         label="arm %d: |λ| (the unstable multiplier)" % a)
        axes[1].plot(e, np.log(np.abs(m)) / period, "o-", ms=3, color=c,
                     label="arm %d: ln|λ| / T" % a)
        stats[a] = {"min": float(np.nanmin(np.abs(m))) if np.any(np.isfinite(m)) else float("nan"),
                    "max": float(np.nanmax(np.abs(m))) if np.any(np.isfinite(m)) else float("nan"),
                    "elliptic": int(np.sum(~np.isfinite(m)))}
    axes[0].set(xlabel=u["E"], ylabel="|λ|", title="Floquet multipliers of the saddle orbits")
    axes[1].set(xlabel=u["E"], ylabel="ln|λ| / T " + u["rate"].replace("flips per", "per"),
                title="The orbits' Lyapunov exponent (instability per unit time)")
    for ax in axes:
        ax.legend(fontsize=7)
    return save_figure(fig, out, "multipliers"), stats


def fig_chaotic_fraction(data, out):
    """The fraction of trajectories the chaos indicator classifies as chaotic, per energy and arm
    (ensemble JSON: chaotic_fraction)."""
    u = units(data["model"])
    fig, ax = plt.subplots(figsize=(7, 4))
    stats = {}
    for a, c in ((2, "tab:red"), (1, "tab:blue")):
        ens = data["main"][a]
        rows = [(en["energy"], num(en["criteria"]["saddle"].get("chaotic_fraction")))
                for en in ens["energies"] if "saddle" in en["criteria"]]
        if not rows:
            continue
        e, f = np.array(rows).T
        ax.plot(e, 100 * f, "o-", ms=3, color=c, label="arm %d ensemble '%s'" % (a, ens["name"]))
        stats[a] = {"min": float(np.nanmin(f)), "at": float(e[np.nanargmin(f)])}
    thr = as_written((data["main"][2].get("chaos") or {}).get("threshold", "?"))
    ax.set(xlabel=u["E"], ylabel="chaotic trajectories [%]",
           title="Chaotic fraction (finite-time Lyapunov exponent > %s)" % thr)
    ax.legend(fontsize=7)
    return save_figure(fig, out, "chaotic-fraction"), stats


def fig_residence_gap(data, out):
    """The shortest residence times between successive flips of arm 2 against E, per criterion
    (ensemble JSON: residence_times min and 0.1 % quantile)."""
    u = units(data["model"])
    ens = data["main"][2]
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    stats = {}
    for c in CRITERIA:
        rows = []
        for en in ens["energies"]:
            rt = (en["criteria"].get(c) or {}).get("residence_times") or {}
            if rt.get("count"):
                rows.append((en["energy"], num(rt.get("min")), num(rt.get("q0.001"))))
        if not rows:
            continue
        e, mn, q = np.array(rows).T
        ax.semilogy(e, positive(mn), "o-", ms=3, color=COLORS[c], label="%s: shortest" % c)
        ax.semilogy(e, positive(q), "s--", ms=3, mfc="none", color=COLORS[c],
                    label="%s: 0.1 %% quantile" % c)
        stats[c] = {"min": float(np.nanmin(mn)), "max_of_min": float(np.nanmax(mn))}
    ax.set(xlabel=u["E"], ylabel="residence time " + u["time"],
           title="Short-time gap of the residence times, arm 2 (N = %d, T = %s)" %
           (ens["trajectories"], as_written(ens["time"])))
    ax.legend(fontsize=7, ncol=2)
    return save_figure(fig, out, "residence-gap"), stats


# ---- single trajectories ([[trajectory]] of the scene) --------------------------------------------

def load_trajectories(run_dir, run, problems):
    """{name: {"states": columns, "events": rows, "energy": H(x0)}} for every
    trajectory-<name>.csv with its -events.csv (energies from run.json's trajectories)."""
    energies = {t.get("name"): num(t.get("energy")) for t in (run or {}).get("trajectories") or []}
    out = {}
    for path in sorted(glob.glob(os.path.join(run_dir, "trajectory-*.csv"))):
        if path.endswith("-events.csv"):
            continue
        name = os.path.basename(path)[len("trajectory-"):-len(".csv")]
        states = columns(read_csv(path, problems), path, ("t", "theta1", "theta2"), problems)
        epath = path[:-len(".csv")] + "-events.csv"
        events = read_csv(epath, problems)
        if states is None or events is None:
            continue
        try:
            ev = [(float(r["time"]), int(r["arm"]), r["criterion"], int(r["direction"]))
                  for r in events]
        except (KeyError, ValueError) as e:
            problems.append("%s: malformed row (%s)" % (epath, e))
            continue
        if name not in energies:
            problems.append("%s: run.json lists no trajectory '%s' (its energy)" %
                            (os.path.join(run_dir, "run.json"), name))
            continue
        out[name] = {"states": states, "events": ev, "energy": energies[name], "path": path}
    return out


def state_at(tr, time):
    st = tr["states"]
    return np.interp(time, st["t"], st["theta1"]), np.interp(time, st["t"], st["theta2"])


def fig_trajectory_typical(data, out, name="typical"):
    """A chaotic trajectory: the paths of both masses in the plane, the tip's position at each
    flip marked, and the flip angles against time (paper Fig. typical trajectory)."""
    tr, model, u = data["trajectories"][name], data["model"], units(data["model"])
    st = tr["states"]
    xa, ya, xb, yb = masses_xy(model, st["theta1"], st["theta2"])
    crit = "saddle" if any(e[2] == "saddle" for e in tr["events"]) else "upright"
    flips = {a: [e for e in tr["events"] if e[1] == a and e[2] == crit] for a in (1, 2)}
    fig, axes = plt.subplots(1, 2, figsize=(12, 5), gridspec_kw={"width_ratios": [1, 1.3]})
    ax = axes[0]
    ax.plot(xa, ya, color="tab:blue", lw=0.6, alpha=0.8, label="mass A (m₁)")
    ax.plot(xb, yb, color="tab:red", lw=0.6, alpha=0.6, label="mass B (m₂)")
    ax.plot(0, 0, "ks", ms=5)
    for a, mk in ((2, "*"), (1, "D")):
        if flips[a]:
            t1, t2 = state_at(tr, np.array([e[0] for e in flips[a]]))
            pa = masses_xy(model, t1, t2)
            x, y = (pa[2], pa[3]) if a == 2 else (pa[0], pa[1])
            ax.plot(x, y, mk, ms=11, color="gold", mec="k",
                    label="flip of arm %d (%s criterion): %d" % (a, crit, len(flips[a])))
    ax.set(aspect="equal", xlabel="x / L", ylabel="y / L",
           title="Paths of the two masses, E = %.4g, T = %s" % (tr["energy"], as_written(st["t"][-1])))
    ax.legend(fontsize=7, loc="lower left")
    ax = axes[1]
    ax.plot(st["t"], st["theta1"] / math.pi, color="tab:blue", lw=0.8, label="θ₁ / π")
    ax.plot(st["t"], st["theta2"] / math.pi, color="tab:red", lw=0.8, label="θ₂ / π")
    for a in (1, 2):
        for k, e in enumerate(flips[a]):
            ax.axvline(e[0], color="gold" if a == 2 else "tab:cyan", lw=1, zorder=0,
                       label="flips of arm %d" % a if k == 0 else None)
    lo, hi = np.floor(min(st["theta1"].min(), st["theta2"].min()) / math.pi), \
        np.ceil(max(st["theta1"].max(), st["theta2"].max()) / math.pi)
    for k in np.arange(lo, hi + 1):
        if int(k) % 2:
            ax.axhline(k, color="0.6", lw=0.5, ls=":")
    ax.set(xlabel="t " + u["time"], ylabel="angle / π (unwrapped; dotted: upright, odd multiples)",
           title="Flip angles against time")
    ax.legend(fontsize=7)
    return save_figure(fig, out, "trajectory-" + name), {
        "energy": tr["energy"], "flips2": len(flips[2]), "flips1": len(flips[1]), "criterion": crit,
        "time": float(st["t"][-1])}


def fig_trajectory_recrossing(data, out, name="recrossing"):
    """A trajectory that crosses the upright arm and falls back without crossing the saddle
    orbit (paper Fig. recrossing): configuration space with the forbidden region (red), the
    trajectory (blue), the upright criterion (dotted), the saddle orbit (purple) and the
    crossing events (yellow)."""
    tr, model = data["trajectories"][name], data["model"]
    st = tr["states"]
    e = tr["energy"]
    fig, ax = plt.subplots(figsize=(6.5, 6))
    (x0, x1), (y0, y1) = (-math.pi / 2, math.pi / 2), (math.pi / 2, 3 * math.pi / 2)  # zoomed
    forbidden_region(ax, model, np.linspace(x0, x1, 401), np.linspace(y0, y1, 401), e, alpha=0.45)
    ax.axhline(math.pi, color="k", ls=":", lw=1.5, label="upright arm θ₂ = π")
    stats = {"energy": e}
    if len(data["curves"][2]["energy"]):
        eo = nearest(data["curves"][2]["energy"], e)
        th1, th2 = curve_in_window(*orbit_curve(data, 2, eo), 2)
        ax.plot(th1, th2, color="tab:purple", lw=2,
                label="saddle orbit (E = %s%s)" % (as_written(eo), "" if abs(eo - e) < 1e-6 else
                                                   ", the orbit nearest the trajectory's E"))
        stats["orbit_energy"] = eo
    t1, t2 = curve_in_window(st["theta1"], st["theta2"], 2)
    ax.plot(t1, t2, color="tab:blue", lw=1.2, label="trajectory, t ∈ [0, %s]" %
            as_written(st["t"][-1]))
    ax.plot(t1[0], t2[0], "o", color="tab:blue")
    for crit, mk in (("upright", "*"), ("approx", "P"), ("saddle", "X")):
        ev = [x for x in tr["events"] if x[1] == 2 and x[2] == crit]
        stats[crit] = len(ev)
        if ev:
            a1, a2 = state_at(tr, np.array([x[0] for x in ev]))
            a1, a2 = curve_in_window(a1, a2, 2)
            ax.plot(a1, a2, mk, ms=14, color="gold", mec="k",
                    label="%s crossings: %s" % (crit, ", ".join("t = %.3g (%+d)" % (x[0], x[3])
                                                                for x in ev)))
    ax.set(xlim=(x0, x1), ylim=(y0, y1), aspect="equal", xlabel="θ₁", ylabel="θ₂",
           title="Recrossing of the upright arm at E = %.6g" % e)
    pi_ticks(ax, "x", x0, x1)
    pi_ticks(ax, "y", y0, y1)
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.1))
    return save_figure(fig, out, "trajectory-" + name), stats


# ---- sensitivity studies (ensembles that re-run the main arm-2 ensemble's trajectories) ----------

def sensitivity_ensembles(data):
    """The arm-2 ensembles with the main one's seed (the same initial conditions at the same
    energies) that count the saddle criterion: those integrated otherwise (method, rtol, atol: the
    tolerance study) and those integrated alike with a chaos threshold each (the threshold
    study)."""
    main = data["main"][2]
    key = lambda e: (e["method"], as_written(e["rtol"]), as_written(e["atol"]))  # noqa: E731
    tol, thr = [], []
    for e in data["ensembles"]:
        if e is main or e["arm"] != 2 or e.get("seed") != main.get("seed") or not e["energies"] \
                or "saddle" not in e["energies"][0]["criteria"]:
            continue
        if key(e) != key(main):
            tol.append(e)
        elif (e.get("chaos") or {}).get("threshold") is not None:
            thr.append(e)
    return tol, sorted(thr, key=lambda e: num(e["chaos"]["threshold"]))


def read_rows(rel, out):
    """The rows of a table this report wrote (tables/<name>.csv), without the header."""
    path = os.path.join(out, rel)
    if path in _KEPT:
        return list(csv.reader(io.StringIO(_KEPT[path], newline="")))[1:]
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.reader(f))[1:]


def energy_entry(ens, energy):
    for en in ens["energies"]:
        if abs(en["energy"] - energy) < 1e-9 * max(1.0, abs(energy)):
            return en
    return None


def tolerance_label(e):
    short = e["json"].get("estimator") == "short"
    return "%s rtol %s atol %s%s" % (e["method"], as_written(e["rtol"]), as_written(e["atol"]),
                                     " (short estimator, T = %s)" % as_written(e["time"])
                                     if short else "")


def fig_tolerance(data, out, tol):
    main, u = data["main"][2], units(data["model"])
    runs = [main] + tol
    energies = [en["energy"] for en in tol[0]["energies"]]
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    rows = []
    for k, ens in enumerate(runs):
        pts = []
        for e in energies:
            en = energy_entry(ens, e)
            if en is None:
                continue
            c = en["criteria"]["saddle"]
            rep = statistics_sections.replicate_entry(c) or {}
            pred, m = num(c.get("predicted_rate")), num(c.get("mean_rate"))
            # the replicate error where the ensemble has replicates (the verdict's error)
            se = num(rep.get("standard_error")) if rep else num(c.get("standard_error"))
            drift = num(c.get("max_energy_drift", en.get("max_energy_drift")))
            pts.append((e, 100 * (m / pred - 1), 100 * se / pred, drift))
            rows.append([ens["name"], tolerance_label(ens), as_written(e), "%.17g" % pred,
                         "%.17g" % m, "%.6g" % se, "%.3f" % (100 * (m / pred - 1)),
                         "%.3f" % (100 * se / pred), "%.3g" % drift])
        if not pts:
            continue
        x, d, err, drift = np.array(pts).T
        lab = tolerance_label(ens) + (" (baseline)" if ens is main else "")
        axes[0].errorbar(x + 0.02 * (k - len(runs) / 2), d, yerr=err, fmt="o", ms=4, capsize=2,
                         label=lab)
        axes[1].semilogy(x, positive(drift), "o-", ms=4, label=lab)
    axes[0].axhline(0, color="k", lw=0.6)
    axes[0].set_yscale("symlog", linthresh=5)  # ±5 % linear: the tight runs and a runaway one
    axes[0].set(xlabel=u["E"], ylabel="R_sim / R_pred − 1 [%] (± SE; linear within ±5 %)",
                title="Saddle-criterion rate of arm 2 against the integrator tolerance")
    axes[1].set(xlabel=u["E"], ylabel="max |H − E| over the ensemble " + u["E"][2:],
                title="Energy drift (T = %s)" % as_written(tol[0]["time"]))
    for ax in axes:
        ax.legend(fontsize=7)
    header = ["ensemble", "integration", "energy", "predicted", "mean",
              "error (replicates where run with them)", "deviation [%]", "error [%]",
              "max energy drift"]
    table = write_table(out, "sensitivity-tolerance", header, rows)
    return save_figure(fig, out, "sensitivity-tolerance"), table, rows


def fig_threshold(data, out, thr):
    u = units(data["model"])
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    rows, pts = [], []
    for ens in thr:
        t = num(ens["chaos"]["threshold"])
        q = json_quality(ens, "saddle", "chaotic_trajectories", "full") or {}
        rep = q.get("replicates") if isinstance(q.get("replicates"), dict) else {}
        # the replicate error where the study has replicates, else the bootstrap's
        err = num(rep.get("PQI_se")) if rep else float("nan")  # no replicates: no error shown
        pts.append((t, 100 * num(q.get("PQI")), 100 * err, 100 * num(q.get("rms_S"))))
        for en in ens["energies"]:
            c = en["criteria"]["saddle"]
            ch = c.get("chaotic") or {}
            pred = num(c.get("predicted_rate"))
            rows.append([as_written(t), as_written(en["energy"]),
                         "%.4f" % num(c.get("chaotic_fraction")),
                         "%.3f" % (100 * (num(ch.get("mean_rate")) / pred - 1)),
                         "%.3f" % (100 * num(ch.get("std")) / pred)])
    t, pqi, sd, rs = np.array(pts).T
    axes[0].errorbar(t, pqi, yerr=sd, fmt="o-", ms=4, capsize=2, color="k",
                     label="PQI over the study's energies (chaotic sub-ensemble)")
    axes[0].plot(t, rs, "s--", ms=3, color="0.5", label="its RMS S(E) part")
    axes[0].set(xscale="log", xlabel="chaos threshold on λ_T [√(α/A)]", ylabel="[%]",
                title="PQI against the chaos threshold (T = %s)" % as_written(thr[0]["time"]))
    energies = sorted({r[1] for r in rows}, key=float)
    for e in energies:
        sel = [r for r in rows if r[1] == e]
        axes[1].plot([float(r[0]) for r in sel], [100 * float(r[2]) for r in sel], "o-", ms=3,
                     label="E = %s" % e)
    axes[1].set(xscale="log", xlabel="chaos threshold on λ_T [√(α/A)]",
                ylabel="chaotic fraction [%]", title="Trajectories kept as chaotic")
    for ax in axes:
        ax.legend(fontsize=7)
    header = ["threshold", "energy", "chaotic fraction", "R(E) chaotic [%]", "S(E) chaotic [%]"]
    table = write_table(out, "sensitivity-threshold", header, rows)
    return save_figure(fig, out, "sensitivity-threshold"), table, pts


# ---- tables -------------------------------------------------------------------------------------

def table_critical_points(data, out):
    header = ["(θ₁, θ₂)", "V (ours)", "V (paper, egalitarian)", "type"]
    rows = []
    egalitarian = is_egalitarian(data["model"])
    for ((x, y), e, kind), (label, pv, _) in zip(critical_points(data["model"]),
                                                PAPER["critical_points"]):
        rows.append([label, "%.17g" % e, pv if egalitarian else "n/a (other model)", kind])
    return write_table(out, "critical-points", header, rows), header, rows


def is_egalitarian(model):
    c = model["coefficients"]
    return all(abs(c[k] - v) < 1e-12 for k, v in (("A", 2), ("B", 1), ("C", 1), ("alpha", 2),
                                                  ("beta", 1)))


def quality_table(data, out, name, a, criterion, kind, paper_values):
    """Rows: regime, energies, flipflux's value ± its bootstrap sd, paper, verdict, noise floor,
    RMS R and S (every number from the ensemble JSON: the report computes no statistic)."""
    ens = data["main"][a]
    subset = "chaotic_trajectories" if kind == "PQI" else "all_trajectories"
    if kind == "PQI" and not any(json_quality(ens, criterion, subset, reg)
                                 for reg, _, _ in regimes(data, a)):
        subset = "all_trajectories"  # no chaos indicator: the whole ensemble
    entries = {reg: json_quality(ens, criterion, subset, reg)
               for reg, _, _ in regimes(data, a)}
    reference = [q["reference"] for q in entries.values() if q and "reference" in q]
    rescale = kind == "PQI" and bool(reference) and \
        abs(float(reference[0]["time"]) - ens["time"]) > 1e-12 * ens["time"]
    # the IQI is the RMS of R(E) by definition: its table does not repeat it as a column
    rms_r = kind != "IQI"
    header = ["regime", "energies", "%s [%%]" % kind, "± (replicates)", "paper [%]", "comparison",
              "noise floor [%]"] + (["RMS R(E) [%]"] if rms_r else []) + ["RMS S(E) [%]"] + \
        ["± (bootstrap)", "replicates' own %s [%%]" % kind]
    if rescale:
        header.append("PQI with S rescaled to T = %s [%%]" % reference[0]["time"])
    rows = []
    for reg, lo, hi in regimes(data, a):
        if reg not in paper_values:
            continue
        q = entries[reg]
        label = REGIME_LABELS[a][reg] if is_egalitarian(data["model"]) else \
            "%s (%.4g ≤ E < %.4g)" % (reg, lo, hi)
        if q is None:
            rows.append([label, 0, "—", "—", paper_values[reg], "no energies", ""] +
                        ([""] if rms_r else []) + ["", "", ""] + (["—"] if rescale else []))
            continue
        ours, boot = 100 * num(q[kind]), 100 * num(q[kind + "_sd"])
        rep = q.get("replicates") if isinstance(q.get("replicates"), dict) else {}
        sd = 100 * num(rep.get(kind + "_se"))
        own = [100 * num(x) for x in rep.get(kind) or []]
        if rescale:
            # S = sd / R_pred of time averages falls as 1/sqrt(T) for mixing trajectories: compare
            # the paper's value with flipflux's estimate at the paper's T (marked as such)
            ref = q["reference"]
            rel_se = sd / ours if ours > 0 and math.isfinite(sd) else float("nan")
            z, verdict = compare(100 * num(ref["PQI"]), 100 * num(ref["PQI"]) * rel_se,
                                 paper_values[reg], ens, kind)
            verdict = "T-rescaled: " + verdict
        else:
            z, verdict = compare(ours, sd if math.isfinite(sd) else None, paper_values[reg], ens,
                                 kind)
        rows.append([label, q["energies"], "%.2f" % ours, "%.2f" % sd if math.isfinite(sd) else "—",
                     "%.2f" % paper_values[reg], verdict, "%.2f" % (100 * num(q["noise_floor"]))] +
                    (["%.2f" % (100 * num(q["IQI"]))] if rms_r else []) +
                    ["%.2f" % (100 * num(q["rms_S"]))] +
                    ["%.2f%s" % (boot, " (⚠ %.1f× the replicates')" % (boot / sd)
                                 if math.isfinite(sd) and sd > 0 and not 0.5 <= boot / sd <= 2
                                 else ""),
                     "%.2f – %.2f" % (min(own), max(own)) if own else "—"] +
                    (["%.2f ± %.2f" % (100 * num(q["reference"]["PQI"]),
                                       100 * num(q["reference"]["PQI_sd"]))] if rescale else []))
    return write_table(out, name, header, rows), header, rows


def table_rms(data, out):
    """RMS relative differences of the predicted rates over the arm-2 ensemble's energies (the
    paper's grid; the ensemble JSON) and over predictions.csv's grid (run.json), as flipflux
    computed them."""
    ens = data["main"][2]
    header = ["difference", "ours, ensemble grid [%]", "ours, predictions grid [%]", "paper [%]",
              "energies (ensemble / predictions)"]
    grid = {tuple(d["criteria"]): d for d in ens.get("prediction_differences") or []}
    run_grid = {tuple(d["criteria"]): d
                for d in (data["run"].get("predictions") or {}).get("rate_differences") or []
                if str(d.get("arm")) == "2"}
    rows = []
    for c, key in (("approx", "rms_approx_saddle"), ("upright", "rms_upright_saddle")):
        d = grid.get((c, "saddle")) or grid.get(("saddle", c)) or {}
        q = run_grid.get((c, "saddle")) or {}
        rows.append(["%s vs saddle (theory)" % c,
                     "%.2f" % (100 * num(d["rms_relative"])) if d else "—",
                     "%.2f" % (100 * num(q["rms_relative"])) if q.get("rms_relative") else "—",
                     "%.2f" % PAPER[key], "%d / %d" % (d.get("energies", 0), q.get("energies", 0))])
    return write_table(out, "rms-differences", header, rows), header, rows


def table_rates(data, out, a):
    """Per energy: predicted and simulated rates (all and chaotic) for every criterion."""
    ens = data["main"][a]
    crit = [c for c in CRITERIA if c in ens["energies"][0]["criteria"]]
    header = ["energy"]
    for c in crit:
        header += ["%s predicted" % c, "%s mean" % c, "%s standard error" % c, "%s sd" % c,
                   "%s chaotic mean" % c, "%s chaotic sd" % c, "%s z" % c,
                   "%s replicate error" % c, "%s z (replicates)" % c,
                   "%s replicate / per-trajectory error" % c]
    series = {c: (rate_series(ens, c), rate_series(ens, c, True)) for c in crit}
    rows = []
    for i, e in enumerate(series[crit[0]][0]["energy"]):
        row = ["%.10g" % e]
        for c in crit:
            s, sc = series[c]
            j = np.where(np.abs(sc["energy"] - e) < 1e-9)[0]
            cm, csd = (sc["mean"][j[0]], sc["std"][j[0]]) if len(j) else (np.nan, np.nan)
            z = s["z"][i]
            row += ["%.17g" % s["predicted"][i], "%.17g" % s["mean"][i], "%.6g" % s["se"][i],
                    "%.6g" % s["std"][i], "%.17g" % cm, "%.6g" % csd, "%.3f" % z,
                    "%.6g" % s["rse"][i], "%.3f" % s["rz"][i], "%.3f" % s["ratio"][i]]
        rows.append(row)
    return write_table(out, "rates-arm%d" % a, header, rows)


# ---- the report ---------------------------------------------------------------------------------

def figure_md(paths, caption):
    png, svg = paths
    name = os.path.splitext(os.path.basename(png))[0]
    return "![%s](%s)\n\n*%s* ([SVG](%s))\n" % (name, png, caption, svg)


def explain_quality(rows, kind, ens, which):
    """A paragraph on the rows that differ from the paper by more than their statistical error."""
    bad = [r for r in rows if "differs" in str(r[5])]
    if any("no verdict" in str(r[5]) for r in rows):
        return "No verdict for %s of %s: the ensemble has no replicates, and a per-trajectory " \
               "error alone cannot see rare islands or sticky orbits (run it with replicates).\n" \
               % (kind, which)
    if not bad:
        return "All %s values of %s agree with the paper's within 2σ of the combined statistical " \
               "error (ours the jackknife over the replicates, the paper's scaled from ours to " \
               "N = %d, T = %d; with R = 10 replicates 2σ of Student's t is a 7.7 %% test).\n" % \
               (kind, which, PAPER["N"], PAPER["T"])
    n, t = ens["trajectories"], ens["time"]
    lines = ["**Where %s of %s differs from the paper** (%s): " %
             (kind, which, "; ".join("%s: ours %s %%, paper %s %%" % (r[0], r[2], r[4])
                                     for r in bad))]
    if kind == "IQI":
        lines.append("the IQI of a correct implementation is its noise floor sqrt(mean (SE/R)²) "
                     "(column 'noise floor'), which scales as 1/sqrt(N T): ours is for N = %d, "
                     "T = %g%s. An IQI at our floor and below the paper's value means our chain "
                     "(prediction, integrator, flip detection) shows no systematic error at this "
                     "resolution, while the paper's excess over its own floor (≈ ours × %.2g) "
                     "would be systematic (its MATLAB quadrature, integrator or saddle orbits); "
                     "an IQI above our floor is a systematic error of ours or a near-threshold "
                     "energy where R_pred → 0 (the low regime depends on the grid's lowest energy)."
                     % (n, t, "" if (n, t) == (PAPER["N"], PAPER["T"]) else
                        " (the paper's: N = 1000, T = 10000)",
                        math.sqrt(n * t / (PAPER["N"] * PAPER["T"]))))
    else:
        lines.append("the PQI is dominated by S(E) = sd/R_pred (column 'RMS S(E)'), the spread of "
                     "per-trajectory rates, which for chaotic trajectories falls as 1/sqrt(T) "
                     "(our T = %g, the paper's 10000%s; the last column rescales S to T = 10000 "
                     "and the comparison uses it, an estimate that assumes mixing) and depends on which trajectories the "
                     "chaos indicator keeps: ours is the finite-time Lyapunov exponent with "
                     "threshold %s (chaos block of the ensemble JSON); the paper does not state "
                     "its indicator or threshold. The energy grid (ours: %d energies) also enters "
                     "through the low regime, where R_pred → 0."
                     % (t, "" if t == PAPER["T"] else ", so S is expected ≈ %.2g× the paper's"
                        % math.sqrt(PAPER["T"] / t),
                        as_written((ens.get("chaos") or {}).get("threshold", "?")),
                        len(ens["energies"])))
    return "".join(lines) + "\n"


def trajectory_sections(data, out):
    """The trajectory figures, from the scene's [[trajectory]] tables named typical and
    recrossing (a run without them says so)."""
    md = []
    tr = data["trajectories"]
    if "typical" in tr:
        paths, st = fig_trajectory_typical(data, out)
        md.append(figure_md(paths, "A typical chaotic trajectory (trajectory-typical.csv, from the "
                            "scene's [[trajectory]] 'typical'): the paths of both masses and the "
                            "tip's position at each flip (left), the flip angles against time "
                            "(right) (paper Fig. typical trajectory)."))
        md.append("E = %.6g, T = %s: arm 2 flips %d times by the %s criterion, arm 1 %d times%s.\n"
                  % (st["energy"], as_written(st["time"]), st["flips2"], st["criterion"],
                     st["flips1"], " (it cannot: E is below its saddle energy %s)" %
                     as_written(data["model"]["saddle"][1])
                     if st["energy"] < data["model"]["saddle"][1] else ""))
    else:
        md.append("*No typical-trajectory figure: the run has no trajectory-typical.csv (the "
                  "scene's [[trajectory]] 'typical', docs/scenes.md).*\n")
    if "recrossing" in tr:
        paths, st = fig_trajectory_recrossing(data, out)
        md.append(figure_md(paths, "A trajectory that recrosses the upright arm (trajectory-"
                            "recrossing.csv): forbidden region red, trajectory blue, upright "
                            "criterion dotted, saddle orbit purple, crossing events yellow (paper "
                            "Fig. recrossing)."))
        md.append("It crosses the upright line %d times and the saddle orbit %d times: the "
                  "upright criterion counts a flip and its undoing where the saddle-orbit "
                  "criterion counts none — the motivation for the saddle criterion.\n" %
                  (st.get("upright", 0), st.get("saddle", 0)))
    else:
        md.append("*No recrossing figure: the run has no trajectory-recrossing.csv.*\n")
    return "\n".join(md)


def beyond_the_paper(data, out):
    """What the run computes and the paper does not show: chaotic fractions, the replicate errors
    the verdicts rest on, flip statistics beyond the mean, the island census."""
    md = ["## What the ensembles show beyond the paper's figures\n"]
    paths, st = fig_chaotic_fraction(data, out)
    md.append(figure_md(paths, "Fraction of trajectories classified as chaotic per energy "
                        "(ensemble JSON chaotic_fraction)."))
    if st:
        md.append("Lowest chaotic fraction: %s.\n" % "; ".join(
            "arm %d %.1f %% at E = %s" % (a, 100 * v["min"], as_written(v["at"]))
            for a, v in sorted(st.items())))
    md.append(statistics_sections.replicate_section(data, out, data["main"]))
    md.append(statistics_sections.flip_statistics_section(data, out))
    md.append(statistics_sections.census_sections(data, out))
    return "\n".join(md)


def sensitivity_sections(data, out):
    """The tolerance and chaos-threshold studies, from ensembles that re-run the main arm-2
    ensemble's trajectories (sensitivity_ensembles); a run without them says so."""
    tol, thr = sensitivity_ensembles(data)
    md = ["## Sensitivity of the simulated rates\n"]
    if tol:
        paths, table, rows = fig_tolerance(data, out, tol)
        md.append(figure_md(paths, "Rates of arm 2 (saddle criterion) with the same initial "
                            "conditions integrated at other tolerances — MATLAB ode45's defaults "
                            "rtol 1e-3, atol 1e-6 emulated by DOPRI5 — against the main "
                            "ensemble's (left), and the largest energy drift (right). [CSV](%s)"
                            % table))
        main = data["main"][2]
        lines = []
        for ens in tol:
            q = json_quality(ens, "saddle", "all_trajectories", "full") or {}
            mine = [r for r in rows if r[0] == ens["name"]]
            base = {r[2]: r for r in rows if r[0] == main["name"]}
            lines.append("%s: IQI %.2f %% over its %d energies (noise floor %.2f %% by its "
                         "per-trajectory errors), deviations "
                         "%s, largest energy drift %s" %
                         (tolerance_label(ens), 100 * num(q.get("IQI")), len(mine),
                          100 * num(q.get("noise_floor")),
                          ", ".join("%s ± %s %% at E = %s (baseline %s ± %s %%)" %
                                    (r[6], r[7], r[2], base[r[2]][6], base[r[2]][7])
                                    if r[2] in base else "%s ± %s %% at E = %s" % (r[6], r[7], r[2])
                                    for r in mine),
                          max((r[8] for r in mine), key=float) if mine else "—"))
        verdicts = []
        for ens in tol:
            mine = [r for r in rows if r[0] == ens["name"]]
            if not mine:
                continue
            dev = max(abs(float(r[6])) for r in mine)
            if not statistics_sections.replicates_of(ens) > 1 and dev <= 5 * 1.05:
                verdicts.append("%s: no verdict (no replicates; its per-trajectory errors alone "
                                "are not trusted)" % tolerance_label(ens))
                continue
            worst = max(mine, key=lambda r: abs(float(r[6])) / float(r[7])
                        if float(r[7]) > 0 else 0)
            z = abs(float(worst[6])) / float(worst[7]) if float(worst[7]) > 0 else 0
            drift = max(float(r[8]) for r in mine)
            # the noise floor of this study: RMS over its energies of its error / R_pred
            floor = math.sqrt(sum(float(r[7]) ** 2 for r in mine) / len(mine))
            if dev > 5 * 1.05:
                verdicts.append("%s integrates a different system: its energy drifts by up to "
                                "%.3g over T = %s and its rates are off by up to %.0f %%, far "
                                "beyond the paper's IQI of 1.05 %%, so the paper's rates cannot "
                                "come from such an integration (the paper does not state its "
                                "tolerances)" % (tolerance_label(ens), drift,
                                                 as_written(ens["time"]), dev))
            elif z <= 3:
                resolved = floor <= 1.05 / 3
                verdicts.append("%s agrees with the prediction: its largest deviation is %.1fσ "
                                "(%s %% at E = %s) at a noise floor of %.2f %% — %s a third of the "
                                "paper's IQI of 1.05 %%, so %s (energy drift up to %.3g)" %
                                (tolerance_label(ens), z, worst[6], worst[2], floor,
                                 "below" if resolved else "above",
                                 "an integrator error of the paper's IQI's size would have shown: "
                                 "this tolerance does not explain it" if resolved else
                                 "an integrator error of that size is not resolved", drift))
            else:
                verdicts.append("%s deviates by %s %% (%.1f SE) at E = %s: a systematic error of "
                                "the integration" % (tolerance_label(ens), worst[6], z, worst[2]))
        md.append("%s.\n\nWhat this shows: %s.\n" % (";\n".join(lines), "; ".join(verdicts)))
        md.append("The emulation is DOPRI5 with Hairer's mixed error norm, not MATLAB's "
                  "(ode45 takes the maximum over components of |err| / max(rtol |y|, atol)); it "
                  "keeps flipflux's energy check (a step may change H by at most 64 (atol + rtol "
                  "|E|)), which bounds each step's energy change, not the drift's accumulation. "
                  "An IQI of 1.05 % at the paper's N and T needs a systematic error of about "
                  "that size; a deviation beyond 2 SE that the baseline does not have is the "
                  "integrator's.\n")
    else:
        md.append("*No tolerance study: the run has no ensemble that re-runs the main arm-2 "
                  "ensemble (same seed) with another integrator or tolerance "
                  "(data/scenes/paper-tenth.toml has them; its report is committed in "
                  "docs/reproduction-tenth/).*\n")
    if thr:
        paths, table, pts = fig_threshold(data, out, thr)
        md.append(figure_md(paths, "The PQI of arm 2's saddle criterion over the study's energies "
                            "against the chaos threshold on the finite-time Lyapunov exponent "
                            "(left), and the fraction of trajectories kept as chaotic (right): the "
                            "same trajectories, classified with each threshold. [CSV](%s)" % table))
        fr = {}
        for t, e, f, _, _ in [(float(r[0]), r[1], float(r[2]), r[3], r[4])
                              for r in read_rows(table, out)]:
            fr.setdefault(t, []).append((f, e))
        cut = [t for t in sorted(fr) if min(fr[t])[0] < 0.5]
        stable = [(t, p) for t, p, _, _ in pts if t not in cut]
        md.append("PQI over the study's energies: %s. %s The paper does not state its indicator "
                  "or threshold. A second, independent indicator (e.g. SALI or the 0-1 test) is "
                  "not implemented: the ensemble classifies by λ_T only.\n" %
                  (", ".join("%.2f ± %.2f %% at threshold %s" % (p, sd, as_written(t))
                             for t, p, sd, _ in pts),
                   ("Between thresholds %s and %s the PQI stays within %.2f %% (%.2f to %.2f %%): "
                    "the threshold sits in the gap between regular and chaotic λ_T. " %
                    (as_written(stable[0][0]), as_written(stable[-1][0]),
                     max(p for _, p in stable) - min(p for _, p in stable),
                     min(p for _, p in stable), max(p for _, p in stable))
                    if len(stable) > 1 else "") +
                   ("At %s the threshold cuts into the chaotic band (chaotic fraction %s), so the "
                    "PQI then measures which chaotic trajectories are dropped, not the "
                    "prediction." % (", ".join(as_written(t) for t in cut),
                                     "; ".join("%.0f %% at E = %s for threshold %s" %
                                               (100 * min(fr[t])[0], min(fr[t])[1],
                                                as_written(t)) for t in cut))
                    if cut else "")))
    else:
        md.append("*No chaos-threshold study: the run has no ensemble that re-runs the main arm-2 "
                  "ensemble with another chaos_threshold (data/scenes/paper-tenth.toml has them; its "
                  "report is committed in docs/reproduction-tenth/).*\n")
    return "\n".join(md)


def load_other_run(run_dir):
    """Another scene's output (another pendulum): run.json's model, predictions.csv and its
    ensembles; None when the directory does not exist (the report notes it)."""
    if not os.path.isdir(run_dir):
        return None
    problems = []
    run = read_json(os.path.join(run_dir, "run.json"), problems)
    other = {"run_dir": run_dir, "run": run,
             "model": load_model(run, os.path.join(run_dir, "run.json"), problems) if run else None,
             "predictions": load_predictions(os.path.join(run_dir, "predictions.csv"), problems),
             "ensembles": load_ensembles(run_dir, problems)}
    if problems:
        raise InputError("\n".join(problems))
    return other


def fig_other_run(other, out):
    """An other pendulum's simulated rates (all trajectories, ± SE) against its predictions, per
    arm and criterion."""
    model, u = other["model"], units(other["model"])
    name = (other["run"] or {}).get("scene", os.path.basename(other["run_dir"].rstrip("/")))
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    rows = []
    for ax, a in zip(axes, (2, 1)):
        for c in CRITERIA:
            pr = other["predictions"].get(("rate-" + c, a))
            if pr is not None:
                ax.plot(pr[:, 0], pr[:, 1], "-" if c != "approx" else "--", color=COLORS[c],
                        label="prediction, %s" % c)
            for ens in other["ensembles"]:
                if ens["arm"] != a or not ens["energies"] or \
                        c not in ens["energies"][0]["criteria"] or \
                        statistics_sections.is_census_or_check(ens, other["run"]):
                    continue
                sr = rate_series(ens, c)
                ax.errorbar(sr["energy"], sr["mean"], yerr=sr["se"], fmt="o", ms=4, capsize=2,
                            color=COLORS[c], mfc="none",
                            label="simulation, %s (N = %d, T = %s)" %
                            (c, ens["trajectories"], as_written(ens["time"])))
                fc = {float(en["energy"]): num(en["criteria"][c].get("chaotic_fraction"))
                      for en in ens["energies"] if c in en["criteria"]}
                for e, p_, m, se, z, rse, rz in zip(sr["energy"], sr["predicted"], sr["mean"],
                                                    sr["se"], sr["z"], sr["rse"], sr["rz"]):
                    # the verdict's z is the replicate error's; without replicates none
                    rows.append([name, a, c, as_written(e), "%.17g" % p_, "%.17g" % m,
                                 "%.6g" % rse, "%.3f" % (100 * (m / p_ - 1)), "%.2f" % rz,
                                 "%.6g" % fc.get(float(e), float("nan")),
                                 str(ens["trajectories"]), "%.6g" % se, "%.2f" % z])
        for e in (model["saddle"][a], model["maximum"]):
            ax.axvline(e, color="0.5", ls=":", lw=0.8)
        ax.set(xlabel=u["E"], ylabel="flip rate of arm %d %s" % (a, u["rate"]),
               title="Arm %d of scene '%s'" % (a, name))
        ax.legend(fontsize=6)
    p = model["parameters"]
    fig.suptitle("m₁ = %s, m₂ = %s, L₁ = %s, L₂ = %s, g = %s: E_s = %s (arm 2), %s (arm 1), "
                 "E_max = %s" % tuple([as_written(p.get(k, "?")) for k in
                                       ("m1", "m2", "L1", "L2", "g")] +
                                      [as_written(model["saddle"][2]), as_written(model["saddle"][1]),
                                       as_written(model["maximum"])]), fontsize=9)
    header = ["scene", "arm", "criterion", "energy", "predicted", "mean", "replicate error",
              "deviation [%]", "z", "chaotic fraction", "trajectories",
              "per-trajectory standard error", "z by the per-trajectory error"]
    table = write_table(out, "other-%s" % name, header, rows)
    return save_figure(fig, out, "other-%s" % name), table, rows


def other_run_sections(data, out):
    md = []
    for d in data.get("other_run_dirs") or []:
        other = data["other_runs"].get(d)
        if other is None:
            md.append("*Other pendulum `%s`: not run (run its scene, e.g. "
                      "data/scenes/appendix-c.toml, before this one).*\n" % d)
            continue
        paths, table, rows = fig_other_run(other, out)
        zs = [float(r[8]) for r in rows if r[8] != "nan"]
        reps = {statistics_sections.replicates_of(e) for e in other["ensembles"]
                if not statistics_sections.is_census_or_check(e, other["run"])}
        R = min(reps) if reps else 1
        expected = len(zs) * (R - 1) / (R - 3) if R > 3 else float("nan")
        md.append(figure_md(paths, "A non-egalitarian pendulum (the paper's Appendix C derives the "
                            "upright-arm rate for general masses and lengths): predicted rates of "
                            "every criterion against simulated means ± SE, from the run directory "
                            "`%s`. [CSV](%s)" % (d, table)))
        md.append("Over its %d (energy, criterion) pairs: largest |R_sim/R_pred − 1| = %.2f %%, "
                  "Σz² = %.1f by the replicate errors (%.1f expected for a correct prediction: "
                  "z is Student-t with R − 1 degrees of freedom; pairs without replicates give "
                  "no z), worst z = %.2f. The paper gives formulas "
                  "for this case but no numbers to compare with.\n" %
                  (len(rows), max(abs(float(r[7])) for r in rows) if rows else float("nan"),
                   sum(z * z for z in zs), expected, max(zs, key=abs) if zs else float("nan")))
        unseen = [r for r in rows if r[8] != "nan" and abs(float(r[8])) > 3 and r[9] == "1"]
        if unseen:
            md.append("Where |z| > 3 with every trajectory chaotic (%s) the mean may be the chaotic "
                      "sea's rate rather than the whole surface's: islands holding a fraction "
                      "≪ 1/N of it with a higher flip rate are then never sampled, and the standard "
                      "error cannot see their share of the variance (docs/theory.md, \"Rare islands "
                      "bias a small ensemble\"; the island census below measures them with an "
                      "independent ensemble).\n" %
                      ", ".join("arm %s %s at E = %s, N = %s, z = %s" % (r[1], r[2], r[3], r[10], r[8])
                                for r in unseen))
    if not md:
        return ""
    return "## Another pendulum (paper Appendix C)\n\n" + "\n".join(md)


def source_state(out, run_dirs, allow_dirty):
    """The git state the report is generated from: {"commit", "dirty"} of the work tree that
    holds the report directory when that directory is tracked there (not ignored); None outside
    git. A tree with uncommitted changes outside the report and run directories is refused
    (InputError) unless allow_dirty: a committed report must say which code drew it."""
    import subprocess
    d = os.path.realpath(out)
    while not os.path.isdir(d):
        d = os.path.dirname(d)

    def git(*args):
        r = subprocess.run(["git", "-C", d] + list(args), capture_output=True, text=True)
        return r.returncode, r.stdout.rstrip("\n")  # porcelain lines start with a space
    try:
        code, top = git("rev-parse", "--show-toplevel")
    except OSError:
        return None
    if code != 0 or not top:
        return None
    top = os.path.realpath(top)
    rel = os.path.relpath(os.path.realpath(out), top)
    if rel.startswith("..") or git("check-ignore", "-q", os.path.realpath(out))[0] == 0:
        return None
    excluded = [":(exclude)%s" % rel]
    for r in run_dirs:
        rr = os.path.relpath(os.path.realpath(r), top)
        if not rr.startswith(".."):
            excluded.append(":(exclude)%s" % rr)
    _, status = git("-C", top, "status", "--porcelain", "--", ".", *excluded)
    _, commit = git("-C", top, "rev-parse", "HEAD")
    dirty = bool(status)
    if dirty and not allow_dirty:
        paths = [line[3:] for line in status.splitlines() if len(line) > 3]
        raise InputError("--out: '%s' is in the git work tree %s, which has uncommitted changes "
                         "(%s%s): commit them first, or pass --allow-dirty "
                         "(FLIPFLUX_REPORT_ALLOW_DIRTY=1 through flipflux run) and the report "
                         "says so" % (out, top, ", ".join(paths[:3]),
                                      " and %d more" % (len(paths) - 3) if len(paths) > 3 else ""))
    return {"commit": commit or "?", "dirty": dirty}


def build_report(data, out):
    t0 = time.time()
    for sub in ("", "figures", "tables"):
        os.makedirs(os.path.join(out, sub), exist_ok=True)
    run, model = data["run"], data["model"]
    md = []
    md.append("# Reproduction of the paper's figures and tables\n")
    md.append("Generated by `tools/report/make_report.py` from the run directory of scene "
              "**%s** (`%s`), computed by flipflux built from commit `%s`, precision %s; the run "
              "took **%.1f s** of wall time.%s\n"
              % (run.get("scene", "?"), run.get("scene_file", "?"), run.get("git_commit", "?"),
                 run.get("precision", "?"), float(run.get("seconds", float("nan"))),
                 "" if not data.get("source") else
                 " The report itself was drawn at commit `%s`%s." %
                 (data["source"]["commit"], " **from a work tree with uncommitted changes**"
                  if data["source"]["dirty"] else " (a clean work tree)")))
    ens_lines = []
    for e in data["ensembles"]:
        ens_lines.append("- `ensemble-%s`: arm %d, %d energies (%.4g…%.4g), N = %d trajectories, "
                         "T = %g, %s, rtol %s, atol %s, chaos indicator threshold %s (classification "
                         "reliable: %s)"
                         % (e["name"], e["arm"], len(e["energies"]),
                            min(x["energy"] for x in e["energies"]),
                            max(x["energy"] for x in e["energies"]), e["trajectories"], e["time"],
                            e["method"], as_written(e["rtol"]), as_written(e.get("atol", "?")),
                            as_written((e.get("chaos") or {}).get("threshold", "—")),
                            (e.get("chaos") or {}).get("classification_reliable", "?")))
    md.append("Ensembles (the paper: N = 1000, T = 10000):\n\n" + "\n".join(ens_lines) + "\n")
    md.append("Statistical errors: every verdict rests on the spread of independent replicates "
              "(the jackknife over the R replicates of each ensemble; section 'The errors every "
              "verdict rests on'), never on a per-trajectory Gaussian error alone; where an "
              "ensemble has no replicates no verdict is printed. A value 'agrees' with the "
              "paper's when within 2σ of the combined error, the paper's own (it states none) "
              "estimated by scaling ours to N = 1000, T = 10000; z against our error alone is "
              "printed beside it. Numbers are never tuned to match.\n")

    # Configuration space
    md.append("## The pendulum, its energy regimes and its trajectories\n")
    md.append(figure_md(fig_schematic(data, out), "The double pendulum: angles θ₁, θ₂ from the "
                        "downward vertical, link lengths L₁, L₂, masses m₁, m₂, gravity g (paper "
                        "Fig. double pendulum system example; a drawing, the run's parameters in "
                        "its title)."))
    md.append(figure_md(fig_energy_regimes(data, out), "Critical energies V(0, π), V(π, 0) and "
                        "V(π, π) of this pendulum and which flips are possible where; the paper's "
                        "chaotic sub-regimes of the quality tables (paper Fig. energy regimes)."))
    md.append(trajectory_sections(data, out))
    md.append("## Potential and configuration space\n")
    md.append(figure_md(fig_potential(data, out), "Potential energy contour map with the four "
                        "critical points (paper Fig. potential)."))
    path, header, rows = table_critical_points(data, out)
    md.append("Critical points (paper Table critical points; [CSV](%s)):\n\n%s\n" %
              (path, markdown_table(header, rows)))
    md.append(figure_md(fig_allowed_region(data, out), "Allowed configuration region V ≤ E below "
                        "the first saddle, between the saddles, between the second saddle and the "
                        "maximum, and above the maximum (paper Fig. allowed configuration space)."))
    paths, chosen = fig_criteria(data, out)
    md.append(figure_md(paths, "The three flip criteria in configuration space: upright arm, "
                        "approximate saddle orbit θ_flip = π + A sin θ_other and the saddle orbit "
                        "(arm 2 at E = %g, arm 1 at E = %g; paper Fig. criteria)." %
                        (chosen[2], chosen[1])))
    slope2 = model["approx_slope"][2]
    md.append("Approximate-curve slope of arm 2: %.17g (paper: 2 − √2 = %.17g for the egalitarian "
              "pendulum; computed here from the centre mode of K v = ω² M v at the saddle)%s.\n" %
              (slope2, 2 - math.sqrt(2), "" if "approx_slope_run" not in model else
               "; run.json: %.17g" % model["approx_slope_run"][2]))
    md.append(figure_md(fig_orbit_family(data, out), "The saddle-orbit families of arm 2 and arm 1, "
                        "coloured by energy, in the orientation of the criteria figure (the flip "
                        "angle about its upright value π)."))
    paths, e_kf = fig_keyframes(data, out)
    md.append(figure_md(paths, "Key frames of the down-up saddle orbit of arm 2 at E = %s: the "
                        "pendulum at a turning point (1), midway where it passes the saddle "
                        "configuration θ₁ = 0 (2), and at the other turning point (3); masses A "
                        "(m₁) and B (m₂) (paper Fig. key frames at E = 2.5; the configurations are "
                        "the orbit's curve in orbit-curves-arm2.csv, turning point to turning "
                        "point, half a period)." % as_written(e_kf)))

    # Orbits and fluxes
    md.append("## Saddle orbits, phase volume and fluxes\n")
    for a in (2, 1):
        paths, st = fig_period_action(data, out, a)
        md.append(figure_md(paths, "Period T(E) and action F(E) of the arm-%d saddle orbits; F "
                            "reconstructed as F(E₀) + ∫ T dE against the shooting's F, and their "
                            "relative residual: the corrected trapezoid rule with the orbits' own "
                            "dT/dE (cubic Hermite), the same Richardson-extrapolated over the "
                            "steps h and 2h, and 4-point interpolation of T alone (paper Fig. "
                            "Time and flux saddle orbit)." % a))
        check = ("the flux through the orbit's curve by the curve-flux quadrature equals 2 F to "
                 "%.1e (relative)" % st["flux_over_action"] if st["flux_over_action"] is not None
                 else "the run predates the curve-flux column, so f3 = 2 F is not checked here")
        md.append("Arm %d: %d orbits, step %.3g. Max |F_rec/F − 1| with the orbits' dT/dE: %.1e "
                  "over the middle half of the energies, %.1e overall (largest at the ends, where T "
                  "diverges logarithmically); 4-point interpolation without dT/dE: %.1e; "
                  "Richardson-extrapolated (E ≤ E₀ + 0.75 ΔE): %.1e. The residual falls as h⁴ "
                  "with the quadrature, so it bounds how consistent the orbits' T and F are "
                  "(at the %.0e level), not their accuracy, which their own error estimates put "
                  "near 1e-14 (red); the paper calls its residual 'very small' without a number. "
                  "Also: %s.\n" % (a, st["energies"], st["step"], st["middle_residual"],
                                    st["max_residual"], st["max_residual_4pt"], st["richardson"],
                                    st["richardson"], check))
    paths, st = fig_multipliers(data, out)
    md.append(figure_md(paths, "Floquet multipliers of the saddle orbits and the instability "
                        "rate ln|λ|/T they imply (orbits-arm<a>.csv multiplier and period; the "
                        "paper computes the multipliers but shows no figure)."))
    if st:
        md.append("Every orbit on the grid is hyperbolic (unstable): |λ| from %s. The large "
                  "multipliers are why the orbits are found by shooting with a Newton polish "
                  "rather than by integrating forward from a guess.\n" %
                  "; ".join("%.3g to %.3g for arm %d (%d elliptic)" %
                            (v["min"], v["max"], a, v["elliptic"]) for a, v in sorted(st.items())))
    md.append(figure_md(fig_fluxes(data, out), "Phase volume Ω(E) and the fluxes of the three "
                        "criteria (paper Fig. phase space flux and criteria flux). Our fluxes count "
                        "both directions (f3 = 2 F)."))

    # Rates
    md.append("## Predicted against simulated flip rates\n")
    stats = {}
    for a, subset, cap in ((2, "all", "paper Figs. saddle orbit criterion second pendulum, all "
                            "trajectories (mean only, and with scattering)"),
                           (2, "chaotic", "paper Fig. chaotic trajectories"),
                           (1, "chaotic", "paper Fig. saddle orbit pendulum 1"),
                           (1, "all", "arm 1, the whole ensemble (used for the IQI)")):
        paths, st = fig_rates(data, out, a, subset)
        stats[(a, subset)] = st
        md.append(figure_md(paths, "Saddle-orbit flip rate of arm %d, %s trajectories, against the "
                            "flux-over-a-saddle prediction; error bars: standard error (left), "
                            "trajectory-to-trajectory sd (middle); right: relative deviation (%s)."
                            % (a, subset, cap)))
        if st["R"] > 1:
            md.append("Largest |R_sim/R_pred − 1| = %.2f %%; with the replicate errors (R = %d "
                      "independent replicates) Σz² = %.1f over %d energies, %.1f expected for a "
                      "correct prediction%s; worst z = %.2f; %s energies where the replicate and "
                      "per-trajectory errors differ by more than 2× (Σz² by the per-trajectory "
                      "error alone: %.1f).%s\n" %
                      (st["max_rel"], st["R"], st["chi2_rep"], st["dof_rep"], st["expected_rep"],
                       "" if subset == "all" else " (the chaotic sub-ensemble is not the "
                       "microcanonical one, so a bias is expected: the census section tests it)",
                       st["worst_z_rep"], st["mismatches"], st["chi2"],
                       " The paper: 'the relative difference remains at the 1 % level'." if
                       (a, subset) == (2, "all") else ""))
        else:
            md.append("Largest |R_sim/R_pred − 1| = %.2f %% over %d energies. No replicates: no "
                      "Σz² verdict is printed (by the per-trajectory error alone it would be "
                      "%.1f).\n" % (st["max_rel"], st["dof"], st["chi2"]))
    md.append(figure_md(fig_rates_criteria(data, out), "Predicted and simulated rates of the "
                        "upright, approximate and saddle criteria, arm 2, chaotic trajectories "
                        "(paper Fig. saddle orbit and upright criterion)."))
    for a in (2, 1):
        md.append("Per-energy rates of arm %d: [CSV](%s).\n" % (a, table_rates(data, out, a)))

    md.append("## Distributions\n")
    paths, st = fig_residence(data, out)
    md.append(figure_md(paths, "Residence times between successive flips of arm 2 at E = %g, "
                        "upright against saddle criterion (paper Fig. waiting times)." %
                        data["e_res"]))
    md.append("Ours: %d (upright) and %d (saddle) residence times; shortest %.4g (upright) and "
              "%.4g (saddle), 0.1 %% quantiles %.4g and %.4g. The paper: 30,000 detected flips, a "
              "short-time gap for the saddle criterion and none for the upright one.\n" %
              (st["upright"]["count"], st["saddle"]["count"], st["upright"]["min"],
               st["saddle"]["min"], st["upright"]["q001"], st["saddle"]["q001"]))
    paths, st = fig_residence_gap(data, out)
    md.append(figure_md(paths, "The short-time gap against E: shortest and 0.1 %-quantile "
                        "residence times of arm 2 per criterion over the main ensemble's energies "
                        "(ensemble JSON, residence_times)."))
    if st:
        md.append("The saddle criterion's shortest residence time stays between %.3g and %.3g "
                  "over the energies, the upright criterion's between %.3g and %.3g: the gap of "
                  "the paper's E = 5 figure holds at every energy, and it is the saddle criterion "
                  "that has it — recrossings of the upright line within a short time are what "
                  "the saddle orbit does not count.\n" %
                  (st["saddle"]["min"], st["saddle"]["max_of_min"], st["upright"]["min"],
                   st["upright"]["max_of_min"]) if "saddle" in st and "upright" in st else "")
    paths, st = fig_rate_histogram(data, out)
    md.append(figure_md(paths, "Per-trajectory flip rates of arm 2 (saddle criterion) at E = %g "
                        "(paper Fig. flip rate histogram)." % data["e_hist"]))
    md.append("Ours: %d trajectories, largest rate %.2f × the mean (the paper: a high-rate tail "
              "'of order three times the mean'; the tail's extent depends on T, since the spread "
              "of time averages falls as 1/sqrt(T)).\n" % (st["n"], st["max_over_mean"]))
    paths, st = fig_approx_vs_saddle(data, out)
    md.append(figure_md(paths, "Relative difference between the approximate and the exact saddle "
                        "criterion, theory and simulation means (paper Fig. relative error saddle "
                        "orbit approximation)."))
    md.append("Ours: theory at most %.3f %%, simulation means at most %.3f %% (the paper: theory "
              "below 1 %%, simulation 'sub-percent, approaching 1 %%').\n" %
              (st["pred_max"], st["sim_max"]))

    md.append(beyond_the_paper(data, out))
    md.append(other_run_sections(data, out))
    md.append(sensitivity_sections(data, out))

    # Quality tables
    md.append("## Quality indices\n")
    md.append("IQI = sqrt(mean R(E)²) over the whole ensemble, PQI = sqrt(mean (R(E)² + S(E)²)) "
              "over the chaotic sub-ensemble, R = |R_sim/R_pred − 1|, S = sd/R_pred (paper eqs. "
              "implementation/prediction quality index). Regimes are the paper's (arm 2: "
              "2/2.8/5/6, arm 1: 4/4.6/6, scaled with the model's saddle and maximum energies); a "
              "regime is [lower, upper).\n")
    specs = (("iqi-arm2", 2, "saddle", "IQI", "iqi_arm2", "Table implementation quality (arm 2)"),
             ("pqi-arm2-saddle", 2, "saddle", "PQI", "pqi_arm2_saddle",
              "Table prediction quality, saddle criterion, arm 2"),
             ("iqi-arm1", 1, "saddle", "IQI", "iqi_arm1", "IQI of arm 1 (text of Sec. flips of arm 1)"),
             ("pqi-arm1-saddle", 1, "saddle", "PQI", "pqi_arm1_saddle",
              "Table prediction quality, arm 1"),
             ("pqi-arm2-approx", 2, "approx", "PQI", "pqi_arm2_approx",
              "Table prediction quality, approximate saddle criterion, arm 2"),
             ("pqi-arm2-upright", 2, "upright", "PQI", "pqi_arm2_upright",
              "Table prediction quality, upright criterion, arm 2"))
    for name, a, crit, kind, key, title in specs:
        path, header, rows = quality_table(data, out, name, a, crit, kind, PAPER[key])
        md.append("### %s\n\n[CSV](%s)\n\n%s\n" % (title, path, markdown_table(header, rows)))
        md.append(explain_quality(rows, kind, data["main"][a], "%s, arm %d" % (crit, a)))
    path, header, rows = table_rms(data, out)
    md.append("### RMS relative differences of the predicted rates\n\n[CSV](%s)\n\n%s\n" %
              (path, markdown_table(header, rows)))
    md.append("These are deterministic (no statistical error): a difference from the paper comes "
              "from the energy grid the RMS is taken over (the paper does not state it; compare "
              "our two grids) and from the accuracy of the paper's saddle orbits and quadratures. "
              "Both the prediction table and the ensemble's predicted rates come from the same "
              "quantity registry.\n")
    md.append("## Inputs\n\nRead from the run directory `%s`: run.json, predictions.csv, "
              "orbits-arm1.csv, orbits-arm2.csv, orbit-curves-arm1.csv, orbit-curves-arm2.csv, %s; "
              "residence times from %s; per-trajectory rates from %s. The report's own checks: "
              "the approximate curve's slope from the saddle's centre mode, dF/dE = T by "
              "quadrature, the curve flux through the saddle orbit against 2 F.\n" %
              (data["run_dir"], ", ".join("ensemble-%s.json" % e["name"] for e in data["ensembles"]),
               ", ".join(os.path.relpath(v[2], data["run_dir"]) for v in data["residence"].values()),
               os.path.relpath(data["histogram"][3], data["run_dir"]))
              + (" Single trajectories: %s." % ", ".join(
                  os.path.relpath(t["path"], data["run_dir"]) for t in data["trajectories"].values())
                 if data["trajectories"] else "")
              + (" Other pendulums: %s." % ", ".join(data.get("other_run_dirs") or [])
                 if data.get("other_run_dirs") else ""))
    finish_rendering()
    md.append("\n---\nReport generated in %.1f s.\n" % (time.time() - t0))
    write_text(os.path.join(out, "README.md"), "\n".join(md))


def main(argv=None):
    p = argparse.ArgumentParser(description="Writes the reproduction report (Markdown, PNG and SVG "
                                "figures, CSV tables) from a scene's run directory.")
    p.add_argument("--run-dir", required=True, help="the scene's output directory")
    p.add_argument("--out", required=True, help="the report directory (created)")
    p.add_argument("--other-run-dir", action="append", default=[],
                   help="another scene's output directory (another pendulum) to draw as well; "
                        "repeatable; a missing one is noted in the report")
    p.add_argument("--allow-dirty", action="store_true",
                   default=os.environ.get("FLIPFLUX_REPORT_ALLOW_DIRTY") == "1",
                   help="generate the report into a git work tree with uncommitted changes (it "
                        "then says so); default: refused. Also FLIPFLUX_REPORT_ALLOW_DIRTY=1")
    p.add_argument("--jobs", type=int, default=0,
                   help="processes that draw the figures (default: the processors this "
                        "process may run on, at most 4; 1: this process alone)")
    args = p.parse_args(argv)
    if args.jobs < 0:
        p.error("--jobs %d: must be 0 (automatic) or a positive count" % args.jobs)
    # each process builds the whole report (~15 % of the serial time) and draws its share: more
    # than four gain little by default
    jobs = args.jobs or min(4, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity")
                            else os.cpu_count() or 1)
    try:
        source = source_state(args.out, [args.run_dir] + args.other_run_dir, args.allow_dirty)
        data = load_inputs(args.run_dir)
        data["source"] = source
        data["other_run_dirs"] = args.other_run_dir
        data["other_runs"] = {d: load_other_run(d) for d in args.other_run_dir}
        start_rendering(jobs)
        try:
            build_report(data, args.out)
        except BaseException as e:
            if not _writes():  # a worker: a bad input is reported by this process
                if not isinstance(e, InputError):
                    traceback.print_exc()
                os._exit(1)
            raise
    except InputError as e:
        for line in str(e).splitlines():
            sys.stderr.write("make_report.py: error: %s\n" % line)
        return 2
    except RenderError as e:
        sys.stderr.write("make_report.py: error: %s\n" % e)
        return 1
    finally:
        if _writes():
            for pid in _workers:
                os.waitpid(pid, 0)
    print("make_report.py: wrote %s" % os.path.join(args.out, "README.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
