// Hamilton's equations in coordinates centred on a flip saddle (docs/theory.md#saddle-orbits).
//
// With theta = q* + delta, q* = (0, pi) for arm 2 and (pi, 0) for arm 1, e_i = cos q*_i (so
// e1 e2 = -1 at both saddles) and d = delta1 - delta2:
//     cos(th1 - th2) = -cos d,   sin(th1 - th2) = -sin d,   sin th_i = e_i sin delta_i,
//     V - E_s = 2 e1 alpha sin^2(delta1 / 2) + 2 e2 beta sin^2(delta2 / 2),
//     M = [[A, -C cos d], [-C cos d, B]],   det M = D0 + C^2 sin^2 d,
//     w = M^-1 l,   P := C sin(th1 - th2) w1 w2 = -C sin(d) w1 w2,
//     delta' = w,   l1' = -P - alpha e1 sin delta1,   l2' = P - beta e2 sin delta2.
// NOTE: nothing here adds an O(1) angle to a small displacement, so an orbit of amplitude 1e-4
// (E - E_s = 1e-8) keeps the relative accuracy of the working precision: this is what makes
// F ~ (E - E_s) T_lin computable to full relative precision.
//
// The functors below are what the Gauss-Legendre integrator integrates: the state alone plus the
// action integral (orbit_flow), and additionally the variational equations Phi' = J Phi
// (orbit_variational_flow, Phi row-major after the action).
#pragma once

#include <array>
#include <cmath>

#include "flipflux/core/constants.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

template <class Real>
class saddle_frame {
  public:
    using state = std::array<Real, 4>;  ///< (delta1, delta2, l1, l2)
    using matrix = std::array<std::array<Real, 4>, 4>;

    saddle_frame(const double_pendulum<Real>& model, arm a)
        : k_(model.coefficients()),
          arm_(a),
          e1_(a == arm::two ? 1 : -1),
          e2_(a == arm::two ? -1 : 1),
          saddle_energy_(model.saddle_energy(a)) {}

    arm flip_arm() const { return arm_; }
    const lagrangian_coefficients<Real>& coefficients() const { return k_; }
    int e1() const { return e1_; }
    int e2() const { return e2_; }
    Real saddle_energy() const { return saddle_energy_; }
    /// The saddle q* in absolute angles.
    std::array<Real, 2> saddle() const {
        return arm_ == arm::two ? std::array<Real, 2>{Real(0), pi<Real>()}
                                : std::array<Real, 2>{pi<Real>(), Real(0)};
    }
    /// Index of the curve parameter s and of the flip angle's offset h in (delta1, delta2):
    /// arm 2: s = delta1, h = delta2; arm 1: s = delta2, h = delta1.
    int s_index() const { return arm_ == arm::two ? 0 : 1; }
    int h_index() const { return arm_ == arm::two ? 1 : 0; }

    /// V - E_s, accurate for small displacements.
    Real excess_potential(const Real& d1, const Real& d2) const {
        using std::sin;
        const Real s1 = sin(d1 / 2), s2 = sin(d2 / 2);
        return 2 * (e1_ * k_.alpha * s1 * s1 + e2_ * k_.beta * s2 * s2);
    }
    /// M at the saddle: [[A, -C], [-C, B]].
    sym2<Real> saddle_mass_matrix() const { return {k_.A, -k_.C, k_.B}; }
    /// w = M^-1 l.
    std::array<Real, 2> velocities(const state& x) const {
        using std::cos;
        using std::sin;
        const Real d = x[0] - x[1];
        const Real c = cos(d), s = sin(d);
        const Real det = k_.D0 + k_.C * k_.C * s * s;
        return {(k_.B * x[2] + k_.C * c * x[3]) / det, (k_.C * c * x[2] + k_.A * x[3]) / det};
    }
    Real kinetic_energy(const state& x) const {
        const auto w = velocities(x);
        return (w[0] * x[2] + w[1] * x[3]) / 2;
    }
    /// H - E_s.
    Real excess_energy(const state& x) const {
        return kinetic_energy(x) + excess_potential(x[0], x[1]);
    }
    /// Absolute phase point (theta1, theta2, l1, l2) of a frame state.
    phase_point<Real> absolute(const state& x) const {
        const auto q = saddle();
        return {q[0] + x[0], q[1] + x[1], x[2], x[3]};
    }

