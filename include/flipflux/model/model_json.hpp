// The model as JSON, every number a decimal string with all the digits of its precision: the
// nine physical parameters and the Lagrangian coefficients. One layout for the CLI's JSON output
// (`flipflux model`, `eval`, `simulate`) and the scene's run.json (tools/report/make_report.py
// reads it).
#pragma once

#include <nlohmann/json.hpp>

#include "flipflux/core/decimal.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

/// {"m1", "m2", "L1", "L2", "a1", "a2", "I1", "I2", "g"}.
template <class Real>
nlohmann::ordered_json parameters_json(const physical_parameters<Real>& p) {
    nlohmann::ordered_json out = nlohmann::ordered_json::object();
    for (std::size_t i = 0; i < parameter_count; ++i)
        out[std::string(parameter_fields[i].name)] = to_decimal(p.*parameter_members<Real>[i]);
    return out;
}

/// ["m1", ..., "g"]: the values without their names, in parameter_fields' order (the checkpoint
/// header's compact layout).
template <class Real>
nlohmann::ordered_json parameter_array(const physical_parameters<Real>& p) {
    nlohmann::ordered_json out = nlohmann::ordered_json::array();
    for (std::size_t i = 0; i < parameter_count; ++i)
        out.push_back(to_decimal(p.*parameter_members<Real>[i]));
    return out;
}

/// {"A", "B", "C", "alpha", "beta", "D0"}, D0 = AB - C^2.
template <class Real>
nlohmann::ordered_json coefficients_json(const lagrangian_coefficients<Real>& k) {
    return {{"A", to_decimal(k.A)},         {"B", to_decimal(k.B)},       {"C", to_decimal(k.C)},
            {"alpha", to_decimal(k.alpha)}, {"beta", to_decimal(k.beta)}, {"D0", to_decimal(k.D0)}};
}

/// The parameters and, under "coefficients", the Lagrangian coefficients: the "model" block of
/// `flipflux eval`, `simulate` and a scene's ensemble-<name>.json.
template <class Real>
nlohmann::ordered_json model_parameters_json(const double_pendulum<Real>& model) {
    nlohmann::ordered_json out = parameters_json(model.parameters());
    out["coefficients"] = coefficients_json(model.coefficients());
    return out;
}

}  // namespace flipflux
