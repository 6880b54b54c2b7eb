// A Monte Carlo study: ensembles, statistics, JSON report and CSVs (study/simulation.hpp).
#include "flipflux/study/simulation.hpp"
#include "flipflux/model/model_json.hpp"
#include "flipflux/study/settings.hpp"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/core/version.hpp"
#include "flipflux/ensemble/statistics.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/io/checksum.hpp"
#include "flipflux/study/checkpoint.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/study_files.hpp"

namespace flipflux {
namespace {

using json = nlohmann::ordered_json;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

}  // namespace

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

namespace {

class single_process final : public process_group {
  public:
    int rank() const override { return 0; }
    int size() const override { return 1; }
    std::string broadcast(const std::string& text) override { return text; }
    std::vector<std::string> gather(const std::string& text) override { return {text}; }
    bool any(bool flag) override { return flag; }
};

// The run's identity, as recorded in (and compared with) a checkpoint header. One study: its
// arm, criteria, energies and bins; several on one set of trajectories: the arrays of these, by
// study (so that neither is mistaken for the other).
json checkpoint_header(const double_pendulum<double>& model,
                       const std::vector<simulation_request>& studies, const ensemble_options& o) {
    const auto& p = model.parameters();
    const simulation_request& q = studies.front();
    json arms = json::array(), criteria = json::array(), energies = json::array(),
         bins = json::array(), thresholds = json::array();
    for (const simulation_request& s : studies) {
        thresholds.push_back(to_decimal(s.options.chaos_threshold));
        json e = json::array();
        for (const auto& [label, value] : s.energies)
            e.push_back(to_decimal(value));
        arms.push_back(to_string(s.flip_arm));
        criteria.push_back(s.criteria);
        energies.push_back(e);
        bins.push_back(s.bins);
    }
    const bool one = studies.size() == 1;
    json header{{"format", checkpoint_format_version},
                {"version", version_string()},
                {"model", parameter_array(p)},
                {"arm", one ? arms[0] : arms},
                {"criteria", one ? criteria[0] : criteria},
                {"energies", one ? energies[0] : energies},
                {"estimator", to_string(q.estimator)},
                {"trajectories", o.trajectories},
                {"first_index", o.first_index},
                {"time", to_decimal(o.time)},
                {"seed", o.seed},
                {"method", to_string(o.method)},
                {"rtol", to_decimal(o.rtol)},
                {"atol", to_decimal(o.atol)},
                {"chaos", o.chaos},
                {"chaos_threshold", one ? thresholds[0] : thresholds},
                {"bins", one ? bins[0] : bins},
                {"replicates", q.replicates}};
    // given initial states (simulate --initial-states): which ones, so that a checkpoint of other
    // states is not resumed (sampled runs keep the header they always had)
    std::string states;
    for (const simulation_request& s : studies)
        for (const auto& list : s.initial_states)
            for (const phase_point<double>& x : *list)
                for (const double v : x)
                    states += to_decimal(v) + ",";
    if (!states.empty()) header["initial_states"] = checksum_hex(states);
    return header;
}

}  // namespace

double trajectory_record_bytes(std::size_t criteria) {
    return static_cast<double>(sizeof(trajectory_result) + 64 + sizeof(std::uint64_t) +
                               criteria * 2 * sizeof(std::vector<double>));
}

namespace {

/// What one energy's ensemble holds in memory, bounded up front (core/limits.hpp): every
/// trajectory's record (with its per-criterion vectors, its node in the map of finished
/// trajectories and its index in the work list) and, with a sample interval, its samples.
void check_sizes(const simulation_request& request, const ensemble_options& o) {
    if (request.bins > max_bins)
        throw input_error::about("bins", "'" + std::to_string(request.bins) +
                                             "' is too many histogram bins (at most " +
                                             std::to_string(max_bins) + ")");
    (void)checked_threads(static_cast<std::uint64_t>(std::max(o.threads, 0)), "threads");
    const double record = trajectory_record_bytes(request.criteria.size());
    const double n = static_cast<double>(o.trajectories);
    const std::string field =
        request.estimator == rate_estimator::short_trajectories ? "short_time" : "trajectories";
    const std::string value = request.estimator == rate_estimator::short_trajectories
                                  ? to_decimal(request.short_time)
                                  : std::to_string(o.trajectories);
    check_memory(field, value, n * record, std::to_string(o.trajectories) + " trajectory records");
    if (o.sample_interval > 0) {
        const double samples = std::floor(o.time / o.sample_interval) + 2;
        check_memory("sample_interval", to_decimal(o.sample_interval),
                     n * samples * sizeof(std::array<double, 5>),
                     "the sampled states of " + std::to_string(o.trajectories) + " trajectories");
    }
}

/// The request checked (every option, the short estimator's budget turned into trajectories) and
/// the CSV directory created: the ensemble options every energy runs with (energy set per energy).
ensemble_options checked_options(const simulation_request& request, const process_group& group) {
    ensemble_options o = request.options;
    o.method = resolved_method(o.method, o.rtol);  // outputs name the concrete integrator
    if (request.energies.empty()) throw input_error::about("energy", "no energy given");
    if (request.criteria.empty()) throw input_error::about("criteria", "no criterion given");
    if (o.sample_interval != 0 && request.csv_dir.empty() && !request.sink)
        throw input_error::about(
            "sample_interval",
            "'" + to_decimal(o.sample_interval) +
                "' needs a CSV directory, csv_dir (the sampled trajectories are written there)");
    if (o.sample_interval != 0 && (!request.checkpoint.empty() || group.size() > 1))
        throw input_error::about(
            "sample_interval", "'" + to_decimal(o.sample_interval) +
                                   "' cannot be combined with a checkpoint or MPI (samples are not "
                                   "checkpointed or gathered)");
    if (!(request.reference_time >= 0) || !std::isfinite(request.reference_time))
        throw input_error::about("reference_time", "'" + to_decimal(request.reference_time) +
                                                       "' is invalid (must be finite and >= 0)");
    if (!(request.checkpoint_interval >= 0))
        throw input_error::about(
            "checkpoint_interval",
            "'" + to_decimal(request.checkpoint_interval) + "' is invalid (must be >= 0)");
    if (request.estimator == rate_estimator::short_trajectories) {
        if (!std::isfinite(request.short_time) || !(request.short_time > 0))
            throw input_error::about("short_time", "'" + to_decimal(request.short_time) +
                                                       "' is invalid (must be finite and > 0)");
        if (!(o.time > 0) || o.trajectories == 0) validate(o);
        if (request.short_time > o.time)
            throw input_error::about("short_time", "'" + to_decimal(request.short_time) +
                                                       "' is longer than the budget's trajectory "
                                                       "length, time = " +
                                                       to_decimal(o.time));
        const double n = std::ceil(static_cast<double>(o.trajectories) * o.time /
                                   request.short_time * (1 - 1e-15));
        if (!(n <= 1e12))
            throw input_error::about("short_time", "'" + to_decimal(request.short_time) +
                                                       "' gives too many trajectories");
        o.trajectories = static_cast<std::uint64_t>(std::max(1.0, n));
        o.time = request.short_time;
    }
    o.atol = effective_atol(o);
    if (request.replicates == 0 || request.replicates > max_replicates)
        throw input_error::about("replicates", "'" + std::to_string(request.replicates) +
                                                   "' is invalid (must be 1 to " +
                                                   std::to_string(max_replicates) + ")");
    if (request.replicates > 1) {
        if (o.trajectories > std::numeric_limits<std::uint64_t>::max() / request.replicates)
            throw input_error::about(
                "replicates", "'" + std::to_string(request.replicates) + "' replicates of " +
                                  std::to_string(o.trajectories) + " trajectories are too many");
        o.trajectories *= request.replicates;
    }
    if (!request.initial_states.empty()) {
        if (request.initial_states.size() != request.energies.size())
            throw std::invalid_argument("simulate: initial_states needs one list per energy");
        if (request.replicates != 1 || request.estimator != rate_estimator::long_trajectories)
            throw input_error::about("initial_states",
                                     "given initial states need one replicate and the long "
                                     "estimator");
        for (const auto& list : request.initial_states)
            if (!list || list->size() != o.trajectories)
                throw input_error::about("initial_states", "every energy needs trajectories = " +
                                                               std::to_string(o.trajectories) +
                                                               " initial states");
    }
    check_sizes(request, o);
    // checked, not created: a refused request leaves no folder (the CSVs create it when written)
    const std::filesystem::path& dir = request.csv_dir;
    if (!dir.empty() && group.rank() == 0) {
        check_output_folder(dir, "csv_dir");
        if (!request.checkpoint.empty()) {
            namespace fs = std::filesystem;
            std::error_code ec;
            const fs::path c = fs::weakly_canonical(fs::absolute(request.checkpoint, ec), ec);
            const fs::path d = fs::weakly_canonical(fs::absolute(dir, ec), ec);
            if (c == d)
                throw input_error::about("checkpoint", "'" + request.checkpoint.string() +
                                                           "' is the CSV directory csv_dir");
            if (c.parent_path() == d && c.extension() == ".csv")
                throw input_error::about(
                    "checkpoint", "'" + request.checkpoint.string() +
                                      "' is a CSV name in the CSV directory csv_dir, where the "
                                      "ensemble's CSVs are written: choose another name");
        }
    }
    if (!request.checkpoint.empty() && group.rank() == 0)
        check_output_file(request.checkpoint, "checkpoint");
    return o;
}

/// Per energy and criterion: the flip criterion and its predicted rate (if any), all built
/// before anything is simulated.
struct study_criteria {
    std::vector<std::vector<ensemble_criterion>> criteria;
    std::vector<std::vector<std::optional<quantity_value<double>>>> predictions;
};

study_criteria build_criteria(const double_pendulum<double>& model,
                              const simulation_request& request, ensemble_options o) {
    study_criteria s;
    for (const auto& [label, e] : request.energies) {
        o.energy = e;
        validate(o);
        check_trajectory_work(model, e, o.time, "time");
        s.criteria.emplace_back();
        s.predictions.emplace_back();
        for (const std::string& n : request.criteria) {
            s.criteria.back().push_back(make_criterion(model, request.flip_arm, n, e));
            s.predictions.back().push_back(criterion_prediction(model, request.flip_arm, n, e));
        }
    }
    return s;
}

/// What a checkpoint holds, and the writer that extends it (rank 0): read on rank 0, its text
/// shared, parsed (and checked against the run's header) on every rank.
struct resumption {
    checkpoint_content saved;
    std::unique_ptr<checkpoint_writer> writer;
};

resumption resume(const simulation_request& request, const json& header,
                  const checkpoint_layout& layout, process_group& group,
                  const std::function<bool(const trajectory_result&)>& chaotic) {
    resumption r;
    if (request.checkpoint.empty()) return r;
    const bool root = group.rank() == 0;
    bool exists = false;
    std::string text, status = "ok";
    std::optional<input_error> failure;  // the root's own, with its field (checkpoint)
    if (root) {
        try {
            text = read_checkpoint_text(request.checkpoint, exists);
        } catch (const input_error& e) {
            status = e.what();
            failure = e;
        }
    }
    if (group.size() > 1) {
        status = group.broadcast(status);
        exists = group.broadcast(exists ? "1" : "0") == "1";
        if (exists && status == "ok") text = group.broadcast(text);
    }
    if (failure) throw *failure;
    if (status != "ok") throw input_error(status);
    if (exists) r.saved = parse_checkpoint(text, header, layout, request.checkpoint);
    if (root)
        r.writer = std::make_unique<checkpoint_writer>(request.checkpoint, header, r.saved,
                                                       request.checkpoint_interval, chaotic);
    return r;
}

/// The result's head: the run's settings and the chaos indicator; no energy yet.
study_result result_head(const double_pendulum<double>& model, const simulation_request& request,
                         const ensemble_options& o) {
    study_result out;
    out.flip_arm = request.flip_arm;
    out.criteria = request.criteria;
    out.options = o;
    out.estimator = request.estimator;
    out.budget_trajectories = request.options.trajectories;
    out.budget_time = request.options.time;
    out.chaos_threshold_rate = chaos_threshold_rate(model, o.chaos_threshold);
    out.classification_reliable =
        o.chaos && chaos_classification_reliable(model, o.chaos_threshold, o.time);
    out.timing = request.timing;
    out.reference_time = request.reference_time;
    out.replicates = request.replicates;
    return out;
}

/// Rank 0: the other ranks' finished trajectories (checkpoint records, one per line) into
/// `have` and the checkpoint.
void receive_trajectories(const std::vector<std::string>& incoming, std::size_t criteria,
                          std::map<std::uint64_t, trajectory_result>& have,
                          checkpoint_writer* writer) {
    for (const std::string& text : incoming) {
        std::size_t pos = 0;
        while (pos < text.size()) {
            const std::size_t nl = text.find('\n', pos);
            const std::string_view line(text.data() + pos, nl - pos);
            std::size_t kk = 0;
            trajectory_result r = parse_trajectory_record(line, criteria, kk);
            if (writer) writer->add(std::string(line) + "\n");
            const std::uint64_t index = r.index;
            have.emplace(index, std::move(r));
            pos = nl + 1;
        }
    }
}

/// One energy's result from its finished ensemble: drift and step counts, and per criterion the
/// statistics against the prediction.
energy_result summarise_energy(
    const ensemble_result& r, const std::string& label, const simulation_request& request,
    const process_group& group,
    const std::vector<std::optional<quantity_value<double>>>& predictions) {
    energy_result e;
    e.label = label;
    e.energy = r.energy;
    e.seconds = r.seconds;
    e.cpu_seconds = r.cpu_seconds;
    e.threads = r.threads;
    e.processes = group.size();
    long steps = 0;
    for (const trajectory_result& t : r.trajectories) {
        e.max_energy_drift = std::max(e.max_energy_drift, t.max_energy_drift);
        steps += t.steps;
        e.failed_trajectories += t.status != rk_status::ok;
        e.energy_check_rejections += t.energy_check_rejections;
    }
    e.steps_per_trajectory =
        static_cast<double>(steps) / static_cast<double>(r.trajectories.size());
    for (std::size_t c = 0; c < request.criteria.size(); ++c) {
        const auto& p = predictions[c];
        e.criteria.push_back(
            {p, analyze(r, c, p ? p->value : nan, request.bins, request.bins, request.replicates)});
    }
    std::vector<double> d;
    for (std::size_t i = 0; i < request.criteria.size(); ++i)
        for (std::size_t j = i + 1; j < request.criteria.size(); ++j) {
            d.clear();
            for (const trajectory_result& t : r.trajectories)  // failed ones are no data
                if (t.status == rk_status::ok)
                    d.push_back(static_cast<double>(t.flips(i)) / r.time -
                                static_cast<double>(t.flips(j)) / r.time);
            e.paired.push_back({i, j, summarize(d)});
        }
    return e;
}

/// The replicate errors of criterion c's quality indices: the indices of each replicate alone and
/// of the ensemble without each replicate (statistics.hpp, replicate_quality), over the energies
/// the pooled indices use.
void add_replicate_quality(study_result& out, std::size_t c) {
    const std::size_t R = out.replicates;
    for (const bool chaotic : {false, true}) {
        std::vector<std::vector<quality_sample>> own(R), without(R);
        for (const energy_result& e : out.energies) {
            const criterion_result& x = e.criteria[c];
            if (!x.prediction) continue;
            const criterion_statistics& st = x.statistics;
            if (chaotic && st.chaotic == 0) continue;
            const auto& parts = chaotic ? st.replicate_chaotic_rates : st.replicate_rates;
            const auto sample = [&](const summary_statistics& r) {
                return quality_sample{
                    e.energy,         r.mean, x.prediction->value, r.standard_deviation,
                    r.standard_error, r.count};
            };
            std::vector<summary_statistics> rest;
            for (std::size_t k = 0; k < R; ++k) {
                own[k].push_back(sample(parts[k]));
                rest.clear();
                for (std::size_t j = 0; j < R; ++j)
                    if (j != k) rest.push_back(parts[j]);
                without[k].push_back(sample(merge(rest)));
            }
        }
        auto& pooled =
            chaotic ? out.quality[c].chaotic_trajectories : out.quality[c].all_trajectories;
        replicate_quality(pooled, own, without, out.regimes);
    }
}

/// The quality indices (paper Sec. 5.6) of each criterion over the energies, per regime: IQI
/// over all trajectories, PQI also over the chaotic sub-ensemble. An energy enters where its
/// criterion has a prediction (and, for the chaotic table, chaotic trajectories).
void add_quality(study_result& out, const double_pendulum<double>& model) {
    out.regimes = paper_regimes(model, out.flip_arm);
    for (std::size_t c = 0; c < out.criteria.size(); ++c) {
        std::vector<quality_sample> all, chaotic;
        for (const energy_result& e : out.energies) {
            const criterion_result& x = e.criteria[c];
            if (!x.prediction) continue;
            const criterion_statistics& st = x.statistics;
            const auto sample = [&](const summary_statistics& r) {
                return quality_sample{
                    e.energy,         r.mean,  x.prediction->value, r.standard_deviation,
                    r.standard_error, r.count, r.skewness,          r.kurtosis};
            };
            all.push_back(sample(st.rates));
            if (st.chaotic > 0) chaotic.push_back(sample(st.chaotic_rates));
        }
        const double scale = out.reference_time > 0 ? out.options.time / out.reference_time : 0;
        out.quality.push_back(
            {quality(all, out.regimes, scale), quality(chaotic, out.regimes, scale)});
        if (out.replicates > 1) add_replicate_quality(out, c);
    }
}

/// z-scores over the energies (paper Sec. 5.5): their chi^2, the worst, the largest relative
/// deviation, for one criterion over all or over the chaotic trajectories.
criterion_agreement agreement(const std::vector<energy_result>& energies, std::size_t c,
                              bool chaotic) {
    criterion_agreement a;
    a.worst_z = a.max_relative_deviation = nan;
    for (const energy_result& e : energies) {
        const criterion_statistics& st = e.criteria[c].statistics;
        const summary_statistics& s = chaotic ? st.chaotic_rates : st.rates;
        const double p = st.predicted_rate;
        if (!(p > 0) || !std::isfinite(s.mean) || !(s.standard_error > 0)) continue;
        const double z = (s.mean - p) / s.standard_error, rel = std::abs(s.mean / p - 1);
        a.chi2 += z * z;
        if (!(std::abs(z) <= std::abs(a.worst_z))) a.worst_z = z;
        if (!(rel <= a.max_relative_deviation)) a.max_relative_deviation = rel;
        ++a.energies;
    }
    return a;
}

/// The agreement of criterion c's pooled means with its predictions by the replicate errors,
/// and each replicate's own chi^2 (criterion_agreement::replicate_verdict).
criterion_agreement::replicate_verdict replicate_agreement(
    const std::vector<energy_result>& energies, std::size_t c, bool chaotic, std::size_t R) {
    criterion_agreement::replicate_verdict v;
    v.worst_z = v.max_error_ratio = v.min_error_ratio = nan;
    v.chi2_of_replicates.assign(R, 0);
    for (const energy_result& e : energies) {
        const criterion_statistics& st = e.criteria[c].statistics;
        const summary_statistics& s = chaotic ? st.chaotic_rates : st.rates;
        const auto& parts = chaotic ? st.replicate_chaotic_rates : st.replicate_rates;
        const double p = st.predicted_rate;
        if (!(p > 0) || !std::isfinite(s.mean) || parts.size() != R) continue;
        for (std::size_t k = 0; k < R; ++k) {
            const double z = (parts[k].mean - p) / parts[k].standard_error;
            if (std::isfinite(z)) v.chi2_of_replicates[k] += z * z;
        }
        const double se = replicate_standard_error(parts);
        if (!(se > 0)) continue;
        const double z = (s.mean - p) / se;
        v.chi2 += z * z;
        if (!(std::abs(z) <= std::abs(v.worst_z))) v.worst_z = z;
        const double ratio = se / s.standard_error;
        if (std::isfinite(ratio)) {
            if (!(ratio <= v.max_error_ratio)) v.max_error_ratio = ratio;
            if (!(ratio >= v.min_error_ratio)) v.min_error_ratio = ratio;
            v.error_mismatches += ratio > 2 || ratio < 0.5;
        }
        ++v.energies;
    }
    const double r = static_cast<double>(R);
    v.expected_chi2 = R > 3 ? static_cast<double>(v.energies) * (r - 1) / (r - 3) : nan;
    return v;
}

/// The agreement of every criterion and the differences between the criteria's predictions.
void add_comparisons(study_result& out) {
    const std::size_t n = out.criteria.size();
    for (std::size_t c = 0; c < n; ++c) {
        out.agreement.push_back(
            {agreement(out.energies, c, false), agreement(out.energies, c, true)});
        if (out.replicates > 1) {
            out.agreement.back().all_trajectories.replicates =
                replicate_agreement(out.energies, c, false, out.replicates);
            out.agreement.back().chaotic_trajectories.replicates =
                replicate_agreement(out.energies, c, true, out.replicates);
        }
    }
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = i + 1; j < n; ++j) {
            prediction_difference d{i, j, 0, 0};
            double sum = 0;
            for (const energy_result& e : out.energies) {
                const auto &p = e.criteria[i].prediction, &q = e.criteria[j].prediction;
                if (!p || !q || !(q->value > 0)) continue;
                const double rel = p->value / q->value - 1;
                sum += rel * rel;
                ++d.energies;
            }
            d.rms_relative = d.energies ? std::sqrt(sum / static_cast<double>(d.energies)) : nan;
            out.prediction_differences.push_back(d);
        }
}

/// The ensemble of one energy from its trajectories, in index order (moved out of `have`).
ensemble_result collect(const double_pendulum<double>& model, const ensemble_options& o,
                        const std::vector<std::string>& names, int threads,
                        std::map<std::uint64_t, trajectory_result>& have) {
    ensemble_result r;
    r.energy = o.energy;
    r.time = o.time;
    r.rtol = o.rtol;
    r.atol = o.atol;
    r.chaos_threshold = o.chaos_threshold;
    r.chaos_threshold_rate = chaos_threshold_rate(model, o.chaos_threshold);
    r.seed = o.seed;
    r.first_index = o.first_index;
    r.method = o.method;
    r.chaos = o.chaos;
    r.criteria = names;
    r.threads = threads;
    r.trajectories.reserve(have.size());
    for (auto& [index, t] : have)
        r.trajectories.push_back(std::move(t));
    return r;
}

simulation_interrupted interruption(const simulation_request& request, const std::string& label,
                                    std::size_t k, const ensemble_options& o,
                                    checkpoint_writer* writer) {
    std::uint64_t kept = 0;
    if (writer) {
        writer->flush();
        kept = writer->saved_trajectories();
    }
    const int signal = o.stop ? o.stop->load() : 0;
    return simulation_interrupted(
        request.checkpoint.empty()
            ? "interrupted (without a checkpoint: the finished trajectories are lost)"
            : "interrupted: " + std::to_string(k) + " energies complete and " +
                  std::to_string(kept) + " trajectories of E = " + label + " saved in '" +
                  request.checkpoint.string() + "'; rerun the same command to resume",
        signal, kept);
}

}  // namespace

