// Elliptic integrals E and F in the parameter convention, Carlson forms (DLMF 19.25.5, 19.25.9)
// plus quasi-periodicity (DLMF 19.2.10). See include/flipflux/special/elliptic.hpp.
#include "flipflux/special/elliptic.hpp"

#include <boost/math/special_functions/ellint_rd.hpp>
#include <boost/math/special_functions/ellint_rf.hpp>
#include <cmath>
#include <stdexcept>
#include <string>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/instantiate.hpp"

namespace flipflux {
namespace {

template <class Real>
[[noreturn]] void domain_failure(const char* function, const Real& phi, const Real& m,
                                 const char* why) {
    throw std::domain_error(std::string(function) + "(phi = " + to_decimal(phi, 17) +
                            ", m = " + to_decimal(m, 17) + "): " + why);
}

template <class Real>
void require_finite(const char* function, const Real& phi, const Real& m) {
    using boost::multiprecision::isfinite;
    using std::isfinite;
    // NOTE: Boost's Carlson series spin for 10^6 iterations on a NaN: reject it here.
    if (!isfinite(phi) || !isfinite(m)) domain_failure(function, phi, m, "argument not finite");
}

/// phi = k pi + r with |r| <= pi/2 (k = nearest integer to phi/pi).
template <class Real>
Real reduce_half_period(const Real& phi, Real& k) {
    using std::round;
    k = round(phi / pi<Real>());
    return phi - k * pi<Real>();
}

/// The reduced argument of E or F: s, c2 and d = 1 - m s^2 for |phi| <= pi/2, with the domain
/// checks for m > 1. Returns the number of half periods k through `k`.
template <class Real>
void reduced_arguments(const char* function, const Real& phi, const Real& m, Real& k, Real& s,
                       Real& c2, Real& d) {
    using std::abs;
    using std::cos;
    using std::sin;
    require_finite(function, phi, m);
    if (m > 1) {
        if (abs(phi) > half_pi<Real>()) {
            domain_failure(function, phi, m, "m > 1 needs m sin^2(u) <= 1 on all of [0, phi]");
        }
        k = 0;
        s = sin(phi);
        const Real c = cos(phi);
        c2 = c * c;
        d = 1 - m * s * s;
        if (d < 0) {
            // NOTE: phi = asin(1/sqrt m) rounded may overshoot the boundary by an ulp or so.
            if (d < -8 * epsilon<Real>()) {
                domain_failure(function, phi, m, "m sin^2(phi) > 1 (integrand imaginary)");
            }
            d = 0;
        }
        return;
    }
    const Real r = reduce_half_period(phi, k);
    s = sin(r);
    const Real c = cos(r);
    c2 = c * c;
    // d = 1 - m s^2 = c^2 + (1 - m) s^2: no cancellation for 0 < m <= 1 (1 - m is exact near 1).
    d = c2 + (1 - m) * s * s;
}

}  // namespace

template <class Real>
Real elliptic_e_carlson(const Real& s, const Real& c2, const Real& d, const Real& m) {
    using boost::math::ellint_rd;
    using boost::math::ellint_rf;
    if (!(c2 >= 0) || !(d >= 0)) {
        domain_failure("elliptic_e_carlson", s, m, "needs cos^2(phi) >= 0 and 1 - m sin^2 >= 0");
    }
    if (s == 0) return Real(0);
    if (c2 == 0 && d == 0) return s;  // m = 1, phi = +-pi/2: E = sin(phi)
    const Real rf = ellint_rf(c2, d, Real(1));
    const Real rd = ellint_rd(c2, d, Real(1));
    return s * rf - m * s * s * s * rd / 3;
}

template <class Real>
Real elliptic_f_carlson(const Real& s, const Real& c2, const Real& d, const Real& m) {
    using boost::math::ellint_rf;
    if (!(c2 >= 0) || !(d >= 0) || (c2 == 0 && d == 0)) {
        domain_failure("elliptic_f_carlson", s, m,
                       "needs cos^2(phi) >= 0, 1 - m sin^2 >= 0, "
                       "not both zero (F diverges there)");
    }
    if (s == 0) return Real(0);
    return s * ellint_rf(c2, d, Real(1));
}

template <class Real>
Real elliptic_e_complete(const Real& m, const Real& mc) {
    using boost::math::ellint_rd;
    using boost::math::ellint_rf;
    require_finite("elliptic_e_complete", mc, m);
    if (!(mc >= 0)) domain_failure("elliptic_e_complete", mc, m, "needs 1 - m >= 0");
    if (mc == 0) return Real(1);
    return ellint_rf(Real(0), mc, Real(1)) - m * ellint_rd(Real(0), mc, Real(1)) / 3;
}

template <class Real>
Real elliptic_k_complete(const Real& m, const Real& mc) {
    using boost::math::ellint_rf;
    require_finite("elliptic_k_complete", mc, m);
    if (!(mc > 0)) domain_failure("elliptic_k_complete", mc, m, "needs 1 - m > 0");
    return ellint_rf(Real(0), mc, Real(1));
}

template <class Real>
Real elliptic_e(const Real& m) {
    require_finite("elliptic_e", m, m);
    return elliptic_e_complete(m, Real(1 - m));
}

template <class Real>
Real elliptic_k(const Real& m) {
    require_finite("elliptic_k", m, m);
    return elliptic_k_complete(m, Real(1 - m));
}

template <class Real>
Real elliptic_e(const Real& phi, const Real& m) {
    Real k, s, c2, d;
    reduced_arguments("elliptic_e", phi, m, k, s, c2, d);
    Real value = elliptic_e_carlson(s, c2, d, m);
    if (k != 0) value += 2 * k * elliptic_e_complete(m, Real(1 - m));
    return value;
}

template <class Real>
Real elliptic_f(const Real& phi, const Real& m) {
    Real k, s, c2, d;
    reduced_arguments("elliptic_f", phi, m, k, s, c2, d);
    if (c2 == 0 && d == 0) domain_failure("elliptic_f", phi, m, "F diverges (m = 1, phi = pi/2)");
    Real value = elliptic_f_carlson(s, c2, d, m);
    if (k != 0) {
        if (!(m < 1)) domain_failure("elliptic_f", phi, m, "K(1) diverges");
        value += 2 * k * elliptic_k_complete(m, Real(1 - m));
    }
    return value;
}

#define FLIPFLUX_ELLIPTIC_INSTANTIATE(R)                                      \
    template R elliptic_e<R>(const R&, const R&);                             \
    template R elliptic_e<R>(const R&);                                       \
    template R elliptic_e_complete<R>(const R&, const R&);                    \
    template R elliptic_k_complete<R>(const R&, const R&);                    \
    template R elliptic_k<R>(const R&);                                       \
    template R elliptic_f<R>(const R&, const R&);                             \
    template R elliptic_e_carlson<R>(const R&, const R&, const R&, const R&); \
    template R elliptic_f_carlson<R>(const R&, const R&, const R&, const R&)
FLIPFLUX_ELLIPTIC_INSTANTIATE(inst_real);

}  // namespace flipflux
