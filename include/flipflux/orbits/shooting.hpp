// The two shooting formulations of the saddle orbit (paper Sec. 5.4; docs/theory.md#saddle-orbits).
//
// Start at the saddle with the circularised momentum y = M*^{-1/2} l of fixed length:
//     l0(beta) = sqrt(2 (E - E_s)) S u(beta),   S = M*^{1/2},   u = (cos beta, sin beta),
// so that 1/2 l0^T M*^-1 l0 = E - E_s exactly (S is the symmetric square root,
// S = (M* + sqrt(D0) I) / sqrt(tr M* + 2 sqrt(D0)) by Cayley-Hamilton).
//
// Periodic shooting (the paper's): unknowns (beta, T), residual r = x(T) - x(0) (4 components),
// Jacobian [(Phi(T) - I) dx0/dbeta, f(x(T))] from the variational equations.
// Symmetric shooting (time reversal): unknowns (beta, tau), residual l(tau) = 0 (the brake point
// at a quarter period, T = 4 tau), Jacobian [Phi_ll(tau) dl0/dbeta, l'(tau)].
// Residuals are divided by sqrt(2 (E - E_s)), which makes the problem O(1) at every energy, and
// the rows of heavy pendulums weighted by exact powers of two (shooting_setup::row_weight) so
// that the residual is invariant when every mass is scaled by a power of 4.
//
// Both integrate with equal steps h = duration / steps of one integrator (Gauss-Legendre, or
// Taylor series of a fixed order: setup.integrator), so the residual is a smooth function of the
// unknowns (an adaptive step sequence would not be).
#pragma once

#include <array>
#include <cmath>
#include <utility>

#include "flipflux/integrators/gauss_legendre.hpp"
#include "flipflux/integrators/taylor.hpp"
#include "flipflux/orbits/saddle_frame.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/orbits/saddle_taylor.hpp"

namespace flipflux::detail {

template <class Real>
struct shooting_setup {
    saddle_frame<Real> frame;
    Real excess;          ///< E - E_s > 0
    Real momentum_scale;  ///< sqrt(2 (E - E_s))
    /// The residual rows' exponent k >= 0 (row_weight): with D0 = det M* in [2^(e-1), 2^e),
    /// k = max(0, e / 4) (integer division), so 2^k ~ D0^(1/4), the square root of a mass scale.
    int row_shift = 0;
    sym2<Real> root_mass;  ///< S = M*^{1/2}
    int stages;            ///< Gauss-Legendre stages
    orbit_integrator integrator;
    int order;  ///< Taylor order (integrator == taylor)

    shooting_setup(const double_pendulum<Real>& model, arm a, const Real& excess_energy, int s,
                   orbit_integrator i = orbit_integrator::gauss_legendre, int taylor_order = 0)
        : frame(model, a), excess(excess_energy), stages(s), integrator(i), order(taylor_order) {
        using std::sqrt;
        momentum_scale = sqrt(2 * excess);
        const auto& k = frame.coefficients();
        {
            // NOTE: angles are invariant and momenta scale with the masses (by lambda: E - E_s
            // and D0^(1/2) by lambda too), so (x(T) - x(0)) / sqrt(2 (E - E_s)) has angle rows
            // ~ lambda^-1/2 and momentum rows ~ lambda^1/2: a heavy pendulum's momentum rows
            // had a rounding floor of eps lambda^1/2 (masses x 2^40 lost 8 digits of the period
            // at double, bench/results/orbit_mass_scaling.txt). Angle rows times 2^k and
            // momentum rows times 2^-k make the residual exactly invariant under lambda = 4^j;
            // k = 0 (the rows as before, the same bits) for D0 < 8, light pendulums included,
            // whose rows' floors are below eps already.
            using std::frexp;
            int e = 0;
            frexp(k.D0, &e);
            row_shift = e > 0 ? e / 4 : 0;
        }
        const Real r = sqrt(k.D0);
        const Real n = sqrt(k.A + k.B + 2 * r);
        root_mass = {(k.A + r) / n, -k.C / n, (k.B + r) / n};
    }

