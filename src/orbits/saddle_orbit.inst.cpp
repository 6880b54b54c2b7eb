// Saddle orbits in Real: the centre-mode guess, the double stage, the Newton / Gauss-Newton polish
// in Real, the final quarter orbit, action, turning points, monodromy and Floquet multipliers
// (see orbits/saddle_orbit.hpp and docs/theory.md#saddle-orbits).
#include <cmath>
#include <cstdio>
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
        throw input_error::about("energy", "'" + to_decimal(energy.value) +
                                               "' is outside the arm-" + to_string(a) +
                                               " saddle-orbit family's range (" + to_decimal(lo) +
                                               ", " + to_decimal(hi) + "), open at both ends");
    }
    // the continuation starts in double: a pendulum double cannot integrate is refused there too
    check_conditioning(model.coefficients(), std::numeric_limits<double>::epsilon());
}

template <class Real>
void throw_not_converged(const double_pendulum<Real>& model, arm a, const level_arg<Real>& energy,
                         const std::string& stage, const std::string& what) {
    const Real lo = model.saddle_energy(a), hi = model.maximum_energy();
    const Real gap = energy.below(model.maximum_level());  // E_max - E, carried exactly
    if (gap <= (hi - lo) / 1000000)
        throw input_error::about(
            "energy", "'" + to_decimal(energy.value) +
                          "' is too close to E_max = " + to_decimal(hi) + " for the arm-" +
                          to_string(a) + " saddle orbit in this precision (E_max - E = " +
                          to_decimal(static_cast<double>(gap), 3) +
                          "): its period diverges there and the continuation from the saddle "
                          "stopped short (" +
                          stage + "; docs/theory.md, \"Near E_max\")");
    throw std::runtime_error(what + " at E = " + to_decimal(energy.value) + " (arm " +
                             to_string(a) + "): no convergence (" + stage + ")");
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

namespace {

template <class Real>
double_pendulum<double> to_double(const double_pendulum<Real>& model) {
    return double_pendulum<double>(convert_parameters<double>(model.parameters()));
}

template <class Real>
Real default_tolerance() {
    return 64 * std::numeric_limits<Real>::epsilon();
}

/// Integration scales of the frame state (+ action) from an approximate orbit.
template <class Real>
std::array<Real, 5> orbit_scales(const detail::shooting_setup<Real>& setup, const Real& beta,
                                 const Real& period) {
    using std::abs;
    using std::max;
    using std::sqrt;
    const auto x0 = setup.start(beta);
    const Real lscale = max(abs(x0[2]), abs(x0[3]));
    const auto& k = setup.frame.coefficients();
    // displacement ~ |w| T / (2 pi), |w| ~ |l| / (A + B)
    const Real dscale = lscale / (k.A + k.B) * period / 4;
    return {dscale, dscale, lscale, lscale, setup.excess * period};
}

/// The double stage: (beta, T) solved at double from the guess (Ceres or Newton); `ok` false
/// when it did not converge, the guess then being returned unchanged.
template <class Real>
struct double_solution {
    Real beta, period;
    bool ok = true;
    std::string report;
};

template <class Real>
double_solution<Real> solve_at_double(const double_pendulum<Real>& model, arm a, const Real& excess,
                                      const orbit_guess<Real>& guess, bool periodic) {
    double_solution<Real> out;
    out.beta = guess.beta;
    out.period = guess.period;
    const double_pendulum<double> md = to_double(model);
    const double ed = static_cast<double>(excess);
    const int sd = default_stages<double>();
    const detail::shooting_setup<double> sdset(md, a, ed, sd);
    const double bd = static_cast<double>(out.beta), pd = static_cast<double>(out.period);
    const auto sc = orbit_scales(sdset, bd, pd);
    const auto x0 = sdset.start(bd);
    const std::array<double, 5> y0{x0[0], x0[1], x0[2], x0[3], 0.0};
    // NOTE: steps are chosen on the quarter orbit for both methods: the endpoint error of a
    // full period is amplified by the multiplier, which says nothing about the local accuracy
    const auto est = steps_for_tolerance<double, 5>(orbit_flow<double>{&sdset.frame}, y0, pd / 4,
                                                    1e-13, sd, sc, 4);
    const long n = periodic ? 4 * est.steps : est.steps;
    const auto r = periodic ? detail::ceres_periodic_shooting(md, a, ed, bd, pd, n, sd)
                            : detail::newton_symmetric_shooting(md, a, ed, bd, pd, n, sd);
    out.report = r.report;
    // NOTE: the guess comes from the continuation (symmetric Newton at double, 1e-12 or better):
    // a "converged" solution whose period is not within a factor of two of it is another root
    // of the residual (regression: arm 1 at E = 6 - 1e-6, periodic, Ceres converged to T < 0)
    if (r.converged && !(r.period > pd / 2 && r.period < 2 * pd)) {
        char note[160];
        std::snprintf(note, sizeof note, "; its period %.17g is not near the guess's %.17g",
                      r.period, pd);
        out.report += note;
        out.ok = false;
        return out;
    }
    if (r.converged) {
        out.beta = Real(std::remainder(r.beta, 2 * M_PI));
        out.period = Real(r.period);
    } else {
        out.ok = false;
    }
    return out;
}

/// The polish in Real: Newton (symmetric) or Gauss-Newton (periodic) on (beta, T), keeping the
/// last monodromy and Jacobian for the monodromy and dT/dE.
template <class Real>
struct polish {
    const detail::shooting_setup<Real>& setup;
    const orbit_options<Real>& options;
    const Real tol;
    const long quarter_steps;
    saddle_orbit<Real>& orbit;
    Real beta, period;
    std::array<std::array<Real, 4>, 4> phi{};
    std::array<std::array<Real, 2>, 4> jac4{};  // last Jacobian (periodic)
    std::array<std::array<Real, 2>, 2> jac2{};  // last Jacobian (symmetric)
    Real beta_at_jacobian;
    bool converged = false, stalled = false, failed = false;
    /// Chord iteration: jac4 / jac2 stay as given (from a lower precision), each iteration is a
    /// shot without the variational equations (linear convergence at a rate of about the
    /// Jacobian's relative error times its condition).
    bool chord = false;
    /// With the chord iteration: when set, the Jacobian is refreshed at every iterate by a shot
    /// of this (lower-order, cheaper) setup: about a third of the digits, so the iteration
    /// gains a factor ~ min(error, 10^(-digits/3)) per step instead of quad's 1e-30.
    const detail::shooting_setup<Real>* jacobian_setup = nullptr;
    /// With the chord iteration: the error of the starting point (quad's accuracy), from which
    /// each state shot is run at the order its iterate needs (0: every shot at the full order).
    /// NOTE: an iterate with error e becomes one with error >= ~ e^2 whatever the residual's
    /// accuracy below that: its shot needs only tolerance ~ e^2 (1e-10 of margin), at an order
    /// (and, graded, a precision) growing with the digits gained. The iterate's error is taken as
    /// the square of the last correction (as if the convergence were quadratic: the smallest it
    /// can be, so the shot is never less accurate than needed). mp:300, E = 4: the first three
    /// shots of four cost ~ 1/100, 1/10 and 2/3 of a full one.
    Real start_error = 0;

    polish(const detail::shooting_setup<Real>& s, const orbit_options<Real>& o, const Real& t,
           long q, saddle_orbit<Real>& out, const Real& b, const Real& T)
        : setup(s),
          options(o),
          tol(t),
          quarter_steps(q),
          orbit(out),
          beta(b),
          period(T),
          beta_at_jacobian(b) {}

    /// One shot at (beta, T): residual norm, monodromy and Jacobian recorded; the Newton update
    /// (dbeta, dT), or nullopt if the integration failed.
    std::optional<std::array<Real, 2>> shoot(bool per, long n, int columns = 2) {
        using std::sqrt;
        if (per) {
            const auto pr = detail::periodic_shooting(setup, beta, period, n, columns);
            if (!pr.end.success) return std::nullopt;
            Real rn = 0;
            for (const Real& v : pr.r)
                rn += v * v;
            orbit.residual = sqrt(rn);
            phi = pr.end.phi;
            jac4 = pr.jacobian;
            beta_at_jacobian = beta;
            return detail::least_squares_4x2(pr.jacobian, pr.r);
        }
        const auto sr = detail::symmetric_shooting(setup, beta, period / 4, n, columns);
        if (!sr.end.success) return std::nullopt;
        orbit.residual = sqrt(sr.r[0] * sr.r[0] + sr.r[1] * sr.r[1]);
        phi = sr.end.phi;
        jac2 = sr.jacobian;
        beta_at_jacobian = beta;
        auto d = detail::solve_2x2(sr.jacobian, sr.r);
        d[1] *= 4;  // tau -> T
        return d;
    }

    /// The final periodic shot with the monodromy from half the period (Taylor route): the frame's
    /// flow is odd (f(-x) = -f(x), so J(-x) = J(x)) and the orbit is P-invariant,
    /// x(t + T/2) = -x(t), hence Phi(T, T/2) = Phi(T/2, 0) and M = Phi(T/2)^2; the second half is
    /// integrated without the variational equations for the residual x(T) - x(0).
    /// NOTE: half the variational work; the rounding error of M is ~ eps |mu|^(1/2) relative
    /// instead of eps |mu| (the published estimate 2 eps |mu| bounds both).
    std::optional<std::array<Real, 2>> shoot_periodic_by_halves(long n) {
        using std::sqrt;
        const auto x0 = setup.start(beta);
        const auto half = detail::integrate_variational(setup, x0, period / 2, n / 2, 4);
        if (!half.success) return std::nullopt;
        const auto rest = detail::integrate_state(setup, half.x, period / 2, n / 2);
        if (!rest.success) return std::nullopt;
        std::array<std::array<Real, 4>, 4> m{};
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                m[i][j] = 0;
                for (int k = 0; k < 4; ++k)
                    m[i][j] += half.phi[i][k] * half.phi[k][j];
            }
        std::array<Real, 4> f, r;
        setup.frame.rhs(rest.x, f);
        const auto dl = setup.momentum_derivative(beta);
        const Real inv = 1 / setup.momentum_scale;
        Real rn = 0;
        for (int i = 0; i < 4; ++i) {
            r[i] = (rest.x[i] - x0[i]) * inv;
            rn += r[i] * r[i];
            Real v = m[i][2] * dl[0] + m[i][3] * dl[1];  // (M - I) dx0/dbeta
            if (i >= 2) v -= dl[i - 2];
            jac4[i][0] = v * inv;
            jac4[i][1] = f[i] * inv;
        }
        orbit.residual = sqrt(rn);
        phi = m;
        beta_at_jacobian = beta;
        return detail::least_squares_4x2(jac4, r);
    }

    /// The chord update at (beta, T): the residual from a state-only shot, the kept Jacobian.
    std::optional<std::array<Real, 2>> chord_step(bool per, long n, const Real& error) {
        using std::max;
        using std::sqrt;
        const auto x0 = setup.start(beta);
        const Real inv = 1 / setup.momentum_scale;
        if (jacobian_setup != nullptr) {
            if (per) {
                const auto pr = detail::periodic_shooting(*jacobian_setup, beta, period, n, 2);
                if (!pr.end.success) return std::nullopt;
                jac4 = pr.jacobian;
            } else {
                const auto sr = detail::symmetric_shooting(*jacobian_setup, beta, period / 4, n, 2);
                if (!sr.end.success) return std::nullopt;
                jac2 = sr.jacobian;
            }
        }
        detail::shooting_setup<Real> ladder = setup;
        if (error > 0) {
            const int order = taylor_order_for(Real(max(tol, Real(error * error / 1e10))));
            if (order < setup.order) ladder.order = order;
        }
        const auto e = detail::integrate_state(ladder, x0, per ? period : period / 4, n);
        if (!e.success) return std::nullopt;
        if (per) {
            std::array<Real, 4> r;
            Real rn = 0;
            for (int i = 0; i < 4; ++i) {
                r[i] = (e.x[i] - x0[i]) * inv;
                rn += r[i] * r[i];
            }
            orbit.residual = sqrt(rn);
            return detail::least_squares_4x2(jac4, r);
        }
        const std::array<Real, 2> r{e.x[2] * inv, e.x[3] * inv};
        orbit.residual = sqrt(r[0] * r[0] + r[1] * r[1]);
        auto d = detail::solve_2x2(jac2, r);
        d[1] *= 4;  // tau -> T
        return d;
    }

    /// Newton / Gauss-Newton (or the chord iteration) on one formulation from (beta, period),
    /// updating them.
    void newton(bool per) {
        using std::abs;
        using std::max;
        using std::sqrt;
        Real last = std::numeric_limits<Real>::max();
        converged = stalled = failed = false;
        const long n = per ? 4 * quarter_steps : quarter_steps;
        int it = 0;
        for (it = 1; it <= options.max_newton_iterations; ++it) {
            const Real error = it == 1 ? start_error : last * last;
            const auto step = chord ? chord_step(per, n, error) : shoot(per, n);
            if (!step) {
                failed = true;
                break;
            }
            const std::array<Real, 2>& d = *step;
            using boost::multiprecision::isfinite;
            using std::isfinite;
            if (!isfinite(d[0]) || !isfinite(d[1])) {
                failed = true;
                break;
            }
            beta -= d[0];
            period -= d[1];
            const Real size = max(abs(d[0]), abs(d[1]) / period);
            orbit.last_update = size;
            // NOTE: Newton converges quadratically (up to the O(tol) inexactness of the T
            // column); the next update is predicted at the observed rate (conservative for
            // quadratic convergence, exact for the chord's linear one), and the iteration stops
            // when it would be below the tolerance. A stall (no halving) means the rounding floor
            // of the residual.
            const Real predicted = it >= 2 ? size * size / last : std::numeric_limits<Real>::max();
            if (size <= tol || predicted <= tol / 4) {
                converged = true;
                break;
            }
            if (it >= 2 && size > last / 2) {
                stalled = size <= sqrt(tol);
                if (stalled) break;
            }
            // NOTE: the polish starts in Newton's basin (from the double stage, 1e-10 or
            // better): a large or growing correction means it did not, and further iterations
            // only wander
            if (size > Real(1) / 1000 || (it >= 2 && size > 2 * last)) {
                failed = true;
                break;
            }
            last = size;
        }
        orbit.newton_iterations += it;
    }
};

/// Equal steps on the quarter orbit from (beta, T) for the tolerance, by the setup's integrator.
/// NOTE: steps are chosen on the quarter orbit for both formulations: the endpoint error of a
/// full period is amplified by the multiplier, which says nothing about the local accuracy
template <class Real>
step_count_estimate<Real> quarter_steps_for(const detail::shooting_setup<Real>& setup,
                                            const Real& beta, const Real& period, const Real& tol) {
    const auto scale = orbit_scales(setup, beta, period);
    const auto x0 = setup.start(beta);
    const std::array<Real, 5> y0{x0[0], x0[1], x0[2], x0[3], Real(0)};
    if (setup.integrator == orbit_integrator::taylor)
        return taylor_steps_for_tolerance<Real, 5>(
            [&setup](int order) { return saddle_taylor_flow<Real>(setup.frame, order); }, y0,
            period / 4, tol, scale, 4);
    return steps_for_tolerance<Real, 5>(orbit_flow<Real>{&setup.frame}, y0, period / 4, tol,
                                        setup.stages, scale, 16);
}

/// The first iterations in quad, for a Real of more digits with the Taylor integrator: Newton in
/// quad from the double stage's (beta, T) to quad's accuracy, then p continues from there by the
/// chord iteration with quad's last Jacobian (converted). False (p unchanged) if quad did not
/// converge.
/// NOTE: the residual's Jacobian need not be exact: with quad's (relative error ~ 1e-32 times
/// the problem's condition) each chord iteration gains ~ 30 digits at the cost of a shot without
/// the variational equations (a quarter of the work of one with them); the monodromy, which
/// must be exact, comes from one variational shot at the solution (refine_saddle_orbit).
template <class Real>
bool polish_in_quad(const double_pendulum<Real>& model, arm a, const Real& excess, bool periodic,
                    polish<Real>& p, std::string& report) {
    const double_pendulum<quad> mq(convert_parameters<quad>(model.parameters()));
    const quad tq = default_tolerance<quad>();
    const detail::shooting_setup<quad> sq(mq, a, convert<quad>(excess), 0, orbit_integrator::taylor,
                                          taylor_order_for(tq));
    const quad bq = convert<quad>(p.beta), Tq = convert<quad>(p.period);
    const auto est = quarter_steps_for(sq, bq, Tq, tq);
    if (est.steps <= 0) return false;
    saddle_orbit<quad> oq;
    const orbit_options<quad> options_q;
    polish<quad> pq{sq, options_q, tq, est.steps, oq, bq, Tq};
    pq.newton(periodic);
    if (!pq.converged) return false;
    p.beta = convert<Real>(pq.beta);
    p.period = convert<Real>(pq.period);
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 2; ++j)
            p.jac4[i][j] = convert<Real>(pq.jac4[i][j]);
    for (int i = 0; i < 2; ++i)
        for (int j = 0; j < 2; ++j)
            p.jac2[i][j] = convert<Real>(pq.jac2[i][j]);
    p.chord = true;
    using std::max;
    p.start_error = 16 * max(convert<Real>(tq), convert<Real>(oq.last_update));
    report += "; Newton in quad (" + std::to_string(oq.newton_iterations) +
              " iterations), then the chord iteration with quad's Jacobian";
    return true;
}

