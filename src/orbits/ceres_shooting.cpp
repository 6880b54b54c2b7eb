// The double-precision stage of the saddle-orbit solver (see orbits/ceres_shooting.hpp): Ceres
// (through its plugin, orbits/least_squares.hpp) for the paper's periodic shooting, a damped
// Newton iteration for the symmetric formulation.
#include "flipflux/orbits/ceres_shooting.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "flipflux/orbits/least_squares.hpp"
#include "flipflux/orbits/shooting.hpp"

namespace flipflux::detail {

/// Marks a converged result as not converged when its orbit leaves the saddle's strip
/// |delta| < pi (see quarter_extent): another periodic orbit, or the family's own beyond its end
/// (continue_double), not a saddle orbit.
static void check_family(const shooting_setup<double>& setup, double_stage_result& r,
                         long quarter_steps) {
    const auto m = quarter_extent(setup, r.beta, r.period / 4, quarter_steps);
    r.extent = m;
    if (r.left_strip()) {
        r.converged = false;
        char buf[160];
        std::snprintf(buf, sizeof buf,
                      "; the solution left the saddle's strip (max |delta| = %.4g, %.4g): not a "
                      "saddle orbit",
                      m[0], m[1]);
        r.report += buf;
    }
}

double_stage_result ceres_periodic_shooting(const double_pendulum<double>& model, arm a,
                                            double excess, double beta0, double period0, long steps,
                                            int stages) {
    const shooting_setup<double> setup(model, a, excess, stages);
    // r(beta, T) = (x(T) - x(0)) / sqrt(2 (E - E_s)) (rows weighted by row_weight), Jacobian from
    // the variational equations
    const least_squares_function residual = [&](const double* p, double* r, double* jacobian) {
        const double beta = p[0], period = p[1];
        if (!(period > 0) || !std::isfinite(beta)) return false;
        if (jacobian == nullptr) {
            // residual only (trial points of the trust region): no variational equations
            const auto x0 = setup.start(beta);
            const auto end = integrate_state(setup, x0, period, steps);
            if (!end.success) return false;
            for (int i = 0; i < 4; ++i)
                r[i] = setup.row_weight(i, (end.x[i] - x0[i]) / setup.momentum_scale);
            return true;
        }
        const auto pr = periodic_shooting(setup, beta, period, steps);
        if (!pr.end.success) return false;
        for (int i = 0; i < 4; ++i) {
            r[i] = pr.r[i];
            jacobian[2 * i] = pr.jacobian[i][0];
            jacobian[2 * i + 1] = pr.jacobian[i][1];
        }
        return true;
    };
    std::vector<double> x{beta0, period0};
    least_squares_settings settings;
    settings.max_iterations = 40;
    // NOTE: the residual is zero at the solution, so only the step-size test is meaningful; the
    // cost and gradient tests are disabled (set far below what double can reach). The Real
    // polish that follows takes the result to the working precision.
    settings.function_tolerance = 1e-30;
    settings.gradient_tolerance = 1e-30;
    settings.parameter_tolerance = 1e-14;
    const auto summary = solve_least_squares(residual, x, 4, {-HUGE_VAL, period0 / 4}, settings);
    double_stage_result r;
    r.beta = x[0];
    r.period = x[1];
    r.iterations = summary.iterations;
    r.residual = std::sqrt(2 * summary.final_cost);
    // converged = Ceres found a zero of the residual (the cost is a sum of squares that vanishes
    // at the orbit; a local minimum with a non-zero cost is not an orbit). NOTE: rounding errors
    // of the integration are amplified by the multiplier |mu| over a period, so the residual
    // cannot fall below ~ eps |dr/dbeta| ~ eps |mu|: a residual at that floor is a zero.
    double floor = 0;
    if (summary.usable && r.residual >= 1e-6) {
        const auto pr = periodic_shooting(setup, r.beta, r.period, steps);
        double norm = 0;
        for (int i = 0; i < 4; ++i)
            norm = std::max(norm, std::abs(pr.jacobian[i][0]));
        floor = 1e3 * 2.220446049250313e-16 * norm;
    }
    // (a floor of order one or more means double cannot resolve the orbit at all)
    r.converged = summary.usable && (r.residual < 1e-6 || (r.residual <= floor && floor < 1e-3));
    r.report = summary.report;
    if (r.converged) check_family(setup, r, steps / 4);
    return r;
}

double_stage_result newton_symmetric_shooting(const double_pendulum<double>& model, arm a,
                                              double excess, double beta0, double period0,
                                              long quarter_steps, int stages) {
    const shooting_setup<double> setup(model, a, excess, stages);
    double beta = beta0, tau = period0 / 4;
    double_stage_result out;
    double last = HUGE_VAL;
    int it = 0;
    for (it = 1; it <= 30; ++it) {
        const auto sr = symmetric_shooting(setup, beta, tau, quarter_steps);
        if (!sr.end.success) break;
        out.residual = std::hypot(sr.r[0], sr.r[1]);
        // F of this iterate (at convergence the update is below 1e-7 relative)
        out.action = 4 * sr.end.action;
        auto d = solve_2x2(sr.jacobian, sr.r);
        if (!std::isfinite(d[0]) || !std::isfinite(d[1])) break;
        // damping: at most 0.3 rad in beta and 30 % of tau per step
        // NOTE: damped to 0.1 rad in beta and 10 % of tau: l(tau) = 0 has later roots (later
        // brake points of other orbits), which an undamped step can jump to
        const double damp = std::min({1.0, 0.1 / std::max(std::abs(d[0]), 1e-300),
                                      0.1 * tau / std::max(std::abs(d[1]), 1e-300)});
        beta -= damp * d[0];
        tau -= damp * d[1];
        const double size = std::max(std::abs(d[0]) / (1 + std::abs(beta)), std::abs(d[1]) / tau);
        // NOTE: near E_max the rounding floor of the updates rises (errors amplified by the
        // quarter period's growth), so stagnation below 1e-7 is accepted as convergence: the
        // polish in the working precision reports the attained accuracy
        if (damp == 1.0 && (size <= 1e-14 || (size >= last / 2 && size <= 1e-7))) {
            out.converged = true;
            break;
        }
        last = damp == 1.0 ? size : HUGE_VAL;
    }
    out.beta = beta;
    out.period = 4 * tau;
    out.iterations = it;
    char buf[160];
    std::snprintf(buf, sizeof buf,
                  "Newton (symmetric): %d iterations, |l(tau)|/sqrt(2 dE) = %.3e, %s", it,
                  out.residual, out.converged ? "converged" : "not converged");
    out.report = buf;
    // (after the report: check_family appends why a converged solution is not the orbit)
    if (out.converged) check_family(setup, out, quarter_steps);
    return out;
}

namespace {

std::string g(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

/// beta reduced to (-pi, pi].
double wrap_angle(double b) {
    return std::remainder(b, 2 * M_PI);
}

/// Steps for one shooting integration (a period if `periodic`, else a quarter) at `tolerance`
/// (relative to the orbit's scale), from a guess. NOTE: chosen on the quarter orbit in both
/// cases; a full period's endpoint error is amplified by the multiplier.
long shooting_steps(const shooting_setup<double>& setup, double beta, double period,
                    double tolerance, bool periodic) {
    const double duration = period / 4;
    const auto x0 = setup.start(beta);
    const std::array<double, 5> y0{x0[0], x0[1], x0[2], x0[3], 0.0};
    // scales: angles ~ momenta / sqrt(A) (order of the orbit's displacement), momenta ~ |l0|,
    // action ~ (E - E_s) T
    const double lscale = std::max(std::abs(x0[2]), std::abs(x0[3]));
    const double k = setup.frame.coefficients().A + setup.frame.coefficients().B;
    const double dscale = lscale / std::sqrt(k) * std::max(1.0, duration);
    const std::array<double, 5> scale{dscale, dscale, lscale, lscale,
                                      setup.excess * std::max(1.0, duration)};
    const auto est = steps_for_tolerance<double, 5>(orbit_flow<double>{&setup.frame}, y0, duration,
                                                    tolerance, setup.stages, scale, 4);
    return periodic ? 4 * est.steps : est.steps;
}

/// The action identity's test of a step from `last` to the corrector's solution `r` at excess
/// `next`: the gap between F's change and the trapezoid, its bound dE |dT| / 2, and F's scale.
struct action_gap {
    bool known = false;  ///< both actions known (the symmetric formulation's)
    double gap = 0, bound = 0, scale = 0;
    double expected = 0;  ///< F(last) + the trapezoid (for the report)
};

/// NOTE: the action identity dF/dE = T. The continuation's predictor test cannot tell the family
/// from another orbit near it when a step is long: arm 2 of m1 = 0.5124, m2 = 2.05,
/// L1 = 1.66, L2 = 0.486 (g = 9.81) stepped from T = 2.824 at E - E_s = 38.8 to T = 3.277
/// at 52.1 (E = 71.6) where the family's T is 3.103, within half the predicted change, and
/// every energy from 71.6 to 72.9 reported that other orbit, with estimates of 1e-9
/// (test SaddleOrbit.ContinuationStaysOnItsFamilyWhereAnotherOrbitIsNear). Along one
/// family, where T is monotone over a step, F(next) - F(last) lies within dE |dT| / 2 of
/// the trapezoid dE (T_last + T_next) / 2; a jump to another orbit moves F by O(F). The
/// steps are kept small enough for that bound (dE |dT| / 2 <= 3e-3 F) to see a jump of more
/// than 0.6 % of F, and for the predictor test to see the jump in T (5.6 % there). Cost:
/// more steps (the paper's arm 1 to E = 5.5: 31 instead of 4; to E_max - 1e-5: 48 instead
/// of 19). The gap may exceed the bound by 1e-4 F: near E_max the Newton stops at ~1e-7 of
/// its iterates and F is no better (arm 2 of m1 3.931, m2 14.1, rigid first link: 6e-5 F
/// at E_max - 11 with 1e-7). F comes with the symmetric Newton's last iterate
/// (solve_saddle_orbit continues in the symmetric formulation for either method); the
/// periodic one has no F: no check.
action_gap action_identity(const double_orbit& last, double next, const double_stage_result& r) {
    action_gap out;
    out.known = std::isfinite(last.action) && std::isfinite(r.action);
    if (!out.known) return out;
    const double denergy = next - last.excess;
    const double trapezoid = 0.5 * denergy * (r.period + last.period);
    out.bound = 0.5 * denergy * std::abs(r.period - last.period);
    out.gap = std::abs(r.action - last.action - trapezoid);
    out.scale = std::max(std::abs(r.action), std::abs(last.action));
    out.expected = last.action + trapezoid;
    return out;
}

/// Ends a continuation that stopped short with `reason`. NOTE: the family's end as saddle orbits.
/// Where a family's swing grows until one angle reaches the vertical opposite its saddle's
/// (|delta| = pi: arm 2 of m1 = 0.1792, m2 = 0.101, L1 = 1.98, L2 = 0.586, a rigid first link
/// a1 = 0.991, I1 = 0.05868, at E - E_s = 5.2529), the corrector's solutions beyond it are the
/// family's orbits outside the strip (check_family), which are not saddle orbits, and the halving
/// brackets the end: where the last refusal followed the family out of the strip and the last
/// accepted orbit (at `excess`, its swings `extent`) reached within 1e-2 of pi, that is the end.
double_continuation& stopped(double_continuation& out, double excess,
                             const std::array<double, 2>& extent, bool left_strip_on_family,
                             const std::string& reason) {
    const int k = extent[1] >= extent[0] ? 2 : 1;
    if (left_strip_on_family && extent[k - 1] >= M_PI - 1e-2) {
        out.strip_end = excess;
        out.strip_angle = k;
        char buf[200];
        std::snprintf(buf, sizeof buf,
                      "the family leaves its saddle's strip at E - E_s = %.6g: there its orbit "
                      "swings theta%d to the vertical opposite the saddle's (max |delta%d| = "
                      "%.6g, pi beyond); ",
                      excess, k, k, extent[k - 1]);
        out.stop_reason = buf + reason;
    } else {
        out.stop_reason = reason;
    }
    return out;
}

}  // namespace

double_continuation continue_double(const double_pendulum<double>& model, arm a, bool periodic,
                                    int stages, double tolerance, double beta_lin,
                                    double period_lin, const std::vector<double>& targets) {
    double_continuation out;
    if (targets.empty()) {
        out.success = true;
        return out;
    }
    const double range = model.maximum_energy() - model.saddle_energy(a);
    auto sigma = [&](double excess) { return -std::log(range - excess); };
    auto solve = [&](double excess, double beta, double period) {
        const shooting_setup<double> setup(model, a, excess, stages);
        const long n = shooting_steps(setup, beta, period, tolerance, periodic);
        if (std::getenv("FLIPFLUX_DEBUG_CONTINUATION"))
            std::fprintf(stderr, "continuation: %ld integration steps\n", n);
        return periodic ? ceres_periodic_shooting(model, a, excess, beta, period, n, stages)
                        : newton_symmetric_shooting(model, a, excess, beta, period, n, stages);
    };
    std::size_t next_target = 0;
    auto record = [&](double excess, double beta, double period) {
        const bool requested = next_target < targets.size() && excess == targets[next_target];
        if (requested) ++next_target;
        out.orbits.push_back({excess, beta, period, requested});
    };
    // the centre mode itself (E - E_s = 0) is the secant's first point
    std::vector<double_orbit> known{{0.0, beta_lin, period_lin, false}};
    // the largest |delta1|, |delta2| of the last accepted orbit's quarter, and whether the last
    // refused step's corrector followed the family out of the saddle's strip
    std::array<double, 2> last_extent{};
    bool left_strip_on_family = false;
    auto stop_at = [&](const std::string& reason) {
        return stopped(out, known.back().excess, last_extent, left_strip_on_family, reason);
    };
    {
        // the first orbit at a small excess, where the linear guess is O(excess) off
        const double e0 = std::min(targets.front(), 1e-4 * range);
        const auto r = solve(e0, beta_lin, period_lin);
        out.steps.push_back({0, e0, r.converged, r.iterations, r.converged ? "" : r.report});
        if (!r.converged || std::abs(r.period - period_lin) > 0.2 * period_lin) {
            out.stop_reason =
                "no orbit near the centre mode at E - E_s = " + g(e0) + ": " + r.report;
            return out;
        }
        known.push_back({e0, wrap_angle(r.beta), r.period, false, r.action});
        record(e0, known.back().beta, known.back().period);
        out.highest_excess = e0;
        last_extent = r.extent;
    }
    double dsigma = 0.25;
    const double min_dsigma = 1e-7;
    // NOTE: near E_max the corrector's rounding floor rises until no step converges; rather than
    // halving to min_dsigma, stop after this many consecutive failures
    const int max_consecutive_failures = 8;
    int failures = 0;
    while (next_target < targets.size()) {
        const double target = targets[next_target];
        const double_orbit& last = known.back();
        double next = range - (range - last.excess) * std::exp(-dsigma);
        if (next > target || target - next < 1e-3 * (next - last.excess)) next = target;
        if (!(next > last.excess)) {
            out.stop_reason =
                "the step in energy fell below the resolution of double at E - E_s = " +
                g(last.excess);
            return out;
        }
        if (std::getenv("FLIPFLUX_DEBUG_CONTINUATION"))
            std::fprintf(stderr,
                         "continuation: %.17g (beta %.17g, T %.17g) -> %.17g (dsigma %.3g)\n",
                         last.excess, last.beta, last.period, next, dsigma);
        // secant predictor in sigma
        const double_orbit& prev = known[known.size() - 2];
        const double f =
            (sigma(next) - sigma(last.excess)) / (sigma(last.excess) - sigma(prev.excess));
        const double beta = last.beta + f * wrap_angle(last.beta - prev.beta);
        const double period = last.period + f * (last.period - prev.period);
        const auto r = solve(next, beta, period);
        const double dbeta = std::abs(wrap_angle(r.beta - beta));
        // NOTE: the corrector may converge to another periodic orbit inside the saddle's strip
        // (an arm-2 family of a rigid pendulum, found by an independent cross-check: its period
        // jumped from 5.457 to 6.013 between E = 11.9 and 11.92 while the family's goes on
        // smoothly, 5.483 at 12). On the family the corrector lands within the predictor's error,
        // a fraction of the step's predicted change (the secant's error is of second order in
        // the step); on another orbit at an O(1) distance. So the corrector's distance from the
        // predictor (beta, T / T) must stay below half the predicted change, or 1e-3.
        const double change =
            std::abs(wrap_angle(beta - last.beta)) + std::abs(period - last.period) / last.period;
        const double moved = dbeta + std::abs(r.period - period) / period;
        bool accepted = r.converged && dbeta < 0.5 && std::abs(r.period - period) < 0.25 * period &&
                        moved <= std::max(0.5 * change, 1e-3);
        // the action identity dF/dE = T (action_identity)
        const action_gap ag = action_identity(last, next, r);
        const double bound = ag.bound, scale = ag.scale;
        const bool off_family = accepted && ag.known && ag.gap > bound + 1e-4 * scale;
        const bool too_coarse = accepted && ag.known && !off_family && bound > 3e-3 * scale;
        if (off_family || too_coarse) accepted = false;
        continuation_step st{last.excess, next, accepted, r.iterations, ""};
        if (!accepted) {
            st.note = too_coarse
                          ? "step too coarse for the action identity (dE |dT| / 2 = " + g(bound) +
                                " for F = " + g(scale) + ")"
                      : !r.converged ? "corrector failed: " + r.report
                      : off_family   ? "corrector left the family (F " + g(r.action) + " for " +
                                         g(ag.expected) + " +- " + g(bound) + " by dF/dE = T; T " +
                                         g(r.period) + ")"
                                   : "corrector left the family (beta moved " + g(dbeta) + ", T " +
                                         g(r.period) + " for predicted " + g(period) + ")";
            out.steps.push_back(st);
            ++out.halvings;
            dsigma /= 2;
            // (the predictor test of a solution outside the strip: on the family's path)
            left_strip_on_family = r.left_strip() && dbeta < 0.5 &&
                                   std::abs(r.period - period) < 0.25 * period &&
                                   moved <= std::max(0.5 * change, 1e-3);
            // a step too coarse is not a failure: not counted towards the consecutive ones
            if (!too_coarse && ++failures >= max_consecutive_failures)
                return stop_at(std::to_string(failures) +
                               " consecutive corrector failures at E - E_s = " + g(last.excess) +
                               " (E_max - E = " + g(range - last.excess) + "): " + st.note);
            if (dsigma < min_dsigma)
                return stop_at("step size fell below " + g(min_dsigma) +
                               " in -log(E_max - E) at E - E_s = " + g(last.excess) + ": " +
                               st.note);
            continue;
        }
        out.steps.push_back(st);
        failures = 0;
        last_extent = r.extent;
        known.push_back({next, wrap_angle(r.beta), r.period, false, r.action});
        if (known.size() > 2) known.erase(known.begin());
        record(next, known.back().beta, known.back().period);
        out.highest_excess = next;
        if (r.iterations <= 6) dsigma = std::min(1.0, dsigma * 1.5);
    }
    out.success = true;
    return out;
}

}  // namespace flipflux::detail