    /// l0(beta).
    std::array<Real, 2> momentum(const Real& beta) const {
        using std::cos;
        using std::sin;
        const Real c = cos(beta), s = sin(beta);
        return {momentum_scale * (root_mass.xx * c + root_mass.xy * s),
                momentum_scale * (root_mass.xy * c + root_mass.yy * s)};
    }
    /// dl0 / dbeta.
    std::array<Real, 2> momentum_derivative(const Real& beta) const {
        using std::cos;
        using std::sin;
        const Real c = cos(beta), s = sin(beta);
        return {momentum_scale * (-root_mass.xx * s + root_mass.xy * c),
                momentum_scale * (-root_mass.xy * s + root_mass.yy * c)};
    }
    /// The direction beta of a momentum l at the saddle: y = S^-1 l.
    Real direction_of(const std::array<Real, 2>& l) const {
        using std::atan2;
        // S^-1 = adj(S) / det S; det S > 0, so the direction is that of adj(S) l
        const Real y1 = root_mass.yy * l[0] - root_mass.xy * l[1];
        const Real y2 = -root_mass.xy * l[0] + root_mass.xx * l[1];
        return atan2(y2, y1);
    }
    /// Residual row i's weight from the common factor `inv` (1 / sqrt(2 (E - E_s)), or a
    /// multiple of it): inv 2^k for the angles (i = 0, 1), inv 2^-k for the momenta (i = 2, 3);
    /// exact scalings.
    Real row_weight(int i, const Real& inv) const {
        using std::ldexp;
        return ldexp(inv, i < 2 ? row_shift : -row_shift);
    }
    std::array<Real, 4> start(const Real& beta) const {
        const auto l = momentum(beta);
        return {Real(0), Real(0), l[0], l[1]};
    }
};

/// The end of an integration with the variational equations.
template <class Real>
struct variational_end {
    std::array<Real, 4> x;                   ///< frame state
    Real action;                             ///< int l.w dt
    std::array<std::array<Real, 4>, 4> phi;  ///< state transition matrix
    integration_statistics statistics;
    bool success = false;
};

/// The variational state's layout, shared by both integrators: x (4), the action, then Phi's last
/// `Columns` columns row by row, y[5 + Columns i + (j - first)] = Phi[i][j] for j >= first =
/// 4 - Columns (Columns = 4: all of Phi, row-major). The start: Phi's columns of the identity.
template <class Real, int Columns, std::size_t N>
std::array<Real, N> variational_start(const std::array<Real, 4>& x0) {
    static_assert(N == 5 + 4 * Columns);
    constexpr int first = 4 - Columns;
    std::array<Real, N> y;
    for (int k = 0; k < 4; ++k)
        y[k] = x0[k];
    y[4] = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < Columns; ++j)
            y[static_cast<std::size_t>(5 + Columns * i + j)] = (i == first + j) ? Real(1) : Real(0);
    return y;
}

/// The end of a variational shot from its state (the columns not integrated are 0).
template <class Real, int Columns, std::size_t N>
variational_end<Real> variational_end_of(const std::array<Real, N>& y,
                                         const integration_result& r) {
    constexpr int first = 4 - Columns;
    variational_end<Real> out;
    out.success = r.success;
    out.statistics = r.statistics;
    for (int k = 0; k < 4; ++k)
        out.x[k] = y[k];
    out.action = y[4];
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            out.phi[i][j] =
                j < first ? Real(0) : y[static_cast<std::size_t>(5 + Columns * i + j - first)];
    return out;
}

/// The Taylor route of integrate_variational: Phi's last `Columns` columns only (the others 0).
template <class Real, int Columns>
variational_end<Real> integrate_variational_taylor(const shooting_setup<Real>& setup,
                                                   const std::array<Real, 4>& x0,
                                                   const Real& duration, long steps) {
    using flow = saddle_taylor_flow<Real, Columns>;
    auto y = variational_start<Real, Columns, flow::size>(x0);
    taylor_integrator<Real, flow::size> ti(setup.order);
    flow f(setup.frame, setup.order);
    const auto r = ti.integrate(f, y, duration / steps, steps);
    return variational_end_of<Real, Columns>(y, r);
}

