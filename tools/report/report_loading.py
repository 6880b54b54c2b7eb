"""The report's inputs (tools/report/make_report.py): the run directory loaded and checked (model,
predictions, orbits, ensembles, trajectories, another run), and what is looked up in it (energies,
regimes and quality entries from the JSON, the paper's verdict by `compare`, the two independent
consistency checks' inputs)."""
import csv
import glob
import io
import math
import os
import time

import numpy as np

import statistics_sections
from report_common import (
    CRITERIA, InputError, PAPER, _KEPT, as_written, columns, num, read_csv, read_json)


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


def critical_points(model):
    es1, es2, em = model["saddle"][1], model["saddle"][2], model["maximum"]
    return [((0.0, 0.0), 0.0, "minimum"), ((0.0, math.pi), es2, "index-one saddle"),
            ((math.pi, 0.0), es1, "index-one saddle"), ((math.pi, math.pi), em, "maximum")]


def orbit_curve(data, a, energy):
    c = data["curves"][a]
    sel = np.abs(c["energy"] - energy) < 1e-9
    return c["theta1"][sel], c["theta2"][sel]


def nearest(values, target):
    values = np.unique(values)
    return float(values[np.argmin(np.abs(values - target))])


def flip_window(a):
    """Axis ranges (θ₁, θ₂) around the flip angle's upright position: arm 2 θ₂ ∈ [0, 2π],
    arm 1 θ₁ ∈ [0, 2π], the other angle in [−π, π] (one orientation for every figure)."""
    return ((-math.pi, math.pi), (0, 2 * math.pi)) if a == 2 else \
        ((0, 2 * math.pi), (-math.pi, math.pi))


def curve_in_window(th1, th2, a):
    """A curve's angles with the flip angle reduced to [0, 2π) (it stays near π)."""
    return (th1, np.mod(th2, 2 * math.pi)) if a == 2 else (np.mod(th1, 2 * math.pi), th2)


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


def lengths(model):
    p = model["parameters"]
    return float(p.get("L1", 1)), float(p.get("L2", 1))


def masses_xy(model, th1, th2):
    """Positions of the joint (mass A) and the tip (mass B), the pivot at the origin, y up."""
    l1, l2 = lengths(model)
    x1, y1 = l1 * np.sin(th1), -l1 * np.cos(th1)
    return x1, y1, x1 + l2 * np.sin(th2), y1 - l2 * np.cos(th2)


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


def is_egalitarian(model):
    c = model["coefficients"]
    return all(abs(c[k] - v) < 1e-12 for k, v in (("A", 2), ("B", 1), ("C", 1), ("alpha", 2),
                                                  ("beta", 1)))


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
