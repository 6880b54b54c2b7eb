// The flip criteria by name, for the ensemble and the CLI: "upright" (the flip angle equals pi),
// "approx" (the approximate saddle curve, a sine with the centre mode's slope), "saddle" (the
// saddle orbit's curve, from orbits/), each for arm 1 or arm 2, and their predicted rates
// R = f / Omega from the quantity registry (prediction/, orbits/).
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {

/// The known criterion names, in the order of the paper.
const std::vector<std::string>& criterion_names();

/// The known criterion a file or option names in any case ("Upright" is "upright"); nullopt
/// for anything else. Files from other simulators are read through it.
std::optional<std::string> criterion_named(const std::string& text);

/// Throws input_error naming `option` unless `name` is a known criterion.
void check_criterion_name(const std::string& name, const std::string& option = "criteria");

/// The lowest energy at which the criterion's curve is accessible: the saddle energy of `a`
/// (below it no flip of `a` is possible and the predicted rate vanishes).
double criterion_threshold(const double_pendulum<double>& model, arm a, const std::string& name);

/// The criterion `name` for arm `a` at energy E (the saddle orbit depends on E). Throws
/// input_error for an unknown name, an energy at or below the threshold, or an energy where the
/// curve does not exist.
ensemble_criterion make_criterion(const double_pendulum<double>& model, arm a,
                                  const std::string& name, double energy);

/// The predicted rate f / Omega at double from the quantity registry: "rate-<name>" (default
/// method), else "flux-<name>" / "omega"; nullopt when neither is registered.
std::optional<quantity_value<double>> criterion_prediction(const double_pendulum<double>& model,
                                                           arm a, const std::string& name,
                                                           double energy);

}  // namespace flipflux
