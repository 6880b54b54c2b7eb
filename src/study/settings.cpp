// The run settings' table, builder and sharing rule (include/flipflux/study/settings.hpp).
#include "flipflux/study/settings.hpp"

#include <charconv>
#include <cmath>
#include <stdexcept>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/core/names.hpp"
#include "flipflux/study/criteria.hpp"

namespace flipflux {

const std::vector<run_setting>& run_settings() {
    // field, option, scene key, keyword, default, scene default, decides trajectories, help, kind
    static const std::vector<run_setting> table{
        {"energy", "--energy", "energies", "energy", "", "", false,
         "energy E, a list E1,E2,... or a range FROM:TO:STEP", setting_kind::text},
        {"arm", "--arm", "arm", "arm", "2", "", false, "the arm whose flips are counted",
         setting_kind::text},
        {"criteria", "--criteria", "criteria", "criteria", "(all)", "", false,
         "comma-separated flip criteria", setting_kind::text},
        {"replicates", "--replicates", "replicates", "replicates", "1", "", true,
         "independent replicates of the trajectories", setting_kind::integer},
        {"trajectories", "--trajectories", "trajectories", "trajectories", "", "1000", true,
         "number of trajectories per energy (> 0)", setting_kind::integer},
        {"time", "--time", "time", "time", "", "10000", true,
         "integration time T per trajectory (> 0)", setting_kind::number},
        {"seed", "--seed", "seed", "seed", "0", "1", true, "random seed (non-negative integer)",
         setting_kind::integer},
        {"first_index", "--first-index", "", "", "0", "", true,
         "index of the first trajectory (split runs across processes)", setting_kind::integer},
        {"rtol", "--rtol", "rtol", "rtol", "1e-10", "", true,
         "relative (and absolute) tolerance of the integrator", setting_kind::number},
        {"atol", "", "atol", "", "0", "", true, "absolute tolerance (0: equal to rtol)",
         setting_kind::number},
        {"method", "--method", "integrator", "method", "auto", "dop853", true,
         "integrator: dop853, dopri5, taylor or auto", setting_kind::text},
        {"threads", "--threads", "", "threads", "0", "", false, "OpenMP threads (0: all available)",
         setting_kind::integer},
        {"chaos_threshold", "--chaos-threshold", "chaos_threshold", "chaos_threshold", "0.05", "",
         false, "Lyapunov threshold for 'chaotic', in units of sqrt(alpha/A)",
         setting_kind::number},
        {"chaos", "--no-chaos", "chaos", "chaos", "true", "false", true,
         "classify trajectories by their finite-time Lyapunov exponent", setting_kind::boolean},
        {"bins", "--bins", "", "", "0", "", false, "histogram bins (0: square-root rule)",
         setting_kind::integer},
        {"sample_interval", "--sample-interval", "", "", "0", "", false,
         "store every trajectory's state at this time interval", setting_kind::number},
        {"checkpoint_interval", "--checkpoint-interval", "", "", "2", "", false,
         "seconds between checkpoint appends", setting_kind::number},
        {"max_seconds", "--max-seconds", "", "max_seconds", "0", "", false,
         "CPU seconds the integration may take (0: no bound)", setting_kind::number},
        {"estimator", "--estimator", "estimator", "", "long", "", true, "long or short",
         setting_kind::text},
        {"short_time", "--short-time", "", "", "20", "", true,
         "trajectory length of the short estimator", setting_kind::number},
        {"reference_time", "--reference-time", "reference_time", "", "0", "", false,
         "also estimate the PQI for trajectories of this length", setting_kind::number},
    };
    return table;
}

const run_setting& run_setting_named(std::string_view field) {
    for (const run_setting& s : run_settings())
        if (s.field == field) return s;
    throw std::logic_error("run_setting_named: no setting '" + std::string(field) + "'");
}

std::string setting_name(const run_setting& s, settings_surface surface) {
    const std::string_view name = surface == settings_surface::command_line ? s.option
                                  : surface == settings_surface::scene      ? s.scene_key
                                                                            : s.keyword;
    return std::string(name.empty() ? s.field : name);
}

std::string setting_default(const run_setting& s, settings_surface surface) {
    if (s.field == "criteria") return criterion_name_list(",");  // every registered criterion
    return std::string(surface == settings_surface::scene && !s.scene_default.empty()
                           ? s.scene_default
                           : s.default_text);
}

arm parse_arm(const std::string& text, const std::string& field) {
    if (const std::optional<arm> a = arm_named(text)) return *a;
    throw input_error::about(field, "'" + text + "' is not an arm (expected 1 or 2)");
}

std::uint64_t parse_unsigned(const std::string& text, const std::string& field, bool positive) {
    std::uint64_t v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end || (positive && v == 0))
        throw input_error::about(field, "'" + text + "' is invalid (expected " +
                                            (positive ? "a positive" : "a non-negative") +
                                            " integer)");
    return v;
}

