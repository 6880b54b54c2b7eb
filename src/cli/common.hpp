// Shared pieces of the command-line layer: the model options every subcommand takes, the
// precision option, JSON output with every number as a decimal string.
#pragma once

#include <signal.h>

#include <CLI/CLI.hpp>
#include <atomic>
#include <filesystem>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/model_json.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/output/command_words.hpp"

namespace flipflux::cli {

using json = nlohmann::ordered_json;

/// Model parameters as given on the command line: decimal text, parsed in the working precision.
using model_options = model_text;
void add_model_options(CLI::App& app, model_options& options);

struct precision_option {
    std::string text = "double";
};
void add_precision_option(CLI::App& app, precision_option& option);

/// --max-seconds: the CPU seconds one evaluation may take (eval, orbit, trajectory). Before an
/// mp:N evaluation of more than pilot_min_digits digits, its cost is estimated from two pilot
/// evaluations at N/16 and N/4 digits (the growth of the CPU time with the digits between them,
/// extrapolated to N): beyond the bound it is refused at once with the estimate. The evaluation
/// itself runs under a CPU budget of that many seconds (core/budget.hpp) and is abandoned there.
struct time_bound_option {
    double max_seconds = 600;
};
void add_time_bound_option(CLI::App& app, time_bound_option& option);
inline constexpr int pilot_min_digits = 400;

namespace detail {
/// The pilots' estimate of f's CPU seconds at p (0 when p needs none); refuses beyond the bound.
/// `pilot` runs f at a precision and discards its result.
void estimate_cost(const precision& p, const time_bound_option& bound,
                   const std::function<void(const precision&)>& pilot);
[[noreturn]] void budget_spent(const time_bound_option& bound, const precision& p);
}  // namespace detail

/// dispatch(p, f) under the bound: pilots first (when `pilots`: f must have no side effects),
/// then f under a CPU budget of bound.max_seconds; input_error naming --max-seconds when spent.
template <class F>
decltype(auto) bounded_dispatch(const precision& p, const time_bound_option& bound, bool pilots,
                                F&& f) {
    if (!(bound.max_seconds > 0))
        throw input_error("--max-seconds: '" + to_decimal(bound.max_seconds) +
                          "' is invalid (must be > 0)");
    if (pilots) detail::estimate_cost(p, bound, [&f](const precision& q) { (void)dispatch(q, f); });
    try {
        const cpu_budget_scope budget(bound.max_seconds);
        return dispatch(p, f);
    } catch (const budget_exceeded&) {
        detail::budget_spent(bound, p);
    }
}

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

/// The one number grammar of the command line, added to every numeric option of every subcommand
/// (by its CLI11 type): an integer option takes decimal digits only ("0x10", "1e3", "+-2" are
/// refused); a real option takes a plain finite decimal number (is_decimal_number) whose double
/// is finite and normal (an underflow to 0 or below 2.2e-308, an overflow to inf, is refused,
/// naming the value). Applied once, in main, after every subcommand is registered.
void apply_number_grammar(CLI::App& app);

/// TEXT on one line, as an error message may quote it: control characters (a newline that could
/// forge a second message line, a tab, an escape) and DEL written as \n, \t, \xHH.
std::string one_line(const std::string& text);

/// A library field as the command line names it: "until" -> "--until", "time_tol" -> "--time-tol"
/// (an input_namer).
std::string option_name(std::string_view field);

/// The command line's words for its commands in generated files (golden provenance, the
/// accuracy report): "flipflux eval --help", "golden --certify", ...
command_words cli_command_words();

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

/// The signal (SIGINT, SIGTERM) that asked a long command (simulate, run) to stop; 0: none. Its
/// computations poll it once per integrator step (ensemble_options::stop): in-flight trajectories
/// are abandoned, finished ones are in the checkpoint, the exit status is 128 + the signal.
std::atomic<int>& stop_signal();

/// Installs the SIGINT/SIGTERM handlers that set stop_signal() for its lifetime (and clears it).
class signal_guard {
  public:
    signal_guard();
    ~signal_guard();
    signal_guard(const signal_guard&) = delete;
    signal_guard& operator=(const signal_guard&) = delete;

  private:
    struct sigaction old_int_ {};
    struct sigaction old_term_ {};
};

}  // namespace flipflux::cli

namespace flipflux::cli {

/// Parses "1" or "2"; throws input_error naming `option` otherwise.
arm parse_arm(const std::string& text, std::string_view option = "--arm");

}  // namespace flipflux::cli
