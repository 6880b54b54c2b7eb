// Shared pieces of the command-line layer: the model options every subcommand takes, the
// precision option, JSON output with every number as a decimal string.
#pragma once

#include <CLI/CLI.hpp>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/model_json.hpp"
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

/// The parameters and, under "coefficients", the Lagrangian coefficients (model/model_json.hpp).
template <class Real>
json parameters_json(const double_pendulum<Real>& model) {
    return model_parameters_json(model);
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

/// The one-line message of bad input as the command line names it: a library field becomes its
/// option (`energy: ...` -> `--energy: ...`, `sample_interval` -> `--sample-interval`); names
/// given in full (an option, a scene's file and key) are kept.
std::string error_text(const input_error& e);

/// A file or directory of the installation, found relative to the running executable
/// (/proc/self/exe): share/flipflux/RELATIVE beside it (build tree) or ../share/flipflux/RELATIVE
/// (installed: PREFIX/bin/flipflux); empty when neither exists. No source path is compiled in.
std::filesystem::path find_share_path(const std::filesystem::path& relative);

/// Writes text to stdout in one piece (the JSON is built completely before anything is printed).
void print(const std::string& text);

}  // namespace flipflux::cli

namespace flipflux::cli {

/// Parses "1" or "2"; throws input_error naming `option` otherwise.
arm parse_arm(const std::string& text, std::string_view option = "--arm");

}  // namespace flipflux::cli
