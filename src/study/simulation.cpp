// A Monte Carlo study: ensembles, statistics, JSON report and CSVs (study/simulation.hpp).
#include "flipflux/study/simulation.hpp"

#include <charconv>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/version.hpp"
#include "flipflux/ensemble/statistics.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/study/checkpoint.hpp"
#include "flipflux/study/criteria.hpp"

namespace flipflux {
namespace {

using json = nlohmann::ordered_json;
constexpr double nan = std::numeric_limits<double>::quiet_NaN();

json number(double x) {
    return std::isfinite(x) ? json(to_decimal(x)) : json(nullptr);
}

json summary_json(const summary_statistics& s, double predicted) {
    return json{{"trajectories", s.count},
                {"mean_rate", number(s.mean)},
                {"std", number(s.standard_deviation)},
                {"standard_error", number(s.standard_error)},
                {"z_score", number((s.mean - predicted) / s.standard_error)}};
}

json histogram_json(const histogram& h) {
    return json{{"lower", to_decimal(h.lower)},
                {"upper", to_decimal(h.upper)},
                {"bin_width", to_decimal(h.bin_width())},
                {"counts", h.counts}};
}

// ---- CSV output ---------------------------------------------------------------------------

void write_atomically(const std::filesystem::path& path, const std::string& content) {
    try {
        write_file_atomically(path, content);
    } catch (const std::runtime_error&) {
        throw input_error::about("csv_dir", "cannot write '" + path.string() + "'");
    }
}

std::string histogram_csv(const histogram& h, std::uint64_t total) {
    std::string s = "bin_lower,bin_upper,count,density\n";
    for (std::size_t i = 0; i < h.counts.size(); ++i) {
        const double lo = h.lower + h.bin_width() * static_cast<double>(i);
        const double density =
            total ? static_cast<double>(h.counts[i]) / (static_cast<double>(total) * h.bin_width())
                  : 0.0;
        s += to_decimal(lo) + "," + to_decimal(lo + h.bin_width()) + "," +
             std::to_string(h.counts[i]) + "," + to_decimal(density) + "\n";
    }
    return s;
}

void write_csvs(const std::filesystem::path& dir, const std::string& label,
                const ensemble_result& r, const std::vector<criterion_statistics>& stats) {
    std::string t = "index,lyapunov,chaotic,max_energy_drift,steps,energy_check_rejections,status";
    for (const std::string& c : r.criteria)
        t += ",flips_" + c + ",rate_" + c;
    t += "\n";
    for (const trajectory_result& x : r.trajectories) {
        t += std::to_string(x.index) + "," +
             (std::isnan(x.lyapunov) ? "" : to_decimal(x.lyapunov)) + "," +
             (x.chaotic ? "1" : "0") + "," + to_decimal(x.max_energy_drift) + "," +
             std::to_string(x.steps) + "," + std::to_string(x.energy_check_rejections) + "," +
             to_string(x.status);
        for (std::size_t c = 0; c < r.criteria.size(); ++c)
            t += "," + std::to_string(x.flips(c)) + "," +
                 to_decimal(static_cast<double>(x.flips(c)) / r.time);
        t += "\n";
    }
    write_atomically(dir / ("trajectories_E" + label + ".csv"), t);
    if (!r.trajectories.empty() && !r.trajectories.front().samples.empty()) {
        std::string smp = "trajectory,t,theta1,theta2,l1,l2\n";
        for (const trajectory_result& x : r.trajectories)
            for (const auto& v : x.samples) {
                smp += std::to_string(x.index);
                for (double c : v)
                    smp += "," + to_decimal(c);
                smp += "\n";
            }
        write_atomically(dir / ("samples_E" + label + ".csv"), smp);
    }
    for (std::size_t c = 0; c < r.criteria.size(); ++c) {
        const std::string& name = r.criteria[c];
        std::string res = "trajectory,crossing_time,residence_time\n";
        for (const trajectory_result& x : r.trajectories) {
            const auto& times = x.crossing_times[c];
            for (std::size_t i = 1; i < times.size(); ++i)
                res += std::to_string(x.index) + "," + to_decimal(times[i]) + "," +
                       to_decimal(times[i] - times[i - 1]) + "\n";
        }
        write_atomically(dir / ("residence_E" + label + "_" + name + ".csv"), res);
        write_atomically(dir / ("rate_histogram_E" + label + "_" + name + ".csv"),
                         histogram_csv(stats[c].rate_distribution, stats[c].rates.count));
        write_atomically(
            dir / ("residence_histogram_E" + label + "_" + name + ".csv"),
            histogram_csv(stats[c].residence.distribution, stats[c].residence.summary.count));
    }
}

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
                                                     v.substr(c2 + 1), option, 100000))
                out.emplace_back(e, parse_real<double>(e, option));
        }
        pos = comma + 1;
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

