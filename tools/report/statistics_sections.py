"""The report's statistics beyond a per-trajectory Gaussian error (issue 41): the replicate errors
every verdict rests on, the island census that predicts the chaotic sea's rate from an ensemble
sharing no trajectory with the tested one, the census classifier's measured misclassification,
and the flip statistics beyond the mean (Fano factors against the window, inter-flip tails, the
renewal CV^2). Every number is read from the ensemble JSON and CSV files flipflux wrote; the only
arithmetic here combines them (the census's R_c and its jackknife over the census's replicates).

make_report.py binds its helpers (figures, tables, formats) with `bind(module)` before use.
"""
import math
import os

K = None  # make_report's module: save_figure, write_table, markdown_table, num, as_written, ...


def bind(module):
    global K
    K = module


def marks(run):
    """run.json's census marks: {name: {"census_of": ..., "classification_check_of": ...}}."""
    out = {}
    for x in (run or {}).get("ensembles") or []:
        if isinstance(x, dict) and isinstance(x.get("name"), str):
            out[x["name"]] = {k: x[k] for k in ("census_of", "classification_check_of")
                              if isinstance(x.get(k), str)}
    return out


def is_census_or_check(ens, run):
    return bool(marks(run).get(ens["name"]))


# ---- replicate errors ---------------------------------------------------------------------------

def replicates_of(ens):
    """R, or 1 for an ensemble without replicates."""
    r = ens["json"].get("replicates")
    return int(r["count"]) if isinstance(r, dict) else 1


def replicate_entry(c, chaotic=False):
    """The criterion entry's replicate block (standard_error, z_score, error_ratio, means), or
    None."""
    r = c.get("replicates")
    if not isinstance(r, dict):
        return None
    return r.get("chaotic_trajectories" if chaotic else "all_trajectories")


def student_t_two_sided(z, dof):
    """P(|t| > |z|) for Student's t with dof degrees of freedom (regularized incomplete beta by
    its continued fraction; dof >= 1)."""
    x = dof / (dof + z * z)
    return _betainc(dof / 2.0, 0.5, x)


def _betainc(a, b, x):
    if x <= 0:
        return 0.0
    if x >= 1:
        return 1.0
    lbeta = math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b)
    front = math.exp(lbeta + a * math.log(x) + b * math.log(1 - x))
    if x > (a + 1) / (a + b + 2):
        return 1.0 - _betainc(b, a, 1 - x)
    # Lentz's continued fraction
    f, c, d = 1.0, 1.0, 1.0 - (a + b) * x / (a + 1)
    d = 1.0 / (d if abs(d) > 1e-300 else 1e-300)
    f = d
    for m in range(1, 300):
        for num_ in ((m * (b - m) * x) / ((a + 2 * m - 1) * (a + 2 * m)),
                     -((a + m) * (a + b + m) * x) / ((a + 2 * m) * (a + 2 * m + 1))):
            d = 1.0 + num_ * d
            d = 1.0 / (d if abs(d) > 1e-300 else 1e-300)
            c = 1.0 + num_ / c
            c = c if abs(c) > 1e-300 else 1e-300
            f *= d * c
        if abs(d * c - 1) < 1e-15:
            break
    return front * f / a


def replicate_agreement_rows(ens, criteria, label):
    """Per criterion and subset: Σz² by per-trajectory errors and by replicate errors, the
    expectation, the replicates' own Σz² range, and the heavy-tail check."""
    rows = []
    for c in criteria:
        ag = (ens.get("agreement") or {}).get(c) or {}
        for subset in ("all_trajectories", "chaotic_trajectories"):
            a = ag.get(subset) or {}
            r = a.get("replicates")
            if not isinstance(r, dict):
                continue
            each = [K.num(x) for x in r.get("chi2_of_replicates") or []]
            rows.append([label, c, subset.split("_")[0], a.get("energies"),
                         "%.1f" % K.num(a.get("chi2")), "%.1f" % K.num(r.get("chi2")),
                         "%.1f" % K.num(r.get("expected_chi2")),
                         "%.1f – %.1f" % (min(each), max(each)) if each else "—",
                         "%.2f – %.2f" % (K.num(r.get("min_error_ratio")),
                                          K.num(r.get("max_error_ratio"))),
                         "%.2g – %.3g" % tuple(ratio_range(r)), r.get("error_mismatches")])
    return rows


