// The saddle-orbit solver's stages in Real (private to src/orbits): the double stage, the Newton /
// Gauss-Newton polish, the final quarter orbit, the monodromy and dT/dE. Used by the solver
// (saddle_orbit.inst.cpp) and by the replay that checks a stored orbit (orbit_replay.inst.cpp),
// which repeats the solver's arithmetic.
#pragma once

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/model/critical_points.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/ceres_shooting.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/orbits/shooting.hpp"

namespace flipflux::saddle_polish {

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
        const Real inv_common = 1 / setup.momentum_scale;
        Real rn = 0;
        for (int i = 0; i < 4; ++i) {
            const Real inv = setup.row_weight(i, inv_common);
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
                r[i] = (e.x[i] - x0[i]) * setup.row_weight(i, inv);
                rn += r[i] * r[i];
            }
            orbit.residual = sqrt(rn);
            return detail::least_squares_4x2(jac4, r);
        }
        const Real inv_l = setup.row_weight(2, inv);
        const std::array<Real, 2> r{e.x[2] * inv_l, e.x[3] * inv_l};
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
            dr[i] = -setup.row_weight(i, v);  // the rows' powers of two (v already carries inv)
        }
        return detail::least_squares_4x2(p.jac4, dr)[1];
    }
    std::array<Real, 2> dr;
    for (int i = 0; i < 2; ++i)
        dr[i] = -setup.row_weight(2, Real(p.phi[2 + i][2] * dl[0] + p.phi[2 + i][3] * dl[1]));
    return 4 * detail::solve_2x2(p.jac2, dr)[1];
}

}  // namespace flipflux::saddle_polish
