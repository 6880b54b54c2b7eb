// Elliptic integrals of the first and second kind in the PARAMETER convention of the paper
// (eq. def:incomplete_elliptic_integral_second_kind; DLMF 19.2.4-19.2.5 with m = k^2):
//     E(phi|m) = int_0^phi sqrt(1 - m sin^2 u) du,      E(m) = E(pi/2|m),
//     F(phi|m) = int_0^phi du / sqrt(1 - m sin^2 u),    K(m) = F(pi/2|m).
//
// Evaluation: Carlson's symmetric forms (DLMF 19.25.5, 19.25.9) through Boost.Math's ellint_rf and
// ellint_rd at double, through carlson_rf_rd (below) at quad and mp, for |phi| <= pi/2 with
// s = sin phi, c = cos phi, D = 1 - m s^2:
//     F(phi|m) = s R_F(c^2, D, 1),
//     E(phi|m) = s R_F(c^2, D, 1) - (m/3) s^3 R_D(c^2, D, 1),
// and quasi-periodicity (DLMF 19.2.10) for any other real phi (only for m <= 1):
//     E(phi + k pi|m) = E(phi|m) + 2 k E(m),   F(phi + k pi|m) = F(phi|m) + 2 k K(m).
// These forms hold for every real m with m sin^2 phi <= 1, including m < 0 (where Boost's ellint_2,
// which takes the modulus k, does not apply), m > 1 and the boundary m sin^2 phi = 1 (where
// Boost's ellint_2 throws although the value is finite). Cross-checks (tests/special): DLMF 19.7.4
// (reciprocal modulus) and 19.7.5 (imaginary modulus) with Boost's ellint_1/ellint_2, and direct
// tanh-sinh quadrature of the defining integrals, at every precision.
//
// Domain (a std::domain_error otherwise, never a silent NaN):
//     m <= 1: any finite real phi;
//     m > 1:  |phi| <= arcsin(1/sqrt m), i.e. m sin^2 phi <= 1 with |phi| <= pi/2 (beyond, the
//             integrand is imaginary somewhere on [0, phi]). A computed 1 - m sin^2 phi that is
//             negative by at most 8 ulp (the rounding of phi = asin(1/sqrt m)) is taken as 0.
//     F is finite on the boundary m sin^2 phi = 1 for m > 1; it diverges only at m = 1,
//     phi = +-pi/2 (mod pi), and K(m) needs m < 1.
// Accuracy: a few ulp times a condition estimate. Near m = 1, phi = pi/2 the two Carlson terms
// are each ~ log(1/cos phi) and cancel to ~ 1: relative error ~ eps log(1/cos phi). Where the
// caller knows 1 - m or 1 - m sin^2 phi more accurately than by subtraction (GeographicLib's
// lesson: a parameter and its complement), use the *_carlson / *_complete forms that take them.
#pragma once

#include <array>

#include "flipflux/core/real.hpp"

