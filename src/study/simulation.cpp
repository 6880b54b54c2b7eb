// A Monte Carlo study: ensembles, statistics, JSON report and CSVs (study/simulation.hpp).
#include "flipflux/study/simulation.hpp"
#include "flipflux/model/model_json.hpp"
#include "flipflux/study/settings.hpp"

#include <algorithm>
#include <atomic>
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
#include "flipflux/ensemble/taylor_ensemble.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/io/checksum.hpp"
#include "flipflux/study/checkpoint.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/study_files.hpp"
#include "study_checks.hpp"
#include "study_statistics.hpp"

namespace flipflux {
namespace {

using json = nlohmann::ordered_json;

}  // namespace

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
    // the Taylor order (its rule changed on 2026-11-29: a checkpoint of another order is not
    // resumed; DOP853 and DOPRI5 runs keep the header they always had)
    if (o.method == integration_method::taylor) header["taylor_order"] = ensemble_taylor_order(o);
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
    // (a bound the caller set on its stop flag, as a scene's run does, is the caller's to name)
    const std::string cause =
        signal != cpu_bound_stop ? "interrupted"
        : request.max_seconds > 0
            ? "stopped at its bound of " + to_shortest_decimal(request.max_seconds) + " CPU seconds"
            : "stopped at its CPU bound";
    const std::string saved = request.checkpoint.empty()
                                  ? std::string()
                                  : std::to_string(k) + " energies complete and " +
                                        std::to_string(kept) + " trajectories of E = " + label +
                                        " saved in '" + request.checkpoint.string() + "'";
    return simulation_interrupted(
        saved.empty() ? cause + " (without a checkpoint: the finished trajectories are lost)"
                      : cause + ": " + saved + "; rerun the same command to resume",
        signal, kept, saved);
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
    std::atomic<int> own_stop_{0};  ///< options.stop when the caller gave none (max_seconds)
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
        o_ = detail::checked_options(q, group_);
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
        energy_result e = detail::summarise_energy(r, q.energies[m.position].first, q, group_,
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
        detail::add_quality(heads_[p], model_);
        detail::add_comparisons(heads_[p]);
    }
    return std::move(heads_);
}

std::optional<std::vector<study_result>> study_run::run() {
    // max_seconds: the lanes poll the run's own stop flag, which a watch on the process's CPU
    // time sets at the bound and into which it relays the caller's flag (a signal's) until then
    const std::atomic<int>* caller_stop = o_.stop;
    if (request_.max_seconds > 0) o_.stop = &own_stop_;
    const cpu_watch watch(request_.max_seconds, own_stop_, cpu_bound_stop, caller_stop);
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
