// Elliptic integrals E and F in the parameter convention, Carlson forms (DLMF 19.25.5, 19.25.9)
// plus quasi-periodicity (DLMF 19.2.10). See include/flipflux/special/elliptic.hpp.
#include "flipflux/special/elliptic.hpp"

#include <mpfr.h>
#include <boost/math/special_functions/ellint_rd.hpp>
#include <boost/math/special_functions/ellint_rf.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/core/mpfr_number.hpp"

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

/// The constants of dirichlet_series for one order and (a2, c2): coef_N = (a)_N / (c)_N
/// (a = a2 / 2, c = c2 / 2) and the recurrence's factors (k - 2 n) for k = 1..3, as Reals, built
/// once per type (the fixed precisions' order never changes): the series then spends no
/// conversion or division on them.
template <class Real>
struct series_constants {
    std::vector<Real> coef;                   ///< coef_n, n = 0..order
    std::vector<std::array<Real, 4>> factor;  ///< factor[n][k] = k - 2 n
    std::vector<Real> twice_n;                ///< 2 n
};

template <class Real>
series_constants<Real> make_series_constants(int order, int a2, int c2) {
    series_constants<Real> t;
    Real coef = 1;
    for (int n = 0; n <= order; ++n) {
        if (n > 0) coef = coef * (a2 + 2 * (n - 1)) / (c2 + 2 * (n - 1));
        t.coef.push_back(coef);
        t.factor.push_back({Real(0), Real(1 - 2 * n), Real(2 - 2 * n), Real(3 - 2 * n)});
        t.twice_n.push_back(Real(2 * n));
    }
    return t;
}

/// The constants for R_F's (1, 3) or R_D's (3, 5) series at `order`, built once per type.
template <class Real>
const series_constants<Real>& constants_of(int order, int a2, int c2) {
    static const series_constants<Real> rf = make_series_constants<Real>(order, 1, 3);
    static const series_constants<Real> rd = make_series_constants<Real>(order, 3, 5);
    const series_constants<Real>& t = a2 == 1 && c2 == 3 ? rf : rd;
    if (static_cast<int>(t.coef.size()) != order + 1 ||
        !((a2 == 1 && c2 == 3) || (a2 == 3 && c2 == 5)))
        throw std::logic_error("dirichlet_series: constants for another order or series");
    return t;
}

/// sum_N coef_N T_N, T_N the coefficient of s^N in (1 - e1 s + e2 s^2 - e3 s^3)^(-1/2)
/// (1 - z s)^(-1) (z = 0: the first factor alone), N = 0..order, coef_N = (a)_N / (c)_N.
/// NOTE: J. C. P. Miller's recurrence for the power w = u^alpha of u = 1 + u1 s + u2 s^2 + u3 s^3,
/// n w_n = sum_{k=1..3} ((alpha + 1) k - n) u_k w_{n-k}: O(order) operations. The same operations
/// in the same order as with the constants computed in the loop (the results are bit for bit
/// those of that form); zero coefficients (e1 = 0 in R_F) are skipped.
template <class Real>
Real dirichlet_series(const Real& e1, const Real& e2, const Real& e3, const Real& z, int order,
                      int a2, int c2) {
    const series_constants<Real>& t = constants_of<Real>(order, a2, c2);
    const std::array<Real, 4> u{Real(1), Real(-e1), e2, Real(-e3)};
    const bool with_e1 = e1 != 0, with_z = z != 0;
    Real h = 1;  // coefficient n of w (1 - z s)^(-1): h_n = w_n + z h_{n-1}
    Real total = 1;
    std::array<Real, 3> last{Real(1), Real(0), Real(0)};  // w_{n-1}, w_{n-2}, w_{n-3}
    for (int n = 1; n <= order; ++n) {
        const auto un = static_cast<std::size_t>(n);
        const std::array<Real, 4>& f = t.factor[un];
        // (alpha + 1) k - n with alpha = -1/2: k/2 - n = (k - 2n) / 2
        Real wn = 0;
        if (with_e1) wn += u[1] * last[0] * f[1];
        if (n >= 2) wn += u[2] * last[1] * f[2];
        if (n >= 3) wn += u[3] * last[2] * f[3];
        wn /= t.twice_n[un];
        last[2] = last[1];
        last[1] = last[0];
        last[0] = wn;
        h = with_z ? Real(wn + z * h) : wn;
        total += t.coef[un] * h;
    }
    return total;
}

