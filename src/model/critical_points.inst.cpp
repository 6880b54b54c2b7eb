// The four critical points of V (down-down minimum, the two index-one saddles, up-up maximum) with
// their energies and normal modes: the eigenproblem K v = omega^2 M v of the linearisation at
// each (paper Sec. 2, docs/theory.md#critical-points); and the route that checks those modes, the
// eigenvalues of the 4x4 Jacobian of Hamilton's equations (core/eigensystem.hpp).
#include "flipflux/model/critical_points.hpp"

#include <algorithm>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/eigensystem.hpp"
#include "flipflux/core/instantiate.hpp"

namespace flipflux {

namespace detail {

template <class Real>
critical_point<Real> make_critical_point(const double_pendulum<Real>& model, int e1, int e2) {
    using std::abs;
    using std::sqrt;
    const auto& k = model.coefficients();
    critical_point<Real> cp;
    cp.theta1 = e1 > 0 ? Real(0) : pi<Real>();
    cp.theta2 = e2 > 0 ? Real(0) : pi<Real>();
    cp.name = std::string(e1 > 0 ? "down" : "up") + "-" + (e2 > 0 ? "down" : "up");
    cp.energy = (e1 > 0 ? Real(0) : 2 * k.alpha) + (e2 > 0 ? Real(0) : 2 * k.beta);
    cp.kind = e1 > 0 && e2 > 0   ? critical_kind::minimum
              : e1 < 0 && e2 < 0 ? critical_kind::maximum
                                 : critical_kind::saddle;
    const int e = e1 * e2;
    // Scale-free: the stiffnesses divided by sa = max(alpha, beta), the inertias by
    // sm = max(A, B), so that no product below overflows or underflows whatever the units
    // (m = L = g = 1e30 gives omega^2 of order 1); the roots x' scale back as x = x' sa / sm.
    const Real sa = k.alpha > k.beta ? k.alpha : k.beta;
    const Real sm = k.A > k.B ? k.A : k.B;
    const Real al = k.alpha / sa, be = k.beta / sa;
    const Real A = k.A / sm, B = k.B / sm, C = k.C / sm, D0 = k.D0 / sm / sm;
    // D0 x^2 - b x + c0 = 0
    const Real b = e1 * al * B + e2 * be * A;
    const Real c0 = e * al * be;
    // NOTE: the discriminant as a sum of non-negative terms, for either sign of e.
    const Real disc =
        e > 0 ? (e1 * al * B - e2 * be * A) * (e1 * al * B - e2 * be * A) + 4 * C * C * al * be
              : b * b + 4 * D0 * al * be;
    const Real root = sqrt(disc);
    // stable roots: q = (b + sign(b) sqrt(disc)) / 2, x1 = q / D0, x2 = c0 / q
    const Real q = (b >= 0 ? b + root : b - root) / 2;
    Real x1 = q / D0, x2 = c0 / q;
    if (x1 < x2) std::swap(x1, x2);
    const Real unit = sa / sm;
    int i = 0;
    for (const Real& x : {x1, x2}) {
        normal_mode<Real>& m = cp.modes[i++];
        m.omega_squared = x * unit;
        m.oscillatory = x > 0;
        m.rate = sqrt(abs(x)) * sqrt(unit);
        // (K* - x M*) a = 0 (scaled); use the row whose coefficient of a2 is larger in magnitude.
        const Real row2_a1 = -x * C * e, row2_a2 = e2 * be - x * B;
        const Real row1_a1 = e1 * al - x * A, row1_a2 = -x * C * e;
        const Real ratio = abs(row2_a2) >= abs(row1_a2) ? -row2_a1 / row2_a2 : -row1_a1 / row1_a2;
        m.direction = {Real(1), ratio};
    }
    return cp;
}

}  // namespace detail

template <class Real>
std::array<critical_point<Real>, 4> critical_points(const double_pendulum<Real>& model) {
    return {detail::make_critical_point(model, 1, 1), detail::make_critical_point(model, 1, -1),
            detail::make_critical_point(model, -1, 1), detail::make_critical_point(model, -1, -1)};
}

template <class Real>
critical_point<Real> flip_saddle(const double_pendulum<Real>& model, arm a) {
    return a == arm::two ? detail::make_critical_point(model, 1, -1)
                         : detail::make_critical_point(model, -1, 1);
}

template <class Real>
std::array<std::complex<Real>, 4> linearized_eigenvalues(
    const double_pendulum<Real>& model, const Real& th1, const Real& th2,
    std::array<std::array<std::complex<Real>, 2>, 4>* theta_directions) {
    const matrix4<Real> J = model.rhs_jacobian({th1, th2, Real(0), Real(0)});
    const eigensystem4<Real> e = eigensystem(J, theta_directions != nullptr);
    std::array<int, 4> order{0, 1, 2, 3};
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return e.values[a].real() != e.values[b].real() ? e.values[a].real() < e.values[b].real()
                                                        : e.values[a].imag() < e.values[b].imag();
    });
    std::array<std::complex<Real>, 4> out;
    for (int i = 0; i < 4; ++i)
        out[i] = e.values[order[i]];
    if (theta_directions != nullptr)
        for (int i = 0; i < 4; ++i)
            (*theta_directions)[i] = {e.vectors[order[i]][0], e.vectors[order[i]][1]};
    return out;
}

template std::array<critical_point<inst_real>, 4> critical_points<inst_real>(
    const double_pendulum<inst_real>&);
template critical_point<inst_real> flip_saddle<inst_real>(const double_pendulum<inst_real>&, arm);
template std::array<std::complex<inst_real>, 4> linearized_eigenvalues<inst_real>(
    const double_pendulum<inst_real>&, const inst_real&, const inst_real&,
    std::array<std::array<std::complex<inst_real>, 2>, 4>*);

}  // namespace flipflux