/// The shot with the variational equations; with the Taylor integrator and columns == 2 only
/// Phi's momentum columns 2, 3 are computed (all a Newton step needs; the others are 0).
template <class Real>
variational_end<Real> integrate_variational(const shooting_setup<Real>& setup,
                                            const std::array<Real, 4>& x0, const Real& duration,
                                            long steps, int columns = 4) {
    if (setup.integrator == orbit_integrator::taylor)
        return columns == 2 ? integrate_variational_taylor<Real, 2>(setup, x0, duration, steps)
                            : integrate_variational_taylor<Real, 4>(setup, x0, duration, steps);
    auto y = variational_start<Real, 4, 21>(x0);
    gauss_legendre<Real, 21> gl(setup.stages);
    const auto r =
        gl.integrate(orbit_variational_flow<Real>{&setup.frame}, y, duration / steps, steps);
    return variational_end_of<Real, 4>(y, r);
}

/// The end of a plain integration (state and action, no variational equations).
template <class Real>
struct state_end {
    std::array<Real, 4> x;
    Real action;
    integration_statistics statistics;
    bool success = false;
};

template <class Real>
state_end<Real> integrate_state(const shooting_setup<Real>& setup, const std::array<Real, 4>& x0,
                                const Real& duration, long steps) {
    std::array<Real, 5> y{x0[0], x0[1], x0[2], x0[3], Real(0)};
    integration_result r;
    if (setup.integrator == orbit_integrator::taylor) {
        taylor_integrator<Real, 5> ti(setup.order);
        saddle_taylor_flow<Real> f(setup.frame, setup.order);
        r = ti.integrate(f, y, duration / steps, steps);
    } else {
        gauss_legendre<Real, 5> gl(setup.stages);
        r = gl.integrate(orbit_flow<Real>{&setup.frame}, y, duration / steps, steps);
    }
    state_end<Real> out;
    out.success = r.success;
    out.statistics = r.statistics;
    for (int k = 0; k < 4; ++k)
        out.x[k] = y[k];
    out.action = y[4];
    return out;
}

/// The largest |delta1|, |delta2| along the quarter orbit from the saddle (beta, duration tau).
/// The saddle orbit stays in the strip around its saddle: |delta| < pi for both angles (it never
/// swings either arm through the other vertical). A shooting solution outside it is another
/// periodic orbit (e.g. one that passes over the top), not the saddle orbit.
template <class Real>
std::array<Real, 2> quarter_extent(const shooting_setup<Real>& setup, const Real& beta,
                                   const Real& tau, long steps) {
    using std::abs;
    const auto x0 = setup.start(beta);
    std::array<Real, 5> y{x0[0], x0[1], x0[2], x0[3], Real(0)};
    std::array<Real, 2> m{Real(0), Real(0)};
    const auto observe = [&m](long, const std::array<Real, 5>& z) {
        if (abs(z[0]) > m[0]) m[0] = abs(z[0]);
        if (abs(z[1]) > m[1]) m[1] = abs(z[1]);
    };
    if (setup.integrator == orbit_integrator::taylor) {
        taylor_integrator<Real, 5> ti(setup.order);
        saddle_taylor_flow<Real> f(setup.frame, setup.order);
        ti.integrate(f, y, tau / steps, steps, observe);
    } else {
        gauss_legendre<Real, 5> gl(setup.stages);
        gl.integrate(orbit_flow<Real>{&setup.frame}, y, tau / steps, steps, observe);
    }
    return m;
}

/// Periodic-shooting residual r (scaled) and Jacobian d r / d(beta, T) at (beta, T).
template <class Real>
struct periodic_residual {
    std::array<Real, 4> r;
    std::array<std::array<Real, 2>, 4> jacobian;
    variational_end<Real> end;
};

/// What both shooting residuals need from one shot of duration `duration` from the saddle at
/// beta: the start x0, the end state with its monodromy, the vector field f there, dl/dbeta of the
/// start's momenta, and the residual scale 1 / momentum_scale (times row_weight's powers of two).
template <class Real>
struct shot {
    std::array<Real, 4> x0, f;
    variational_end<Real> end;
    std::array<Real, 2> dl;
    Real inv;
};

template <class Real>
shot<Real> shoot(const shooting_setup<Real>& setup, const Real& beta, const Real& duration,
                 long steps, int columns = 4) {
    shot<Real> s;
    s.x0 = setup.start(beta);
    s.end = integrate_variational(setup, s.x0, duration, steps, columns);
    setup.frame.rhs(s.end.x, s.f);
    s.dl = setup.momentum_derivative(beta);
    s.inv = 1 / setup.momentum_scale;
    return s;
}

