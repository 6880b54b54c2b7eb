// Omega(E) by 2-D quadrature over configuration space (paper eq.
// eq:phase_space_volume_egalitatian_double_pendu, generalised): the outer integral over th2
// (tanh-sinh, split where the allowed th1-interval reaches its full and empty extents), the inner
// over th1 between the boundary points -t1(th2), t1(th2) of V = E (Gauss-Kronrod panels sized by
// the integrand's strip of analyticity, tanh-sinh as fallback). The
// discontinuous step Theta(E - V) is never integrated: the boundary is solved for.
// Independent of the elliptic route: other integration order, other inner rule, no elliptic
// integrals.
#include <cmath>

#include "allowed_region.hpp"
#include "flipflux/core/constants.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/quadrature/quadrature.hpp"
#include "phase_volume_detail.hpp"

namespace flipflux::detail {

namespace {

/// The integral of sqrt(det M) = sqrt(D0 + C^2 sin^2 u) over u in [a, b]: fixed-panel
/// Gauss-Kronrod sized by the strip of analyticity |Im u| < asinh(sqrt(D0)/C) (the zeros of
/// D0 + C^2 sin^2 u), tanh-sinh when that would need too many panels or misses the tolerance.
template <class Real>
quadrature_result<Real> sqrt_det_integral(const lagrangian_coefficients<Real>& k, const Real& a,
                                          const Real& b, const Real& strip) {
    using std::pow;
    using std::sin;
    using std::sqrt;
    const Real C2 = k.C * k.C;
    auto f = [&](const Real& u) -> Real {
        const Real s = sin(u);
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
    // every j pi inside, each piece has them at its ends, where tanh-sinh converges fast
    using std::ceil;
    quadrature_result<Real> sum;
    Real from = a;
    for (Real j = ceil(a / pi<Real>()); j * pi<Real>() < b; j += 1) {
        const Real cut = j * pi<Real>();
        if (!(cut > from)) continue;
        sum += tanh_sinh_integrate<Real>(
            [&](const Real& u, const Real&, const Real&) -> Real { return f(u); }, from, cut);
        from = cut;
    }
    sum += tanh_sinh_integrate<Real>(
        [&](const Real& u, const Real&, const Real&) -> Real { return f(u); }, from, b);
    return sum;
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
        const quadrature_result<Real> ring = sqrt_det_integral(k, -pi<Real>(), pi<Real>(), strip);
        total.value = sup.theta_full * ring.value;
        total.error_estimate = sup.theta_full * ring.error_estimate;
        total.l1_norm = total.value;
        total.evaluations = ring.evaluations;
    }
    if (sup.theta_full < sup.theta_edge) {
        auto inner = [&](const Real& th2, const Real& to_a, const Real& to_b) {
            const Real t1 = sup.half_width(th2, to_b, to_a);
            // th1 in [-t1, t1] is u = th1 - th2 in [-t1 - th2, t1 - th2]
            return sqrt_det_integral(k, Real(-t1 - th2), Real(t1 - th2), strip);
        };
        const std::array<Real, 2> near = singularity_distances(sup, sup.theta_edge);
        total += nested_integrate<Real>(inner, sup.theta_full, sup.theta_edge, near[0], near[1]);
    }
    // th2 in [-pi, 0] mirrors [0, pi]; the momenta contribute 2 pi.
    const Real factor = 2 * two_pi<Real>();
    r.value = factor * total.value;
    r.error_estimate = factor * total.error_estimate + 8 * epsilon<Real>() * r.value;
    r.evaluations = total.evaluations;
    return r;
}

template prediction_result<inst_real> phase_volume_quadrature_2d<inst_real>(
    const double_pendulum<inst_real>&, const energy_level<inst_real>&);

}  // namespace flipflux::detail
