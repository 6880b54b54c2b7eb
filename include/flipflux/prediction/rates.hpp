// Predicted flip rates R = f / Omega (paper eqs. eq:flip_rate_formula,
// eq:three_flip_rate_predictions) for the criteria that need no periodic orbit. The saddle-orbit
// rate is rate_from(saddle flux, phase_volume(...)) with the flux from orbits/.
//
// Routes (each combines independent routes for f and Omega):
//   closed_form  Omega: elliptic 1-D reduction; f1: elliptic closed forms; f2: kinetic 1-D
//   quadrature   Omega: 2-D quadrature; f1: 1-D integral; f2: momentum 2-D quadrature
// R = 0 for E <= E_s. Domain: E > 0 (std::domain_error otherwise: Omega = 0).
#pragma once

#include <string>

#include "flipflux/core/names.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/energy_level.hpp"
#include "flipflux/prediction/result.hpp"

namespace flipflux {

enum class flip_criterion { upright, approximate_saddle };
enum class rate_route { closed_form, quadrature };

/// "upright", "approximate-saddle"; "closed-form", "quadrature".
template <>
struct enum_table<flip_criterion> {
    static constexpr std::string_view noun = "a predicted criterion";
    static constexpr std::array<std::pair<flip_criterion, std::string_view>, 2> entries{
        {{flip_criterion::upright, "upright"}, {flip_criterion::approximate_saddle, "approx"}}};
};
template <>
struct enum_table<rate_route> {
    static constexpr std::string_view noun = "a rate route";
    static constexpr std::array<std::pair<rate_route, std::string_view>, 2> entries{
        {{rate_route::closed_form, "closed-form"}, {rate_route::quadrature, "quadrature"}}};
};

template <class Real>
prediction_result<Real> predicted_rate(const double_pendulum<Real>& model, arm a,
                                       flip_criterion criterion, const level_arg<Real>& energy,
                                       rate_route route = rate_route::closed_form);

#define FLIPFLUX_RATES_EXTERN(R)                            \
    extern template prediction_result<R> predicted_rate<R>( \
        const double_pendulum<R>&, arm, flip_criterion, const level_arg<R>&, rate_route);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_RATES_EXTERN)
#undef FLIPFLUX_RATES_EXTERN

}  // namespace flipflux