    /// Hamilton's equations; also returns l.w (= 2 x kinetic energy, the action's integrand).
    Real rhs(const state& x, state& dx) const {
        using std::cos;
        using std::sin;
        const Real d = x[0] - x[1];
        const Real c = cos(d), s = sin(d);
        const Real det = k_.D0 + k_.C * k_.C * s * s;
        const Real w1 = (k_.B * x[2] + k_.C * c * x[3]) / det;
        const Real w2 = (k_.C * c * x[2] + k_.A * x[3]) / det;
        const Real P = -k_.C * s * w1 * w2;
        dx[0] = w1;
        dx[1] = w2;
        dx[2] = -P - e1_ * k_.alpha * sin(x[0]);
        dx[3] = P - e2_ * k_.beta * sin(x[1]);
        return w1 * x[2] + w2 * x[3];
    }

    /// Hamilton's equations and their Jacobian J = d rhs / d x (row i = component i).
    Real rhs_and_jacobian(const state& x, state& dx, matrix& J) const {
        using std::cos;
        using std::sin;
        const Real d = x[0] - x[1];
        const Real c = cos(d), s = sin(d);
        const Real det = k_.D0 + k_.C * k_.C * s * s;
        // inverse mass matrix
        const Real i11 = k_.B / det, i12 = k_.C * c / det, i22 = k_.A / det;
        const Real w1 = i11 * x[2] + i12 * x[3];
        const Real w2 = i12 * x[2] + i22 * x[3];
        const Real P = -k_.C * s * w1 * w2;
        dx[0] = w1;
        dx[1] = w2;
        dx[2] = -P - e1_ * k_.alpha * sin(x[0]);
        dx[3] = P - e2_ * k_.beta * sin(x[1]);
        // derivatives along d at fixed l: det' = 2 C^2 s c, (C c)' = -C s
        const Real ddet = 2 * k_.C * k_.C * s * c;
        const Real dw1 = (-k_.C * s * x[3] - w1 * ddet) / det;
        const Real dw2 = (-k_.C * s * x[2] - w2 * ddet) / det;
        // P = -C s w1 w2
        const Real dP_dd = -k_.C * (c * w1 * w2 + s * (dw1 * w2 + w1 * dw2));
        const Real dP_dl1 = -k_.C * s * (i11 * w2 + w1 * i12);
        const Real dP_dl2 = -k_.C * s * (i12 * w2 + w1 * i22);
        J[0] = {dw1, -dw1, i11, i12};
        J[1] = {dw2, -dw2, i12, i22};
        J[2] = {-dP_dd - e1_ * k_.alpha * cos(x[0]), dP_dd, -dP_dl1, -dP_dl2};
        J[3] = {dP_dd, -dP_dd - e2_ * k_.beta * cos(x[1]), dP_dl1, dP_dl2};
        return w1 * x[2] + w2 * x[3];
    }

  private:
    lagrangian_coefficients<Real> k_;
    arm arm_;
    int e1_, e2_;
    Real saddle_energy_;
};

/// The orbit's flow for the integrator: (delta1, delta2, l1, l2, action), action' = l.w.
template <class Real>
struct orbit_flow {
    const saddle_frame<Real>* frame;
    void operator()(const std::array<Real, 5>& x, std::array<Real, 5>& dx) const {
        typename saddle_frame<Real>::state y{x[0], x[1], x[2], x[3]}, dy;
        dx[4] = frame->rhs(y, dy);
        for (int k = 0; k < 4; ++k)
            dx[k] = dy[k];
    }
};

/// The flow with the variational equations: (x (4), action, Phi (16, row-major)).
template <class Real>
struct orbit_variational_flow {
    const saddle_frame<Real>* frame;
    void operator()(const std::array<Real, 21>& x, std::array<Real, 21>& dx) const {
        typename saddle_frame<Real>::state y{x[0], x[1], x[2], x[3]}, dy;
        typename saddle_frame<Real>::matrix J;
        dx[4] = frame->rhs_and_jacobian(y, dy, J);
        for (int k = 0; k < 4; ++k)
            dx[k] = dy[k];
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 4; ++j) {
                Real v = J[i][0] * x[5 + 0 * 4 + j];
                for (int m = 1; m < 4; ++m)
                    v += J[i][m] * x[5 + m * 4 + j];
                dx[5 + i * 4 + j] = v;
            }
    }
};

}  // namespace flipflux