/// The series of dirichlet_series in MPFR with graded precision (mp only). Its terms decrease
/// like M^n, M = max |X_j| (the duplication's target r): T_N <= (N + 1)^2 M^N, coef_N <= 1, so
/// term N changes the sum (~1) only in its leading bits + 16 + 4 log2(N + 2) + N log2 M bits
/// (the guard covers the recurrence's cancellation, <= 3 N (N + 1) M^N). Each term is computed
/// in that precision (at least 64 bits): the products' cost falls quadratically with N, and the
/// sum is accumulated in the working precision. Same recurrence and order as the uniform one.
[[maybe_unused]] mp dirichlet_series_graded(const mp& e1, const mp& e2, const mp& e3, const mp& z,
                                            int order, int a2, int c2, double log2_m) {
    mp total = 1;  // the working precision (the thread's default)
    const auto bits = static_cast<double>(mpfr_get_prec(total.backend().data()));
    log2_m = std::max(log2_m, -bits);
    const auto prec_of = [&](int n) {
        const double p = bits + 16 + 4 * std::log2(n + 2.0) + n * log2_m;
        return static_cast<mpfr_prec_t>(std::clamp(std::ceil(p), 64.0, bits + 16));
    };
    const mpfr_prec_t top = prec_of(0);
    const mpfr_srcptr u_full[4] = {nullptr, e1.backend().data(), e2.backend().data(),
                                   e3.backend().data()};
    const int u_sign[4] = {0, -1, 1, -1};  // u = 1 - e1 s + e2 s^2 - e3 s^3
    mpfr_number u[4]{mpfr_number(top), mpfr_number(top), mpfr_number(top), mpfr_number(top)};
    // w_{n-1}, w_{n-2}, w_{n-3}
    mpfr_number last[3]{mpfr_number(top), mpfr_number(top), mpfr_number(top)};
    mpfr_number wn(top), h(top), coef(top), t(top), zr(top);
    mpfr_set_ui(last[0].get(), 1, MPFR_RNDN);
    mpfr_set_zero(last[1].get(), 1);
    mpfr_set_zero(last[2].get(), 1);
    mpfr_set_ui(h.get(), 1, MPFR_RNDN);
    mpfr_set_ui(coef.get(), 1, MPFR_RNDN);
    const bool with_z = !mpfr_zero_p(z.backend().data());
    for (int n = 1; n <= order; ++n) {
        const mpfr_prec_t p = prec_of(n);
        mpfr_set_zero(wn.at(p), 1);
        for (int k = 1; k <= 3 && k <= n; ++k) {
            if (mpfr_zero_p(u_full[k])) continue;
            mpfr_set(u[k].at(p), u_full[k], MPFR_RNDN);
            mpfr_mul(t.at(p), u[k].get(), last[k - 1].get(), MPFR_RNDN);
            mpfr_mul_si(t.get(), t.get(), u_sign[k] * (k - 2 * n), MPFR_RNDN);
            mpfr_add(wn.get(), wn.get(), t.get(), MPFR_RNDN);
        }
        mpfr_div_ui(wn.get(), wn.get(), static_cast<unsigned long>(2 * n), MPFR_RNDN);
        mpfr_swap(last[2].get(), last[1].get());  // w_{n-3} is dropped into wn (reset next term)
        mpfr_swap(last[1].get(), last[0].get());
        mpfr_swap(last[0].get(), wn.get());
        mpfr_prec_round(h.get(), p, MPFR_RNDN);  // h_n = w_n + z h_{n-1}
        if (with_z) {
            mpfr_set(zr.at(p), z.backend().data(), MPFR_RNDN);
            mpfr_mul(h.get(), h.get(), zr.get(), MPFR_RNDN);
            mpfr_add(h.get(), h.get(), last[0].get(), MPFR_RNDN);
        } else {
            mpfr_set(h.get(), last[0].get(), MPFR_RNDN);
        }
        mpfr_prec_round(coef.get(), p, MPFR_RNDN);
        mpfr_mul_ui(coef.get(), coef.get(), static_cast<unsigned long>(a2 + 2 * (n - 1)),
                    MPFR_RNDN);
        mpfr_div_ui(coef.get(), coef.get(), static_cast<unsigned long>(c2 + 2 * (n - 1)),
                    MPFR_RNDN);
        mpfr_mul(t.at(p), coef.get(), h.get(), MPFR_RNDN);
        mpfr_add(total.backend().data(), total.backend().data(), t.get(), MPFR_RNDN);
    }
    return total;
}

