#!/usr/bin/env python3
"""The reproduction report: every figure and table of the paper regenerated from a scene's run
directory and compared with the paper's values.

    make_report.py --run-dir OUT --out REPORT_DIR

Inputs (written by `flipflux run SCENE` into the scene's output directory OUT):
    run.json                       scene, scene_file, precision, git_commit, seconds, model
    predictions.csv                quantity,arm,energy,value,error_estimate,method
    orbits-arm<a>.csv              energy,period,action,flux,curve_flux,... (a = 1, 2)
    orbit-curves-arm<a>.csv        energy,theta1,theta2 (the saddle orbits' curves)
    ensemble-<name>.json           the JSON of `flipflux simulate` (one per [[ensemble]])
    ensemble-<name>/               the CSVs of `flipflux simulate --csv-dir`
The report needs an arm-2 ensemble with the upright, approx and saddle criteria, an arm-1 ensemble
with the saddle criterion, residence times of arm 2 (upright and saddle) at E = 5 and per-trajectory
rates of arm 2 (saddle) at E = 5.3 (energies scaled with the model: see `special_energies`).

The report draws; flipflux computes. Every statistic in it comes from the C++ results: the quality
indices with their bootstrap errors, noise floors and reference-length PQI, chi^2 and worst z over
the energies, paired criterion differences, residence-time statistics, RMS differences of the
predicted rates (ensemble JSON; run.json for the prediction grid). What the report computes itself
is the verdict against the paper's published numbers (`compare`, with the paper's N and T) and two
independent consistency checks of the inputs (dF/dE = T by quadrature, the approximate curve's
slope from the saddle's centre mode).

Outputs (REPORT_DIR): README.md (the report), figures/<name>.png and .svg, tables/<name>.csv.
Every file is written to a temporary name and renamed. A missing or malformed input is a one-line
error per problem on stderr and exit status 2; nothing is written then.

Only the standard library, numpy and matplotlib (Debian's python3-matplotlib) are used.
"""
import argparse
import csv
import glob
import importlib.util
import io
import json
import math
import os
import sys
import time

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


class InputError(Exception):
    """A missing or malformed input: one line per problem."""


# ---- atomic output ------------------------------------------------------------------------------

def write_text(path, text):
    tmp = "%s.tmp%d" % (path, os.getpid())
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def save_figure(fig, report_dir, name):
    """Writes figures/<name>.png and .svg atomically; returns the relative PNG and SVG paths."""
    paths = []
    for ext in ("png", "svg"):
        rel = "figures/%s.%s" % (name, ext)
        path = os.path.join(report_dir, rel)
        tmp = "%s.tmp%d" % (path, os.getpid())
        fig.savefig(tmp, format=ext, dpi=120, bbox_inches="tight",
                    metadata={"Date": None} if ext == "svg" else None)
        os.replace(tmp, path)
        paths.append(rel)
    plt.close(fig)
    return paths


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
        rows.append((en["energy"], num(c.get("predicted_rate")), num(s.get("mean_rate")),
                     num(s.get("std")), num(s.get("standard_error")), float(n),
                     num(s.get("z_score"))))
    a = np.array(rows, dtype=float).reshape(-1, 7)
    order = np.argsort(a[:, 0])
    a = a[order]
    return {"energy": a[:, 0], "predicted": a[:, 1], "mean": a[:, 2], "std": a[:, 3],
            "se": a[:, 4], "n": a[:, 5], "z": a[:, 6]}


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
        data["residence"] = {}
        for c in ("upright", "saddle"):
            for e in arm2:
                f = find_at_energy(energy_label_files(e["csv_dir"], "residence_E", "_%s.csv" % c),
                                   e_res)
                if f:
                    data["residence"][c] = (f, e)
                    break
            else:
                problems.append("%s: no ensemble-*/residence_E%g_%s.csv (arm 2, residence_times "
                                "= true at E = %g)" % (run_dir, e_res, c, e_res))
        data["histogram"] = None
        for e in arm2:
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
    if problems:
        raise InputError("\n".join(problems))
    return data