double parse_positive(const std::string& text, const std::string& field) {
    const double v = parse_real<double>(text, field);
    if (!(v > 0)) throw input_error::about(field, "'" + text + "' is invalid (must be > 0)");
    return v;
}

namespace {

/// The given settings with their defaults, and each one's name on the surface.
struct settings_reader {
    const settings_text& given;
    settings_surface surface;

    bool has(std::string_view field) const { return given.find(field) != given.end(); }
    std::string text(std::string_view field) const {
        const auto it = given.find(field);
        return it != given.end() ? it->second : setting_default(run_setting_named(field), surface);
    }
    std::string name(std::string_view field) const {
        return setting_name(run_setting_named(field), surface);
    }
    double real(std::string_view field) const {
        return parse_real<double>(text(field), name(field));
    }
    double positive(std::string_view field) const {
        return parse_positive(text(field), name(field));
    }
    std::uint64_t count(std::string_view field, bool positive) const {
        return parse_unsigned(text(field), name(field), positive);
    }
    bool boolean(std::string_view field) const {
        const std::string t = text(field);
        if (t != "true" && t != "false")
            throw input_error::about(name(field), "'" + t + "' is not true or false");
        return t == "true";
    }
};

}  // namespace

simulation_request make_simulation_request(const settings_text& given, settings_surface surface) {
    for (const auto& [field, text] : given)
        (void)run_setting_named(field);  // a caller's typo is a programming error
    const settings_reader r{given, surface};
    simulation_request q;
    q.flip_arm = parse_arm(r.text("arm"), r.name("arm"));
    if (r.has("energy")) q.energies = parse_energy_list(r.text("energy"), r.name("energy"));
    q.criteria = parse_criterion_list(r.text("criteria"), r.name("criteria"));
    ensemble_options& o = q.options;
    o.trajectories = r.count("trajectories", true);
    if (o.trajectories > max_trajectories)
        throw input_error::about(r.name("trajectories"),
                                 "'" + r.text("trajectories") + "' is too many (at most " +
                                     std::to_string(max_trajectories) + " per energy)");
    q.replicates = r.count("replicates", true);
    if (q.replicates > max_replicates)
        throw input_error::about(r.name("replicates"), "'" + r.text("replicates") +
                                                           "' is too many (at most " +
                                                           std::to_string(max_replicates) + ")");
    o.time = r.positive("time");
    o.seed = r.count("seed", false);
    o.first_index = r.count("first_index", false);
    o.rtol = r.positive("rtol");
    o.atol = r.real("atol");
    if (!(o.atol >= 0) || std::signbit(o.atol))
        throw input_error::about(r.name("atol"),
                                 "'" + r.text("atol") + "' must be >= 0 (0: equal to rtol)");
    o.threads = checked_threads(r.count("threads", false), r.name("threads"));
    o.method =
        resolved_method(parse_name<integration_method>(r.text("method"), r.name("method")), o.rtol);
    if (const std::string p = rtol_problem(o.rtol, r.text("rtol"), o.method); !p.empty())
        throw input_error::about(r.name("rtol"), p);
    o.chaos = r.boolean("chaos");
    o.chaos_threshold = r.positive("chaos_threshold");
    o.sample_interval = r.real("sample_interval");
    q.bins = r.count("bins", false);
    q.checkpoint_interval = r.real("checkpoint_interval");
    q.max_seconds = r.real("max_seconds");
    q.estimator = parse_name<rate_estimator>(r.text("estimator"), r.name("estimator"));
    q.short_time = r.positive("short_time");
    q.reference_time = r.real("reference_time");
    if (!(q.reference_time >= 0) || std::signbit(q.reference_time))
        throw input_error::about(
            r.name("reference_time"),
            "'" + to_shortest_decimal(q.reference_time) + "' is invalid (must be finite and >= 0)");
    return q;
}