# The heavy-tail check's fixed range before 2026-11-30, for runs written by a flipflux that did
# not yet record error_ratio_range (the committed runs of docs/reproduction*): the report on such
# a run applies the rule that run's own error_mismatches counted.
LEGACY_RATIO_RANGE = (0.5, 2.0)


def ratio_range(verdict):
    """The heavy-tail check's range of the replicate error over the per-trajectory one, as the run
    computed it (a verdict's error_ratio_range: chi^2 quantiles for its R replicates), or the
    legacy fixed range for an older run."""
    rg = (verdict or {}).get("error_ratio_range")
    if not isinstance(rg, list) or len(rg) != 2:
        return list(LEGACY_RATIO_RANGE)
    return [K.num(rg[0]), K.num(rg[1])]


def legacy_run(mains):
    """Whether a main ensemble's replicate verdicts lack error_ratio_range (an older run)."""
    for ens in mains.values():
        for ag in (ens.get("agreement") or {}).values():
            r = ((ag or {}).get("all_trajectories") or {}).get("replicates")
            if isinstance(r, dict) and "error_ratio_range" not in r:
                return True
    return False


def replicate_section(data, out, mains):
    """The errors the verdicts rest on: for each main ensemble, Σz² with the replicates' errors
    beside the per-trajectory one, and the energies where the two errors disagree beyond chance
    (the heavy-tail check)."""
    md = ["## The errors every verdict rests on: independent replicates\n"]
    rows, warnings = [], []
    for a, ens in sorted(mains.items(), reverse=True):
        R = replicates_of(ens)
        if R < 2:
            md.append("*Ensemble `%s` has no replicates: its verdicts below are not printed "
                      "(a per-trajectory Gaussian error alone cannot see rare islands or sticky "
                      "orbits).*\n" % ens["name"])
            continue
        crit = [c for c in K.CRITERIA if c in ens["energies"][0]["criteria"]]
        rows += replicate_agreement_rows(ens, crit, "%s (arm %d)" % (ens["name"], a))
        for en in ens["energies"]:
            for c in crit:
                for chaotic in (False, True):
                    r = replicate_entry(en["criteria"][c], chaotic)
                    ratio = K.num((r or {}).get("error_ratio"))
                    if not math.isfinite(ratio):
                        continue
                    subset = "chaotic_trajectories" if chaotic else "all_trajectories"
                    lo, hi = ratio_range(((ens.get("agreement") or {}).get(c) or {})
                                         .get(subset, {}).get("replicates"))
                    if ratio > hi or ratio < lo:
                        warnings.append("%s %s%s at E = %s: replicate error %.2f× the "
                                        "per-trajectory one" %
                                        (ens["name"], c, " (chaotic)" if chaotic else "",
                                         K.as_written(en["energy"]), ratio))
    if not rows:
        return "\n".join(md)
    R = replicates_of(mains[2]) if 2 in mains else replicates_of(next(iter(mains.values())))
    header = ["ensemble", "criterion", "trajectories", "energies", "Σz² (per-trajectory SE)",
              "Σz² (replicate SE)", "expected (correct prediction)", "Σz² of each replicate",
              "replicate SE / per-trajectory SE", "its range (99.9 %, correct per-trajectory SE)",
              "energies outside the range"]
    table = K.write_table(out, "replicate-agreement", header, rows)
    md.append("Each main ensemble is R = %d independent replicates: trajectory i's initial state "
              "and tangent vector are a function of (seed, E, i) only, and replicate k holds the "
              "k-th block of indices, so the replicates share no random number. The pooled "
              "statistics are those of one ensemble of all R N trajectories, bit for bit. Every "
              "rate's error below is the jackknife over the replicates (each replicate left out "
              "in turn), which sees whatever makes whole ensembles differ — a rare island one "
              "replicate hits and another misses, a sticky orbit — and not only the "
              "trajectory-to-trajectory spread. A z from it is Student-t with R − 1 = %d degrees "
              "of freedom, so Σz² over n energies is expected near n (R − 1)/(R − 3) for a correct "
              "prediction. [CSV](%s)\n\n%s\n" % (R, R - 1, table, K.markdown_table(header, rows)))
    md.append("The heavy-tail check: the replicate error over the per-trajectory standard error "
              "is the square root of a χ² with R − 1 degrees of freedom over R − 1 when the "
              "per-trajectory error is right; an energy is flagged where it falls outside that "
              "distribution's central 99.9 %% (the table's range), and there the per-trajectory "
              "error is not to be trusted.%s %s\n"
              % (" This run predates that rule: its flipflux flagged outside a fixed [½, 2] "
                 "(the table's range), as the report does for it." if legacy_run(mains) else "",
                 "No energy is flagged." if not warnings else
                 "Flagged: " + "; ".join(warnings[:40]) +
                 (" (and %d more)" % (len(warnings) - 40) if len(warnings) > 40 else "") + "."))
    return "\n".join(md)