/// dirichlet_series, graded at mp. `log2_m`: log2 max |X_j|.
template <class Real>
Real series(const Real& e1, const Real& e2, const Real& e3, const Real& z, int order, int a2,
            int c2, double log2_m) {
    if constexpr (has_variable_precision_v<Real>)
        return dirichlet_series_graded(e1, e2, e3, z, order, a2, c2, log2_m);
    else
        return dirichlet_series(e1, e2, e3, z, order, a2, c2);
}

/// series' `log2_m`: log2 max(|a|, |b|, |c|) (-inf for zeros) at mp, where the graded series
/// uses it; not computed at the fixed precisions (0).
template <class Real>
double log2_max(const Real& a, const Real& b, const Real& c) {
    if constexpr (has_variable_precision_v<Real>) {
        using std::abs;
        using std::max;
        return std::log2(static_cast<double>(max({abs(a), abs(b), abs(c)})));
    } else {
        return 0;
    }
}

/// carlson_rf_rd; without R_D (`with_rd` false: R_F alone, 0 in its place) the duplication skips
/// R_D's sum and stopping test and the series its tail.
template <class Real>
std::array<Real, 2> carlson_duplication(const Real& x0, const Real& y0, const Real& z0,
                                        bool with_rd) {
    using boost::multiprecision::isfinite;
    using std::abs;
    using std::ceil;
    using std::isfinite;
    using std::ldexp;
    using std::max;
    using std::sqrt;
    if (!(x0 >= 0) || !(y0 >= 0) || !(z0 > 0) || (x0 == 0 && y0 == 0) || !isfinite(x0) ||
        !isfinite(y0) || !isfinite(z0))
        throw std::domain_error("carlson_rf_rd(" + to_decimal(x0, 17) + ", " + to_decimal(y0, 17) +
                                ", " + to_decimal(z0, 17) +
                                "): needs finite x, y >= 0, not both zero, and z > 0");
    const int bits = binary_digits<Real>();
    // the series' order K ~ sqrt(bits) and the duplications' target |Z| <= r, r^(K+1) = 2^-bits /
    // 256 (the omitted terms are ~ |Z|^(K+1) of the sum)
    const int order = std::max(8, static_cast<int>(ceil(std::sqrt(static_cast<double>(bits)))));
    const Real r = ldexp(Real(1), -static_cast<int>(ceil((bits + 8.0) / (order + 1))));
    Real x = x0, y = y0, z = z0;
    const Real af0 = (x0 + y0 + z0) / 3, ad0 = (x0 + y0 + 3 * z0) / 5;
    Real af = af0, ad = ad0;
    const Real qf = max({abs(af0 - x0), abs(af0 - y0), abs(af0 - z0)});
    const Real qd = max({abs(ad0 - x0), abs(ad0 - y0), abs(ad0 - z0)});
    Real sum = 0, scale = 1;  // scale = 4^-n
    const Real quarter = 0.25;
    for (int n = 0; scale * qf > r * af || (with_rd && scale * qd > r * ad); ++n) {
        if (n > 4 * bits)
            throw std::runtime_error("carlson_rf_rd: the duplication did not converge");
        const Real sx = sqrt(x), sy = sqrt(y), sz = sqrt(z);
        const Real lambda = sx * (sy + sz) + sy * sz;
        if (with_rd) sum += scale / (sz * (z + lambda));
        // times 1/4 (exact, as dividing by 4 is; a float128 product costs half a quotient)
        scale *= quarter;
        x = (x + lambda) * quarter;
        y = (y + lambda) * quarter;
        z = (z + lambda) * quarter;
        af = (af + lambda) * quarter;
        ad = (ad + lambda) * quarter;
    }
    // R_F = A^(-1/2) sum_N (1/2)_N / (3/2)_N T_N, Z_j = (A0 - z_j) 4^-n / A (sum Z_j = 0)
    const Real X = (af0 - x0) * scale / af, Y = (af0 - y0) * scale / af, Z = -(X + Y);
    const Real rf = series(Real(0), Real(X * Y - Z * Z), Real(X * Y * Z), Real(0), order, 1, 3,
                           log2_max(X, Y, Z)) /
                    sqrt(af);
    if (!with_rd) return {rf, Real(0)};
    // R_D = 4^-n A^(-3/2) sum_N (3/2)_N / (5/2)_N T_N + 3 sum, T_N of
    // (1 - s X)^(-1/2) (1 - s Y)^(-1/2) (1 - s Z)^(-3/2), X + Y + 3 Z = 0
    const Real Xd = (ad0 - x0) * scale / ad, Yd = (ad0 - y0) * scale / ad, Zd = -(Xd + Yd) / 3;
    const Real e1 = Xd + Yd + Zd, e2 = Xd * Yd + Zd * (Xd + Yd), e3 = Xd * Yd * Zd;
    const Real rd =
        scale * series(e1, e2, e3, Zd, order, 3, 5, log2_max(Xd, Yd, Zd)) / (ad * sqrt(ad)) +
        3 * sum;
    return {rf, rd};
}

