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

Only the standard library, numpy and matplotlib (Debian's python3-matplotlib) are used. The code:
this file (the sections, build_report, main), report_common.py (the paper's values, output, the
figure workers, readers), report_loading.py (the inputs), report_figures.py, report_tables.py and
statistics_sections.py.
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
from report_common import (  # noqa: E402
    COLORS, CRITERIA, InputError, PAPER, RenderError, _workers, _writes, as_written, figure_md,
    finish_rendering, markdown_table, num, positive, read_csv, save_figure, start_rendering,
    units, write_table, write_text)
from report_loading import (  # noqa: E402
    energy_entry, energy_label_files, find_at_energy, json_quality, load_inputs, load_other_run,
    read_rows, sensitivity_ensembles, tolerance_label)
from report_tables import (  # noqa: E402
    explain_quality, quality_table, table_critical_points, table_rates, table_rms)
from report_figures import (  # noqa: E402
    fig_allowed_region, fig_approx_vs_saddle, fig_chaotic_fraction, fig_criteria,
    fig_energy_regimes, fig_fluxes, fig_keyframes, fig_multipliers, fig_orbit_family,
    fig_other_run, fig_period_action, fig_potential, fig_rate_histogram, fig_rates,
    fig_rates_criteria, fig_residence, fig_residence_gap, fig_schematic, fig_threshold,
    fig_tolerance, fig_trajectory_recrossing, fig_trajectory_typical)

matplotlib.rcParams.update({"svg.hashsalt": "flipflux", "figure.dpi": 100, "font.size": 9,
                            "axes.grid": True, "grid.alpha": 0.3,
                            "figure.constrained_layout.use": True})


statistics_sections.bind(sys.modules[__name__])


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
                      "per-trajectory errors differ beyond chance (the heavy-tail check; Σz² by "
                      "the per-trajectory error alone: %.1f).%s\n" %
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