trajectory_key trajectory_key_of(const simulation_request& q) {
    const ensemble_options& o = q.options;
    trajectory_key k;
    k.trajectories = o.trajectories;
    k.first_index = o.first_index;
    k.seed = o.seed;
    k.replicates = q.replicates;
    k.time = o.time;
    k.rtol = o.rtol;
    k.atol = effective_atol(o);
    k.short_time = q.estimator == rate_estimator::short_trajectories ? q.short_time : 0;
    k.method = o.method;
    k.chaos = o.chaos;
    k.sampled = q.initial_states.empty();
    k.estimator = q.estimator;
    return k;
}

/// "5", "2.5,3,3.5" or "2.1:5.9:0.1" (a grid by decimal_grid's rule, core/decimal.hpp).
std::vector<std::pair<std::string, double>> parse_energy_list(const std::string& text,
                                                              const std::string& option) {
    std::vector<std::pair<std::string, double>> out;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        const std::size_t comma = std::min(text.find(',', pos), text.size());
        const std::string item = text.substr(pos, comma - pos);
        const std::size_t c1 = item.find(':');
        if (c1 == std::string::npos) {
            out.emplace_back(item, parse_real<double>(item, option));
        } else {
            const std::size_t c2 = item.find(':', c1 + 1);
            if (c2 == std::string::npos || item.find(':', c2 + 1) != std::string::npos)
                throw input_error::about(option, "'" + item + "' is not a range (FROM:TO:STEP)");
            const std::string_view v(item);
            for (const std::string& e : decimal_grid(v.substr(0, c1), v.substr(c1 + 1, c2 - c1 - 1),
                                                     v.substr(c2 + 1), option, max_energy_count))
                out.emplace_back(e, parse_real<double>(e, option));
        }
        pos = comma + 1;
        if (out.size() > max_energy_count)
            throw input_error::about(option, "more than " + std::to_string(max_energy_count) +
                                                 " energies (docs/limits.md)");
    }
    // one energy once: "3,3.0" would run two identical ensembles (compared as the doubles run)
    std::vector<std::pair<double, std::size_t>> sorted;
    for (std::size_t i = 0; i < out.size(); ++i)
        sorted.emplace_back(out[i].second, i);
    std::sort(sorted.begin(), sorted.end());
    for (std::size_t i = 1; i < sorted.size(); ++i)
        if (sorted[i].first == sorted[i - 1].first) {
            const std::size_t a = std::min(sorted[i].second, sorted[i - 1].second);
            const std::size_t b = std::max(sorted[i].second, sorted[i - 1].second);
            throw input_error::about(
                option, "E = " + out[b].first + " is given twice (as '" + out[a].first + "')");
        }
    return out;
}

std::vector<std::string> parse_criterion_list(const std::string& text, const std::string& option) {
    std::vector<std::string> out;
    std::size_t pos = 0;
    while (pos <= text.size()) {
        const std::size_t comma = std::min(text.find(',', pos), text.size());
        const std::string name = text.substr(pos, comma - pos);
        check_criterion_name(name, option);
        for (const std::string& seen : out)
            if (seen == name) throw input_error::about(option, "'" + name + "' is given twice");
        out.push_back(name);
        pos = comma + 1;
    }
    return out;
}

}  // namespace flipflux
