// Saddle orbits in Real: the centre-mode guess, the double stage, the Newton / Gauss-Newton polish
// in Real, the final quarter orbit, action, turning points, monodromy and Floquet multipliers
// (see orbits/saddle_orbit.hpp and docs/theory.md#saddle-orbits).
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <string>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/model/critical_points.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/ceres_shooting.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/orbits/shooting.hpp"
#include "saddle_polish.hpp"

namespace flipflux {

template <class Real>
int default_stages() {
    // NOTE: 6 stages at double (53 bits), 10 at quad (113), 14 at 50 digits (168), 20 at 100
    // (334), measured; beyond, as the square root of the digits, capped by the tableau's limit
    const int s = scaled_with_precision(binary_digits<Real>(),
                                        {{53, 6}, {113, 10}, {168, 14}, {334, 20}}, 0.5);
    return s < max_gauss_legendre_stages ? s : max_gauss_legendre_stages;
}

template <class Real>
void check_orbit_energy(const double_pendulum<Real>& model, arm a, const level_arg<Real>& energy) {
    using boost::multiprecision::isfinite;
    using std::isfinite;
    const Real lo = model.saddle_energy(a), hi = model.maximum_energy();
    if (!isfinite(energy.value) || !isfinite(energy.residual) ||
        !(energy.above(model.saddle_level(a)) > 0) || !(energy.below(model.maximum_level()) > 0)) {
        throw input_error::about("energy", "'" + energy.text() + "' is outside the arm-" +
                                               to_string(a) + " saddle-orbit family's range (" +
                                               to_decimal(lo) + ", " + to_decimal(hi) +
                                               "), open at both ends");
    }
    // the continuation starts in double: a pendulum double cannot integrate is refused there too
    check_conditioning(model.coefficients(), std::numeric_limits<double>::epsilon());
}

// log10 of the saddle orbits' Floquet multiplier near the saddle, |mu| ~ exp(lambda T_c) (lambda
// the saddle's growth rate, T_c = 2 pi / omega_c its centre mode's period); growth and centre
// returned too.
template <class Real>
double saddle_log10_multiplier(const double_pendulum<Real>& model, arm a, double& growth,
                               double& centre) {
    const critical_point<Real> cp = flip_saddle(model, a);
    growth = static_cast<double>(cp.modes[1].rate);
    centre = static_cast<double>(cp.modes[0].rate);
    return growth * 2 * std::numbers::pi / centre / std::numbers::ln10;
}

// NOTE: the continuation's quarter-period shots run in double and amplify rounding by about
// |mu|^(1/4): beyond |mu|^(1/4) = 1/eps (log10 |mu| > 4 log10 2^52 = 62.6) they lose every digit
// and it cannot converge, yet its halving steps may take minutes to find that out (a lower link
// 2^20 times heavier, arm 1: log10 |mu| ~ 5.9e3, no result in 60 s). Not attempted there; the
// caller's not-converged path then names the cause (throw_not_converged).
constexpr double hopeless_log10_multiplier = 4 * 52 * 0.30102999566398120;

template <class Real>
std::string continuation_hopeless(const double_pendulum<Real>& model, arm a) {
    double growth = 0, centre = 0;
    const double log10_mu = saddle_log10_multiplier(model, a, growth, centre);
    if (!(log10_mu > hopeless_log10_multiplier)) return "";
    char buf[200];
    std::snprintf(buf, sizeof buf,
                  "not attempted: the multiplier near the saddle is about 1e%.0f, beyond 1e%.1f, "
                  "where a quarter-period shot in double loses every digit",
                  log10_mu, hopeless_log10_multiplier);
    return buf;
}

template <class Real>
void throw_not_converged(const double_pendulum<Real>& model, arm a, const level_arg<Real>& energy,
                         const saddle_orbit<Real>& orbit, const std::string& what) {
    const std::string& stage = orbit.double_stage;
    const Real lo = model.saddle_energy(a), hi = model.maximum_energy();
    if (std::isfinite(orbit.family_end)) {
        // the family ends as saddle orbits below E (continue_double's strip_end)
        const double end = static_cast<double>(lo) + orbit.family_end;
        char buf[96];
        std::snprintf(buf, sizeof buf, "%.6g (E - E_s = %.6g)", end, orbit.family_end);
        throw input_error::about(
            "energy", "'" + energy.text() + "' lies beyond the end of the arm-" + to_string(a) +
                          " saddle-orbit family at E = " + buf + ": there the orbit swings theta" +
                          std::to_string(orbit.family_end_angle) +
                          " to the vertical opposite the saddle's, and beyond it the family's "
                          "orbits leave the saddle's strip |delta| < pi, so they are no dividing "
                          "curve of this saddle (docs/limits.md)");
    }
    const Real gap = energy.below(model.maximum_level());  // E_max - E, carried exactly
    if (gap <= (hi - lo) / 1000000)
        throw input_error::about(
            "energy", "'" + energy.text() + "' is too close to E_max = " + to_decimal(hi) +
                          " for the arm-" + to_string(a) +
                          " saddle orbit in this precision (E_max - E = " +
                          to_decimal(static_cast<double>(gap), 3) +
                          "): its period diverges there and the continuation from the saddle "
                          "stopped short (" +
                          stage + "; docs/theory.md, \"Near E_max\")");
    // A saddle orbit too unstable for the continuation: near the saddle its Floquet multiplier is
    // about exp(lambda T_c) (lambda the saddle's growth rate, T_c = 2 pi / omega_c its centre
    // mode's period), and the continuation's symmetric shooting, which runs in double whatever
    // the precision, amplifies rounding by about |mu|^(1/4): measured, it finds orbits up to
    // |mu| ~ 1e39 near the saddle and fails from ~1e45 (docs/limits.md). Named as the cause
    // where the estimate exceeds 1e30 (a failure below that is not explained by it).
    double growth = 0, centre = 0;
    const double log10_mu = saddle_log10_multiplier(model, a, growth, centre);
    if (log10_mu > 30) {
        char mu[96];
        std::snprintf(mu, sizeof mu,
                      "1e%.0f (exp of the saddle's growth rate %.4g times its centre period %.4g)",
                      log10_mu, growth, 2 * std::numbers::pi / centre);
        throw input_error(what + " at E = " + energy.text() + " (arm " + to_string(a) +
                          "): the pendulum's saddle orbits for this arm are too unstable to be "
                          "found by shooting: their Floquet multiplier near the saddle is about " +
                          mu +
                          ", and the continuation from the saddle (in double at every "
                          "precision) resolves multipliers up to about 1e39 (docs/limits.md; " +
                          stage + ")");
    }
    // Otherwise the cause is not known; the ratio of the saddle's centre frequency to its growth
    // rate is named: where it is large (measured: 2.2e3 for a heavy lower link, docs/limits.md)
    // the quarter-period shots barely see the hyperbolic mode and the shooting is nearly
    // degenerate.
    char ratio[160];
    std::snprintf(ratio, sizeof ratio,
                  "; the saddle's centre frequency %.4g is %.3g times its growth rate %.4g, "
                  "docs/limits.md",
                  centre, centre / growth, growth);
    throw convergence_error(what + " at E = " + to_decimal(energy.value) + " (arm " + to_string(a) +
                            "): no convergence (" + stage + ratio + ")");
}

template <class Real>
orbit_guess<Real> linear_guess(const double_pendulum<Real>& model, arm a) {
    using std::sqrt;
    const critical_point<Real> cp = flip_saddle(model, a);
    const normal_mode<Real>& centre = cp.modes[0];  // oscillatory: largest omega^2 > 0
    std::array<Real, 2> dir = centre.direction;
    const int s = a == arm::two ? 0 : 1;
    if (dir[s] < 0) dir = {-dir[0], -dir[1]};  // start towards positive s
    // velocity along the mode, momentum l = M* a, circularised y = S^-1 l = S a
    const detail::shooting_setup<Real> setup(model, a, Real(1), 1);
    const sym2<Real> m = setup.frame.saddle_mass_matrix();
    const std::array<Real, 2> l{m.xx * dir[0] + m.xy * dir[1], m.xy * dir[0] + m.yy * dir[1]};
    return {setup.direction_of(l), two_pi<Real>() / centre.rate};
}

using namespace saddle_polish;  // the solver's stages

namespace {

/// The periodic residual's rounding floor (~ eps |mu| of the orbit's scale) can leave T farther
/// from the orbit's than the iteration's corrections show, stalled or converged (double: arm 1 of
/// --m1 1 --m2 0.05 --L1 1 --L2 10 --g 0.5 at E = 1.5, |mu| = 1.7e14, stalled, T off by 1.4e-7
/// relative against 4 x its last correction, 1.5e-8; arm 2 of --m1 0.6268 --m2 1.522 --L1 4.369
/// --L2 0.9752 --g 4.816 at E = 41.42421294592, |mu| = 9.0e10, converged, T off by 1.3e-11
/// relative against an estimate of 1.2e-12). Where that floor exceeds 1e-9, the symmetric
/// formulation solved from the periodic solution `p` (a quarter period: amplification
/// ~ |mu|^(1/4)) is an independent solution of the same orbit: the two periods' difference (0 if
/// it does not converge; 0 where the periodic formulation was not used or its floor is below
/// that), of which twice is taken as the period's error if that is larger.
template <class Real>
Real symmetric_period_gap(const detail::shooting_setup<Real>& setup,
                          const orbit_options<Real>& options, const Real& tol, long quarter_steps,
                          const polish<Real>& p, bool periodic_used) {
    using std::abs;
    const Real eps = std::numeric_limits<Real>::epsilon();
    if (!periodic_used || p.chord || !(eps * abs(p.orbit.floquet.multiplier) > Real(1e-9)))
        return 0;
    saddle_orbit<Real> scratch;  // (the cross-check's iteration records its own)
    polish<Real> q{setup, options, tol, quarter_steps, scratch, p.beta, p.period};
    q.newton(false);
    return !q.failed && (q.converged || q.stalled) ? Real(abs(q.period - p.period)) : Real(0);
}

}  // namespace

template <class Real>
saddle_orbit<Real> refine_saddle_orbit(const double_pendulum<Real>& model, arm a,
                                       const level_arg<Real>& energy,
                                       const orbit_guess<Real>& guess,
                                       const orbit_options<Real>& options) {
    using std::abs;
    using std::max;
    check_orbit_energy(model, a, energy);
    const bool periodic = options.method == orbit_method::periodic;
    const bool taylor = options.integrator == orbit_integrator::taylor;
    const Real tol = options.tolerance > 0 ? options.tolerance : default_tolerance<Real>();
    const int stages = taylor ? 0 : (options.stages > 0 ? options.stages : default_stages<Real>());
    const int order = taylor ? taylor_order_for(tol) : 2 * stages;
    const Real excess = energy.above(model.saddle_level(a));
    const Real eps = std::numeric_limits<Real>::epsilon();

    saddle_orbit<Real> orbit;
    orbit.flip_arm = a;
    orbit.energy = energy.value;
    orbit.excess = excess;
    orbit.method = options.method;
    orbit.integrator = options.integrator;
    orbit.stages = stages;
    orbit.order = order;
    orbit.tolerance = tol;

    const double_solution<Real> start = solve_at_double(model, a, excess, guess, periodic);
    orbit.double_stage = start.report;
    if (!start.ok) {
        // NOTE: near E_max the periodic residual's rounding floor at double, eps |mu|, can
        // exceed the orbit's scale (|mu| ~ 1e27 at E_max - 1e-6), while in Real it does not:
        // the polish then starts from the guess itself
        orbit.double_stage +=
            "; not converged at double, polishing the guess in " + precision_name<Real>();
    }

    // ---- polish in Real ----------------------------------------------------------------------
    const detail::shooting_setup<Real> setup(model, a, excess, stages, options.integrator, order);
    const auto est = quarter_steps_for(setup, start.beta, start.period, tol);
    const long quarter_steps = est.steps;
    const Real integration_error = est.error_estimate;
    if (quarter_steps <= 0) {
        orbit.status = orbit_status::not_converged;
        orbit.double_stage += "; the step-size selection failed (non-finite Taylor series)";
        return orbit;
    }
    orbit.steps = periodic ? 4 * quarter_steps : quarter_steps;
    polish<Real> p{setup, options, tol, quarter_steps, orbit, start.beta, start.period};
    if (periodic && !start.ok) {
        // NOTE: where double cannot resolve the periodic residual (eps |mu| too large), the
        // periodic shooting's Newton basin (~ 1 / |mu| in beta) is narrower than the guess's
        // accuracy: the symmetric formulation brings the guess to the working precision first;
        // the periodic residual then decides the orbit.
        p.newton(false);
        orbit.double_stage += p.failed ? "; the symmetric pre-polish failed too"
                                       : "; guess pre-polished by the symmetric formulation";
    }
    // the symmetric solution, kept in case the periodic residual cannot be resolved
    const bool pre_polished = periodic && !start.ok && !p.failed && (p.converged || p.stalled);
    const Real pre_beta = p.beta, pre_period = p.period, pre_update = orbit.last_update;
    const bool pre_converged = p.converged;
    const bool chorded =
        run_polish(model, a, excess, periodic, taylor && start.ok, p, orbit.double_stage);
    bool periodic_used = periodic;
    // (a periodic iterate far from the symmetric solution is another root of the residual:
    // regression, arm 1 at E = 6 - 1e-6 in double reached T < 0)
    const bool periodic_settled = !p.failed && (p.converged || p.stalled) &&
                                  p.period > pre_period / 2 && p.period < 2 * pre_period;
    if (pre_polished && !periodic_settled) {
        // NOTE: the periodic residual's rounding floor is ~ eps |mu| times the orbit's scale;
        // where |mu| > 1 / eps (E_max - E < 1e-4 at double) no periodic iteration can resolve it,
        // while the symmetric formulation (a quarter period, amplification ~ |mu|^(1/4)) still
        // determines the same orbit: it is reported, and the method says so.
        p.beta = pre_beta;
        p.period = pre_period;
        p.failed = false;
        p.converged = pre_converged;
        p.stalled = !pre_converged;
        orbit.last_update = pre_update;
        periodic_used = false;
        orbit.method = orbit_method::symmetric;
        orbit.double_stage += "; the periodic residual is below its rounding floor eps |mu| in " +
                              precision_name<Real>() + ": the symmetric solution is reported";
    }
    if (p.failed || (!p.converged && !p.stalled)) {
        orbit.status = orbit_status::not_converged;
        return orbit;
    }
    orbit.status = p.converged ? orbit_status::converged : orbit_status::stalled;
    orbit.steps = periodic_used ? 4 * quarter_steps : quarter_steps;
    final_shot(p, periodic_used, quarter_steps, chorded);
    orbit.beta = p.beta;
    orbit.period = p.period;

    if (!(orbit.period > 0) || !final_orbit(setup, quarter_steps, orbit) || !(orbit.action > 0)) {
        orbit.status = orbit_status::not_converged;
        return orbit;
    }
    orbit.monodromy = periodic_used ? p.phi : monodromy_from_quarter(p.phi);
    orbit.floquet = floquet_analysis(orbit.monodromy);
    orbit.period_derivative = period_derivative(setup, p, periodic_used);
    // ---- error estimates ---------------------------------------------------------------------
    // NOTE: besides the integration and Newton errors, rounding perturbs the orbit's energy by
    // about eps (E - E_s) (the frame's quantities are all on that scale; plus the measured
    // drift), which moves T by |dT/dE| dE: near E_max, where
    // T ~ log(1 / (E_max - E)), this dominates the period's error (the action is well conditioned,
    // dF/dE = T).
    // NOTE: a stalled iteration stopped improving: its remaining error is of the order of its
    // last corrections, not bounded by the last one (periodic, arm 2, E = 5.999 in double: error
    // 1.06 x the last correction); four times it is taken
    const Real update =
        orbit.status == orbit_status::stalled ? 4 * orbit.last_update : orbit.last_update;
    const Real rel = max({integration_error, update, 16 * eps});
    const Real denergy = (4 * eps + orbit.energy_error) * excess;
    orbit.error_estimate_period =
        max(rel * orbit.period + abs(orbit.period_derivative) * denergy,
            2 * symmetric_period_gap(setup, options, tol, quarter_steps, p, periodic_used));
    orbit.error_estimate_action = rel * orbit.action + orbit.period * denergy;
    return orbit;
}

template <class Real>
saddle_orbit<Real> solve_saddle_orbit(const double_pendulum<Real>& model, arm a,
                                      const level_arg<Real>& energy,
                                      const orbit_options<Real>& options) {
    check_orbit_energy(model, a, energy);
    const orbit_guess<Real> lin = linear_guess(model, a);
    const double_pendulum<double> md = to_double(model);
    const double target = static_cast<double>(energy.above(model.saddle_level(a)));
    auto failed = [&](const std::string& reason, double family_end = NAN, int angle = 0) {
        saddle_orbit<Real> f;
        f.flip_arm = a;
        f.energy = energy.value;
        f.excess = energy.above(model.saddle_level(a));
        f.status = orbit_status::not_converged;
        f.double_stage = "continuation from the centre mode failed: " + reason;
        f.family_end = family_end;
        f.family_end_angle = angle;
        return f;
    };
    if (const std::string hopeless = continuation_hopeless(model, a); !hopeless.empty())
        return failed(hopeless);
    // NOTE: the continuation's corrector is the symmetric Newton iteration whatever the method:
    // its basin is that of a quarter period, about sqrt(|mu|) times wider than the periodic
    // shooting's (Ceres' continuation stalls near E_max, see docs/theory.md); the orbit itself
    // is then found by the requested formulation from this guess.
    const auto c = detail::continue_double(md, a, false, default_stages<double>(), 1e-12,
                                           static_cast<double>(lin.beta),
                                           static_cast<double>(lin.period), {target});
    if (!c.success) return failed(c.stop_reason, c.strip_end, c.strip_angle);
    const detail::double_orbit& o = c.orbits.back();
    return refine_saddle_orbit(model, a, energy, orbit_guess<Real>{Real(o.beta), Real(o.period)},
                               options);
}

template <class Real>
saddle_family<Real> continue_saddle_family(const double_pendulum<Real>& model, arm a,
                                           const std::vector<energy_level<Real>>& energies,
                                           const orbit_options<Real>& options) {
    saddle_family<Real> family;
    family.flip_arm = a;
    std::vector<double> targets;
    for (std::size_t i = 0; i < energies.size(); ++i) {
        check_orbit_energy(model, a, energies[i]);
        const Real excess = energies[i].above(model.saddle_level(a));
        if (i > 0 && !(excess > energies[i - 1].above(model.saddle_level(a))))
            throw input_error::about("energy", "the energies must increase ('" +
                                                   to_decimal(energies[i].value) + "' follows '" +
                                                   to_decimal(energies[i - 1].value) + "')");
        targets.push_back(static_cast<double>(excess));
        if (i > 0 && !(targets[i] > targets[i - 1]))
            throw input_error::about(
                "energy", "'" + to_shortest_decimal(energies[i].value) +
                              "' is not distinguishable from the previous energy at double");
    }
    if (const std::string hopeless = continuation_hopeless(model, a); !hopeless.empty()) {
        family.stop_reason = hopeless;
        return family;
    }
    const orbit_guess<Real> lin = linear_guess(model, a);
    const auto c = detail::continue_double(to_double(model), a, false, default_stages<double>(),
                                           1e-12, static_cast<double>(lin.beta),
                                           static_cast<double>(lin.period), targets);
    family.steps = c.steps;
    family.halvings = c.halvings;
    family.highest_excess = c.highest_excess;
    family.stop_reason = c.stop_reason;
    std::size_t i = 0;
    for (const detail::double_orbit& o : c.orbits) {
        if (!o.requested) continue;
        family.orbits.push_back(refine_saddle_orbit(
            model, a, energies[i], orbit_guess<Real>{Real(o.beta), Real(o.period)}, options));
        ++i;
    }
    return family;
}

template <class Real>
phase_point<Real> orbit_state(const double_pendulum<Real>& model, const saddle_orbit<Real>& orbit,
                              const Real& t) {
    using std::floor;
    if (orbit.quarter.size() < 2 || !(orbit.period > 0))
        throw std::invalid_argument("orbit_state: the orbit has no solution stored");
    const Real T = orbit.period, tau = T / 4;
    Real u = t - floor(t / T) * T;  // [0, T)
    int sign = 1;                   // P = -1 in frame coordinates
    if (u >= 2 * tau) {
        u -= 2 * tau;
        sign = -1;
    }
    bool reversed = false;  // R: l -> -l, t -> 2 tau - t
    if (u > tau) {
        u = 2 * tau - u;
        reversed = true;
    }
    const long n = static_cast<long>(orbit.quarter.size()) - 1;
    long j = static_cast<long>(floor(u / orbit.quarter_step));
    if (j < 0) j = 0;
    if (j > n) j = n;
    std::array<Real, 4> x = orbit.quarter[static_cast<std::size_t>(j)];
    const Real dt = u - j * orbit.quarter_step;
    if (dt != 0) {
        const saddle_frame<Real> frame(model, orbit.flip_arm);
        std::array<Real, 5> y{x[0], x[1], x[2], x[3], Real(0)};
        if (orbit.integrator == orbit_integrator::taylor && orbit.order > 0) {
            // dense output: the step's Taylor polynomial at dt
            taylor_integrator<Real, 5> ti(orbit.order);
            saddle_taylor_flow<Real> f(frame, orbit.order);
            ti.integrate(f, y, dt, 1);
        } else {
            gauss_legendre<Real, 5> gl(orbit.stages > 0 ? orbit.stages : default_stages<Real>());
            gl.integrate(orbit_flow<Real>{&frame}, y, dt, 1);
        }
        x = {y[0], y[1], y[2], y[3]};
    }
    if (reversed) {
        x[2] = -x[2];
        x[3] = -x[3];
    }
    for (Real& v : x)
        v *= sign;
    const saddle_frame<Real> frame(model, orbit.flip_arm);
    return frame.absolute(x);
}

template int default_stages<inst_real>();
template void check_orbit_energy<inst_real>(const double_pendulum<inst_real>&, arm,
                                            const level_arg<inst_real>&);
template void throw_not_converged<inst_real>(const double_pendulum<inst_real>&, arm,
                                             const level_arg<inst_real>&,
                                             const saddle_orbit<inst_real>&, const std::string&);
template orbit_guess<inst_real> linear_guess<inst_real>(const double_pendulum<inst_real>&, arm);
template saddle_orbit<inst_real> refine_saddle_orbit<inst_real>(const double_pendulum<inst_real>&,
                                                                arm, const level_arg<inst_real>&,
                                                                const orbit_guess<inst_real>&,
                                                                const orbit_options<inst_real>&);
template saddle_orbit<inst_real> solve_saddle_orbit<inst_real>(const double_pendulum<inst_real>&,
                                                               arm, const level_arg<inst_real>&,
                                                               const orbit_options<inst_real>&);
template saddle_family<inst_real> continue_saddle_family<inst_real>(
    const double_pendulum<inst_real>&, arm, const std::vector<energy_level<inst_real>>&,
    const orbit_options<inst_real>&);
template phase_point<inst_real> orbit_state<inst_real>(const double_pendulum<inst_real>&,
                                                       const saddle_orbit<inst_real>&,
                                                       const inst_real&);

}  // namespace flipflux
