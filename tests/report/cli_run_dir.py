#!/usr/bin/env python3
"""Builds a scene output directory (the run-dir contract of tools/report/make_report.py) from the
single-purpose CLI commands (`flipflux model`, `eval`, `orbit`, `simulate`) instead of
`flipflux run`: an independent stand-in for the scene executor, used to develop the report and to
cross-check the executor's output.

    cli_run_dir.py --flipflux build/release/flipflux --out OUT [--quick]

Writes OUT/run.json, predictions.csv, orbits-arm<a>.csv, orbit-curves-arm<a>.csv,
ensemble-<name>.json and ensemble-<name>/ (the CSVs of `simulate --csv-dir`).
"""
import argparse
import json
import os
import subprocess
import sys
import time


def grid(lo, hi, step):
    n = int(round((hi - lo) / step))
    return ["%.10g" % (lo + i * step) for i in range(n + 1)]


def run(cmd):
    out = subprocess.run(cmd, check=True, capture_output=True, text=True)
    return out.stdout


def write(path, text):
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write(text)
    os.replace(tmp, path)


def evaluate(ff, quantity, arm, energy):
    try:
        d = json.loads(run([ff, "eval", quantity, "--arm", str(arm), "--energy", energy]))
    except subprocess.CalledProcessError:
        return None
    return d


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--flipflux", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--quick", action="store_true")
    p.add_argument("--threads", default="1")
    a = p.parse_args()
    ff, out = a.flipflux, a.out
    os.makedirs(out, exist_ok=True)
    start = time.time()
    model = json.loads(run([ff, "model"]))["model"]
    quantities = ["omega", "flux-upright", "flux-approx", "flux-saddle", "rate-upright",
                  "rate-approx", "rate-saddle", "period", "action"]
    pred_e = grid(2.05, 5.95, 0.1) if a.quick else grid(2.05, 5.95, 0.05)
    rows = ["quantity,arm,energy,value,error_estimate,method"]
    for arm in (1, 2):
        for q in quantities:
            if q == "omega" and arm == 1:
                continue
            for e in pred_e:
                d = evaluate(ff, q, arm, e)
                if d is None and q == "rate-saddle":
                    f = evaluate(ff, "flux-saddle", arm, e)
                    o = evaluate(ff, "omega", arm, e)
                    if f and o:
                        d = {"value": repr(float(f["value"]) / float(o["value"])),
                             "error_estimate": "0", "method": "flux-saddle / omega"}
                if d is None:
                    continue
                rows.append("%s,%s,%s,%s,%s,\"%s\"" % (q, "" if q == "omega" else arm, e,
                                                       d["value"], d["error_estimate"],
                                                       d["method"].replace('"', "'")))
    write(os.path.join(out, "predictions.csv"), "\n".join(rows) + "\n")

    orbit_e = {2: grid(2.1, 5.9, 0.2 if a.quick else 0.1), 1: grid(4.1, 5.9, 0.2 if a.quick else 0.1)}
    for arm in (1, 2):
        rows = ["energy,period,action,flux,multiplier,stability_index"]
        curves = ["energy,theta1,theta2"]
        for e in orbit_e[arm]:
            vals = [evaluate(ff, q, arm, e) for q in
                    ("period", "action", "flux-saddle", "multiplier", "stability-index")]
            if any(v is None for v in vals):
                continue
            rows.append(",".join([e] + [v["value"] for v in vals]))
            text = run([ff, "orbit", "--arm", str(arm), "--energy", e, "--samples", "65"])
            for line in text.strip().splitlines()[1:]:
                c = line.split(",")
                curves.append("%s,%s,%s" % (e, c[1], c[2]))
        write(os.path.join(out, "orbits-arm%d.csv" % arm), "\n".join(rows) + "\n")
        write(os.path.join(out, "orbit-curves-arm%d.csv" % arm), "\n".join(curves) + "\n")

    n, t = ("50", "200") if a.quick else ("1000", "10000")
    ensembles = [
        ("arm2", "2", "2.5,3.5,4.5,5.5" if a.quick else "2.1:5.9:0.1"),
        ("arm1", "1", "4.5,5.5" if a.quick else "4.1:5.9:0.1"),
        ("arm2-E5", "2", "5"),
        ("arm2-E5.3", "2", "5.3"),
    ]
    for name, arm, energies in ensembles:
        csv_dir = os.path.join(out, "ensemble-" + name)
        text = run([ff, "simulate", "--arm", arm, "--energy", energies, "--trajectories", n,
                    "--time", t, "--seed", "1", "--threads", a.threads, "--csv-dir", csv_dir])
        write(os.path.join(out, "ensemble-%s.json" % name), text)

    git = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True,
                         cwd=os.path.dirname(os.path.abspath(__file__))).stdout.strip()
    coeff = model["coefficients"]
    alpha, beta = float(coeff["alpha"]), float(coeff["beta"])
    run_json = {
        "scene": "paper-quick (cli_run_dir.py)" if a.quick else "paper (cli_run_dir.py)",
        "scene_file": "tests/report/cli_run_dir.py",
        "precision": "double",
        "git_commit": git,
        "seconds": time.time() - start,
        "model": {
            "parameters": {k: model[k] for k in ("m1", "m2", "L1", "L2", "a1", "a2", "I1", "I2", "g")},
            "coefficients": {"A": coeff["A"], "B": coeff["B"], "C": coeff["C"], "alpha": coeff["alpha"],
                             "beta": coeff["beta"], "D0": coeff["D0"]},
            "saddle_energy": {"1": repr(2 * alpha), "2": repr(2 * beta)},
            "maximum_energy": repr(2 * (alpha + beta)),
        },
    }
    write(os.path.join(out, "run.json"), json.dumps(run_json, indent=2) + "\n")
    print("wrote %s in %.1f s" % (out, time.time() - start))
    return 0


if __name__ == "__main__":
    sys.exit(main())
