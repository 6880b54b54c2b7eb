"""The report's figures (tools/report/make_report.py): each fig_* draws one figure from the loaded
data and saves it through report_common.save_figure."""
import math
import os

import matplotlib
import numpy as np
import matplotlib.pyplot as plt

import statistics_sections
from report_common import (
    COLORS, CRITERIA, as_written, num, pi_ticks, positive, save_figure, units, write_table)
from report_loading import (
    critical_points, cumulative_integral, curve_in_window, energy_entry, flip_window,
    hermite_integral, is_egalitarian, json_quality, lengths, masses_xy, nearest, orbit_curve,
    paired_difference, potential, rate_series, regimes, state_at, tolerance_label)


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


def forbidden_region(ax, model, x, y, energy, **kw):
    """Shades V > energy over the grid x, y (θ₁ along x, θ₂ along y) as filled contour polygons
    of the continuous V (vector paths with interpolated, smooth edges; no raster)."""
    t1, t2 = np.meshgrid(x, y, indexing="xy")
    v = potential(model, t1, t2)
    if np.max(v) > energy:
        ax.contourf(t1, t2, v, levels=[energy, np.max(v) + 1], colors=[kw.get("color", "tab:red")],
                    alpha=kw.get("alpha", 0.3))
        ax.contour(t1, t2, v, levels=[energy], colors=[kw.get("color", "tab:red")], linewidths=0.8)


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
