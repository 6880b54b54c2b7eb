#!/usr/bin/env python3
"""Checks of the reproduction report (tools/report/make_report.py).

    test_report.py                                   self-contained: a synthetic run directory
    test_report.py --workers                         the synthetic run's figures drawn by two
                                                     processes equal the serial run's, byte for
                                                     byte (a second report: `verify` runs it)
    test_report.py --flipflux BIN --scene SCENE      runs `BIN run SCENE` in a temporary working
                                                     directory, then checks the scene's report
    test_report.py --report-dir DIR                  checks an existing report

The self-contained mode writes a schema-conformant run directory (run.json, predictions.csv,
orbits, orbit curves, ensemble JSONs and CSVs) with known values, runs the generator, and asserts
that every figure (PNG and SVG) and table is written, that the tables carry the values the
synthetic data implies (IQI from known deviations, RMS differences from known rates), and that a
missing or malformed input is a named error with exit status 2 and no report. Exit status 0 when
every check passes; prints 'N passed, N failed'.
"""
import argparse
import csv
import filecmp
import glob
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(os.path.dirname(HERE))
GENERATOR = os.path.join(REPO, "tools", "report", "make_report.py")

# Every figure and table of the paper the report must contain (egalitarian pendulum: the residence
# times at E = 5 and the rate histogram at E = 5.3).
FIGURES = ["potential", "allowed-region", "criteria", "orbit-family", "period-action-arm2",
           "period-action-arm1", "fluxes", "rates-arm2-all", "rates-arm2-chaotic",
           "rates-arm1-chaotic", "rates-arm1-all", "rates-criteria", "residence-E5",
           "rate-histogram-E5.3", "approx-vs-saddle", "schematic", "energy-regimes",
           "keyframes-E2.5", "multipliers", "residence-gap", "chaotic-fraction",
           "flip-statistics-arm2", "flip-statistics-arm1"]
# drawn from the scene's [[trajectory]] tables and the sensitivity ensembles (paper-quick.toml has
# them; the synthetic run too)
OPTIONAL_FIGURES = ["trajectory-typical", "trajectory-recrossing", "sensitivity-tolerance",
                    "sensitivity-threshold"]
TABLES = ["critical-points", "iqi-arm2", "pqi-arm2-saddle", "iqi-arm1", "pqi-arm1-saddle",
          "pqi-arm2-approx", "pqi-arm2-upright", "rms-differences", "rates-arm2", "rates-arm1"]

RESULTS = {"passed": 0, "failed": 0}


def check(condition, what):
    if condition:
        RESULTS["passed"] += 1
    else:
        RESULTS["failed"] += 1
        print("FAILED: " + what)


# ---- the synthetic run directory ----------------------------------------------------------------

def grid(lo, hi, step):
    return [round(lo + i * step, 10) for i in range(int(round((hi - lo) / step)) + 1)]


def rates(e):
    """Synthetic predicted rates: saddle, approx = saddle (1 + 0.002 (E - 2)), upright = 1.1 saddle."""
    s = 0.05 * (e - 2)
    return {"saddle": s, "approx": s * (1 + 0.002 * (e - 2)), "upright": 1.1 * s}


