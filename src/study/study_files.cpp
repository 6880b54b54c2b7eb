// A study's results as JSON and CSV (include/flipflux/study/study_files.hpp).
#include "flipflux/study/study_files.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <set>
#include <stdexcept>
#include <string>
#include <system_error>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/version.hpp"
#include "flipflux/ensemble/replicate_check.hpp"
#include "flipflux/ensemble/taylor_ensemble.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/io/csv.hpp"

namespace flipflux {
namespace {

using json = nlohmann::ordered_json;

json number(double x) {
    return std::isfinite(x) ? json(to_decimal(x)) : json(nullptr);
}

json histogram_json(const histogram& h) {
    return json{{"lower", to_decimal(h.lower)},
                {"upper", to_decimal(h.upper)},
                {"bin_width", to_decimal(h.bin_width())},
                {"counts", h.counts}};
}

/// The pooled mean's replicate error (jackknife), its z and its ratio to the per-trajectory
/// standard error, with every replicate's mean and size: over all trajectories and the chaotic.
json replicates_json(const criterion_statistics& st) {
    const auto part = [&](const std::vector<summary_statistics>& parts,
                          const summary_statistics& pooled) {
        json means = json::array(), counts = json::array();
        for (const summary_statistics& r : parts) {
            means.push_back(number(r.mean));
            counts.push_back(r.count);
        }
        const double se = replicate_standard_error(parts);
        return json{{"standard_error", number(se)},
                    {"z_score", number((pooled.mean - st.predicted_rate) / se)},
                    {"error_ratio", number(se / pooled.standard_error)},
                    {"trajectories", counts},
                    {"means", means}};
    };
    return json{{"count", st.replicate_rates.size()},
                {"all_trajectories", part(st.replicate_rates, st.rates)},
                {"chaotic_trajectories", part(st.replicate_chaotic_rates, st.chaotic_rates)}};
}

json counts_json(const flip_count_statistics& x) {
    json fano = json::array(), tail = json::array();
    for (const window_fano& f : x.fano)
        fano.push_back(json{{"window", to_decimal(f.window)},
                            {"windows", f.windows},
                            {"mean_count", number(f.mean_count)},
                            {"fano", number(f.fano)},
                            {"windows_chaotic", f.windows_chaotic},
                            {"mean_count_chaotic", number(f.mean_count_chaotic)},
                            {"fano_chaotic", number(f.fano_chaotic)}});
    for (const auto& p : x.survival)
        tail.push_back(
            json::array({to_decimal(p.time), number(p.survival), number(p.survival_chaotic)}));
    return json{{"fano", fano},
                {"inter_flip_cv2", number(x.cv2)},
                {"inter_flip_cv2_chaotic", number(x.cv2_chaotic)},
                {"inter_flip_survival", tail}};
}

// `classified`: the chaos indicator ran (ensemble_options::chaos); without it no trajectory is
// classified, and the chaotic fraction and the chaotic subset's block are null, not zeros.
json criterion_json(const criterion_result& c, double max_energy_drift, bool classified) {
    const criterion_statistics& st = c.statistics;
    const auto& p = c.prediction;
    json j{{"predicted_rate", number(st.predicted_rate)},
           {"prediction_method", p ? json(p->method) : json(nullptr)},
           {"mean_rate", number(st.rates.mean)},
           {"std", number(st.rates.standard_deviation)},
           {"standard_error", number(st.rates.standard_error)},
           {"skewness", number(st.rates.skewness)},
           {"kurtosis", number(st.rates.kurtosis)},
           {"z_score", number(st.z_score)},
           {"flips", st.flips},
           {"chaotic_fraction", classified ? number(st.chaotic_fraction) : json(nullptr)},
           {"max_energy_drift", to_decimal(max_energy_drift)}};
    j["chaotic"] = !classified ? json(nullptr)
                               : json{{"trajectories", st.chaotic_rates.count},
                                      {"mean_rate", number(st.chaotic_rates.mean)},
                                      {"std", number(st.chaotic_rates.standard_deviation)},
                                      {"standard_error", number(st.chaotic_rates.standard_error)},
                                      {"skewness", number(st.chaotic_rates.skewness)},
                                      {"kurtosis", number(st.chaotic_rates.kurtosis)},
                                      {"z_score", number(st.chaotic_z_score)}};
    const residence_statistics& r = st.residence;
    j["residence_times"] = json{{"count", r.summary.count},   {"min", number(r.summary.minimum)},
                                {"q0.001", number(r.q001)},   {"q0.01", number(r.q01)},
                                {"median", number(r.median)}, {"mean", number(r.summary.mean)}};
    j["rate_histogram"] = histogram_json(st.rate_distribution);
    j["max_rate"] = number(st.rates.maximum);
    if (!st.replicate_rates.empty()) j["replicates"] = replicates_json(st);
    j["flip_counts"] = counts_json(st.counts);
    return j;
}

json energy_json(const energy_result& e, const std::vector<std::string>& names, bool timing,
                 bool classified) {
    json j{{"energy", e.label}};
    if (timing) {
        j["seconds"] = e.seconds;
        j["cpu_seconds"] = e.cpu_seconds;
        j["threads"] = e.threads;
        j["processes"] = e.processes;
    }
    j["steps_per_trajectory"] = e.steps_per_trajectory;
    j["failed_trajectories"] = e.failed_trajectories;
    j["energy_check_rejections"] = e.energy_check_rejections;
    j["max_energy_drift"] = to_decimal(e.max_energy_drift);
    json per_criterion = json::object();
    for (const criterion_result& c : e.criteria)
        per_criterion[c.statistics.criterion] = criterion_json(c, e.max_energy_drift, classified);
    j["criteria"] = per_criterion;
    json paired = json::array();
    for (const paired_difference& d : e.paired)
        paired.push_back(json{{"criteria", json::array({names.at(d.first), names.at(d.second)})},
                              {"mean", number(d.difference.mean)},
                              {"std", number(d.difference.standard_deviation)},
                              {"standard_error", number(d.difference.standard_error)}});
    j["paired_differences"] = paired;
    return j;
}

json quality_table(const std::vector<quality_indices>& table, double reference_time) {
    json arr = json::array();
    for (const quality_indices& q : table) {
        if (q.energies == 0) continue;
        json j{{"regime", q.regime},
               {"energies", q.energies},
               {"IQI", number(q.iqi)},
               {"PQI", number(q.pqi)},
               {"IQI_sd", number(q.iqi_sd)},
               {"PQI_sd", number(q.pqi_sd)},
               {"noise_floor", number(q.noise_floor)},
               {"rms_S", number(q.rms_spread)}};
        if (reference_time > 0)
            j["reference"] = json{{"time", to_decimal(reference_time)},
                                  {"PQI", number(q.pqi_reference)},
                                  {"PQI_sd", number(q.pqi_reference_sd)}};
        if (!q.iqi_replicates.empty()) {
            json iqi = json::array(), pqi = json::array();
            for (std::size_t k = 0; k < q.iqi_replicates.size(); ++k) {
                iqi.push_back(number(q.iqi_replicates[k]));
                pqi.push_back(number(q.pqi_replicates[k]));
            }
            j["replicates"] = json{{"IQI_se", number(q.iqi_replicate_se)},
                                   {"PQI_se", number(q.pqi_replicate_se)},
                                   {"IQI", iqi},
                                   {"PQI", pqi}};
        }
        arr.push_back(j);
    }
    return arr;
}

void write_atomically(const std::filesystem::path& path, const std::string& content) {
    write_file_atomically(path, content);  // output_error (exit 1) naming the path
}

table_column integer_column(std::string name) {
    table_column c;
    c.name = std::move(name);
    c.type = table_column::kind::integer;
    return c;
}

table_column real_column(std::string name, bool nan_is_empty = false) {
    table_column c;
    c.name = std::move(name);
    c.type = table_column::kind::real;
    c.nan_is_empty = nan_is_empty;
    return c;
}

table_column text_column(std::string name) {
    table_column c;
    c.name = std::move(name);
    c.type = table_column::kind::text;
    return c;
}

energy_table histogram_table(std::string name, const histogram& h, std::uint64_t total) {
    energy_table t{std::move(name),
                   {real_column("bin_lower"), real_column("bin_upper"), integer_column("count"),
                    real_column("density")}};
    for (std::size_t i = 0; i < h.counts.size(); ++i) {
        const double lo = h.lower + h.bin_width() * static_cast<double>(i);
        const double density =
            total ? static_cast<double>(h.counts[i]) / (static_cast<double>(total) * h.bin_width())
                  : 0.0;
        t.columns[0].reals.push_back(lo);
        t.columns[1].reals.push_back(lo + h.bin_width());
        t.columns[2].integers.push_back(h.counts[i]);
        t.columns[3].reals.push_back(density);
    }
    return t;
}

energy_table trajectories_table(const std::string& label, const ensemble_result& r) {
    energy_table t{
        "trajectories_E" + label,
        {integer_column("index"), real_column("lyapunov", true), integer_column("chaotic"),
         real_column("max_energy_drift"), integer_column("steps"),
         integer_column("energy_check_rejections"), text_column("status")}};
    for (const std::string& c : r.criteria) {
        t.columns.push_back(integer_column("flips_" + c));
        t.columns.push_back(real_column("rate_" + c));
    }
    for (const trajectory_result& x : r.trajectories) {
        t.columns[0].integers.push_back(x.index);
        t.columns[1].reals.push_back(x.lyapunov);
        t.columns[2].integers.push_back(r.chaotic(x) ? 1 : 0);
        t.columns[3].reals.push_back(x.max_energy_drift);
        t.columns[4].integers.push_back(static_cast<std::uint64_t>(x.steps));
        t.columns[5].integers.push_back(static_cast<std::uint64_t>(x.energy_check_rejections));
        t.columns[6].texts.emplace_back(to_string(x.status));
        for (std::size_t c = 0; c < r.criteria.size(); ++c) {
            t.columns[7 + 2 * c].integers.push_back(x.flips(c));
            t.columns[8 + 2 * c].reals.push_back(static_cast<double>(x.flips(c)) / r.time);
        }
    }
    return t;
}

energy_table samples_table(const std::string& label, const ensemble_result& r) {
    energy_table t{"samples_E" + label,
                   {integer_column("trajectory"), real_column("t"), real_column("theta1"),
                    real_column("theta2"), real_column("l1"), real_column("l2")}};
    for (const trajectory_result& x : r.trajectories)
        for (const auto& v : x.samples) {
            t.columns[0].integers.push_back(x.index);
            for (std::size_t i = 0; i < v.size(); ++i)
                t.columns[1 + i].reals.push_back(v[i]);
        }
    return t;
}

energy_table residence_table(const std::string& label, const ensemble_result& r, std::size_t c) {
    energy_table t{"residence_E" + label + "_" + r.criteria[c],
                   {integer_column("trajectory"), real_column("crossing_time"),
                    real_column("residence_time")}};
    for (const trajectory_result& x : r.trajectories) {
        const auto& times = x.crossing_times[c];
        for (std::size_t i = 1; i < times.size(); ++i) {
            t.columns[0].integers.push_back(x.index);
            t.columns[1].reals.push_back(times[i]);
            t.columns[2].reals.push_back(times[i] - times[i - 1]);
        }
    }
    return t;
}

}  // namespace

json study_json(const study_result& s) {
    const ensemble_options& o = s.options;
    json out{{"command", "simulate"},          {"arm", to_string(s.flip_arm)},
             {"trajectories", o.trajectories}, {"first_index", o.first_index},
             {"time", to_decimal(o.time)},     {"seed", o.seed},
             {"method", to_string(o.method)},  {"rtol", to_decimal(o.rtol)},
             {"atol", to_decimal(o.atol)},     {"estimator", to_string(s.estimator)}};
    // the binary that computed it (its version and commit: --version's, with "-dirty" when built
    // from a modified tree)
    out["flipflux"] = json{{"version", version_string()}, {"git_commit", git_commit()}};
    if (o.method == integration_method::taylor) out["taylor_order"] = ensemble_taylor_order(o);
    if (s.replicates > 1)
        out["replicates"] =
            json{{"count", s.replicates},
                 {"trajectories_each", o.trajectories / s.replicates},
                 {"rule",
                  "replicate k holds the trajectories first_index + k N ... + (k + 1) N - 1 "
                  "(N = trajectories_each): distinct random streams of (seed, E, index)"}};
    if (s.estimator == rate_estimator::short_trajectories)
        out["budget"] =
            json{{"trajectories", s.budget_trajectories}, {"time", to_decimal(s.budget_time)}};
    out["chaos"] =
        json{{"indicator",
              o.chaos ? "finite-time maximal Lyapunov exponent (variational equations)" : "none"},
             {"threshold", to_decimal(o.chaos_threshold)},
             {"threshold_rate", to_decimal(s.chaos_threshold_rate)},
             {"classification_reliable", s.classification_reliable}};
    json energies = json::array();
    for (const energy_result& e : s.energies)
        energies.push_back(energy_json(e, s.criteria, s.timing, o.chaos));
    out["energies"] = energies;
    json quality = json::object();
    for (std::size_t c = 0; c < s.criteria.size() && c < s.quality.size(); ++c)
        quality[s.criteria[c]] = json{
            {"all_trajectories", quality_table(s.quality[c].all_trajectories, s.reference_time)},
            {"chaotic_trajectories",
             o.chaos ? quality_table(s.quality[c].chaotic_trajectories, s.reference_time)
                     : json(nullptr)}};
    out["quality"] = quality;
    json regimes = json::array();
    for (const energy_regime& g : s.regimes)
        if (std::isfinite(g.lower))
            regimes.push_back(json{{"regime", g.name},
                                   {"lower", to_decimal(g.lower)},
                                   {"upper", to_decimal(g.upper)}});
    out["regimes"] = regimes;
    json agreement = json::object();
    auto agreement_json = [](const criterion_agreement& a) {
        json j{{"energies", a.energies},
               {"chi2", number(a.chi2)},
               {"worst_z", number(a.worst_z)},
               {"max_relative_deviation", number(a.max_relative_deviation)}};
        if (a.replicates) {
            const auto& v = *a.replicates;
            json each = json::array();
            for (double x : v.chi2_of_replicates)
                each.push_back(number(x));
            j["replicates"] = json{{"energies", v.energies},
                                   {"chi2", number(v.chi2)},
                                   {"expected_chi2", number(v.expected_chi2)},
                                   {"worst_z", number(v.worst_z)},
                                   {"chi2_of_replicates", each},
                                   {"max_error_ratio", number(v.max_error_ratio)},
                                   {"min_error_ratio", number(v.min_error_ratio)},
                                   {"error_mismatches", v.error_mismatches}};
            if (v.chi2_of_replicates.size() >= 2) {
                const std::array<double, 2> range =
                    replicate_error_ratio_range(v.chi2_of_replicates.size());
                j["replicates"]["error_ratio_range"] =
                    json::array({number(range[0]), number(range[1])});
                j["replicates"]["degrees_of_freedom"] = v.chi2_of_replicates.size() - 1;
            }
        }
        return j;
    };
    for (std::size_t c = 0; c < s.criteria.size() && c < s.agreement.size(); ++c)
        agreement[s.criteria[c]] =
            json{{"all_trajectories", agreement_json(s.agreement[c].all_trajectories)},
                 {"chaotic_trajectories", agreement_json(s.agreement[c].chaotic_trajectories)}};
    out["agreement"] = agreement;
    json differences = json::array();
    for (const prediction_difference& d : s.prediction_differences)
        differences.push_back(
            json{{"criteria", json::array({s.criteria.at(d.first), s.criteria.at(d.second)})},
                 {"energies", d.energies},
                 {"rms_relative", number(d.rms_relative)}});
    out["prediction_differences"] = differences;
    return out;
}

std::size_t table_column::size() const {
    switch (type) {
        case kind::integer:
            return integers.size();
        case kind::real:
            return reals.size();
        case kind::text:
            return texts.size();
    }
    return 0;
}

std::size_t energy_table::rows() const {
    return columns.empty() ? 0 : columns.front().size();
}

void for_each_energy_table(const ensemble_result& r, const energy_result& summary,
                           bool residence_times, const std::function<void(energy_table&&)>& f) {
    const std::string& label = summary.label;
    f(trajectories_table(label, r));
    if (!r.trajectories.empty() && !r.trajectories.front().samples.empty())
        f(samples_table(label, r));
    for (std::size_t c = 0; c < r.criteria.size(); ++c) {
        const std::string& name = r.criteria[c];
        const criterion_statistics& st = summary.criteria.at(c).statistics;
        if (residence_times) f(residence_table(label, r, c));
        f(histogram_table("rate_histogram_E" + label + "_" + name, st.rate_distribution,
                          st.rates.count));
        f(histogram_table("residence_histogram_E" + label + "_" + name, st.residence.distribution,
                          st.residence.summary.count));
    }
}

std::vector<energy_table> energy_tables(const ensemble_result& r, const energy_result& summary,
                                        bool residence_times) {
    std::vector<energy_table> out;
    for_each_energy_table(r, summary, residence_times,
                          [&](energy_table&& t) { out.push_back(std::move(t)); });
    return out;
}

std::string csv_text(const energy_table& t) {
    std::string s;
    for (std::size_t j = 0; j < t.columns.size(); ++j)
        s += (j ? "," : "") + t.columns[j].name;
    s += "\n";
    const std::size_t rows = t.rows();
    for (std::size_t i = 0; i < rows; ++i) {
        for (std::size_t j = 0; j < t.columns.size(); ++j) {
            const table_column& c = t.columns[j];
            if (j) s += ",";
            switch (c.type) {
                case table_column::kind::integer:
                    s += std::to_string(c.integers[i]);
                    break;
                case table_column::kind::real:
                    if (!(c.nan_is_empty && std::isnan(c.reals[i]))) s += to_decimal(c.reals[i]);
                    break;
                case table_column::kind::text:
                    s += c.texts[i];
                    break;
            }
        }
        s += "\n";
    }
    return s;
}

bool csv_directory_sink::has(const std::string& label) const {
    std::error_code ec;
    return std::filesystem::is_regular_file(dir_ / ("trajectories_E" + label + ".csv"), ec);
}

void csv_directory_sink::put(const ensemble_result& ensemble, const energy_result& summary) {
    // one table in memory at a time (a residence table is the largest output by far)
    for_each_energy_table(ensemble, summary, residence_times_, [&](energy_table&& t) {
        write_atomically(dir_ / (t.name + ".csv"), csv_text(t));
    });
}

std::string initial_states_csv(const std::vector<initial_state_set>& sets,
                               std::uint64_t first_index) {
    std::string out = "trajectory,energy,theta1,theta2,l1,l2\n";
    for (const initial_state_set& set : sets)
        for (std::size_t i = 0; i < set.states.size(); ++i) {
            out += std::to_string(first_index + i) + "," + set.label;
            for (const double x : set.states[i])
                out += "," + to_decimal(x);
            out += "\n";
        }
    return out;
}

initial_state_columns::initial_state_columns(const csv_table& t)
    : energy(column_index(t, "energy")),
      state{column_index(t, "theta1"), column_index(t, "theta2"), column_index(t, "l1"),
            column_index(t, "l2")} {}

bool initial_state_columns::complete() const {
    return energy >= 0 && std::find(state.begin(), state.end(), -1) == state.end();
}

std::pair<double, phase_point<double>> read_initial_state(const csv_row& r,
                                                          const initial_state_columns& c,
                                                          const double_pendulum<double>& model,
                                                          const std::string& at) {
    const auto field = [&](int k) -> const std::string& {
        return r.fields[static_cast<std::size_t>(k)];
    };
    const double e = finite_field(field(c.energy), "energy", at);
    if (!(e > 0)) throw input_error(at + "energy '" + field(c.energy) + "' must be > 0");
    static const std::array<const char*, 4> names{"theta1", "theta2", "l1", "l2"};
    phase_point<double> x{};
    for (std::size_t i = 0; i < 4; ++i)
        x[i] = finite_field(field(c.state[i]), names[i], at);
    const double h = model.hamiltonian(x);
    if (!(std::abs(h - e) <= 1e-8 * std::max(1.0, std::abs(e))))
        throw input_error(at + "the state's energy H = " + to_decimal(h) +
                          " is not E = " + field(c.energy) +
                          " (to a relative 1e-8): another pendulum or another energy?");
    return {e, x};
}

std::vector<initial_state_set> read_initial_states(const std::filesystem::path& file,
                                                   const double_pendulum<double>& model) {
    const csv_table t = read_csv(file);
    const initial_state_columns c(t);
    if (!c.complete())
        throw input_error(file.string() + ":" + std::to_string(t.header_line) +
                          ": the header must name the columns energy, theta1, theta2, l1, l2");
    std::vector<initial_state_set> sets;
    std::vector<std::set<phase_point<double>>> seen;  // per set: its states, for repeats
    for (const csv_row& r : t.rows) {
        const std::string at = file.string() + ":" + std::to_string(r.line) + ": ";
        if (r.fields.size() != t.header.size()) throw input_error(at + "wrong number of fields");
        // named, not structured bindings: clang 14 cannot capture those in the lambda below
        const std::pair<double, phase_point<double>> row = read_initial_state(r, c, model, at);
        const double e = row.first;
        const phase_point<double>& x = row.second;
        const std::string& label = r.fields[static_cast<std::size_t>(c.energy)];
        auto set = std::find_if(sets.begin(), sets.end(),
                                [&](const initial_state_set& s) { return s.energy == e; });
        if (set == sets.end()) {
            set = sets.insert(sets.end(), {label, e, {}, {}, 0});
            seen.emplace_back();
        }
        if (!seen[static_cast<std::size_t>(set - sets.begin())].insert(x).second) {
            ++set->repeated;  // a state already read at this energy
            continue;
        }
        set->states.push_back(x);
        set->lines.push_back(r.line);
    }
    if (sets.empty()) throw input_error(file.string() + ": no initial states");
    return sets;
}

}  // namespace flipflux