template <class Real>
periodic_residual<Real> periodic_shooting(const shooting_setup<Real>& setup, const Real& beta,
                                          const Real& period, long steps, int columns = 4) {
    periodic_residual<Real> out;
    shot<Real> s = shoot(setup, beta, period, steps, columns);
    const auto& e = s.end;
    const auto& x0 = s.x0;
    const auto& f = s.f;
    const auto& dl = s.dl;
    for (int i = 0; i < 4; ++i) {
        const Real inv = setup.row_weight(i, s.inv);
        out.r[i] = (e.x[i] - x0[i]) * inv;
        // (Phi - I) dx0/dbeta with dx0/dbeta = (0, 0, dl)
        Real v = e.phi[i][2] * dl[0] + e.phi[i][3] * dl[1];
        if (i >= 2) v -= dl[i - 2];
        out.jacobian[i][0] = v * inv;
        out.jacobian[i][1] = f[i] * inv;
    }
    out.end = std::move(s.end);
    return out;
}

/// Symmetric-shooting residual l(tau) (scaled) and Jacobian d l(tau) / d(beta, tau).
template <class Real>
struct symmetric_residual {
    std::array<Real, 2> r;
    std::array<std::array<Real, 2>, 2> jacobian;
    variational_end<Real> end;
};

template <class Real>
symmetric_residual<Real> symmetric_shooting(const shooting_setup<Real>& setup, const Real& beta,
                                            const Real& quarter, long steps, int columns = 4) {
    symmetric_residual<Real> out;
    shot<Real> s = shoot(setup, beta, quarter, steps, columns);
    const auto& e = s.end;
    const Real inv = setup.row_weight(2, s.inv);
    for (int i = 0; i < 2; ++i) {
        out.r[i] = e.x[2 + i] * inv;
        out.jacobian[i][0] = (e.phi[2 + i][2] * s.dl[0] + e.phi[2 + i][3] * s.dl[1]) * inv;
        out.jacobian[i][1] = s.f[2 + i] * inv;
    }
    out.end = std::move(s.end);
    return out;
}

/// Least-squares solution of the 4x2 system J dx = r by Householder QR (J full column rank).
template <class Real>
std::array<Real, 2> least_squares_4x2(std::array<std::array<Real, 2>, 4> J, std::array<Real, 4> r) {
    using std::abs;
    using std::sqrt;
    for (int col = 0; col < 2; ++col) {
        Real norm = 0;
        for (int i = col; i < 4; ++i)
            norm += J[i][col] * J[i][col];
        norm = sqrt(norm);
        if (norm == 0) continue;
        const Real alpha = J[col][col] > 0 ? -norm : norm;
        std::array<Real, 4> v{};
        for (int i = col; i < 4; ++i)
            v[i] = J[i][col];
        v[col] -= alpha;
        Real vv = 0;
        for (int i = col; i < 4; ++i)
            vv += v[i] * v[i];
        if (vv == 0) continue;
        for (int c = col; c < 2; ++c) {
            Real dot = 0;
            for (int i = col; i < 4; ++i)
                dot += v[i] * J[i][c];
            const Real f = 2 * dot / vv;
            for (int i = col; i < 4; ++i)
                J[i][c] -= f * v[i];
        }
        Real dot = 0;
        for (int i = col; i < 4; ++i)
            dot += v[i] * r[i];
        const Real f = 2 * dot / vv;
        for (int i = col; i < 4; ++i)
            r[i] -= f * v[i];
    }
    std::array<Real, 2> x;
    x[1] = r[1] / J[1][1];
    x[0] = (r[0] - J[0][1] * x[1]) / J[0][0];
    return x;
}

/// Solution of the 2x2 system J dx = r (partial pivoting).
template <class Real>
std::array<Real, 2> solve_2x2(const std::array<std::array<Real, 2>, 2>& J,
                              const std::array<Real, 2>& r) {
    using std::abs;
    const bool swap = abs(J[1][0]) > abs(J[0][0]);
    const auto& a = swap ? J[1] : J[0];
    const auto& b = swap ? J[0] : J[1];
    const Real ra = swap ? r[1] : r[0], rb = swap ? r[0] : r[1];
    const Real m = b[0] / a[0];
    const Real x1 = (rb - m * ra) / (b[1] - m * a[1]);
    const Real x0 = (ra - a[1] * x1) / a[0];
    return {x0, x1};
}

}  // namespace flipflux::detail
