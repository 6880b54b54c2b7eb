// The run settings of a Monte Carlo study: one table, one builder, one sharing rule.
//
// Every setting of a simulation_request that a user gives (rtol, time, seed, the integrator,
// ...) is described once here: its field name (the library's input_error field), its command-line
// option, its scene key, its Python keyword, its default on each surface, and whether it decides
// the trajectories. The command line (`flipflux simulate`), a scene's [[ensemble]] and Python's
// flipflux.simulate all give their settings as text to make_simulation_request, which parses and
// checks each once and names an offending setting as the caller's surface calls it ("--rtol",
// "rtol" in a scene, keyword "rtol" in Python). trajectory_key decides which studies share
// trajectories (a scene's plan and simulate's own check).
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <tuple>
#include <vector>

#include "flipflux/study/simulation.hpp"

namespace flipflux {

/// Who gives the settings: each names them its own way.
enum class settings_surface { command_line, scene, python };

/// What a setting's value is (a scene reads it as this TOML type; every surface gives it as text).
enum class setting_kind { text, integer, number, boolean };

/// One run setting.
struct run_setting {
    std::string_view field;          ///< the library's name: settings_text keys, input_error
    std::string_view option;         ///< the command line's option ("" if not there)
    std::string_view scene_key;      ///< a scene [[ensemble]]'s key ("" if not there)
    std::string_view keyword;        ///< Python's keyword ("" if not there)
    std::string_view default_text;   ///< the default on the command line and in Python
    std::string_view scene_default;  ///< a scene's default where it differs ("" : the same)
    bool decides_trajectories;       ///< part of trajectory_key
    std::string_view help;           ///< one line for help texts
    setting_kind kind;               ///< its value's type
};

/// Every run setting, in the command line's order.
const std::vector<run_setting>& run_settings();

/// The setting named `field`; std::logic_error for an unknown field (a programming error).
const run_setting& run_setting_named(std::string_view field);

/// The name `surface` gives the setting (option, scene key or keyword; the field if it has none).
std::string setting_name(const run_setting& s, settings_surface surface);

/// The default text of the setting on `surface`.
std::string setting_default(const run_setting& s, settings_surface surface);

/// Settings as text by field name ("rtol" -> "1e-10"; booleans "true"/"false"). A field not given
/// takes its default for the surface; energies, criteria and arm may be left to the caller.
using settings_text = std::map<std::string, std::string, std::less<>>;

/// The checked request the settings describe (energies only if "energy" is given; csv_dir,
/// checkpoint, group and the like are the caller's). `auto` is resolved by rtol. Throws
/// input_error about the setting, named as `surface` names it.
simulation_request make_simulation_request(const settings_text& given, settings_surface surface);

/// Everything that decides a study's trajectories (bit for bit), after defaults and rules (atol
/// 0 is rtol, `auto` resolved): two studies with equal keys integrate the same trajectories.
struct trajectory_key {
    std::uint64_t trajectories = 0, first_index = 0, seed = 0;
    std::size_t replicates = 1;
    double time = 0, rtol = 0, atol = 0, short_time = 0;
    integration_method method = integration_method::dop853;
    bool chaos = false, sampled = true;
    rate_estimator estimator = rate_estimator::long_trajectories;
    bool operator==(const trajectory_key&) const = default;
};

trajectory_key trajectory_key_of(const simulation_request& request);

/// The arm named "1" or "2"; input_error about `field` otherwise.
arm parse_arm(const std::string& text, const std::string& field = "arm");

/// A non-negative (positive) integer; input_error about `field` otherwise.
std::uint64_t parse_unsigned(const std::string& text, const std::string& field, bool positive);

/// A number > 0; input_error about `field` otherwise.
double parse_positive(const std::string& text, const std::string& field);

/// "5", "2.5,3,3.5" or "FROM:TO:STEP" items (a grid by the one grid rule, core/decimal.hpp's
/// decimal_grid: TO - FROM a multiple of STEP, at most 1e5 values), in order, each with its decimal
/// text as label; throws input_error naming `option`.
std::vector<std::pair<std::string, double>> parse_energy_list(const std::string& text,
                                                              const std::string& option = "energy");

/// Comma-separated criterion names, each known and at most once; throws input_error naming
/// `option`.
std::vector<std::string> parse_criterion_list(const std::string& text,
                                              const std::string& option = "criteria");

}  // namespace flipflux