/// Newton from p's (beta, T); for a Real above quad with the Taylor integrator (`ladder`), quad's
/// Newton first, then the chord iteration in Real (Newton if it does not converge). True if the
/// chord iteration was used.
template <class Real>
bool run_polish(const double_pendulum<Real>& model, arm a, const Real& excess, bool periodic,
                bool ladder, polish<Real>& p, std::string& report) {
    bool chorded = false;
    detail::shooting_setup<Real> lower = p.setup;
    if constexpr (has_variable_precision_v<Real>) {
        if (ladder && !p.failed && binary_digits<Real>() > std::numeric_limits<quad>::digits)
            chorded = polish_in_quad(model, a, excess, periodic, p, report);
        // NOTE: above ~ 4 x quad's digits quad's Jacobian gains too few digits per iteration
        // (ten iterations at mp:300): the Jacobian is then refreshed at each iterate by a shot
        // of a third of the order (a third of the digits, ~ 1/9 of the work)
        if (chorded && binary_digits<Real>() > 4 * std::numeric_limits<quad>::digits) {
            using std::cbrt;
            lower.order = taylor_order_for(cbrt(p.tol));
            p.jacobian_setup = &lower;
            report +=
                " refreshed at every iterate by an order-" + std::to_string(lower.order) + " shot";
        }
    } else {
        (void)model, (void)a, (void)excess, (void)ladder, (void)report;
    }
    if (!p.failed) p.newton(periodic);
    if (chorded && (p.failed || (!p.converged && !p.stalled))) {
        report += "; the chord iteration did not converge: Newton";
        p.chord = false;
        p.failed = false;
        p.newton(periodic);
    }
    p.chord = false;
    p.jacobian_setup = nullptr;
    return chorded;
}