/// R_F and R_D: Carlson's duplication with the high-order series above double (at quad the joint
/// duplication shares its square roots between R_F and R_D and needs no pow: Omega at quad 1.3-2x
/// faster than with Boost's two), Boost.Math's in double (its tails need only a few duplications
/// there).
template <class Real>
std::array<Real, 2> rf_rd(const Real& x, const Real& y, const Real& z) {
    if constexpr (!std::is_same_v<Real, double>)
        return carlson_duplication(x, y, z, true);
    else
        return {boost::math::ellint_rf(x, y, z), boost::math::ellint_rd(x, y, z)};
}

/// R_F alone, likewise.
template <class Real>
Real rf(const Real& x, const Real& y, const Real& z) {
    if constexpr (has_variable_precision_v<Real>)
        return carlson_duplication(x, y, z, false)[0];
    else
        return boost::math::ellint_rf(x, y, z);
}

}  // namespace

template <class Real>
std::array<Real, 2> carlson_rf_rd(const Real& x, const Real& y, const Real& z) {
    return carlson_duplication(x, y, z, true);
}

template <class Real>
Real elliptic_e_carlson(const Real& s, const Real& c2, const Real& d, const Real& m) {
    if (!(c2 >= 0) || !(d >= 0)) {
        domain_failure("elliptic_e_carlson", s, m, "needs cos^2(phi) >= 0 and 1 - m sin^2 >= 0");
    }
    if (s == 0) return Real(0);
    if (c2 == 0 && d == 0) return s;  // m = 1, phi = +-pi/2: E = sin(phi)
    if (d == 0) {
        // the turning point m s^2 = 1 (c2 = 1 - s^2): E = s c2 R_D(0, 1, c2) / 3 (DLMF 19.25.10
        // with c - k^2 = 0, and 2 R_G(0, 1, c2) = c2 R_F + c2 (1 - c2) R_D / 3 by DLMF 19.21.10),
        // one positive term. s R_F - m s^3 R_D / 3 cancels there as c2 -> 0, both terms growing
        // like log(1/c2): ~25 eps at c2 = 1e-21 (f1 just below E_max; regression).
        // Carlson's own duplication at every precision: Boost's R_D loses ~14 eps at the spread
        // (0, 1, 1e-40) in quad, this one < 1
        return s * c2 * carlson_duplication(Real(0), Real(1), c2, true)[1] / 3;
    }
    const auto [rf, rd] = rf_rd(c2, d, Real(1));
    return s * rf - m * s * s * s * rd / 3;
}

template <class Real>
Real elliptic_f_carlson(const Real& s, const Real& c2, const Real& d, const Real& m) {
    if (!(c2 >= 0) || !(d >= 0) || (c2 == 0 && d == 0)) {
        domain_failure("elliptic_f_carlson", s, m,
                       "needs cos^2(phi) >= 0, 1 - m sin^2 >= 0, "
                       "not both zero (F diverges there)");
    }
    if (s == 0) return Real(0);
    return s * rf(c2, d, Real(1));
}