# ---- flip statistics beyond the mean ------------------------------------------------------------

def counts_entry(en, c):
    return (en["criteria"].get(c) or {}).get("flip_counts")


def pick_energies(ens, k=5):
    es = [en["energy"] for en in ens["energies"]]
    if len(es) <= k:
        return es
    return [es[round(i * (len(es) - 1) / (k - 1))] for i in range(k)]


def fig_fano(data, out, ens, criterion="saddle"):
    plt = K.plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    shown = pick_energies(ens)
    cmap = plt.get_cmap("viridis")
    for i, e in enumerate(shown):
        en = K.energy_entry(ens, e)
        fc = counts_entry(en, criterion) if en else None
        if not fc or not fc.get("fano"):
            continue
        color = cmap(i / max(1, len(shown) - 1))
        w = [K.num(f["window"]) for f in fc["fano"]]
        for key, ls, lab in (("fano", "o-", "all"), ("fano_chaotic", "s:", "chaotic")):
            y = [K.num(f.get(key)) for f in fc["fano"]]
            axes[0].loglog(w, K.positive(y), ls, ms=3, color=color,
                           label="E = %s, %s" % (K.as_written(e), lab))
        cv2 = K.num(fc.get("inter_flip_cv2_chaotic"))
        if math.isfinite(cv2) and cv2 > 0:
            axes[0].axhline(cv2, color=color, lw=0.8, ls="--")
        tail = fc.get("inter_flip_survival") or []
        t = [K.num(p[0]) for p in tail]
        for col, ls in ((1, "-"), (2, ":")):
            y = [K.num(p[col]) for p in tail]
            axes[1].loglog(t, K.positive(y), ls, color=color,
                           label="E = %s, %s" % (K.as_written(e), "all" if col == 1 else "chaotic"))
    axes[0].axhline(1, color="k", lw=0.8, ls="-.", label="Poisson (Fano = 1)")
    axes[0].set(xlabel="window length", ylabel="Fano factor Var(N_w) / ⟨N_w⟩",
                title="Flip counts in windows, arm %d %s (dashed: renewal CV² of the chaotic "
                      "inter-flip times)" % (ens["arm"], criterion))
    axes[1].set(xlabel="inter-flip time τ", ylabel="P(τ' > τ)",
                title="Inter-flip time tails (solid all, dotted chaotic)")
    axes[0].legend(fontsize=6, ncol=2)
    axes[1].legend(fontsize=6, ncol=2)
    return K.save_figure(fig, out, "flip-statistics-arm%d" % ens["arm"])


def tail_exponent(tail, col):
    """The log-log slope of P(τ > t) over its last decade with at least 1e-4 of the mass: a power
    law's -exponent (sticky regime) or a steepening slope (exponential)."""
    pts = [(K.num(p[0]), K.num(p[col])) for p in tail]
    pts = [(t, s) for t, s in pts if t > 0 and s >= 1e-4 and math.isfinite(s)]
    if len(pts) < 3:
        return float("nan")
    t1, s1 = pts[-1]
    lo = [p for p in pts if p[0] <= t1 / 10] or pts[:1]
    t0, s0 = lo[-1]
    return (math.log(s1) - math.log(s0)) / (math.log(t1) - math.log(t0)) if t1 > t0 else \
        float("nan")


def flip_statistics_rows(ens, criterion="saddle"):
    rows = []
    for en in ens["energies"]:
        fc = counts_entry(en, criterion)
        if not fc or not fc.get("fano"):
            continue
        fano = fc["fano"]
        # the largest window with at least ten windows per trajectory: the renewal limit's probe
        probe = fano[1] if len(fano) > 1 else fano[0]
        cv2 = K.num(fc.get("inter_flip_cv2_chaotic"))
        f = K.num(probe.get("fano_chaotic"))
        rows.append([K.as_written(en["energy"]), "%.4g" % K.num(fano[0].get("fano")),
                     K.as_written(probe["window"]), "%.4g" % f, "%.4g" % cv2,
                     "%.3f" % (f / cv2) if cv2 > 0 else "—",
                     "%.2f" % tail_exponent(fc.get("inter_flip_survival") or [], 2)])
    return rows