/// The variational shot at the final (beta, T): the monodromy, the Jacobian (for dT/dE) and the
/// residual are those of the reported orbit (those of the last Newton iterate are off by its
/// correction, amplified by |mu| in the monodromy: quad's stability index was 1e-24 off at
/// E = 4, mu = 3.7e3).
template <class Real>
void final_shot(polish<Real>& p, bool periodic, long quarter_steps, bool chorded) {
    using std::abs;
    using std::max;
    const bool halves = periodic && p.setup.integrator == orbit_integrator::taylor;
    const auto update = halves ? p.shoot_periodic_by_halves(4 * quarter_steps)
                               : p.shoot(periodic, periodic ? 4 * quarter_steps : quarter_steps, 4);
    // NOTE: after the chord iteration the distance to the root is measured, not bounded by the
    // last correction applied (the chord's rate is ~ 1e-30: that bound would be 30 digits too
    // pessimistic): it is the Newton correction at the reported point (exact Jacobian; not
    // applied: the monodromy is that point's), accurate to its square
    if (chorded && update)
        p.orbit.last_update = max(abs((*update)[0]), abs((*update)[1]) / p.period);
}

/// The final orbit at (beta, T): the quarter grid, the action F, the strip check, the energy
/// drift and the turning points. False if the integration failed or the orbit left its strip.
template <class Real>
bool final_orbit(const detail::shooting_setup<Real>& setup, long quarter_steps,
                 saddle_orbit<Real>& orbit) {
    using std::abs;
    const auto x0 = setup.start(orbit.beta);
    orbit.quarter_step = orbit.period / 4 / quarter_steps;
    orbit.quarter.reserve(static_cast<std::size_t>(quarter_steps + 1));
    orbit.quarter.push_back(x0);
    {
        std::array<Real, 5> y{x0[0], x0[1], x0[2], x0[3], Real(0)};
        const auto keep = [&](long, const std::array<Real, 5>& z) {
            orbit.quarter.push_back({z[0], z[1], z[2], z[3]});
        };
        integration_result r;
        if (setup.integrator == orbit_integrator::taylor) {
            taylor_integrator<Real, 5> ti(setup.order);
            saddle_taylor_flow<Real> f(setup.frame, setup.order);
            r = ti.integrate(f, y, orbit.quarter_step, quarter_steps, keep);
        } else {
            gauss_legendre<Real, 5> gl(setup.stages);
            r = gl.integrate(orbit_flow<Real>{&setup.frame}, y, orbit.quarter_step, quarter_steps,
                             keep);
        }
        if (!r.success) return false;
        // NOTE: F = 4 x the quarter's action (time reversal and reflection map the quarter onto
        // the other three). Integrating the whole period instead would follow the unstable orbit
        // for four times longer, with rounding errors amplified by |mu| instead of |mu|^(1/4).
        orbit.action = 4 * y[4];
    }
    // the saddle orbit stays in its saddle's strip |delta| < pi (see detail::quarter_extent)
    for (const auto& z : orbit.quarter) {
        if (!(abs(z[0]) < pi<Real>()) || !(abs(z[1]) < pi<Real>())) {
            orbit.double_stage += "; the refined solution left the saddle's strip |delta| < pi";
            return false;
        }
    }
    Real energy_error = 0;
    for (const auto& z : orbit.quarter) {
        const Real e = abs(setup.frame.excess_energy(z) - orbit.excess) / orbit.excess;
        if (e > energy_error) energy_error = e;
    }
    orbit.energy_error = energy_error;
    const auto q = setup.frame.saddle();
    orbit.saddle = q;
    orbit.start = setup.frame.absolute(x0);
    const auto& tp = orbit.quarter.back();
    orbit.turning_points = {std::array<Real, 2>{q[0] + tp[0], q[1] + tp[1]},
                            std::array<Real, 2>{q[0] - tp[0], q[1] - tp[1]}};
    return true;
}

