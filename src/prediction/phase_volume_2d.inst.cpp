// Omega(E) by 2-D quadrature over configuration space (paper eq.
// eq:phase_space_volume_egalitatian_double_pendu, generalised): the outer integral over th2
// (tanh-sinh, split where the allowed th1-interval reaches its full and empty extents), the inner
// over th1 between the boundary points -t1(th2), t1(th2) of V = E (Gauss-Kronrod panels sized by
// the integrand's strip of analyticity, tanh-sinh as fallback). The
// discontinuous step Theta(E - V) is never integrated: the boundary is solved for.
// Independent of the elliptic route: other integration order, other inner rule, no elliptic
// integrals.
#include <algorithm>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <functional>
#include <utility>
#include <vector>

#include "allowed_region.hpp"
#include "flipflux/core/constants.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/quadrature/quadrature.hpp"
#include "phase_volume_detail.hpp"

namespace flipflux::detail {

namespace {

/// The integral of sqrt(det M) = sqrt(D0 + C^2 sin^2 u), u = th1 - th2, over th1 in [a, b]:
/// fixed-panel Gauss-Kronrod sized by the strip of analyticity |Im u| < asinh(sqrt(D0)/C) (the
/// zeros of D0 + C^2 sin^2 u), tanh-sinh when that would need too many panels or misses the
/// tolerance. In th1, not u: the interval's width 2 t1 is then exact, where u's ends t1 - th2 and
/// -t1 - th2 differ by a rounding of th2 (a light lower link, t1 ~ 5e-4 at th2 ~ 1: Omega 1e-14
/// relative off at double, 10x its estimate).
template <class Real>
quadrature_result<Real> sqrt_det_integral(const lagrangian_coefficients<Real>& k, const Real& a,
                                          const Real& b, const Real& th2, const Real& strip) {
    using std::pow;
    using std::sin;
    using std::sqrt;
    const Real C2 = k.C * k.C;
    auto f = [&](const Real& th1) -> Real {
        const Real s = sin(Real(th1 - th2));
        return sqrt(k.D0 + C2 * s * s);
    };
    const std::size_t panels = kronrod_panels(Real(b - a), strip);
    if (panels > 0) {
        quadrature_result<Real> r = gauss_kronrod_fixed<Real>(f, a, b, panels);
        if (r.error_estimate <= pow(epsilon<Real>(), Real(2) / 3) * r.l1_norm) return r;
    }
    // NOTE: the integrand's near-singularities are u = j pi +- i strip (the zeros of sin u):
    // with a narrow strip (a nearly massless link: m1 = 1e-8 gives 1e-4) tanh-sinh over [a, b]
    // resolves a near-kink inside the interval only with ever more levels (minutes); split at
    // every th1 = th2 + j pi inside, each piece has them at its ends, where tanh-sinh converges
    // fast
    using std::ceil;
    quadrature_result<Real> sum;
    Real from = a;
    for (Real j = ceil((a - th2) / pi<Real>()); th2 + j * pi<Real>() < b; j += 1) {
        const Real cut = th2 + j * pi<Real>();
        if (!(cut > from)) continue;
        sum += tanh_sinh_integrate<Real>(
            [&](const Real& x, const Real&, const Real&) -> Real { return f(x); }, from, cut);
        from = cut;
    }
    sum += tanh_sinh_integrate<Real>(
        [&](const Real& x, const Real&, const Real&) -> Real { return f(x); }, from, b);
    return sum;
}

/// The outer integral's break points: a, the th2 in (a, b) where t1(th2) - th2 or
/// t1(th2) + th2 - pi changes sign (found among 64 samples, refined by TOMS 748), b; and at each
/// interior one the distance strip / |du/dth2| of the outer integrand's near-singularities.
template <class Real>
struct split_points {
    std::vector<Real> at, radius;
};

template <class Real>
split_points<Real> outer_cuts(const angle_support<Real>& sup, const Real& a, const Real& b,
                              const Real& strip) {
    using std::abs;
    const auto t1 = [&](const Real& th2) {
        return sup.half_width(th2, Real(b - th2), Real(th2 - a));
    };
    const std::array<std::function<Real(const Real&)>, 2> crossing{
        [&](const Real& th2) { return Real(t1(th2) - th2); },
        [&](const Real& th2) { return Real(t1(th2) + th2 - pi<Real>()); }};
    split_points<Real> r;
    r.at.push_back(a);
    r.radius.push_back(Real(0));
    constexpr int n = 64;
    const Real step = (b - a) / n;
    // strip / |du/dth2| at a crossing m, du/dth2 = t1' + sign (t1' from a symmetric difference
    // over 1/64 of a sample step)
    const auto radius_at = [&](const Real& m, int sign) {
        const Real d = step / 64;
        const Real lo = m - d > a ? Real(m - d) : a, hi = m + d < b ? Real(m + d) : b;
        const Real slope = (t1(hi) - t1(lo)) / (hi - lo) + sign;
        return Real(strip / std::max(Real(abs(slope)), Real(1)));
    };
    std::vector<std::pair<Real, Real>> found;  // (th2, radius)
    for (int c = 0; c < 2; ++c) {
        const int sign = c == 0 ? -1 : 1;
        Real x0 = a, g0 = crossing[c](a);
        for (int i = 1; i <= n; ++i) {
            const Real x1 = i == n ? b : Real(a + step * i), g1 = crossing[c](x1);
            if (g1 == 0 && i < n) {  // a sample on the crossing itself
                found.emplace_back(x1, radius_at(x1, sign));
            } else if ((g0 < 0 && g1 > 0) || (g0 > 0 && g1 < 0)) {
                std::uintmax_t iterations = 200;
                const auto root = boost::math::tools::toms748_solve(
                    crossing[c], x0, x1, g0, g1,
                    boost::math::tools::eps_tolerance<Real>(binary_digits<Real>() - 2), iterations);
                const Real m = (root.first + root.second) / 2;
                if (m > a && m < b) found.emplace_back(m, radius_at(m, sign));
            }
            x0 = x1;
            g0 = g1;
        }
    }
    std::sort(found.begin(), found.end());
    for (const auto& [m, radius] : found)
        if (m > r.at.back()) {
            r.at.push_back(m);
            r.radius.push_back(radius);
        }
    r.at.push_back(b);
    r.radius.push_back(Real(0));
    return r;
}

}  // namespace

template <class Real>
prediction_result<Real> phase_volume_quadrature_2d(const double_pendulum<Real>& model,
                                                   const energy_level<Real>& energy) {
    using std::asinh;
    using std::sqrt;
    prediction_result<Real> r;
    if (!(energy.value > 0)) return r;
    const auto& k = model.coefficients();
    const Real strip = asinh(sqrt(k.D0) / k.C);
    const angle_support<Real> sup(model, energy, configuration_angle::theta2);
    quadrature_result<Real> total;
    if (sup.theta_full > 0) {
        // every th1 allowed: the inner integral over a whole period, the same for every th2
        const quadrature_result<Real> ring =
            sqrt_det_integral(k, -pi<Real>(), pi<Real>(), Real(0), strip);
        total.value = sup.theta_full * ring.value;
        total.error_estimate = sup.theta_full * ring.error_estimate;
        total.l1_norm = total.value;
        total.evaluations = ring.evaluations;
    }
    if (sup.theta_full < sup.theta_edge) {
        const Real a = sup.theta_full, b = sup.theta_edge;
        const std::array<Real, 2> near = singularity_distances(sup, b);
        // th1 in [-t1, t1], u = th1 - th2 in [-t1 - th2, t1 - th2]; the inner integrand's
        // near-zeros u = j pi (`strip` off the real axis) reach an end of that interval where
        // t1 - th2 = 0 or t1 + th2 = pi, and there the outer integrand has a near-kink of width
        // ~ strip / |du/dth2| that tanh-sinh across it resolves slowly while its level differences
        // stay small (a lower link 2^20 times heavier, strip 7e-4: Omega at double 7.8e-6 off
        // against an estimate of 4.2e-8). The outer integral is split at those th2 and graded
        // towards them.
        const split_points<Real> cuts = outer_cuts(sup, a, b, strip);
        for (std::size_t i = 0; i + 1 < cuts.at.size(); ++i) {
            const Real lo = cuts.at[i], hi = cuts.at[i + 1];
            // the distances to a and b from the piece's own (exact at the outer ends)
            const Real lo_from_a = lo - a, hi_to_b = b - hi;
            auto inner = [&](const Real& th2, const Real& to_lo, const Real& to_hi) {
                const Real t1 = sup.half_width(th2, Real(hi_to_b + to_hi), Real(lo_from_a + to_lo));
                return sqrt_det_integral(k, Real(-t1), t1, th2, strip);
            };
            total += nested_integrate<Real>(inner, lo, hi, i == 0 ? near[0] : cuts.radius[i],
                                            i + 2 == cuts.at.size() ? near[1] : cuts.radius[i + 1]);
        }
    }
    // th2 in [-pi, 0] mirrors [0, pi]; the momenta contribute 2 pi.
    const Real factor = 2 * two_pi<Real>();
    r.value = factor * total.value;
    // the quadratures' estimates and the rounding of the nested sums: measured up to 30 eps of the
    // value at double just below arm 2's saddle level (a light and a heavy lower link, against
    // 45-digit references of an independent cross-check), hence 32 eps
    r.error_estimate = factor * total.error_estimate + 32 * epsilon<Real>() * r.value;
    r.evaluations = total.evaluations;
    return r;
}

template prediction_result<inst_real> phase_volume_quadrature_2d<inst_real>(
    const double_pendulum<inst_real>&, const energy_level<inst_real>&);

}  // namespace flipflux::detail