def write_csv(path, header, rows):
    with open(path, "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(header)
        w.writerows(rows)


def replicate_block(p, m, n, R, chaotic_mean, chaotic_n, all_se, chaotic_se):
    """flipflux's replicate block of a criterion: replicate k's mean m (1 + 0.01 (k - (R-1)/2))
    (their average is m), chaotic means all chaotic_mean; the jackknife errors as given."""
    def part(mean, count, se, spread):
        return {"standard_error": repr(se), "z_score": repr((mean - p) / se),
                "error_ratio": "1.25", "trajectories": [count // R] * R,
                "means": [repr(mean * (1 + spread * (k - (R - 1) / 2))) for k in range(R)]}
    return {"count": R, "all_trajectories": part(m, n, all_se, 0.01),
            "chaotic_trajectories": part(chaotic_mean, chaotic_n, chaotic_se, 0.0)}


def flip_counts(t):
    """A Poisson-like flip_counts block: Fano 1 in every window, CV^2 1, an exponential tail."""
    windows = [t / 10 ** k for k in range(5) if t / 10 ** k >= 1]
    return {"fano": [{"window": repr(w), "windows": 10, "mean_count": "1", "fano": "1.5",
                      "windows_chaotic": 9, "mean_count_chaotic": "1", "fano_chaotic": "1.2"}
                     for w in windows],
            "inter_flip_cv2": "1", "inter_flip_cv2_chaotic": "0.8",
            "inter_flip_survival": [[repr(0.1 * 2 ** j), repr(math.exp(-0.1 * 2 ** j)),
                                     repr(math.exp(-0.1 * 2 ** j))] for j in range(24)]}


def ensemble_json(arm, energies, criteria, deviation, n, t, seed=1, method="dop853",
                  rtol="1e-10", atol="1e-10", threshold="0.050000000000000003", replicates=5,
                  census=None):
    """Simulated mean = predicted (1 + deviation); sd = 0.1 predicted (chaotic: 0.05); R
    replicates (0: none) with jackknife errors 1.25x the per-trajectory ones. census (f_r, r_r):
    a census's replicate blocks with regular fraction f_r and regular rate r_r x predicted."""
    out = {"command": "simulate", "arm": str(arm), "trajectories": n, "first_index": 0,
           "time": str(t), "seed": seed, "method": method, "rtol": rtol, "atol": atol,
           "chaos": {"indicator": "finite-time maximal Lyapunov exponent",
                     "threshold": threshold},
           "energies": [], "quality": {}, "regimes": []}
    if replicates:
        out["replicates"] = {"count": replicates, "trajectories_each": n // replicates}
    for e in energies:
        crit = {}
        for c in criteria:
            p = rates(e)[c] if arm == 2 else 0.04 * (e - 4)
            m, sd = p * (1 + deviation), 0.1 * p
            crit[c] = {"predicted_rate": repr(p), "prediction_method": "synthetic",
                       "mean_rate": repr(m), "std": repr(sd),
                       "standard_error": repr(sd / math.sqrt(n)),
                       "z_score": repr(deviation * math.sqrt(n) / 0.1), "max_rate": repr(1.5 * m),
                       "flips": int(m * n * t), "chaotic_fraction": "0.9",
                       "chaotic": {"trajectories": int(0.9 * n), "mean_rate": repr(p),
                                   "std": repr(0.05 * p),
                                   "standard_error": repr(0.05 * p / math.sqrt(0.9 * n)),
                                   "z_score": "0"},
                       "flip_counts": flip_counts(t)}
            if census:
                f_r, r_r = census
                rc = (1 - f_r * r_r) / (1 - f_r) * p  # so that the mean is p
                crit[c]["replicates"] = replicate_block(p, p, n, replicates, rc,
                                                        int(round((1 - f_r) * n)), 0.01 * p,
                                                        0.001 * p)
            elif replicates:
                crit[c]["replicates"] = replicate_block(
                    p, m, n, replicates, p, int(0.9 * n), 1.25 * sd / math.sqrt(n),
                    1.25 * 0.05 * p / math.sqrt(0.9 * n))
        paired = [{"criteria": [c, d], "mean": repr(rates(e)[c] - rates(e)[d]), "std": "0.001",
                   "standard_error": repr(0.001 / math.sqrt(n))}
                  for i, c in enumerate(criteria) for d in criteria[i + 1:]] if arm == 2 else []
        out["energies"].append({"energy": "%.10g" % e, "seconds": 0.1, "criteria": crit,
                                "paired_differences": paired})
    # what flipflux computes over the energies: z = deviation sqrt(n) / 0.1 at every energy
    z = deviation * math.sqrt(n) / 0.1
    out["agreement"] = {c: {"all_trajectories": {"energies": len(energies),
                                                 "chi2": repr(len(energies) * z * z),
                                                 "worst_z": repr(z),
                                                 "max_relative_deviation": repr(abs(deviation))},
                            "chaotic_trajectories": {"energies": len(energies), "chi2": "0",
                                                     "worst_z": "0",
                                                     "max_relative_deviation": "0"}}
                        for c in criteria}
    if replicates:
        assert replicates == 5, "the synthetic error_ratio_range below is R = 5's"
        for c in criteria:
            out["agreement"][c]["all_trajectories"]["replicates"] = {
                "energies": len(energies), "chi2": repr(len(energies) * (z / 1.25) ** 2),
                "expected_chi2": repr(len(energies) * (replicates - 1) / (replicates - 3)),
                "worst_z": repr(z / 1.25), "chi2_of_replicates": ["1"] * replicates,
                "max_error_ratio": "1.25", "min_error_ratio": "1.25", "error_mismatches": 0,
                # chi^2 quantiles of R - 1 = 4 degrees of freedom (mpmath), the run's for R = 5
                "error_ratio_range": ["0.12641404640299837", "2.2359201123501488"],
                "degrees_of_freedom": replicates - 1}
            out["agreement"][c]["chaotic_trajectories"]["replicates"] = dict(
                out["agreement"][c]["all_trajectories"]["replicates"])
    out["prediction_differences"] = [
        {"criteria": [c, d], "energies": len(energies),
         "rms_relative": repr(math.sqrt(sum((rates(e)[c] / rates(e)[d] - 1) ** 2
                                            for e in energies) / len(energies)))}
        for i, c in enumerate(criteria) for d in criteria[i + 1:]] if arm == 2 else []
    # flipflux's quality indices as the C++ writes them (the report draws them, computes none):
    # all trajectories R = deviation, S = 0.1; chaotic R = 0, S = 0.05
    names = ("full", "low", "central", "high") if arm == 2 else ("full", "low", "high")
    def table(r, spread):
        rows = [{"regime": g, "energies": len(energies), "IQI": repr(abs(r)),
                 "PQI": repr(math.sqrt(r * r + spread * spread)), "IQI_sd": "0.001",
                 "PQI_sd": "0.002", "noise_floor": repr(spread / math.sqrt(n)),
                 "rms_S": repr(spread)} for g in names]
        if replicates:
            for q in rows:
                q["replicates"] = {"IQI_se": "0.002", "PQI_se": "0.003",
                                   "IQI": [repr(abs(r))] * replicates,
                                   "PQI": [repr(math.sqrt(r * r + spread * spread))] * replicates}
        return rows
    for c in criteria:
        out["quality"][c] = {"all_trajectories": table(deviation, 0.1),
                             "chaotic_trajectories": table(0.0, 0.05)}
    # the regimes as the C++ writes them (the paper's fractions of E_max - E_s above E_s)
    es, em = (2.0, 6.0) if arm == 2 else (4.0, 6.0)
    cuts = (0.2, 0.75) if arm == 2 else (0.3,)
    bounds = [es] + [es + f * (em - es) for f in cuts] + [em]
    out["regimes"] = [{"regime": "full", "lower": repr(es), "upper": repr(em)}] + [
        {"regime": g, "lower": repr(lo), "upper": repr(hi)}
        for g, lo, hi in zip(names[1:], bounds, bounds[1:])]
    return out


def write_ensemble(run_dir, name, data, csv_files):
    with open(os.path.join(run_dir, "ensemble-%s.json" % name), "w") as f:
        json.dump(data, f, indent=1)
    d = os.path.join(run_dir, "ensemble-" + name)
    os.makedirs(d, exist_ok=True)
    for fname, (header, rows) in csv_files.items():
        write_csv(os.path.join(d, fname), header, rows)


def make_synthetic_run(run_dir):
    os.makedirs(run_dir, exist_ok=True)
    run = {"scene": "synthetic", "scene_file": "tests/report/test_report.py",
           "precision": "double", "git_commit": "0" * 40, "seconds": 1.5,
           "model": {"parameters": {k: "1" for k in ("m1", "m2", "L1", "L2", "a1", "a2", "g")},
                     "coefficients": {"A": "2", "B": "1", "C": "1", "alpha": "2", "beta": "1",
                                      "D0": "1"},
                     "saddle_energy": {"1": "4", "2": "2"}, "maximum_energy": "6",
                     "approximate_curve": {"1": {"offset": "3.14159", "slope": "0.29289321881345"},
                                           "2": {"offset": "3.14159", "slope": "0.58578643762690"}}}}
    run["model"]["parameters"].update({"I1": "0", "I2": "0"})
    run["trajectories"] = [{"name": "typical", "energy": "3.6"},
                           {"name": "recrossing", "energy": "2.5"}]
    # what the scene computes from its predictions (arm 2, 2 < E < 6)
    inside = [e for e in grid(2.05, 5.95, 0.1) if 2 < e < 6]
    run["predictions"] = {"file": "predictions.csv", "skipped": [], "rate_differences": [
        {"arm": "2", "criteria": [c, "saddle"], "energies": len(inside),
         "rms_relative": repr(math.sqrt(sum((rates(e)[c] / rates(e)["saddle"] - 1) ** 2
                                            for e in inside) / len(inside)))}
        for c in ("upright", "approx")]}
    # the scene's marks: the report takes the residence times and the rate histogram from the
    # ensembles marked for them, although arm2 has a residence_E5 file too (written below)
    run["ensembles"] = [{"name": n, "file": "ensemble-%s.json" % n,
                         "residence_times": n == "residence-E5", "histogram": n == "arm2"}
                        for n in ("arm2", "arm1", "residence-E5")]
    run["ensembles"] += [{"name": "census-arm2", "file": "ensemble-census-arm2.json",
                          "census_of": "arm2"},
                         {"name": "census-check", "file": "ensemble-census-check.json",
                          "classification_check_of": "census-arm2"}]
    with open(os.path.join(run_dir, "run.json"), "w") as f:
        json.dump(run, f, indent=1)
    rows = []
    for e in grid(2.05, 5.95, 0.1):
        rows.append(["omega", "", e, repr(10 * e * e), "1e-15", "synthetic"])
        for a in (1, 2):
            if a == 1 and e <= 4:
                continue
            r = rates(e) if a == 2 else {c: 0.04 * (e - 4) for c in ("saddle", "approx", "upright")}
            for c in ("upright", "approx", "saddle"):
                rows.append(["rate-" + c, a, e, repr(r[c]), "1e-15", "synthetic"])
                rows.append(["flux-" + c, a, e, repr(r[c] * 10 * e * e), "1e-15", "synthetic"])
    write_csv(os.path.join(run_dir, "predictions.csv"),
              ["quantity", "arm", "energy", "value", "error_estimate", "method"], rows)
    for a, lo in ((2, 2.1), (1, 4.1)):
        es = 2.0 if a == 2 else 4.0
        orbits, curves = [], []
        for e in grid(lo, 5.9, 0.2):
            period = 5 + 0.2 * e  # F = 5 (E - Es) + 0.1 (E^2 - Es^2): dF/dE = T exactly
            action = 5 * (e - es) + 0.1 * (e * e - es * es)
            orbits.append([e, repr(period), repr(action), repr(2 * action), "100", "102", "0.2"])
            for k in range(33):
                s = -1 + 2 * k / 32
                curves.append([e, repr(s), repr(math.pi + 0.5858 * math.sin(s))] if a == 2 else
                              [e, repr(math.pi + 0.2929 * math.sin(s)), repr(s)])
        write_csv(os.path.join(run_dir, "orbits-arm%d.csv" % a),
                  ["energy", "period", "action", "flux", "multiplier", "stability_index",
                   "period_derivative"], orbits)
        write_csv(os.path.join(run_dir, "orbit-curves-arm%d.csv" % a),
                  ["energy", "theta1", "theta2"], curves)
    e2 = [2.5, 3.5, 5.3]
    traj = (["index", "lyapunov", "chaotic", "rate_upright", "rate_approx", "rate_saddle"],
            [[i, "0.3", int(i % 10 != 0), repr(0.18 + 0.001 * i), repr(0.165 + 0.001 * i),
              repr(0.165 + 0.001 * (i % 37))] for i in range(50)])
    decoy = {"residence_E5_%s.csv" % c: (["trajectory", "crossing_time", "residence_time"],
                                         [[0, i, "0.5"] for i in range(7)])
             for c in ("upright", "saddle")}
    write_ensemble(run_dir, "arm2", ensemble_json(2, e2, ("upright", "approx", "saddle"), 0.01,
                                                  50, 200),
                   dict({"trajectories_E%g.csv" % e: traj for e in e2}, **decoy))
    write_ensemble(run_dir, "arm1", ensemble_json(1, [4.3, 5.3], ("saddle",), 0.02, 50, 200), {})
    res = {}
    for c, gap in (("upright", 0.0), ("saddle", 1.9)):
        res["residence_E5_%s.csv" % c] = (["trajectory", "crossing_time", "residence_time"],
                                          [[i % 20, i, repr(gap + 0.01 * (i % 500))]
                                           for i in range(2000)])
    write_ensemble(run_dir, "residence-E5", ensemble_json(2, [5], ("upright", "saddle"), 0.0,
                                                          20, 200, seed=3), res)
    # the island census: regular fraction 10 %, regular rate 2 R, so R_c = 8/9 R (-11.111 %); its
    # check re-integrates 20 of its trajectories with one changing class per energy
    census_traj = (["index", "lyapunov", "chaotic"],
                   [[i, "0.3" if i % 10 else "0.001", int(i % 10 != 0)] for i in range(100)])
    check_traj = (["index", "lyapunov", "chaotic"],
                  [[i, "0.3" if i % 10 and i != 3 else "0.001", int(i % 10 != 0 and i != 3)]
                   for i in range(20)])
    write_ensemble(run_dir, "census-arm2",
                   ensemble_json(2, [2.5, 3.5], ("saddle",), 0.0, 100, 200, seed=1001,
                                 census=(0.1, 2.0)),
                   {"trajectories_E%g.csv" % e: census_traj for e in (2.5, 3.5)})
    write_ensemble(run_dir, "census-check",
                   ensemble_json(2, [2.5, 3.5], ("saddle",), 0.0, 20, 1000, seed=1001,
                                 replicates=0),
                   {"trajectories_E%g.csv" % e: check_traj for e in (2.5, 3.5)})
    # the sensitivity studies: the main arm-2 ensemble's seed, ode45's tolerances (rates 5 % high)
    # and another chaos threshold
    write_ensemble(run_dir, "tolerance-ode45",
                   ensemble_json(2, [3.5, 5.3], ("saddle",), 0.05, 50, 200, method="dopri5",
                                 rtol="0.001", atol="9.9999999999999995e-07"), {})
    write_ensemble(run_dir, "chaos-threshold-0.05",
                   ensemble_json(2, e2, ("saddle",), 0.01, 50, 200), {})
    write_ensemble(run_dir, "chaos-threshold-0.2",
                   ensemble_json(2, e2, ("saddle",), 0.01, 50, 200,
                                 threshold="0.20000000000000001"), {})
    # single trajectories: arm 2 at E = 3.6 turning twice (two upright and saddle flips), and one
    # crossing the upright line at t = 0.5 and back at t = 1.5 (no saddle event)
    states = [[repr(0.1 * k), repr(0.3 * math.sin(0.1 * k)), repr(2.5 + 0.2 * k), "0", "0", "0"]
              for k in range(101)]
    write_csv(os.path.join(run_dir, "trajectory-typical.csv"),
              ["t", "theta1", "theta2", "l1", "l2", "energy_drift"], states)
    write_csv(os.path.join(run_dir, "trajectory-typical-events.csv"),
              ["time", "arm", "criterion", "direction"],
              [["3.2079632679489662", 2, "saddle", 1], ["3.2079632679489662", 2, "upright", 1],
               ["9.4911485751285526", 2, "saddle", 1], ["9.4911485751285526", 2, "upright", 1]])
    states = [[repr(0.01 * k), "0.5", repr(math.pi - 0.1 + 0.2 * math.sin(math.pi * 0.01 * k / 2)),
               "0", "0", "0"] for k in range(251)]
    write_csv(os.path.join(run_dir, "trajectory-recrossing.csv"),
              ["t", "theta1", "theta2", "l1", "l2", "energy_drift"], states)
    write_csv(os.path.join(run_dir, "trajectory-recrossing-events.csv"),
              ["time", "arm", "criterion", "direction"],
              [["0.33", 2, "upright", 1], ["1.67", 2, "upright", -1]])


# ---- checks -------------------------------------------------------------------------------------

def run_generator(run_dir, out, extra=()):
    return subprocess.run([sys.executable, GENERATOR, "--run-dir", run_dir, "--out", out] +
                          list(extra), capture_output=True, text=True)


def read_table(report, name):
    with open(os.path.join(report, "tables", name + ".csv"), newline="") as f:
        return list(csv.reader(f))


def check_report(report, optional=True):
    readme = os.path.join(report, "README.md")
    check(os.path.isfile(readme), "report README.md exists in " + report)
    text = open(readme, encoding="utf-8").read() if os.path.isfile(readme) else ""
    for name in FIGURES + (OPTIONAL_FIGURES if optional else []):
        png = os.path.join(report, "figures", name + ".png")
        svg = os.path.join(report, "figures", name + ".svg")
        ok_png = os.path.isfile(png) and open(png, "rb").read(8) == b"\x89PNG\r\n\x1a\n"
        check(ok_png and os.path.getsize(png) > 5000, "figure %s.png is a PNG" % name)
        ok_svg = os.path.isfile(svg) and "<svg" in open(svg, encoding="utf-8").read(2000)
        check(ok_svg, "figure %s.svg is an SVG" % name)
        check("figures/%s.png" % name in text and "figures/%s.svg" % name in text,
              "README.md shows figure %s" % name)
    for name in TABLES:
        path = os.path.join(report, "tables", name + ".csv")
        check(os.path.isfile(path) and len(read_table(report, name)) >= 2,
              "table %s.csv has rows" % name)
        check("tables/%s.csv" % name in text, "README.md links table %s" % name)
    for word in ("commit", "wall time", "paper"):
        check(word in text, "README.md states the %s" % word)
    leftovers = [f for _, _, files in os.walk(report) for f in files if ".tmp" in f]
    check(not leftovers, "no temporary files left: %s" % leftovers)
    return text


def check_statistics_helpers():
    """The report's Student-t tail and Poisson bound against tabulated values (an independent
    route: the tables, not the code's continued fraction)."""
    sys.path.insert(0, os.path.join(REPO, "tools", "report"))
    import statistics_sections as st
    for t, dof, p in ((2.262157163, 9, 0.05), (3.249835541, 9, 0.01), (1.812461123, 10, 0.10),
                      (12.70620474, 1, 0.05), (1.959963985, 10 ** 7, 0.05)):
        check(abs(st.student_t_two_sided(t, dof) - p) < 1e-6 * p + 1e-9,
              "P(|t_%d| > %g) = %g: %r" % (dof, t, p, st.student_t_two_sided(t, dof)))
    check(abs(st.poisson_upper(0) - 2.995732274) < 1e-9 and
          abs(st.poisson_upper(10) - 17.0) < 0.05,
          "95 %% Poisson upper bounds: %r %r" % (st.poisson_upper(0), st.poisson_upper(10)))


def check_synthetic_values(report):
    """The tables carry the values the synthetic data implies."""
    iqi = {r[0]: r for r in read_table(report, "iqi-arm2")[1:]}
    full = [r for k, r in iqi.items() if k.startswith("full")][0]
    check(abs(float(full[2]) - 1.0) < 1e-9, "IQI arm 2 = 1 %% (simulated means 1 %% high): %s"
          % full[2])
    check(full[4] == "1.05", "IQI arm 2 beside the paper's 1.05: %s" % full[4])
    check(full[3] == "0.20", "its replicate error from the JSON (0.002 = 0.20 %%): %s" % full[3])
    check(full[5].startswith("agrees") or full[5].startswith("**differs"),
          "a verdict from the replicate error: %s" % full[5])
    census = read_table(report, "census-main-census-arm2")[1:]
    check(len(census) == 2 and all(r[8] == "-11.1111" and abs(float(r[3]) - 0.1) < 1e-12
                                   for r in census),
          "census: f_r = 10 %%, R_c = 8/9 R from the census's replicates: %s" % census)
    mis = read_table(report, "misclassification-main-census-check")[1:]
    check([r[1:] for r in mis] == [["20", "2", "3", "0", "1", "5.000"]] * 2,
          "census check: 1 of 20 trajectories changes class per energy: %s" % mis)
    iqi1 = read_table(report, "iqi-arm1")[1]
    check(abs(float(iqi1[2]) - 2.0) < 1e-9, "IQI arm 1 = 2 %%: %s" % iqi1[2])
    pqi = read_table(report, "pqi-arm2-saddle")[1]  # chaotic: mean = predicted, sd = 5 %
    check(abs(float(pqi[2]) - 5.0) < 1e-9, "PQI arm 2 saddle = 5 %%: %s" % pqi[2])
    rms = {r[0]: r for r in read_table(report, "rms-differences")[1:]}
    up = rms["upright vs saddle (theory)"]
    check(abs(float(up[1]) - 10.0) < 1e-9 and abs(float(up[2]) - 10.0) < 1e-9,
          "RMS upright vs saddle = 10 %%: %s" % up[1:3])
    tol = [r for r in read_table(report, "sensitivity-tolerance")[1:] if r[0] == "tolerance-ode45"]
    check([r[6] for r in tol] == ["5.000", "5.000"] and tol[0][1] == "dopri5 rtol 0.001 atol 1e-06",
          "tolerance study: ode45's rates 5 %% high, its tolerances as written: %s" % tol)
    thr = read_table(report, "sensitivity-threshold")[1:]
    check(sorted({r[0] for r in thr}) == ["0.05", "0.2"], "threshold study: 0.05 and 0.2 (as "
          "written, not 0.050000000000000003): %s" % sorted({r[0] for r in thr}))
    text = open(os.path.join(report, "README.md"), encoding="utf-8").read()
    m = re.search(r"Arm 2: \d+ orbits, step [\d.]+\. Max \|F_rec/F − 1\| with the orbits' dT/dE: "
                  r"([\d.e+-]+|nan)", text)
    check("residence times from ensemble-residence-E5/residence_E5_upright.csv, "
          "ensemble-residence-E5/residence_E5_saddle.csv" in text,
          "residence times from the ensemble marked residence_times in run.json")
    check(m is not None and float(m.group(1)) < 1e-13, "dF/dE = T with the orbits' dT/dE: exact "
          "for the synthetic T linear in E (Hermite is exact for cubics): %s" %
          (m.group(1) if m else None))
    check("crosses the upright line 2 times and the saddle orbit 0 times" in text,
          "the recrossing paragraph counts the synthetic events")
    check("arm 2 flips 2 times by the saddle criterion, arm 1 0 times" in text,
          "the typical trajectory's flips are counted")
    cp = read_table(report, "critical-points")
    check([r[1] for r in cp[1:]] == ["0", "2", "4", "6"], "critical energies 0, 2, 4, 6: %s" % cp)


def check_errors(base):
    """A missing or malformed input is a named error, exit status 2, and nothing is written."""
    for victim, mangle, expect in (("orbits-arm1.csv", None, "orbits-arm1.csv"),
                                   ("ensemble-residence-E5.json", None, "residence_E5_saddle"),
                                   ("run.json", "{not json", "malformed JSON"),
                                   ("predictions.csv", "quantity,arm,energy,value\nomega,,x,1\n",
                                    "predictions.csv:2")):
        run_dir = os.path.join(base, "broken-" + victim)
        make_synthetic_run(run_dir)
        if mangle is None:
            os.remove(os.path.join(run_dir, victim))
            if victim.endswith(".json"):
                shutil.rmtree(os.path.join(run_dir, victim[:-5]))
        else:
            with open(os.path.join(run_dir, victim), "w") as f:
                f.write(mangle)
        out = os.path.join(base, "report-" + victim)
        r = run_generator(run_dir, out)
        check(r.returncode == 2, "%s: exit status 2 (got %d)" % (victim, r.returncode))
        check(expect in r.stderr and "error" in r.stderr,
              "%s: the error names '%s': %r" % (victim, expect, r.stderr))
        check(not os.path.exists(os.path.join(out, "README.md")), "%s: no report written" % victim)
    r = run_generator(os.path.join(base, "does-not-exist"), os.path.join(base, "r"))
    check(r.returncode == 2 and "--run-dir" in r.stderr, "missing run dir is named: %r" % r.stderr)


def scene_report_dir(scene, cwd):
    import tomllib
    with open(scene, "rb") as f:
        s = tomllib.load(f)
    return os.path.join(cwd, s["report"]["dir"])


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--flipflux", help="the flipflux executable (with --scene)")
    p.add_argument("--scene", help="a scene with a [report] section, run in a temporary directory")
    p.add_argument("--report-dir", help="check this existing report")
    p.add_argument("--workers", action="store_true",
                   help="only: the synthetic report drawn by --jobs 2 equals the serial one")
    p.add_argument("--keep", action="store_true", help="keep the temporary directory")
    a = p.parse_args()
    if a.workers and (a.scene or a.report_dir):
        p.error("--workers checks the synthetic run: not with --scene or --report-dir")
    base = tempfile.mkdtemp(prefix="flipflux-report-")
    try:
        if a.report_dir:
            check_report(a.report_dir)
        elif a.scene:
            scene = os.path.abspath(a.scene)
            r = subprocess.run([os.path.abspath(a.flipflux), "run", scene], cwd=base,
                               capture_output=True, text=True)
            sys.stdout.write(r.stdout[-3000:])
            sys.stderr.write(r.stderr[-3000:])
            check(r.returncode == 0, "flipflux run %s: exit status %d" % (a.scene, r.returncode))
            check_report(scene_report_dir(scene, base))
        else:
            run_dir, report = os.path.join(base, "run"), os.path.join(base, "report")
            make_synthetic_run(run_dir)
            # another pendulum's run (Appendix C section): the synthetic one again, and a
            # directory that was never run (noted, not an error)
            other = os.path.join(base, "other")
            make_synthetic_run(other)
            # every trajectory of the other run chaotic: its rows with |z| > 3 get the note on
            # unsampled islands
            for path in glob.glob(os.path.join(other, "ensemble-*.json")):
                with open(path, encoding="utf-8") as f:
                    ens = json.load(f)
                for en in ens["energies"]:
                    for c in en["criteria"].values():
                        c["chaotic_fraction"] = "1"
                        # and replicate errors half the per-trajectory ones: z doubles
                        rep = (c.get("replicates") or {}).get("all_trajectories")
                        if rep:
                            rep["standard_error"] = repr(float(c["standard_error"]) / 2)
                            rep["z_score"] = repr(2 * float(c["z_score"]))
                with open(path, "w", encoding="utf-8") as f:
                    json.dump(ens, f)
            others = ["--other-run-dir", other, "--other-run-dir", os.path.join(base, "never")]
            r = run_generator(run_dir, report, ["--jobs", "2"] + others)
            check(r.returncode == 0, "generator exit status 0: %s" % r.stderr)
            if a.workers:
                # the figures drawn by two processes, each its share, are the serial run's, byte
                # for byte (a second full report: half this test's time, so in `verify` only)
                serial = os.path.join(base, "report-serial")
                r = run_generator(run_dir, serial, ["--jobs", "1"] + others)
                check(r.returncode == 0, "serial generator exit status 0: %s" % r.stderr)
                figs = sorted(os.listdir(os.path.join(report, "figures")))
                differ = [f for f in figs if not filecmp.cmp(os.path.join(report, "figures", f),
                                                             os.path.join(serial, "figures", f),
                                                             shallow=False)]
                check(len(figs) > 20 and figs == sorted(os.listdir(os.path.join(serial, "figures")))
                      and not differ, "%d figures drawn by 2 workers equal the serial ones "
                      "(differ: %s)" % (len(figs), differ))
                return finish(base, a.keep)
            check_report(report)
            r = run_generator(run_dir, os.path.join(base, "report-bad-jobs"), ["--jobs", "-1"])
            check(r.returncode == 2 and "--jobs -1" in r.stderr, "--jobs -1 is named: %r" % r.stderr)
            check_synthetic_values(report)
            check_statistics_helpers()
            text = open(os.path.join(report, "README.md"), encoding="utf-8").read()
            check("figures/other-synthetic.png" in text and "largest |R_sim/R_pred − 1| = 5.00 %"
                  in text, "the other pendulum's section: its largest deviation (ode45 rows 5 %)")
            check("Where |z| > 3 with every trajectory chaotic (arm 2 " in text and
                  "Rare islands bias a small ensemble" in text,
                  "the other pendulum's rows with |z| > 3 and no regular trajectory are explained")
            check("`%s`: not run" % os.path.join(base, "never") in text,
                  "a missing other run is noted")
            check_errors(base)
    except BaseException:
        if a.keep:
            print("kept " + base)
        else:
            shutil.rmtree(base, ignore_errors=True)
        raise
    return finish(base, a.keep)


def finish(base, keep):
    """Removes (or keeps) the temporary directory, prints the tally; the exit status."""
    if keep:
        print("kept " + base)
    else:
        shutil.rmtree(base, ignore_errors=True)
    print("%d passed, %d failed" % (RESULTS["passed"], RESULTS["failed"]))
    return 0 if RESULTS["failed"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