/// The monodromy from the quarter orbit's: M = (R Phi_q^-1 R Phi_q)^2 with Phi_q^-1 = -J Phi_q^T J
/// (symplectic), R = diag(1,1,-1,-1).
template <class Real>
std::array<std::array<Real, 4>, 4> monodromy_from_quarter(
    const std::array<std::array<Real, 4>, 4>& phi) {
    std::array<std::array<Real, 4>, 4> inv{}, half{}, m{};
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            // (-J Phi^T J)_ij: J = [[0, I], [-I, 0]]; (Phi^-1)_ij = s_ij Phi_{j', i'}
            const int ii = (i + 2) % 4, jj = (j + 2) % 4;
            const int sgn = ((i < 2) == (j < 2)) ? 1 : -1;
            inv[i][j] = sgn * phi[jj][ii];
        }
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            Real v = 0;
            for (int k = 0; k < 4; ++k) {
                const int ri = i < 2 ? 1 : -1, rk = k < 2 ? 1 : -1;
                v += ri * inv[i][k] * rk * phi[k][j];
            }
            half[i][j] = v;
        }
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            Real v = 0;
            for (int k = 0; k < 4; ++k)
                v += half[i][k] * half[k][j];
            m[i][j] = v;
        }
    return m;
}

/// dT/dE from the last Jacobian: J (dbeta, dT)/dE = -dr/dE, where x0 depends on E through
/// l0 = sqrt(2 (E - E_s)) S u(beta), dl0/dE = l0 / (2 (E - E_s)).
template <class Real>
Real period_derivative(const detail::shooting_setup<Real>& setup, const polish<Real>& p,
                       bool periodic) {
    const auto l0 = setup.momentum(p.beta_at_jacobian);
    const Real inv = 1 / (2 * p.orbit.excess * setup.momentum_scale);  // scaled residuals
    const std::array<Real, 2> dl{l0[0] * inv, l0[1] * inv};
    if (periodic) {
        std::array<Real, 4> dr;
        for (int i = 0; i < 4; ++i) {
            Real v = p.phi[i][2] * dl[0] + p.phi[i][3] * dl[1];
            if (i >= 2) v -= dl[i - 2];
            dr[i] = -v;
        }
        return detail::least_squares_4x2(p.jac4, dr)[1];
    }
    std::array<Real, 2> dr;
    for (int i = 0; i < 2; ++i)
        dr[i] = -(p.phi[2 + i][2] * dl[0] + p.phi[2 + i][3] * dl[1]);
    return 4 * detail::solve_2x2(p.jac2, dr)[1];
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
    orbit.error_estimate_period = rel * orbit.period + abs(orbit.period_derivative) * denergy;
    orbit.error_estimate_action = rel * orbit.action + orbit.period * denergy;
    return orbit;
}

