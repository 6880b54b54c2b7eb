// Enclosures of the phase volume and the upright flux in Arb balls (private to certified/;
// derivations in docs/certified.md).
#pragma once

#include <functional>
#include <vector>

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

/// -1, 0 (both exact and equal), +1, or 2 (undecided) for E against the kink K.
int compare_energy(const arb_t E, const arb_t K);

using energy_function = std::function<void(arb_t, const arb_t)>;

/// f(E) for f non-decreasing in E whose formula changes at the kinks: when E is undecided
/// against a kink, the union of f at exact energies strictly below and above both.
void monotone_enclosure(arb_t res, const energy_function& f, const arb_t E,
                        const std::vector<const arb_struct*>& kinks, slong prec, int depth = 0);

/// The slope A of the saddle's centre mode for arm a (model/critical_points.hpp), so that the
/// approximate saddle curve is th_flip = pi + A sin s.
void enclose_centre_mode_slope(arb_t res, const pendulum_balls& p, arm a, slong prec);

/// f2(E) of arm a (prediction/curve_flux.hpp: the flux through the approximate saddle curve).
void enclose_approximate_flux(arb_t res, const pendulum_balls& p, arm a, const arb_t E, slong prec);

/// True when it is proven that the approximate curve of arm a touches the saddle's energy level
/// only at the saddle (w_f A^2 < w_s; then V > E_s elsewhere on it, since sin^2(A sin(s)/2) <=
/// A^2 sin^2(s/2)): f2 = 0 for every E <= E_s.
bool approximate_curve_above_saddle(const pendulum_balls& p, arm a, slong prec);

}  // namespace flipflux::certified_detail