namespace {

/// The energies of several studies run on one set of trajectories: their union (in the order of
/// first appearance, study by study), and per union energy the criteria counted there -- each
/// (arm, criterion) once, whichever studies ask for it -- and which study uses which of them.
struct shared_energies {
    struct member {
        std::size_t study = 0, position = 0;  ///< the study and the energy's place in it
        std::vector<std::size_t> columns;     ///< per criterion of the study: its column
    };
    struct energy {
        std::string label;  ///< the first study's text of it
        double value = 0;
        std::vector<ensemble_criterion> criteria;  ///< the columns of the trajectory results
        std::vector<member> members;
    };
    std::vector<energy> energies;
};

shared_energies share_energies(const std::vector<simulation_request>& requests,
                               const std::vector<study_criteria>& setups) {
    shared_energies out;
    for (std::size_t p = 0; p < requests.size(); ++p) {
        const simulation_request& q = requests[p];
        for (std::size_t j = 0; j < q.energies.size(); ++j) {
            const double value = q.energies[j].second;
            auto it =
                std::find_if(out.energies.begin(), out.energies.end(),
                             [&](const shared_energies::energy& e) { return e.value == value; });
            if (it == out.energies.end()) {
                out.energies.push_back({q.energies[j].first, value, {}, {}});
                it = std::prev(out.energies.end());
            }
            shared_energies::member m{p, j, {}};
            for (std::size_t c = 0; c < q.criteria.size(); ++c) {
                const std::string key = to_string(q.flip_arm) + ":" + q.criteria[c];
                std::size_t column = 0;
                while (column < it->criteria.size() && it->criteria[column].name != key)
                    ++column;
                if (column == it->criteria.size())
                    it->criteria.push_back({key, setups[p].criteria[j][c].detector});
                m.columns.push_back(column);
            }
            it->members.push_back(std::move(m));
        }
    }
    return out;
}

/// Study `m`'s view of an energy's trajectories: its criteria's columns, under its names, and
/// each trajectory classified with its chaos threshold (the run's may be another study's: the
/// threshold changes no trajectory, only which count as chaotic; is_chaotic, the ensemble's rule,
/// so a separate run's bits).
ensemble_result project(const double_pendulum<double>& model, const ensemble_result& all,
                        const shared_energies::member& m, const simulation_request& study) {
    ensemble_result r = all;
    r.criteria = study.criteria;
    r.chaos_threshold = study.options.chaos_threshold;
    r.chaos_threshold_rate = chaos_threshold_rate(model, r.chaos_threshold);
    for (trajectory_result& t : r.trajectories) {
        std::vector<std::vector<double>> times;
        std::vector<std::vector<crossing>> crossings;
        for (std::size_t column : m.columns) {
            times.push_back(t.crossing_times[column]);
            if (!t.crossings.empty()) crossings.push_back(t.crossings[column]);
        }
        t.crossing_times = std::move(times);
        t.crossings = std::move(crossings);
    }
    return r;
}

/// Several requests may share trajectories when everything that determines the trajectories and
/// how the run is driven is the same (the chaos threshold may differ: it only classifies them).
void check_shareable(const simulation_request& a, const simulation_request& b) {
    const ensemble_options &x = a.options, &y = b.options;
    // what decides the trajectories (study/settings.hpp), then how the run is driven
    const bool same = trajectory_key_of(a) == trajectory_key_of(b) && x.threads == y.threads &&
                      x.keep_crossings == y.keep_crossings &&
                      x.sample_interval == y.sample_interval &&
                      x.unwrapped_angles == y.unwrapped_angles && a.checkpoint == b.checkpoint &&
                      a.checkpoint_interval == b.checkpoint_interval && a.timing == b.timing &&
                      a.group == b.group;
    if (!same)
        throw std::invalid_argument(
            "simulate: studies sharing trajectories need the same ensemble options, estimator, "
            "checkpoint and process group");
}

}  // namespace