template <class Real>
std::string replica_problem(const double_pendulum<Real>& model, const saddle_orbit<Real>& o) {
    using std::abs;
    using std::max;
    using std::pow;
    const bool periodic = o.method == orbit_method::periodic;
    const bool taylor = o.integrator == orbit_integrator::taylor;
    const long quarter_steps = static_cast<long>(o.quarter.size()) - 1;
    // the record's own numbers decide the work: bounded as a solve would choose them
    if (quarter_steps < 1 || quarter_steps > 100000000L) return "its quarter grid is out of range";
    // (a solve picks about eps's Taylor order, or default_stages: a record asking for far more
    // work per step than that is no record of this program)
    const int most_order =
        std::min(2 * taylor_order_for(std::numeric_limits<Real>::epsilon()) + 10, max_taylor_order);
    if (taylor ? (o.order < 1 || o.order > most_order)
               : (o.stages < 1 ||
                  o.stages > std::min(4 * default_stages<Real>() + 8, max_gauss_legendre_stages)))
        return "its integrator order is out of range";
    if (!(o.period > 0) || !(o.excess > 0)) return "its period or energy is not > 0";
    const int order = taylor ? o.order : 2 * o.stages;
    const detail::shooting_setup<Real> setup(model, o.flip_arm, o.excess, taylor ? 0 : o.stages,
                                             o.integrator, order);
    orbit_options<Real> options;
    options.method = o.method;
    options.integrator = o.integrator;
    saddle_orbit<Real> r;
    r.flip_arm = o.flip_arm;
    r.excess = o.excess;
    polish<Real> p{setup, options, o.tolerance, quarter_steps, r, o.beta, o.period};
    // the solver's last shot and final orbit, replayed at the recorded (beta, T)
    const bool halves = periodic && taylor;
    const auto shot = halves ? p.shoot_periodic_by_halves(4 * quarter_steps)
                             : p.shoot(periodic, periodic ? 4 * quarter_steps : quarter_steps, 4);
    r.beta = o.beta;
    r.period = o.period;
    if (!shot || !final_orbit(setup, quarter_steps, r))
        return "its orbit cannot be integrated again";
    const auto monodromy = periodic ? p.phi : monodromy_from_quarter(p.phi);
    const floquet_multipliers<Real> floquet = floquet_analysis(monodromy);
    const Real period_slope = period_derivative(setup, p, periodic);
    // NOTE: the replay repeats the solver's arithmetic, so it agrees to the rounding of the
    // record's decimals (exact at double and quad; mp:N records N + 2 of its guard digits),
    // amplified by the multiplier in the monodromy and dT/dE; 1000 times that is allowed (and
    // never more than 1e-3: a doubled value is always found)
    const Real eps = std::numeric_limits<Real>::epsilon();
    const Real printed = pow(Real(10), Real(1 - output_digits<Real>()));
    const Real base = 1000 * max(eps, printed);
    const Real mu = max(Real(1), abs(floquet.multiplier));
    const Real cap = Real(1) / 1000;
    const Real tight = base < cap ? base : cap;
    const Real loose = base * mu < cap ? base * mu : cap;
    const auto differs = [](const Real& a, const Real& b, const Real& tol) {
        return !(abs(a - b) <= tol * max(abs(a), abs(b)));
    };
    if (differs(o.action, r.action, tight))
        return "its action F = " + to_decimal(o.action) + " is not its orbit's (" +
               to_decimal(r.action) + " by quadrature along the recorded orbit)";
    Real scale = 0, deviation = 0;
    for (std::size_t i = 0; i < o.quarter.size(); ++i)
        for (int k = 0; k < 4; ++k) {
            scale = max(scale, abs(r.quarter[i][k]));
            deviation = max(deviation, abs(o.quarter[i][k] - r.quarter[i][k]));
        }
    if (!(deviation <= tight * scale)) return "its quarter orbit is not the recorded (beta, T)'s";
    Real m_scale = 0, m_deviation = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            m_scale = max(m_scale, abs(monodromy[i][j]));
            m_deviation = max(m_deviation, abs(o.monodromy[i][j] - monodromy[i][j]));
        }
    if (!(m_deviation <= loose * m_scale))
        return "its monodromy is not its orbit's (integrated again along it)";
    if (differs(o.floquet.multiplier, floquet.multiplier, loose) ||
        differs(o.floquet.stability_index, floquet.stability_index, loose) ||
        differs(o.floquet.trace, floquet.trace, loose))
        return "its multiplier " + to_decimal(o.floquet.multiplier) + " (stability index " +
               to_decimal(o.floquet.stability_index) + ") is not its monodromy's (" +
               to_decimal(floquet.multiplier) + ", " + to_decimal(floquet.stability_index) + ")";
    if (differs(o.period_derivative, period_slope, loose))
        return "its dT/dE = " + to_decimal(o.period_derivative) + " is not its orbit's (" +
               to_decimal(period_slope) + ")";
    return {};
}