// exact (shortest round-trip) text of a double, and back
std::string exact(double x) {
    char buf[40];
    return std::string(buf, std::to_chars(buf, buf + sizeof buf, x).ptr);
}

double from_exact(const json& j) {
    const std::string t = j.get<std::string>();
    double v = 0;
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
        throw std::runtime_error("checkpoint: '" + t + "' is not a number");
    return v;
}

json quality_json(const quality_sample& q) {
    return json::array({exact(q.energy), exact(q.simulated), exact(q.predicted), exact(q.spread)});
}

quality_sample quality_from_json(const json& j) {
    return {from_exact(j.at(0)), from_exact(j.at(1)), from_exact(j.at(2)), from_exact(j.at(3))};
}

// The run's identity, as recorded in (and compared with) a checkpoint header.
json checkpoint_header(const double_pendulum<double>& model, const simulation_request& q,
                       const ensemble_options& o) {
    const auto& p = model.parameters();
    json energies = json::array();
    for (const auto& [label, e] : q.energies)
        energies.push_back(to_decimal(e));
    return json{{"format", checkpoint_format_version},
                {"version", version_string()},
                {"model", json::array({to_decimal(p.m1), to_decimal(p.m2), to_decimal(p.L1),
                                       to_decimal(p.L2), to_decimal(p.a1), to_decimal(p.a2),
                                       to_decimal(p.I1), to_decimal(p.I2), to_decimal(p.g)})},
                {"arm", to_string(q.flip_arm)},
                {"criteria", q.criteria},
                {"energies", energies},
                {"estimator", to_string(q.estimator)},
                {"trajectories", o.trajectories},
                {"first_index", o.first_index},
                {"time", to_decimal(o.time)},
                {"seed", o.seed},
                {"method", to_string(o.method)},
                {"rtol", to_decimal(o.rtol)},
                {"atol", to_decimal(o.atol)},
                {"chaos", o.chaos},
                {"chaos_threshold", to_decimal(o.chaos_threshold)},
                {"bins", q.bins}};
}

}  // namespace