template <class Real>
Real elliptic_e_complete(const Real& m, const Real& mc) {
    require_finite("elliptic_e_complete", mc, m);
    if (!(mc >= 0)) domain_failure("elliptic_e_complete", mc, m, "needs 1 - m >= 0");
    if (mc == 0) return Real(1);
    if (mc < Real(0.5)) {
        // E = 2 R_G(0, mc, 1) = mc R_F(0, 1, mc) + m mc R_D(0, 1, mc) / 3 (DLMF 19.25.1 and
        // 19.21.10 with the small argument last): positive terms. R_F - m R_D(0, mc, 1) / 3
        // cancels as mc -> 0, both terms growing like log(1/mc) (~25 eps at mc = 1e-21).
        const auto [rf, rd] = carlson_duplication(Real(0), Real(1), mc, true);  // as above
        return mc * rf + m * mc * rd / 3;
    }
    const auto [rf, rd] = rf_rd(Real(0), mc, Real(1));
    return rf - m * rd / 3;
}

template <class Real>
Real elliptic_k_complete(const Real& m, const Real& mc) {
    require_finite("elliptic_k_complete", mc, m);
    if (!(mc > 0)) domain_failure("elliptic_k_complete", mc, m, "needs 1 - m > 0");
    return rf(Real(0), mc, Real(1));
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
Real elliptic_e(const Real& phi, const Real& m, const Real& complete) {
    Real k, s, c2, d;
    reduced_arguments("elliptic_e", phi, m, k, s, c2, d);
    Real value = elliptic_e_carlson(s, c2, d, m);
    if (k != 0) value += 2 * k * complete;
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

template <class Real>
Real elliptic_e_sum(const Real& t, const Real& y, const Real& m, const Real& complete) {
    using std::cos;
    using std::sin;
    using std::sqrt;
    if (!(m <= 0))
        return elliptic_e(Real(t + y), m, complete) + elliptic_e(Real(t - y), m, complete);
    const Real st = sin(t), ct = cos(t), sy = sin(y), cy = cos(y);
    const Real su = st * cy + ct * sy, cu = ct * cy - st * sy;          // u = t + y
    const Real sv = st * cy - ct * sy, cv = ct * cy + st * sy;          // v = t - y
    const Real du = sqrt(1 - m * su * su), dv = sqrt(1 - m * sv * sv);  // >= 1: m <= 0
    const Real den = 1 - m * (su * su) * (sv * sv);                     // >= 1
    const Real ss = (su * cv * dv + sv * cu * du) / den;                // sn, cn of the sum
    const Real cs = (cu * cv - su * sv * du * dv) / den;
    // sigma = k pi + x, |x| <= pi/2: F(sigma) = 2 k K + F(x), so k is F(u) + F(v) over 2 K
    // rounded (in double: only its integer part matters), and (-1)^k cos sigma = cos x >= 0
    // decides between two neighbours where F(x) is near +-K
    const double md = static_cast<double>(m);
    const double q = (elliptic_f<double>(static_cast<double>(t + y), md) +
                      elliptic_f<double>(static_cast<double>(t - y), md)) /
                     (2 * elliptic_k_complete<double>(md, 1 - md));
    long k = std::lround(q);
    if ((k % 2 == 0) != (cs >= 0)) k += q > static_cast<double>(k) ? 1 : -1;
    const Real sx = k % 2 == 0 ? ss : Real(-ss), cx = k % 2 == 0 ? cs : Real(-cs);
    Real e_sigma = elliptic_e_carlson(sx, Real(cx * cx), Real(1 - m * sx * sx), m);
    if (k != 0) e_sigma += 2 * Real(k) * complete;
    return e_sigma + m * su * sv * ss;
}

#define FLIPFLUX_ELLIPTIC_INSTANTIATE(R)                                      \
    template R elliptic_e<R>(const R&, const R&);                             \
    template R elliptic_e<R>(const R&);                                       \
    template R elliptic_e<R>(const R&, const R&, const R&);                   \
    template R elliptic_e_sum<R>(const R&, const R&, const R&, const R&);     \
    template R elliptic_e_complete<R>(const R&, const R&);                    \
    template R elliptic_k_complete<R>(const R&, const R&);                    \
    template R elliptic_k<R>(const R&);                                       \
    template R elliptic_f<R>(const R&, const R&);                             \
    template R elliptic_e_carlson<R>(const R&, const R&, const R&, const R&); \
    template R elliptic_f_carlson<R>(const R&, const R&, const R&, const R&); \
    template std::array<R, 2> carlson_rf_rd<R>(const R&, const R&, const R&)
FLIPFLUX_ELLIPTIC_INSTANTIATE(inst_real);

}  // namespace flipflux
