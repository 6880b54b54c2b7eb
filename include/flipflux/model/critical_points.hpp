// Critical points of the potential and the normal modes there (paper App. B, generalised).
//
// At th* in {0, pi}^2 with e_i = cos th*_i, the linearisation M* xi'' + K* xi = 0 has
// M* = [[A, C e1 e2], [C e1 e2, B]] and K* = diag(alpha e1, beta e2). Normal modes xi = a exp(i W
// t) solve det(K* - W^2 M*) = 0, a quadratic in x = W^2:
//     D0 x^2 - (alpha e1 B + beta e2 A) x + alpha beta e1 e2 = 0,   D0 = A B - C^2.
// x > 0: oscillation with frequency sqrt(x); x < 0: runaway with rate sqrt(-x). The discriminant
// is evaluated as a sum of non-negative terms (no cancellation), the roots by the stable formula.
// Mode direction (theta-space): a = (1, x C e1 e2 / (beta e2 - x B)), or the first row's form
// when that is better conditioned. Egalitarian: x = +-sqrt(2) at both saddles; at (0, pi) the
// centre mode is (1, 2 - sqrt 2).
//
// Independent check: linearized_eigenvalues() diagonalises the 4x4 Jacobian of Hamilton's
// equations at the point (Eigen), whose eigenvalues are +-sqrt(-x).
#pragma once

#include <array>
#include <complex>
#include <string>

#include "flipflux/core/names.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

enum class critical_kind { minimum, saddle, maximum };
template <>
struct enum_table<critical_kind> {
    static constexpr std::string_view noun = "a kind of critical point";
    static constexpr std::array<std::pair<critical_kind, std::string_view>, 3> entries{
        {{critical_kind::minimum, "minimum"},
         {critical_kind::saddle, "index-one saddle"},
         {critical_kind::maximum, "maximum"}}};
};

template <class Real>
struct normal_mode {
    Real omega_squared;             ///< x = W^2, a root of det(K* - x M*) = 0
    bool oscillatory;               ///< x > 0
    Real rate;                      ///< frequency sqrt(x) or growth rate sqrt(-x)
    std::array<Real, 2> direction;  ///< (a1, a2), normalised to a1 = 1
};

template <class Real>
struct critical_point {
    std::string name;     ///< "down-down", "down-up", "up-down", "up-up"
    Real theta1, theta2;  ///< 0 or pi
    Real energy;          ///< V at the point
    critical_kind kind;
    std::array<normal_mode<Real>, 2> modes;  ///< ordered by decreasing omega_squared
};

/// The four critical points (0,0), (0,pi), (pi,0), (pi,pi), in this order.
template <class Real>
std::array<critical_point<Real>, 4> critical_points(const double_pendulum<Real>& model);

/// The critical point over which `a` flips: arm 2 -> (0, pi), arm 1 -> (pi, 0).
template <class Real>
critical_point<Real> flip_saddle(const double_pendulum<Real>& model, arm a);

/// Eigenvalues of the Jacobian of Hamilton's equations at (th1, th2, 0, 0), by Eigen's
/// EigenSolver in Real, sorted by (real part, imaginary part). With `theta_directions`, also the
/// theta components (v1, v2) of each eigenvector, in the same order.
template <class Real>
std::array<std::complex<Real>, 4> linearized_eigenvalues(
    const double_pendulum<Real>& model, const Real& th1, const Real& th2,
    std::array<std::array<std::complex<Real>, 2>, 4>* theta_directions = nullptr);

#define FLIPFLUX_CRITICAL_EXTERN(R)                                                   \
    extern template std::array<critical_point<R>, 4> critical_points<R>(              \
        const double_pendulum<R>&);                                                   \
    extern template critical_point<R> flip_saddle<R>(const double_pendulum<R>&, arm); \
    extern template std::array<std::complex<R>, 4> linearized_eigenvalues<R>(         \
        const double_pendulum<R>&, const R&, const R&,                                \
        std::array<std::array<std::complex<R>, 2>, 4>*);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_CRITICAL_EXTERN)
#undef FLIPFLUX_CRITICAL_EXTERN

}  // namespace flipflux