namespace {

/// The request checked (every option, the short estimator's budget turned into trajectories) and
/// the CSV directory created: the ensemble options every energy runs with (energy set per energy).
ensemble_options checked_options(const simulation_request& request, const process_group& group) {
    ensemble_options o = request.options;
    if (request.energies.empty()) throw input_error::about("energy", "no energy given");
    if (request.criteria.empty()) throw input_error::about("criteria", "no criterion given");
    if (o.sample_interval != 0 && request.csv_dir.empty())
        throw input_error::about(
            "sample_interval",
            "'" + to_decimal(o.sample_interval) +
                "' needs a CSV directory, csv_dir (the sampled trajectories are written there)");
    if (o.sample_interval != 0 && (!request.checkpoint.empty() || group.size() > 1))
        throw input_error::about(
            "sample_interval", "'" + to_decimal(o.sample_interval) +
                                   "' cannot be combined with a checkpoint or MPI (samples are not "
                                   "checkpointed or gathered)");
    if (!(request.checkpoint_interval >= 0))
        throw input_error::about(
            "checkpoint_interval",
            "'" + to_decimal(request.checkpoint_interval) + "' is invalid (must be >= 0)");
    if (request.estimator == rate_estimator::short_trajectories) {
        if (!std::isfinite(request.short_time) || !(request.short_time > 0))
            throw input_error::about("short_time", "'" + to_decimal(request.short_time) +
                                                       "' is invalid (must be finite and > 0)");
        if (!(o.time > 0) || o.trajectories == 0) validate(o);
        const double n = std::ceil(static_cast<double>(o.trajectories) * o.time /
                                   request.short_time * (1 - 1e-15));
        if (!(n <= 1e12))
            throw input_error::about("short_time", "'" + to_decimal(request.short_time) +
                                                       "' gives too many trajectories");
        o.trajectories = static_cast<std::uint64_t>(std::max(1.0, n));
        o.time = request.short_time;
    }
    o.atol = o.atol > 0 ? o.atol : o.rtol;
    const std::filesystem::path& dir = request.csv_dir;
    if (!dir.empty() && group.rank() == 0) {
        std::error_code ec;
        std::filesystem::create_directories(dir, ec);
        if (!std::filesystem::is_directory(dir))
            throw input_error::about("csv_dir",
                                     "'" + dir.string() + "' is not a writable directory");
    }
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

resumption resume(const simulation_request& request, const json& header, process_group& group) {
    resumption r;
    if (request.checkpoint.empty()) return r;
    const bool root = group.rank() == 0;
    bool exists = false;
    std::string text, status = "ok";
    if (root) {
        try {
            text = read_checkpoint_text(request.checkpoint, exists);
        } catch (const input_error& e) {
            status = e.what();
        }
    }
    if (group.size() > 1) {
        status = group.broadcast(status);
        exists = group.broadcast(exists ? "1" : "0") == "1";
        if (exists && status == "ok") text = group.broadcast(text);
    }
    if (status != "ok") throw input_error(status);
    if (exists)
        r.saved = parse_checkpoint(text, header, request.criteria.size(), request.checkpoint);
    if (root)
        r.writer = std::make_unique<checkpoint_writer>(request.checkpoint, header, r.saved,
                                                       request.checkpoint_interval);
    return r;
}

/// The report's head: the run's settings and the chaos indicator.
json report_head(const double_pendulum<double>& model, const simulation_request& request,
                 const ensemble_options& o) {
    json out{{"command", "simulate"},          {"arm", to_string(request.flip_arm)},
             {"trajectories", o.trajectories}, {"first_index", o.first_index},
             {"time", to_decimal(o.time)},     {"seed", o.seed},
             {"method", to_string(o.method)},  {"rtol", to_decimal(o.rtol)},
             {"atol", to_decimal(o.atol)},     {"estimator", to_string(request.estimator)}};
    if (request.estimator == rate_estimator::short_trajectories)
        out["budget"] = json{{"trajectories", request.options.trajectories},
                             {"time", to_decimal(request.options.time)}};
    out["chaos"] =
        json{{"indicator",
              o.chaos ? "finite-time maximal Lyapunov exponent (variational equations)" : "none"},
             {"threshold", to_decimal(o.chaos_threshold)},
             {"threshold_rate", to_decimal(chaos_threshold_rate(model, o.chaos_threshold))},
             {"classification_reliable",
              o.chaos && chaos_classification_reliable(model, o.chaos_threshold, o.time)}};
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

/// The quality samples of one energy, per criterion: over all trajectories and over the chaotic
/// ones (null where there is no prediction or no chaotic trajectory).
struct energy_quality {
    std::vector<std::optional<quality_sample>> all, chaotic;
};

/// One energy's report entry from its finished ensemble: drift and step counts, per criterion the
/// statistics against the prediction, and the quality samples.
json energy_report(const ensemble_result& r, const std::string& label,
                   const simulation_request& request, const process_group& group,
                   const std::vector<std::optional<quantity_value<double>>>& predictions,
                   std::vector<criterion_statistics>& stats, energy_quality& quality) {
    const std::vector<std::string>& names = request.criteria;
    double drift = 0;
    long steps = 0;
    std::size_t failed = 0;
    long energy_rejections = 0;
    for (const trajectory_result& t : r.trajectories) {
        drift = std::max(drift, t.max_energy_drift);
        steps += t.steps;
        failed += t.status != rk_status::ok;
        energy_rejections += t.energy_check_rejections;
    }
    json e{{"energy", label}};
    if (request.timing) {
        e["seconds"] = r.seconds;
        e["threads"] = r.threads;
        e["processes"] = group.size();
    }
    e["steps_per_trajectory"] =
        static_cast<double>(steps) / static_cast<double>(r.trajectories.size());
    e["failed_trajectories"] = failed;
    e["energy_check_rejections"] = energy_rejections;
    e["max_energy_drift"] = to_decimal(drift);
    json per_criterion = json::object();
    for (std::size_t c = 0; c < names.size(); ++c) {
        const auto& p = predictions[c];
        const double predicted = p ? p->value : nan;
        stats.push_back(analyze(r, c, predicted, request.bins, request.bins));
        const criterion_statistics& st = stats.back();
        json j{{"predicted_rate", number(predicted)},
               {"prediction_method", p ? json(p->method) : json(nullptr)},
               {"mean_rate", number(st.rates.mean)},
               {"std", number(st.rates.standard_deviation)},
               {"standard_error", number(st.rates.standard_error)},
               {"z_score", number(st.z_score)},
               {"flips", st.flips},
               {"chaotic_fraction", number(st.chaotic_fraction)},
               {"max_energy_drift", to_decimal(drift)}};
        j["chaotic"] = summary_json(st.chaotic_rates, predicted);
        j["residence_times"] = json{
            {"count", st.residence.summary.count},   {"min", number(st.residence.summary.minimum)},
            {"q0.001", number(st.residence.q001)},   {"q0.01", number(st.residence.q01)},
            {"median", number(st.residence.median)}, {"mean", number(st.residence.summary.mean)}};
        j["rate_histogram"] = histogram_json(st.rate_distribution);
        per_criterion[names[c]] = j;
        std::optional<quality_sample> qa, qc;
        if (p) {
            qa = quality_sample{r.energy, st.rates.mean, predicted, st.rates.standard_deviation};
            if (st.chaotic > 0)
                qc = quality_sample{r.energy, st.chaotic_rates.mean, predicted,
                                    st.chaotic_rates.standard_deviation};
        }
        quality.all.push_back(qa);
        quality.chaotic.push_back(qc);
    }
    e["criteria"] = per_criterion;
    return e;
}

/// The quality indices (paper Sec. 5.6): IQI over all trajectories, PQI also over the chaotic
/// sub-ensemble (the paper's PQI tables use the chaotic trajectories), and the regimes.
void add_quality(json& out, const double_pendulum<double>& model, arm a,
                 const std::vector<std::string>& names,
                 const std::vector<std::vector<quality_sample>>& all,
                 const std::vector<std::vector<quality_sample>>& chaotic) {
    const std::vector<energy_regime> regimes = paper_regimes(model, a);
    auto quality_table = [&](const std::vector<quality_sample>& samples) {
        json arr = json::array();
        for (const quality_indices& q : quality(samples, regimes))
            if (q.energies > 0)
                arr.push_back(json{{"regime", q.regime},
                                   {"energies", q.energies},
                                   {"IQI", number(q.iqi)},
                                   {"PQI", number(q.pqi)}});
        return arr;
    };
    json qual = json::object();
    for (std::size_t c = 0; c < names.size(); ++c)
        qual[names[c]] = json{{"all_trajectories", quality_table(all[c])},
                              {"chaotic_trajectories", quality_table(chaotic[c])}};
    out["quality"] = qual;
    json reg = json::array();
    for (const energy_regime& g : regimes)
        if (std::isfinite(g.lower))
            reg.push_back(json{{"regime", g.name},
                               {"lower", to_decimal(g.lower)},
                               {"upper", to_decimal(g.upper)}});
    out["regimes"] = reg;
}

/// The ensemble of one energy from its trajectories, in index order (moved out of `have`).
ensemble_result collect(const ensemble_options& o, const std::vector<std::string>& names,
                        int threads, std::map<std::uint64_t, trajectory_result>& have) {
    ensemble_result r;
    r.energy = o.energy;
    r.time = o.time;
    r.rtol = o.rtol;
    r.atol = o.atol;
    r.chaos_threshold = o.chaos_threshold;
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

simulation_interrupted interruption(const simulation_request& request, std::size_t k,
                                    const ensemble_options& o, checkpoint_writer* writer) {
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
                  std::to_string(kept) + " trajectories of E = " + request.energies[k].first +
                  " saved in '" + request.checkpoint.string() +
                  "'; rerun the same command to resume",
        signal, kept);
}

}  // namespace

json simulate(const double_pendulum<double>& model, const simulation_request& request) {
    const auto& energies = request.energies;
    const std::vector<std::string>& names = request.criteria;
    single_process alone;
    process_group& group = request.group ? *request.group : alone;
    const bool root = group.rank() == 0;
    ensemble_options o = checked_options(request, group);
    // every input is checked, and every curve built, before anything is simulated
    const study_criteria setup = build_criteria(model, request, o);
    resumption resumed = resume(request, checkpoint_header(model, request, o), group);
    checkpoint_content& saved = resumed.saved;
    checkpoint_writer* writer = resumed.writer.get();

    json out = report_head(model, request, o);
    json per_energy = json::array();
    std::vector<std::vector<quality_sample>> all(names.size()), chaotic(names.size());

    simulation_progress progress;
    progress.energies = energies.size();
    progress.total = o.trajectories * energies.size();
    progress.done += o.trajectories * saved.completed.size();
    for (const auto& [k, t] : saved.trajectories)
        progress.done += t.size();
    progress.resumed = progress.done;
    const auto ranks = static_cast<std::uint64_t>(group.size());

    for (std::size_t k = 0; k < energies.size(); ++k) {
        o.energy = energies[k].second;
        if (const auto it = saved.completed.find(k); it != saved.completed.end()) {
            if (root) {
                per_energy.push_back(it->second.entry);
                const json& qj = it->second.quality;
                for (std::size_t c = 0; c < names.size(); ++c) {
                    if (!qj.at(0).at(c).is_null()) all[c].push_back(quality_from_json(qj[0][c]));
                    if (!qj.at(1).at(c).is_null())
                        chaotic[c].push_back(quality_from_json(qj[1][c]));
                }
            }
            continue;
        }
        const auto start = std::chrono::steady_clock::now();
        std::map<std::uint64_t, trajectory_result>& have = saved.trajectories[k];
        // the trajectories still to do, dealt out round-robin over the ranks
        std::vector<std::uint64_t> mine;
        std::uint64_t position = 0;
        for (std::uint64_t i = 0; i < o.trajectories; ++i) {
            const std::uint64_t index = o.first_index + i;
            if (have.count(index)) continue;
            if (position++ % ranks == static_cast<std::uint64_t>(group.rank()))
                mine.push_back(index);
        }
        progress.energy = k;
        std::string outgoing;
        const batch_outcome b =
            run_trajectories(model, o, setup.criteria[k], mine, [&](trajectory_result&& r) {
                if (root) {
                    if (writer) writer->add(trajectory_record(k, r));
                    const std::uint64_t index = r.index;
                    have.emplace(index, std::move(r));
                    progress.done = std::min(progress.total, progress.done + ranks);
                    if (request.progress) request.progress(progress);
                } else {
                    outgoing += trajectory_record(k, r);
                }
            });
        const bool interrupted = group.size() > 1 ? group.any(b.interrupted) : b.interrupted;
        if (group.size() > 1)
            receive_trajectories(group.gather(outgoing), names.size(), have, writer);
        if (interrupted) throw interruption(request, k, o, writer);
        if (!root) {
            saved.trajectories.erase(k);
            continue;
        }
        if (have.size() != o.trajectories)
            throw std::logic_error("simulate: trajectories missing after the gather");
        ensemble_result r = collect(o, names, b.threads, have);
        saved.trajectories.erase(k);
        r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

        std::vector<criterion_statistics> stats;
        energy_quality q;
        json e =
            energy_report(r, energies[k].first, request, group, setup.predictions[k], stats, q);
        json q_all = json::array(), q_chaotic = json::array();
        for (std::size_t c = 0; c < names.size(); ++c) {
            q_all.push_back(q.all[c] ? quality_json(*q.all[c]) : json(nullptr));
            q_chaotic.push_back(q.chaotic[c] ? quality_json(*q.chaotic[c]) : json(nullptr));
            if (q.all[c]) all[c].push_back(*q.all[c]);
            if (q.chaotic[c]) chaotic[c].push_back(*q.chaotic[c]);
        }
        if (!request.csv_dir.empty()) write_csvs(request.csv_dir, energies[k].first, r, stats);
        if (writer) writer->complete(k, {e, json::array({q_all, q_chaotic})});
        per_energy.push_back(std::move(e));
    }
    if (!root) return nullptr;
    out["energies"] = per_energy;
    add_quality(out, model, request.flip_arm, names, all, chaotic);
    return out;
}

}  // namespace flipflux