namespace flipflux {

/// E(phi|m) for any real phi (m <= 1) or |phi| <= arcsin(1/sqrt m) (m > 1).
template <class Real>
Real elliptic_e(const Real& phi, const Real& m);

/// E(phi|m) given the complete E(m) = `complete` (m <= 1), for many phi at one m, without
/// recomputing E(m) for the half periods: with complete = elliptic_e_complete(m, 1 - m), the same
/// value as elliptic_e(phi, m) bit for bit.
template <class Real>
Real elliptic_e(const Real& phi, const Real& m, const Real& complete);

/// E(t + y|m) + E(t - y|m) for m <= 0, given complete = elliptic_e_complete(m, 1 - m), with one
/// incomplete integral instead of two: by the addition theorem of Jacobi's epsilon function,
///     E(u|m) + E(v|m) = E(sigma|m) + m sin u sin v sin sigma,   F(sigma) = F(u) + F(v),
/// sin and cos of sigma algebraic in those of u and v (DLMF 22.8.1, 22.8.2; 22.16.27), its half
/// periods counted from a double estimate of F(u) + F(v) and the sign of cos sigma. Agrees with
/// the two-integral sum to a few ulp of its terms (tests/special/test_elliptic.cpp); for m > 0 it
/// is that sum.
template <class Real>
Real elliptic_e_sum(const Real& t, const Real& y, const Real& m, const Real& complete);

/// Complete E(m) = E(pi/2|m), m <= 1.
template <class Real>
Real elliptic_e(const Real& m);

/// Complete E(m) with its complement mc = 1 - m supplied (to full relative accuracy), mc >= 0.
template <class Real>
Real elliptic_e_complete(const Real& m, const Real& mc);

/// Complete K(m) = F(pi/2|m) with mc = 1 - m supplied, mc > 0.
template <class Real>
Real elliptic_k_complete(const Real& m, const Real& mc);

/// Complete K(m), m < 1.
template <class Real>
Real elliptic_k(const Real& m);

/// F(phi|m) for any real phi (m < 1), |phi| < pi/2 (m = 1) or |phi| <= arcsin(1/sqrt m) (m > 1).
template <class Real>
Real elliptic_f(const Real& phi, const Real& m);

/// E(phi|m) for |phi| <= pi/2 from s = sin phi (signed), c2 = cos^2 phi and d = 1 - m s^2, each
/// supplied to full relative accuracy (c2 >= 0, d >= 0; not both zero unless m = 1, |s| = 1).
/// The building block of the closed forms in prediction/, which know c2 and d without
/// cancellation (e.g. d = 0 exactly on the boundary of the upright flux).
template <class Real>
Real elliptic_e_carlson(const Real& s, const Real& c2, const Real& d, const Real& m);

/// F(phi|m) for |phi| <= pi/2 from s, c2 and d = 1 - m s^2 as above (not both c2 and d zero).
template <class Real>
Real elliptic_f_carlson(const Real& s, const Real& c2, const Real& d, const Real& m);

/// Carlson's R_F(x, y, z) and R_D(x, y, z) together (DLMF 19.16.5, 19.16.6), for x, y >= 0 (not
/// both zero), z > 0: the duplication (DLMF 19.26.18) shared by both, then the series of the
/// Dirichlet average about the (weighted) mean A (DLMF 19.19.5-19.19.7 with the generating
/// function prod_j (1 - s Z_j)^(-b_j) of T_N) to order K ~ sqrt(binary digits), so that ~ K/2
/// duplications suffice instead of ~ digits/3.6: at mp:1000 ~ 30 instead of ~ 280 each, and the
/// square roots of one duplication serve both integrals. Boost.Math's ellint_rf/ellint_rd (order-5
/// and order-7 tails) are the independent route (tests/special).
template <class Real>
std::array<Real, 2> carlson_rf_rd(const Real& x, const Real& y, const Real& z);

#define FLIPFLUX_ELLIPTIC_EXTERN(R)                                                  \
    extern template R elliptic_e<R>(const R&, const R&);                             \
    extern template R elliptic_e<R>(const R&);                                       \
    extern template R elliptic_e<R>(const R&, const R&, const R&);                   \
    extern template R elliptic_e_sum<R>(const R&, const R&, const R&, const R&);     \
    extern template R elliptic_e_complete<R>(const R&, const R&);                    \
    extern template R elliptic_k_complete<R>(const R&, const R&);                    \
    extern template R elliptic_k<R>(const R&);                                       \
    extern template R elliptic_f<R>(const R&, const R&);                             \
    extern template R elliptic_e_carlson<R>(const R&, const R&, const R&, const R&); \
    extern template R elliptic_f_carlson<R>(const R&, const R&, const R&, const R&); \
    extern template std::array<R, 2> carlson_rf_rd<R>(const R&, const R&, const R&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_ELLIPTIC_EXTERN)
#undef FLIPFLUX_ELLIPTIC_EXTERN

}  // namespace flipflux
