// f1: flux through the upright surface th_flip = pi (paper eqs. eq:upright_arm_flux_integral,
// eq:upright_arm_flux_incomplete_elliptic, eq:upright_arm_flux_complete_elliptic, App. C),
// generalised to either arm and any pendulum. See include/flipflux/prediction/upright_flux.hpp.
#include <cmath>
#include <stdexcept>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/prediction/curve_flux.hpp"
#include "flipflux/prediction/upright_flux.hpp"
#include "flipflux/quadrature/quadrature.hpp"
#include "flipflux/special/elliptic.hpp"

namespace flipflux {
namespace {

/// The constants of f1 for arm a: J = n^T adj(M) n, w the weight of the other angle in V,
/// delta = E - E_s, and E_max - E.
template <class Real>
struct upright_geometry {
    Real J, w, delta, below_max;
    upright_geometry(const double_pendulum<Real>& model, arm a, const energy_level<Real>& energy) {
        using boost::multiprecision::isfinite;
        using std::isfinite;
        if (!isfinite(energy.value) || !isfinite(energy.residual))
            throw std::domain_error("upright_flux: energy not finite");
        const auto& k = model.coefficients();
        J = a == arm::two ? k.A : k.B;
        w = a == arm::two ? k.alpha : k.beta;
        delta = energy.above(model.saddle_level(a));
        below_max = energy.below(model.maximum_level());
        // 2w = (E - E_s) + (E_max - E), exactly for the decimal inputs: taken from the two
        // distances where their sum does not cancel (E_s < E <= E_max + w), so that the
        // elliptic modulus m = 2w/delta and 1 - m = (E - E_max)/delta are consistent. Near E_max
        // E(m) has the condition ~log(1/(1 - m)), and the parameters' rounding of w moved f1 by
        // 25 ulp there (E = E_max + 1e-20 of --m1 1.3 --m2 0.45 --L1 0.8 --L2 1.7 --g 9.81).
        if (delta > 0 && below_max > -w && isfinite(below_max)) w = (delta + below_max) / 2;
    }
};

/// 4 sqrt(2 J) * integral_{-pi}^{pi} sqrt(delta - 2 w sin^2(s/2))_+ ds by tanh-sinh.
template <class Real>
prediction_result<Real> upright_flux_integral(const upright_geometry<Real>& g) {
    using std::asin;
    using std::cos;
    using std::sin;
    using std::sqrt;
    prediction_result<Real> r;
    if (!(g.delta > 0)) return r;
    quadrature_result<Real> q;
    if (g.below_max > 0) {
        // K = 2 w (sin^2(s*/2) - sin^2(s/2)) = 2 w sin((s* - s)/2) sin(s* - (s* - s)/2) on
        // [0, s*]; when s* is near pi the second sine is taken from u* = pi - s*, computed from
        // E_max - E, as sin(u* + (s* - s)/2).
        const bool near_pi = g.delta > g.w;  // s* > pi/2
        const Real s_star = near_pi ? Real(pi<Real>() - 2 * asin(sqrt(g.below_max / (2 * g.w))))
                                    : Real(2 * asin(sqrt(g.delta / (2 * g.w))));
        const Real u_star = near_pi ? Real(2 * asin(sqrt(g.below_max / (2 * g.w)))) : Real(0);
        auto f = [&](const Real&, const Real&, const Real& to_b) -> Real {
            const Real mean = near_pi ? sin(u_star + to_b / 2) : sin(s_star - to_b / 2);
            const Real K = 2 * g.w * sin(to_b / 2) * mean;
            return K > 0 ? sqrt(K) : Real(0);
        };
        // sqrt(K) has its next branch point at the mirror zero 2 pi - s*, 2 u* beyond s*
        q = tanh_sinh_integrate_graded<Real>(f, Real(0), s_star, Real(0),
                                             Real(2 * (pi<Real>() - s_star)));
    } else {
        // K = (E - E_max) + 2 w sin^2((pi - s)/2) > 0 on [0, pi]: no zero, no cancellation; its
        // complex zeros lie sqrt(2 (E - E_max)/w) beyond pi
        auto f = [&](const Real&, const Real&, const Real& to_b) -> Real {
            const Real c = sin(to_b / 2);
            return sqrt(-g.below_max + 2 * g.w * c * c);
        };
        q = tanh_sinh_integrate_graded<Real>(f, Real(0), pi<Real>(), Real(0),
                                             Real(sqrt(-2 * g.below_max / g.w)));
    }
    const Real factor = 8 * sqrt(2 * g.J);  // 4 sqrt(2J) and the mirror half [-pi, 0]
    r.value = factor * q.value;
    r.error_estimate = factor * q.error_estimate + 4 * epsilon<Real>() * r.value;
    r.evaluations = q.evaluations;
    return r;
}

}  // namespace

template <class Real>
Real upright_flux_incomplete_elliptic(const double_pendulum<Real>& model, arm a,
                                      const level_arg<Real>& energy) {
    using std::sqrt;
    const upright_geometry<Real> g(model, a, energy);
    if (!(g.delta > 0) || !(g.below_max >= 0)) {
        throw std::domain_error("upright_flux_incomplete_elliptic: needs E_s < E <= E_max");
    }
    // phi_0 with sin^2 = delta/(2w), cos^2 = (E_max - E)/(2w), and 1 - m sin^2 = 0 exactly.
    const Real two_w = 2 * g.w;
    const Real value = elliptic_e_carlson(sqrt(g.delta / two_w), Real(g.below_max / two_w), Real(0),
                                          Real(two_w / g.delta));
    return 16 * sqrt(2 * g.J * g.delta) * value;
}

template <class Real>
Real upright_flux_complete_elliptic(const double_pendulum<Real>& model, arm a,
                                    const level_arg<Real>& energy) {
    using std::sqrt;
    const upright_geometry<Real> g(model, a, energy);
    if (!(g.below_max <= 0)) {
        throw std::domain_error("upright_flux_complete_elliptic: needs E >= E_max");
    }
    // m = 2w/delta, 1 - m = (E - E_max)/delta
    return 16 * sqrt(2 * g.J * g.delta) *
           elliptic_e_complete(Real(2 * g.w / g.delta), Real(-g.below_max / g.delta));
}

template <class Real>
Real upright_flux_reciprocal_modulus(const double_pendulum<Real>& model, arm a,
                                     const level_arg<Real>& energy) {
    using std::sqrt;
    const upright_geometry<Real> g(model, a, energy);
    if (!(g.delta > 0) || !(g.below_max > 0)) {
        throw std::domain_error("upright_flux_reciprocal_modulus: needs E_s < E < E_max");
    }
    const Real two_w = 2 * g.w;
    const Real p = g.delta / two_w, pc = g.below_max / two_w;
    return 16 * sqrt(g.J / g.w) *
           (two_w * elliptic_e_complete(p, pc) - g.below_max * elliptic_k_complete(p, pc));
}

template <class Real>
Real upright_flux_near_saddle(const double_pendulum<Real>& model, arm a,
                              const level_arg<Real>& energy) {
    using std::sqrt;
    const upright_geometry<Real> g(model, a, energy);
    return 4 * pi<Real>() * sqrt(g.J / g.w) * g.delta * (1 + g.delta / (16 * g.w));
}

template <class Real>
prediction_result<Real> upright_flux(const double_pendulum<Real>& model, arm a,
                                     const level_arg<Real>& energy, upright_flux_method method) {
    const upright_geometry<Real> g(model, a, energy);
    prediction_result<Real> r;
    if (!(g.delta > 0)) return r;  // the surface is not reached
    switch (method) {
        case upright_flux_method::elliptic:
            r.value = g.below_max >= 0 ? upright_flux_incomplete_elliptic(model, a, energy)
                                       : upright_flux_complete_elliptic(model, a, energy);
            r.error_estimate = 16 * epsilon<Real>() * r.value;
            return r;
        case upright_flux_method::integral:
            return upright_flux_integral(g);
        case upright_flux_method::curve:
        case upright_flux_method::momentum:
            break;
    }
    const curve_flux_result<Real> c =
        curve_flux(model, energy, upright_curve<Real>{a},
                   method == upright_flux_method::curve ? curve_flux_method::kinetic
                                                        : curve_flux_method::momentum);
    r.value = c.value;
    r.error_estimate = c.error_estimate;
    r.evaluations = c.evaluations;
    return r;
}

#define FLIPFLUX_UPRIGHT_FLUX_INSTANTIATE(R)                                                 \
    template prediction_result<R> upright_flux<R>(const double_pendulum<R>&, arm,            \
                                                  const level_arg<R>&, upright_flux_method); \
    template R upright_flux_incomplete_elliptic<R>(const double_pendulum<R>&, arm,           \
                                                   const level_arg<R>&);                     \
    template R upright_flux_complete_elliptic<R>(const double_pendulum<R>&, arm,             \
                                                 const level_arg<R>&);                       \
    template R upright_flux_reciprocal_modulus<R>(const double_pendulum<R>&, arm,            \
                                                  const level_arg<R>&);                      \
    template R upright_flux_near_saddle<R>(const double_pendulum<R>&, arm, const level_arg<R>&)
FLIPFLUX_UPRIGHT_FLUX_INSTANTIATE(inst_real);

}  // namespace flipflux
