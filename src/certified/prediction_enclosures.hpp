// Enclosures of the phase volume and the upright flux in Arb balls (private to certified/;
// derivations in docs/certified.md).
#pragma once

#include "arb_handle.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/model_text.hpp"

namespace flipflux::certified_detail {

/// The Lagrangian's coefficients (model/double_pendulum.hpp) as balls containing their exact
/// values for the decimal parameters.
struct pendulum_balls {
    arb_ball A, B, C, alpha, beta, D0;
};

/// Parses the decimal parameters into balls at prec bits and forms the coefficients; throws
/// input_error naming a malformed or out-of-domain parameter.
pendulum_balls pendulum_from_text(const model_text& t, slong prec);

/// Parses a decimal energy into a ball containing it; input_error naming "energy" otherwise.
void energy_from_text(arb_t E, const std::string& text, slong prec);

/// Omega(E) (prediction/phase_volume.hpp) for E > 0.
void enclose_phase_volume(arb_t res, const pendulum_balls& p, const arb_t E, slong prec);

/// f1(E) of arm a (prediction/upright_flux.hpp): 0 at and below the saddle.
void enclose_upright_flux(arb_t res, const pendulum_balls& p, arm a, const arb_t E, slong prec);

}  // namespace flipflux::certified_detail
