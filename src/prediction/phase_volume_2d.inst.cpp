// Omega(E) by 2-D quadrature over configuration space (paper eq.
// eq:phase_space_volume_egalitatian_double_pendu, generalised): the outer integral over th2
// (tanh-sinh, split where the allowed th1-interval reaches its full and empty extents), the inner
// over th1 between the boundary points -t1(th2), t1(th2) of V = E (adaptive Gauss-Kronrod). The
// discontinuous step Theta(E - V) is never integrated: the boundary is solved for.
// Independent of the elliptic route: other integration order, other rule, no elliptic integrals.
#include <cmath>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/quadrature/quadrature.hpp"
#include "phase_volume_detail.hpp"
#include "support.hpp"

namespace flipflux::detail {

template <class Real>
prediction_result<Real> phase_volume_quadrature_2d(const double_pendulum<Real>& model,
                                                   const Real& energy) {
    using std::sin;
    using std::sqrt;
    prediction_result<Real> r;
    if (!(energy > 0)) return r;
    const auto& k = model.coefficients();
    const angle_support<Real> sup(model, energy, configuration_angle::theta2);
    // sqrt(det M) as a function of th1 - th2
    auto sqrt_det = [&k](const Real& u) -> Real {
        const Real s = sin(u);
        return sqrt(k.D0 + k.C * k.C * s * s);
    };
    quadrature_result<Real> total;
    if (sup.theta_full > 0) {
        // every th1 allowed: the inner integral over a whole period, the same for every th2
        quadrature_result<Real> ring = gauss_kronrod_integrate<Real>(
            [&](const Real& u) -> Real { return sqrt_det(u); }, -pi<Real>(), pi<Real>());
        total.value = sup.theta_full * ring.value;
        total.error_estimate = sup.theta_full * ring.error_estimate;
        total.l1_norm = total.value;
        total.evaluations = ring.evaluations;
    }
    if (sup.theta_full < sup.theta_edge) {
        auto inner = [&](const Real& th2, const Real& to_a, const Real& to_b) {
            const Real t1 = sup.half_width(th2, to_b, to_a);
            return gauss_kronrod_integrate<Real>(
                [&](const Real& th1) -> Real { return sqrt_det(th1 - th2); }, -t1, t1);
        };
        total += nested_integrate<Real>(inner, sup.theta_full, sup.theta_edge);
    }
    // th2 in [-pi, 0] mirrors [0, pi]; the momenta contribute 2 pi.
    const Real factor = 2 * two_pi<Real>();
    r.value = factor * total.value;
    r.error_estimate = factor * total.error_estimate + 8 * epsilon<Real>() * r.value;
    r.evaluations = total.evaluations;
    return r;
}

template prediction_result<inst_real> phase_volume_quadrature_2d<inst_real>(
    const double_pendulum<inst_real>&, const inst_real&);

}  // namespace flipflux::detail