# ---- statistics ---------------------------------------------------------------------------------

def regimes(model, a):
    es, em = model["saddle"][a], model["maximum"]
    d = em - es
    if a == 2:
        return [("full", es, em), ("low", es, es + 0.2 * d), ("central", es + 0.2 * d, es + 0.75 * d),
                ("high", es + 0.75 * d, em)]
    return [("full", es, em), ("low", es, es + 0.3 * d), ("high", es + 0.3 * d, em)]


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


def compare(ours, sd_ours, paper, ensemble, kind):
    """(difference in sigma, verdict). The paper's own statistical error is estimated by scaling
    ours to its ensemble: IQI error ~ 1/sqrt(N T), PQI error ~ 1/sqrt(N)."""
    n, t = ensemble["trajectories"], ensemble["time"]
    scale = math.sqrt(n * t / (PAPER["N"] * PAPER["T"])) if kind == "IQI" else \
        math.sqrt(n / PAPER["N"])
    sigma = math.sqrt(sd_ours ** 2 + (sd_ours * scale) ** 2)
    z = (ours - paper) / sigma if sigma > 0 else float("inf")
    return z, ("agrees (%.1fσ)" % z) if abs(z) <= 2 else ("**differs (%.1fσ)**" % z)


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
    axes[2].errorbar(s["energy"], 100 * rel, yerr=100 * s["se"] / s["predicted"], fmt="o", ms=3,
                     capsize=2, color="k")
    axes[2].axhline(0, color=COLORS["saddle"])
    if subset == "all" and a == 2:
        axes[2].axhspan(-1, 1, color="0.85", zorder=0, label="the paper: 'at the 1 % level'")
        axes[2].legend(fontsize=7)
    axes[2].set(xlabel=units(data["model"])["E"], ylabel="R_sim / R_pred − 1 [%]",
                title="relative deviation ± SE")
    fig.suptitle("Saddle-orbit criterion, arm %d, %s trajectories (N = %d, T = %g)" %
                 (a, subset, ens["trajectories"], ens["time"]))
    g = ((ens.get("agreement") or {}).get("saddle") or {}).get(
        "chaotic_trajectories" if subset == "chaotic" else "all_trajectories") or {}
    stats = {"max_rel": 100 * num(g.get("max_relative_deviation")), "chi2": num(g.get("chi2")),
             "dof": int(g.get("energies", 0)), "worst_z": num(g.get("worst_z"))}
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
                                 for reg, _, _ in regimes(data["model"], a)):
        subset = "all_trajectories"  # no chaos indicator: the whole ensemble
    entries = {reg: json_quality(ens, criterion, subset, reg)
               for reg, _, _ in regimes(data["model"], a)}
    reference = [q["reference"] for q in entries.values() if q and "reference" in q]
    rescale = kind == "PQI" and bool(reference) and \
        abs(float(reference[0]["time"]) - ens["time"]) > 1e-12 * ens["time"]
    # the IQI is the RMS of R(E) by definition: its table does not repeat it as a column
    rms_r = kind != "IQI"
    header = ["regime", "energies", "%s [%%]" % kind, "± (bootstrap)", "paper [%]", "comparison",
              "noise floor [%]"] + (["RMS R(E) [%]"] if rms_r else []) + ["RMS S(E) [%]"]
    if rescale:
        header.append("PQI with S rescaled to T = %s [%%]" % reference[0]["time"])
    rows = []
    for reg, lo, hi in regimes(data["model"], a):
        if reg not in paper_values:
            continue
        q = entries[reg]
        label = REGIME_LABELS[a][reg] if is_egalitarian(data["model"]) else \
            "%s (%.4g ≤ E < %.4g)" % (reg, lo, hi)
        if q is None:
            rows.append([label, 0, "—", "—", paper_values[reg], "no energies", ""] +
                        ([""] if rms_r else []) + [""] + (["—"] if rescale else []))
            continue
        ours, sd = 100 * num(q[kind]), 100 * num(q[kind + "_sd"])
        if rescale:
            # S = sd / R_pred of time averages falls as 1/sqrt(T) for mixing trajectories: compare
            # the paper's value with flipflux's estimate at the paper's T (marked as such)
            ref = q["reference"]
            z, verdict = compare(100 * num(ref["PQI"]), 100 * num(ref["PQI_sd"]),
                                 paper_values[reg], ens, kind)
            verdict = "T-rescaled: " + verdict
        else:
            z, verdict = compare(ours, sd, paper_values[reg], ens, kind)
        rows.append([label, q["energies"], "%.2f" % ours, "%.2f" % sd, "%.2f" % paper_values[reg],
                     verdict, "%.2f" % (100 * num(q["noise_floor"]))] +
                    (["%.2f" % (100 * num(q["IQI"]))] if rms_r else []) +
                    ["%.2f" % (100 * num(q["rms_S"]))] +
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
                   "%s chaotic mean" % c, "%s chaotic sd" % c, "%s z" % c]
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
                    "%.6g" % s["std"][i], "%.17g" % cm, "%.6g" % csd, "%.3f" % z]
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
    if not bad:
        return "All %s values of %s agree with the paper's within 2σ of the combined statistical " \
               "error (ours by bootstrap, the paper's scaled from ours to N = %d, T = %d).\n" % \
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


