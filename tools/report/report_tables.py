"""The report's tables (tools/report/make_report.py): critical points, quality indices against the
paper, RMS differences and rates, written as CSV and Markdown."""
import math

import numpy as np

from report_common import (
    CRITERIA, PAPER, REGIME_LABELS, as_written, num, write_table)
from report_loading import (
    compare, critical_points, is_egalitarian, json_quality, rate_series, regimes)


def table_critical_points(data, out):
    header = ["(θ₁, θ₂)", "V (ours)", "V (paper, egalitarian)", "type"]
    rows = []
    egalitarian = is_egalitarian(data["model"])
    for ((x, y), e, kind), (label, pv, _) in zip(critical_points(data["model"]),
                                                PAPER["critical_points"]):
        rows.append([label, "%.17g" % e, pv if egalitarian else "n/a (other model)", kind])
    return write_table(out, "critical-points", header, rows), header, rows


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