template <class Real>
std::string orbit_replica_problem(const double_pendulum<Real>& model, const saddle_orbit<Real>& o) {
    try {
        return replica_problem(model, o);
    } catch (const budget_exceeded&) {
        throw;
    } catch (const std::exception& e) {  // a record that makes the replay fail is no record of ours
        return std::string("its replay failed (") + e.what() + ")";
    }
}

template <class Real>
saddle_orbit<Real> solve_saddle_orbit(const double_pendulum<Real>& model, arm a,
                                      const level_arg<Real>& energy,
                                      const orbit_options<Real>& options) {
    check_orbit_energy(model, a, energy);
    const orbit_guess<Real> lin = linear_guess(model, a);
    const double_pendulum<double> md = to_double(model);
    const double target = static_cast<double>(energy.above(model.saddle_level(a)));
    // NOTE: the continuation's corrector is the symmetric Newton iteration whatever the method:
    // its basin is that of a quarter period, about sqrt(|mu|) times wider than the periodic
    // shooting's (Ceres' continuation stalls near E_max, see docs/theory.md); the orbit itself
    // is then found by the requested formulation from this guess.
    const auto c = detail::continue_double(md, a, false, default_stages<double>(), 1e-12,
                                           static_cast<double>(lin.beta),
                                           static_cast<double>(lin.period), {target});
    if (!c.success) {
        saddle_orbit<Real> failed;
        failed.flip_arm = a;
        failed.energy = energy.value;
        failed.excess = energy.above(model.saddle_level(a));
        failed.status = orbit_status::not_converged;
        failed.double_stage = "continuation from the centre mode failed: " + c.stop_reason;
        return failed;
    }
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
                "energy", "'" + to_decimal(energies[i].value) +
                              "' is not distinguishable from the previous energy at double");
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
                                             const level_arg<inst_real>&, const std::string&,
                                             const std::string&);
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
template std::string orbit_replica_problem<inst_real>(const double_pendulum<inst_real>&,
                                                      const saddle_orbit<inst_real>&);
template phase_point<inst_real> orbit_state<inst_real>(const double_pendulum<inst_real>&,
                                                       const saddle_orbit<inst_real>&,
                                                       const inst_real&);

}  // namespace flipflux