def build_report(data, out):
    t0 = time.time()
    for sub in ("", "figures", "tables"):
        os.makedirs(os.path.join(out, sub), exist_ok=True)
    run, model = data["run"], data["model"]
    md = []
    md.append("# Reproduction of the paper's figures and tables\n")
    md.append("Generated by `tools/report/make_report.py` from the run directory of scene "
              "**%s** (`%s`), commit `%s`, precision %s; the run took **%.1f s** of wall time.\n"
              % (run.get("scene", "?"), run.get("scene_file", "?"), run.get("git_commit", "?"),
                 run.get("precision", "?"), float(run.get("seconds", float("nan")))))
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
    md.append("Statistical errors: ± values are bootstrap standard deviations over our ensemble; "
              "a value 'agrees' with the paper's when within 2σ of the combined error (the paper's "
              "own error estimated by scaling ours to N = 1000, T = 10000). Numbers are never "
              "tuned to match.\n")

    # Configuration space
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
                        "coloured by energy."))

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
        md.append("Largest |R_sim/R_pred − 1| = %.2f %%; Σz² = %.1f over %d energies (≈ %d "
                  "expected from statistics alone%s); worst z = %.2f.%s\n" %
                  (st["max_rel"], st["chi2"], st["dof"], st["dof"],
                   "" if subset == "all" else "; the chaotic sub-ensemble is not the "
                   "microcanonical one, so a bias is expected", st["worst_z"],
                   " The paper: 'the relative difference remains at the 1 % level'." if
                   (a, subset) == (2, "all") else ""))
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
               os.path.relpath(data["histogram"][3], data["run_dir"])))
    md.append("\n---\nReport generated in %.1f s.\n" % (time.time() - t0))
    write_text(os.path.join(out, "README.md"), "\n".join(md))


def main(argv=None):
    p = argparse.ArgumentParser(description="Writes the reproduction report (Markdown, PNG and SVG "
                                "figures, CSV tables) from a scene's run directory.")
    p.add_argument("--run-dir", required=True, help="the scene's output directory")
    p.add_argument("--out", required=True, help="the report directory (created)")
    args = p.parse_args(argv)
    try:
        data = load_inputs(args.run_dir)
        build_report(data, args.out)
    except InputError as e:
        for line in str(e).splitlines():
            sys.stderr.write("make_report.py: error: %s\n" % line)
        return 2
    print("make_report.py: wrote %s" % os.path.join(args.out, "README.md"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
