// Shared pieces of the command-line layer: the model options every subcommand takes, the
// precision option, JSON output with every number as a decimal string.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/model_text.hpp"

namespace flipflux::cli {

using json = nlohmann::ordered_json;

/// Model parameters as given on the command line: decimal text, parsed in the working precision.
using model_options = model_text;
void add_model_options(CLI::App& app, model_options& options);

struct precision_option {
    std::string text = "double";
};
void add_precision_option(CLI::App& app, precision_option& option);

template <class Real>
json parameters_json(const double_pendulum<Real>& model) {
    const auto& p = model.parameters();
    const auto& k = model.coefficients();
    return json{{"m1", to_decimal(p.m1)},
                {"m2", to_decimal(p.m2)},
                {"L1", to_decimal(p.L1)},
                {"L2", to_decimal(p.L2)},
                {"a1", to_decimal(p.a1)},
                {"a2", to_decimal(p.a2)},
                {"I1", to_decimal(p.I1)},
                {"I2", to_decimal(p.I2)},
                {"g", to_decimal(p.g)},
                {"coefficients",
                 {{"A", to_decimal(k.A)},
                  {"B", to_decimal(k.B)},
                  {"C", to_decimal(k.C)},
                  {"alpha", to_decimal(k.alpha)},
                  {"beta", to_decimal(k.beta)},
                  {"AB_minus_C2", to_decimal(k.D0)}}}};
}

/// Registry of subcommands: each src/cli/*_command.cpp registers one at static-init time.
struct command {
    std::function<void(CLI::App&)> setup;  ///< adds the subcommand, its options and its callback
};
std::vector<command>& commands();
struct register_command {
    explicit register_command(std::function<void(CLI::App&)> setup);
};

/// The process exit status once the subcommand has run (0 unless it sets a failure, e.g.
/// `validate` sets 1 when a row fails); bad input is reported by throwing input_error (status 2).
int& exit_status();

/// Writes text to stdout in one piece (the JSON is built completely before anything is printed).
void print(const std::string& text);

}  // namespace flipflux::cli

namespace flipflux::cli {

/// Parses "1" or "2"; throws input_error naming `option` otherwise.
arm parse_arm(const std::string& text, std::string_view option = "--arm");

}  // namespace flipflux::cli