namespace {

/// One run of simulate(): its phases, in order, share this state.
///   1. check (constructor): every input checked and every curve built, the energies shared;
///   2. resume: the checkpoint read, and energies whose results are gone from their sink redone;
///   3. per energy: restore (complete in the checkpoint) or integrate, then finish (statistics,
///      the sink, the checkpoint's record);
///   4. finish the studies: the quality indices and comparisons over the energies.
class study_run {
  public:
    study_run(const double_pendulum<double>& model,
              const std::vector<simulation_request>& requests);
    std::optional<std::vector<study_result>> run();

  private:
    void resume_checkpoint();
    void redo_missing_results();
    void set_initial_states(std::size_t k);
    void restore_energy(std::size_t k);
    std::optional<ensemble_result> integrate_energy(std::size_t k);
    void finish_energy(std::size_t k, const ensemble_result& all);
    std::vector<study_result> finish_studies();
    /// An energy is complete when every study that has it is (their records are written
    /// together).
    bool complete(std::size_t k) const;
    /// The run's classification of a trajectory (its ensemble's rule and threshold), for the
    /// checkpoint's records.
    bool chaotic(const trajectory_result& r) const {
        return is_chaotic(model_, o_.chaos, o_.chaos_threshold, r.lyapunov);
    }

    const double_pendulum<double>& model_;
    const std::vector<simulation_request>& requests_;
    const simulation_request& request_;  ///< the first: the shared settings
    const std::size_t studies_;
    single_process alone_;
    process_group& group_;
    const bool root_;
    ensemble_options o_;
    std::vector<study_criteria> setups_;
    shared_energies shared_;
    resumption resumed_;
    std::vector<energy_sink*> sinks_;  ///< per study (null: none)
    std::vector<std::unique_ptr<csv_directory_sink>> owned_sinks_;
    std::vector<study_result> heads_;  ///< per study, until its energies join it
    std::vector<std::vector<std::optional<energy_result>>> done_;
    simulation_progress progress_;
};

study_run::study_run(const double_pendulum<double>& model,
                     const std::vector<simulation_request>& requests)
    : model_(model),
      requests_(requests),
      request_(requests.front()),
      studies_(requests.size()),
      group_(request_.group ? *request_.group : alone_),
      root_(group_.rank() == 0) {
    for (const simulation_request& q : requests)
        check_shareable(request_, q);
    for (const simulation_request& q : requests) {
        o_ = checked_options(q, group_);
        setups_.push_back(build_criteria(model, q, o_));
    }
    shared_ = share_energies(requests, setups_);
    for (const simulation_request& q : requests) {
        if (!q.sink && !q.csv_dir.empty())
            owned_sinks_.push_back(
                std::make_unique<csv_directory_sink>(q.csv_dir, q.residence_times));
        sinks_.push_back(q.sink ? q.sink : q.csv_dir.empty() ? nullptr : owned_sinks_.back().get());
    }
}

bool study_run::complete(std::size_t k) const {
    for (const shared_energies::member& m : shared_.energies[k].members)
        if (!resumed_.saved.completed.count(k * studies_ + m.study)) return false;
    return true;
}

void study_run::resume_checkpoint() {
    checkpoint_layout layout;
    layout.studies = studies_;
    layout.energy_criteria.assign(shared_.energies.size() * studies_, 0);
    for (std::size_t k = 0; k < shared_.energies.size(); ++k) {
        layout.trajectory_criteria.push_back(shared_.energies[k].criteria.size());
        for (const shared_energies::member& m : shared_.energies[k].members)
            layout.energy_criteria[k * studies_ + m.study] = m.columns.size();
    }
    resumed_ = resume(request_, checkpoint_header(model_, requests_, o_), layout, group_,
                      [this](const trajectory_result& r) { return chaotic(r); });
}

/// A complete energy's checkpoint holds its statistics only: its per-trajectory results went to
/// the sink when it completed. Where they are gone (a folder deleted before the rerun), the energy
/// is integrated again rather than reported without them. Rank 0 decides.
void study_run::redo_missing_results() {
    const auto& energies = shared_.energies;
    std::string redo(energies.size(), '0');
    if (root_)
        for (std::size_t k = 0; k < energies.size(); ++k)
            for (const shared_energies::member& m : energies[k].members) {
                const energy_sink* sink = sinks_[m.study];
                if (complete(k) && sink &&
                    !sink->has(requests_[m.study].energies[m.position].first))
                    redo[k] = '1';
            }
    if (group_.size() > 1) redo = group_.broadcast(redo);
    for (std::size_t k = 0; k < energies.size(); ++k)
        if (redo[k] == '1')
            for (const shared_energies::member& m : energies[k].members)
                resumed_.saved.completed.erase(k * studies_ + m.study);
}

/// Given initial states: the same list in every member study of energy k.
void study_run::set_initial_states(std::size_t k) {
    o_.energy = shared_.energies[k].value;
    o_.initial_states = nullptr;
    for (const shared_energies::member& m : shared_.energies[k].members) {
        const simulation_request& q = requests_[m.study];
        if (q.initial_states.empty()) continue;
        if (o_.initial_states && o_.initial_states != q.initial_states[m.position])
            throw std::invalid_argument(
                "simulate: studies sharing an energy need the same "
                "initial states");
        o_.initial_states = q.initial_states[m.position];
    }
}

/// The checkpoint stores a complete energy's statistics; the label, energy and predictions are
/// this run's (the header guarantees they are the same).
void study_run::restore_energy(std::size_t k) {
    for (const shared_energies::member& m : shared_.energies[k].members) {
        const simulation_request& q = requests_[m.study];
        energy_result e = std::move(resumed_.saved.completed.at(k * studies_ + m.study));
        e.label = q.energies[m.position].first;
        e.energy = o_.energy;
        for (std::size_t c = 0; c < q.criteria.size(); ++c) {
            e.criteria[c].prediction = setups_[m.study].predictions[m.position][c];
            e.criteria[c].statistics.criterion = q.criteria[c];
        }
        done_[m.study][m.position] = std::move(e);
    }
}

/// Energy k's trajectories not yet in the checkpoint, dealt out round-robin over the ranks and
/// gathered on rank 0: its ensemble there, nothing elsewhere.
std::optional<ensemble_result> study_run::integrate_energy(std::size_t k) {
    const auto& energy = shared_.energies[k];
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    checkpoint_writer* writer = resumed_.writer.get();
    std::map<std::uint64_t, trajectory_result>& have = resumed_.saved.trajectories[k];
    // NOTE: a record's hash covers the record, not the run: one spliced in from another run
    // (another seed, say) would pass. Its initial state must be this run's sample.
    if (!have.empty()) {
        const microcanonical_sampler sampler(model_, o_.energy);
        for (const auto& [index, t] : have)
            if (!(initial_state_of(sampler, o_, index) == t.initial_state))
                throw input_error::about(
                    "checkpoint",
                    "'" + request_.checkpoint.string() + "': the record of trajectory " +
                        std::to_string(index) + " at E = " + energy.label +
                        " is not this run's (its initial state is not " +
                        (o_.initial_states ? std::string("the given one")
                                           : "the sample of seed " + std::to_string(o_.seed)) +
                        "): the file mixes runs");
    }
    const auto ranks = static_cast<std::uint64_t>(group_.size());
    std::vector<std::uint64_t> mine;
    std::uint64_t position = 0;
    for (std::uint64_t i = 0; i < o_.trajectories; ++i) {
        const std::uint64_t index = o_.first_index + i;
        if (have.count(index)) continue;
        if (position++ % ranks == static_cast<std::uint64_t>(group_.rank())) mine.push_back(index);
    }
    progress_.energy = k;
    std::string outgoing;
    const batch_outcome b =
        run_trajectories(model_, o_, energy.criteria, mine, [&](trajectory_result&& r) {
            if (root_) {
                if (writer) writer->add(trajectory_record(k, r, chaotic(r)));
                const std::uint64_t index = r.index;
                have.emplace(index, std::move(r));
                progress_.done = std::min(progress_.total, progress_.done + ranks);
                if (request_.progress) request_.progress(progress_);
            } else {
                outgoing += trajectory_record(k, r, chaotic(r));
            }
        });
    const bool interrupted = group_.size() > 1 ? group_.any(b.interrupted) : b.interrupted;
    if (group_.size() > 1)
        receive_trajectories(group_.gather(outgoing), energy.criteria.size(), have, writer);
    if (interrupted) throw interruption(request_, energy.label, k, o_, writer);
    if (!root_) {
        resumed_.saved.trajectories.erase(k);
        return std::nullopt;
    }
    if (have.size() != o_.trajectories)
        throw std::logic_error("simulate: trajectories missing after the gather");
    std::vector<std::string> columns;
    for (const ensemble_criterion& c : energy.criteria)
        columns.push_back(c.name);
    ensemble_result all = collect(model_, o_, columns, b.threads, have);
    resumed_.saved.trajectories.erase(k);
    all.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    all.cpu_seconds = process_cpu_seconds() - cpu_start;
    return all;
}

/// Each member study's view of energy k: its statistics, its sink, the checkpoint's record.
void study_run::finish_energy(std::size_t k, const ensemble_result& all) {
    std::vector<std::pair<std::size_t, const energy_result*>> records;
    for (const shared_energies::member& m : shared_.energies[k].members) {
        const simulation_request& q = requests_[m.study];
        const ensemble_result r = project(model_, all, m, q);
        energy_result e = summarise_energy(r, q.energies[m.position].first, q, group_,
                                           setups_[m.study].predictions[m.position]);
        if (energy_sink* sink = sinks_[m.study]) sink->put(r, e);
        done_[m.study][m.position] = std::move(e);
        records.emplace_back(k * studies_ + m.study, &*done_[m.study][m.position]);
    }
    if (checkpoint_writer* writer = resumed_.writer.get()) writer->complete(records);
}

std::vector<study_result> study_run::finish_studies() {
    for (std::size_t p = 0; p < studies_; ++p) {
        for (std::optional<energy_result>& e : done_[p])
            heads_[p].energies.push_back(std::move(*e));
        add_quality(heads_[p], model_);
        add_comparisons(heads_[p]);
    }
    return std::move(heads_);
}

std::optional<std::vector<study_result>> study_run::run() {
    resume_checkpoint();
    redo_missing_results();
    const auto& energies = shared_.energies;
    for (std::size_t p = 0; p < studies_; ++p) {
        ensemble_options own = o_;  // the result's head: the run's settings, no energy yet
        own.chaos_threshold = requests_[p].options.chaos_threshold;
        heads_.push_back(result_head(model_, requests_[p], own));
        done_.emplace_back(requests_[p].energies.size());
    }
    progress_.energies = energies.size();
    progress_.total = o_.trajectories * energies.size();
    for (std::size_t k = 0; k < energies.size(); ++k)
        progress_.done += complete(k) ? o_.trajectories : 0;
    for (const auto& [k, t] : resumed_.saved.trajectories)
        progress_.done += t.size();
    progress_.resumed = progress_.done;
    for (std::size_t k = 0; k < energies.size(); ++k) {
        set_initial_states(k);
        if (complete(k)) {
            restore_energy(k);
            continue;
        }
        if (const std::optional<ensemble_result> all = integrate_energy(k)) finish_energy(k, *all);
    }
    if (!root_) return std::nullopt;
    return finish_studies();
}

}  // namespace

std::optional<std::vector<study_result>> simulate(const double_pendulum<double>& model,
                                                  const std::vector<simulation_request>& requests) {
    if (requests.empty()) throw std::invalid_argument("simulate: no study");
    return study_run(model, requests).run();
}

std::optional<study_result> simulate(const double_pendulum<double>& model,
                                     const simulation_request& request) {
    std::optional<std::vector<study_result>> r = simulate(model, std::vector{request});
    if (!r) return std::nullopt;
    return std::move(r->front());
}

}  // namespace flipflux