def flip_statistics_section(data, out):
    md = ["## Flip statistics beyond the mean: Fano factors, inter-flip tails, renewal\n"]
    for a in (2, 1):
        ens = data["main"].get(a)
        if ens is None or not ens["energies"] or \
                not counts_entry(ens["energies"][0], "saddle"):
            continue
        md.append(K.figure_md(fig_fano(data, out, ens), "Arm %d, saddle criterion: the Fano "
                              "factor of the flip counts in windows of length w (left; every "
                              "trajectory cut into T/w windows; solid all trajectories, dotted "
                              "chaotic ones; dashed: the chaotic inter-flip times' CV², the "
                              "renewal prediction for large windows) and the inter-flip time "
                              "distribution's tail (right). Ensemble JSON, flip_counts." % a))
        rows = flip_statistics_rows(ens)
        header = ["energy", "Fano, window T (all)", "window w", "Fano at w (chaotic)",
                  "renewal CV² (chaotic)", "Fano / CV²", "tail slope d ln P / d ln τ (chaotic)"]
        table = K.write_table(out, "flip-statistics-arm%d" % a, header, rows)
        md.append("[CSV](%s)\n\n%s\n" % (table, K.markdown_table(header, rows)))
        ratios = [float(r[5]) for r in rows if r[5] != "—" and math.isfinite(float(r[5]))]
        if ratios:
            md.append("Arm %d: Fano/CV² from %.2f to %.2f (median %.2f) over %d energies. A "
                      "renewal process (independent inter-flip times) has Fano → CV² for large "
                      "windows: a ratio near 1 says successive flips are uncorrelated beyond their "
                      "waiting-time law; above 1, long-range correlations (sticking near islands, "
                      "bursts of rotation) make counts cluster more than the waiting times alone "
                      "imply. The window T (one window per trajectory) holds the rates' "
                      "trajectory-to-trajectory spread, so it grows with T where regular "
                      "trajectories exist. A tail slope near a constant over a decade is a power "
                      "law (sticky regime); a slope falling away is an exponential (mixing).\n" %
                      (a, min(ratios), max(ratios), sorted(ratios)[len(ratios) // 2], len(ratios)))
    return "\n".join(md) if len(md) > 1 else ""


# ---- the island census --------------------------------------------------------------------------

def _census_parts(c):
    """Per replicate of a census energy entry: (n, n m, n_c, n_c m_c)."""
    rep = c.get("replicates")
    if isinstance(rep, dict):
        a, ch = rep["all_trajectories"], rep["chaotic_trajectories"]
        parts = []
        for n, m, nc, mc in zip(a["trajectories"], a["means"], ch["trajectories"], ch["means"]):
            parts.append((int(n), int(n) * K.num(m) if int(n) else 0.0, int(nc),
                          int(nc) * K.num(mc) if int(nc) else 0.0))
        return parts
    return None  # a census without replicates has no error: not used


def census_prediction(parts, R):
    """R_c = (R N - (S - S_c)) / N_c from summed parts (n, S, n_c, S_c), f_r and R_r."""
    N = sum(p[0] for p in parts)
    S = sum(p[1] for p in parts)
    Nc = sum(p[2] for p in parts)
    Sc = sum(p[3] for p in parts)
    if Nc == 0 or N == 0:
        return float("nan"), float("nan"), float("nan")
    fr = (N - Nc) / N
    rr = (S - Sc) / (N - Nc) if N > Nc else float("nan")
    return (R * N - (S - Sc)) / Nc, fr, rr


def jackknife(values):
    r = len(values)
    if r < 2 or not all(math.isfinite(v) for v in values):
        return float("nan")
    m = sum(values) / r
    return math.sqrt((r - 1) / r * sum((v - m) ** 2 for v in values))


def census_rows(census, tested, criteria):
    """Per energy and criterion: the census's f_r, R_r and R_c (± jackknife over the census's
    replicates) against the tested ensemble's chaotic mean (± its replicate error)."""
    rows = []
    for en in census["energies"]:
        te = K.energy_entry(tested, en["energy"])
        if te is None:
            continue
        for c in criteria:
            cc, tc = en["criteria"].get(c), te["criteria"].get(c)
            if cc is None or tc is None:
                continue
            R = K.num(cc.get("predicted_rate"))
            parts = _census_parts(cc)
            if not parts or not math.isfinite(R):
                continue
            rc, fr, rr = census_prediction(parts, R)
            loo = [census_prediction(parts[:k] + parts[k + 1:], R)[0] for k in range(len(parts))]
            fr_loo = [census_prediction(parts[:k] + parts[k + 1:], R)[1] for k in range(len(parts))]
            se_rc, se_fr = jackknife(loo), jackknife(fr_loo)
            # a census with few or no regular trajectories: the jackknife of a count near 0 is
            # near 0 too, so the error of f_r is at least the binomial one of max(f_r, 1/N),
            # carried to R_c by dR_c/df_r = (R - R_r)/(1 - f_r)^2 (R_r = 0 where none was seen)
            n_census = sum(p[0] for p in parts)
            if n_census == 0:
                continue
            f_floor = max(fr, 1.0 / n_census)
            se_fr = max(se_fr, math.sqrt(f_floor * (1 - f_floor) / n_census))
            # R_r where the census saw no regular trajectory: the tested ensemble's regular mean
            # if it has one, else 0
            tfc = K.num(tc.get("chaotic_fraction"))
            tested_rr = (K.num(tc.get("mean_rate")) - tfc * K.num((tc.get("chaotic") or {})
                                                                   .get("mean_rate"))) / (1 - tfc) \
                if 0 <= tfc < 1 else float("nan")
            r_reg = rr if math.isfinite(rr) else (tested_rr if math.isfinite(tested_rr) else 0.0)
            slope = abs(R - r_reg) / (1 - fr) ** 2
            se_rc = max(se_rc, slope * se_fr)
            ch = tc.get("chaotic") or {}
            mc = K.num(ch.get("mean_rate"))
            rep = replicate_entry(tc, True)
            se_mc = K.num((rep or {}).get("standard_error"))
            sigma = math.sqrt(se_mc ** 2 + se_rc ** 2) if math.isfinite(se_mc) else float("nan")
            z_c = (mc - rc) / sigma if sigma > 0 else float("nan")
            z_0 = (mc - R) / se_mc if se_mc > 0 else float("nan")
            m_all = K.num(tc.get("mean_rate"))
            rep_all = replicate_entry(tc, False)
            se_all = K.num((rep_all or {}).get("standard_error"))
            z_all = (m_all - R) / se_all if se_all > 0 else float("nan")
            rows.append({"energy": en["energy"], "criterion": c, "R": R, "f_r": fr, "se_f_r": se_fr,
                         "R_r": rr, "R_c": rc, "se_R_c": se_rc, "chaotic_mean": mc,
                         "se_chaotic": se_mc, "z_c": z_c, "z_0": z_0, "z_all": z_all,
                         "all_mean": m_all, "census_n": sum(p[0] for p in parts),
                         "tested_fc": K.num(tc.get("chaotic_fraction"))})
    return rows


def read_classification(path):
    """{index: (lyapunov, chaotic)} of a trajectories_E<E>.csv."""
    out = {}
    rows = K.read_csv(path, [])
    for r in rows or []:
        if r.get("status", "ok") != "ok":  # a failed trajectory has no class (chaotic = 0)
            continue
        try:
            out[int(r["index"])] = (float(r["lyapunov"]) if r["lyapunov"] else float("nan"),
                                    r["chaotic"] == "1")
        except (KeyError, ValueError):
            continue
    return out


def misclassification_rows(check, census):
    """Per energy: the census's trajectories re-integrated to the check's T, paired by index:
    how many change class between the census's T and the check's."""
    rows = []
    for en in check["energies"]:
        a = K.find_at_energy(K.energy_label_files(census["csv_dir"], "trajectories_E", ".csv"),
                             en["energy"])
        b = K.find_at_energy(K.energy_label_files(check["csv_dir"], "trajectories_E", ".csv"),
                             en["energy"])
        if not a or not b:
            continue
        x, y = read_classification(a), read_classification(b)
        common = sorted(set(x) & set(y))
        if not common:
            continue
        reg_census = sum(1 for i in common if not x[i][1])
        reg_check = sum(1 for i in common if not y[i][1])
        to_chaotic = sum(1 for i in common if not x[i][1] and y[i][1])
        to_regular = sum(1 for i in common if x[i][1] and not y[i][1])
        rows.append({"energy": en["energy"], "n": len(common), "regular_census": reg_census,
                     "regular_check": reg_check, "to_chaotic": to_chaotic,
                     "to_regular": to_regular, "rate": (to_chaotic + to_regular) / len(common)})
    return rows


def census_groups(ensembles, run):
    """[(census, tested, [checks])] from run.json's marks."""
    m = marks(run)
    by_name = {e["name"]: e for e in ensembles}
    out = []
    for e in ensembles:
        tested = m.get(e["name"], {}).get("census_of")
        if tested and tested in by_name:
            checks = [x for x in ensembles
                      if m.get(x["name"], {}).get("classification_check_of") == e["name"]]
            out.append((e, by_name[tested], checks))
    return out


def fig_census(rows, out, name, u):
    plt = K.plt
    fig, axes = plt.subplots(1, 2, figsize=(12, 4.2))
    crit = sorted({r["criterion"] for r in rows})
    for k, c in enumerate(crit):
        sel = [r for r in rows if r["criterion"] == c]
        e = [r["energy"] + 0.01 * k for r in sel]
        color = K.COLORS.get(c, "k")
        axes[0].errorbar(e, [100 * (r["chaotic_mean"] / r["R"] - 1) for r in sel],
                         yerr=[100 * r["se_chaotic"] / r["R"] for r in sel], fmt="o", ms=3,
                         capsize=2, color=color, mfc="none",
                         label="%s: tested chaotic mean vs R" % c)
        axes[0].errorbar(e, [100 * (r["R_c"] / r["R"] - 1) for r in sel],
                         yerr=[100 * r["se_R_c"] / r["R"] for r in sel], fmt="s", ms=3,
                         capsize=2, color=color, label="%s: census R_c vs R" % c)
    sel = [r for r in rows if r["criterion"] == crit[-1]]
    axes[1].errorbar([r["energy"] for r in sel], [100 * r["f_r"] for r in sel],
                     yerr=[100 * r["se_f_r"] for r in sel], fmt="o-", ms=3, capsize=2,
                     color="tab:green", label="census regular fraction f_r")
    axes[1].plot([r["energy"] for r in sel], [100 * (1 - r["tested_fc"]) for r in sel], "x",
                 color="k", label="tested ensemble's regular fraction")
    axes[0].axhline(0, color="k", lw=0.6)
    axes[0].set(xlabel=u["E"], ylabel="relative to the prediction R [%]",
                title="Chaotic sea: census prediction R_c against the tested ensemble")
    axes[1].set(xlabel=u["E"], ylabel="regular fraction [%]", title="Regular islands (census)")
    for ax in axes:
        ax.legend(fontsize=6)
    return K.save_figure(fig, out, "census-%s" % name)


def census_section(ensembles, run, model, out, title_run):
    """The island census of one run (the main one or another pendulum's)."""
    md = []
    u = K.units(model)
    for census, tested, checks in census_groups(ensembles, run):
        crit = [c for c in K.CRITERIA if c in census["energies"][0]["criteria"]
                and c in tested["energies"][0]["criteria"]]
        rows = census_rows(census, tested, crit)
        if not rows:
            continue
        name = "%s-%s" % (title_run, census["name"])
        md.append("### Island census `%s` → ensemble `%s` (%s)\n" %
                  (census["name"], tested["name"], title_run))
        if abs(census["time"] - tested["time"]) > 1e-9 * tested["time"]:
            md.append("The census classifies at T = %s, the tested ensemble at T = %s: the "
                      "classification check below measures how many trajectories change class "
                      "between the census's T and a longer one, which bounds the difference "
                      "the two lengths make.\n" % (K.as_written(census["time"]),
                                                    K.as_written(tested["time"])))
        md.append("Independence: the census has seed %s, the tested ensemble seed %s (the plan "
                  "refuses a census that shares a seed with the ensemble it tests or with any "
                  "ensemble sharing its trajectories); every trajectory is a function of (seed, "
                  "E, index), so no trajectory is common to both. Census: %d trajectories per "
                  "energy (%d replicates) of T = %s; tested: %d of T = %s (%d replicates).\n" %
                  (census.get("seed"), tested.get("seed"), census["trajectories"],
                   replicates_of(census), K.as_written(census["time"]), tested["trajectories"],
                   K.as_written(tested["time"]), replicates_of(tested)))
        md.append(K.figure_md(fig_census(rows, out, name, u), "Left: the census's prediction "
                              "of the chaotic sea's rate, R_c = (R − f_r R_r)/(1 − f_r) (filled), "
                              "and the tested ensemble's chaotic-trajectory mean (open), both "
                              "relative to the microcanonical prediction R, ± their replicate "
                              "errors (the census's by the jackknife over its replicates). Right: "
                              "the census's regular fraction f_r and the tested ensemble's."))
        header = ["energy", "criterion", "f_r [%]", "R_r / R", "R_c / R − 1 [%]",
                  "tested chaotic mean / R − 1 [%]", "z (tested chaotic vs R_c)",
                  "z (tested chaotic vs R)", "z (tested all vs R)", "noise floor [%]"]
        table_rows = []
        for r in rows:
            floor = 100 * math.sqrt(r["se_chaotic"] ** 2 + r["se_R_c"] ** 2) / r["R"]
            table_rows.append([K.as_written(r["energy"]), r["criterion"],
                               "%.3f ± %.3f" % (100 * r["f_r"], 100 * r["se_f_r"]),
                               "%.3f" % (r["R_r"] / r["R"]) if math.isfinite(r["R_r"]) else "—",
                               "%+.3f ± %.3f" % (100 * (r["R_c"] / r["R"] - 1),
                                                 100 * r["se_R_c"] / r["R"]),
                               "%+.3f ± %.3f" % (100 * (r["chaotic_mean"] / r["R"] - 1),
                                                 100 * r["se_chaotic"] / r["R"]),
                               "%.2f" % r["z_c"], "%.2f" % r["z_0"], "%.2f" % r["z_all"],
                               "%.3f" % floor])
        # the CSV: one number per cell (values and their errors apart), all digits
        csv_header = ["energy", "criterion", "R", "f_r", "f_r error", "R_r", "R_c", "R_c error",
                      "R_c / R - 1 [%]", "tested chaotic mean", "tested chaotic error",
                      "tested chaotic / R - 1 [%]", "z (tested chaotic vs R_c)",
                      "z (tested chaotic vs R)", "tested all mean", "z (tested all vs R)",
                      "tested regular fraction", "census trajectories", "noise floor [%]"]
        csv_rows = [[K.as_written(r["energy"]), r["criterion"], "%.17g" % r["R"], "%.17g" % r["f_r"],
                     "%.6g" % r["se_f_r"], "%.17g" % r["R_r"], "%.17g" % r["R_c"],
                     "%.6g" % r["se_R_c"], "%.4f" % (100 * (r["R_c"] / r["R"] - 1)),
                     "%.17g" % r["chaotic_mean"], "%.6g" % r["se_chaotic"],
                     "%.4f" % (100 * (r["chaotic_mean"] / r["R"] - 1)), "%.3f" % r["z_c"],
                     "%.3f" % r["z_0"], "%.17g" % r["all_mean"], "%.3f" % r["z_all"],
                     "%.6g" % (1 - r["tested_fc"]), r["census_n"],
                     "%.4f" % (100 * math.sqrt(r["se_chaotic"] ** 2 + r["se_R_c"] ** 2) / r["R"])]
                    for r in rows]
        table = K.write_table(out, "census-%s" % name, csv_header, csv_rows)
        md.append("[CSV](%s)\n\n%s\n" % (table, K.markdown_table(header, table_rows)))
        zc = [r["z_c"] for r in rows if math.isfinite(r["z_c"])]
        z0 = [r["z_0"] for r in rows if math.isfinite(r["z_0"])]
        md.append("**Outcome.** %s\n" % census_outcome(rows, zc, z0, replicates_of(tested)))
        for check in checks:
            mrows = misclassification_rows(check, census)
            if not mrows:
                continue
            header = ["energy", "paired trajectories", "regular at T = %s" %
                      K.as_written(census["time"]), "regular at T = %s" %
                      K.as_written(check["time"]), "regular → chaotic", "chaotic → regular",
                      "changed [%]"]
            trows = [[K.as_written(r["energy"]), r["n"], r["regular_census"], r["regular_check"],
                      r["to_chaotic"], r["to_regular"], "%.3f" % (100 * r["rate"])]
                     for r in mrows]
            n = sum(r["n"] for r in mrows)
            changed = sum(r["to_chaotic"] + r["to_regular"] for r in mrows)
            table = K.write_table(out, "misclassification-%s-%s" % (title_run, check["name"]),
                                  header, trows)
            md.append("Classification check `%s`: the census's first %d trajectories per energy "
                      "re-integrated to T = %s (same seed, so the same initial states and tangent "
                      "vectors), paired by index. [CSV](%s)\n\n%s\n\n%d of %d trajectories "
                      "(%.3f %%, 95 %% upper bound %.3f %%) change class between T = %s and T = "
                      "%s: %s.\n" %
                      (check["name"], max(r["n"] for r in mrows), K.as_written(check["time"]),
                       table, K.markdown_table(header, trows), changed, n, 100 * changed / n,
                       100 * poisson_upper(changed) / n, K.as_written(census["time"]),
                       K.as_written(check["time"]),
                       "the census's classification at T = %s is measured against %s" %
                       (K.as_written(census["time"]),
                        "a %.3g× longer integration" % (check["time"] / census["time"])
                        if check["time"] > census["time"] else
                        "a %.3g× shorter one: the rate at which a shorter census would be wrong"
                        % (census["time"] / check["time"]))))
    return "\n".join(md)


def census_outcome(rows, zc, z0, R):
    """One verdict from one test: the worst |z| over the energies against Student's t with R - 1
    degrees of freedom, Sidak-corrected for the number of energies (the criteria at one energy
    count the same trajectories' flips: strongly correlated, so energies, not pairs, are the
    independent tests)."""
    if not zc:
        return ("No verdict: the tested ensemble has no replicates, so its chaotic mean has no "
                "error that could see rare islands.")
    dof = R - 1
    energies = len({r["energy"] for r in rows if math.isfinite(r["z_c"])})
    worst = max((r for r in rows if math.isfinite(r["z_c"])), key=lambda r: abs(r["z_c"]))
    p1 = student_t_two_sided(worst["z_c"], dof)
    family = 1 - (1 - p1) ** energies
    expect = len(zc) * dof / (dof - 2) if dof > 2 else float("nan")
    return ("With the census's regular fraction and regular rate, the predicted chaotic-sea rate "
            "R_c **%s** the tested chaotic sub-ensemble: the worst z is %.2f (E = %s, %s), "
            "two-sided p = %.2g for one energy and %.2g for the worst of %d energies (Student's t "
            "with %d degrees of freedom; 'agrees' when that exceeds 0.05). Σz² = %.1f over %d "
            "(energy, criterion) pairs, %.1f expected for a correct prediction. Against the "
            "uncorrected prediction R the same chaotic means give Σz² = %.1f: the difference is "
            "the regular islands' share of R, measured by an ensemble that shares no trajectory "
            "with the one it is tested on." %
            ("agrees with" if family > 0.05 else "differs from", worst["z_c"],
             K.as_written(worst["energy"]), worst["criterion"], p1, family, energies, dof,
             sum(z * z for z in zc), len(zc), expect, sum(z * z for z in z0)))


def poisson_upper(k):
    """The 95 % one-sided upper bound of a Poisson mean given k events (chi-square quantile by
    Wilson-Hilferty)."""
    if k == 0:
        return -math.log(0.05)  # exact: P(0 | mu) = exp(-mu) = 0.05
    dof = 2 * (k + 1)
    z = 1.6448536269514722
    return dof * (1 - 2 / (9 * dof) + z * math.sqrt(2 / (9 * dof))) ** 3 / 2


def census_sections(data, out):
    md = ["## The island census: regular fraction, regular rate and the chaotic sea's rate\n",
          "The paper compares its chaotic trajectories with the microcanonical prediction R and "
          "leaves open how the regular islands enter. A census — an ensemble with its own seed — "
          "classifies trajectories by the finite-time Lyapunov exponent and measures the regular "
          "fraction f_r(E) and the regular trajectories' mean rate R_r. If R is right and the "
          "chaotic sea is ergodic, its rate is R_c = (R − f_r R_r)/(1 − f_r), a prediction the "
          "tested ensemble's chaotic sub-ensemble, integrated from other initial states, can "
          "refute. (Built from the tested ensemble's own f_r and R_r instead, R_c − mean_c = "
          "(R − mean)/f_c identically: no test at all.)\n"]
    body = census_section(data["ensembles"], data["run"], data["model"], out, "main")
    for d in data.get("other_run_dirs") or []:
        other = data["other_runs"].get(d)
        if other is not None:
            name = (other["run"] or {}).get("scene", os.path.basename(d.rstrip("/")))
            body += "\n" + census_section(other["ensembles"], other["run"], other["model"], out,
                                          name)
    if not body.strip():
        md.append("*No census in this run (data/scenes/paper.toml and paper-tenth.toml have "
                  "them).*\n")
    else:
        md.append(body)
    return "\n".join(md)
