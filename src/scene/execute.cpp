// Scene execution: runs each plan step and writes its outputs atomically under the scene's output
// directory (file formats: docs/scenes.md).
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/version.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/io/viewer_page.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/model/model_json.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/output/accuracy_markdown.hpp"
#include "flipflux/output/golden_files.hpp"
#include "flipflux/prediction/curve_flux.hpp"
#include "flipflux/quantities/accuracy.hpp"
#include "flipflux/quantities/golden.hpp"
#include "flipflux/quantities/registry.hpp"

#include "execute_steps.hpp"
#include "flipflux/scene/plan.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/saddle_viewer.hpp"
#include "flipflux/study/simulation.hpp"
#include "flipflux/study/study_files.hpp"
#include "flipflux/study/trajectory.hpp"
#include "flipflux/study/trajectory_files.hpp"

#ifndef FLIPFLUX_SOURCE_DIR
#define FLIPFLUX_SOURCE_DIR "."
#endif

namespace flipflux {

std::size_t saddle_orbit_memo_misses();  // src/orbits/orbit_names.cpp

using namespace scene_steps;  // the run's context and the steps of execute_steps.cpp

std::filesystem::path default_cache_dir() {
    if (const char* d = std::getenv("FLIPFLUX_CACHE_DIR"); d && *d) return d;
    if (const char* d = std::getenv("XDG_CACHE_HOME"); d && *d)
        return std::filesystem::path(d) / "flipflux";
    if (const char* d = std::getenv("HOME"); d && *d)
        return std::filesystem::path(d) / ".cache" / "flipflux";
    return ".flipflux-cache";
}

namespace {

template <class Real>
json model_json(const double_pendulum<Real>& model) {
    const auto& p = model.parameters();
    const auto& k = model.coefficients();
    json curves = json::object();
    for (arm a : {arm::one, arm::two}) {
        const sine_curve<Real> c = approximate_saddle_curve(model, a);
        curves[to_string(a)] = {{"offset", "pi + slope sin(s)"},
                                {"slope", to_decimal(c.slope(Real(0)))}};
    }
    return {{"parameters", parameters_json(p)},
            {"coefficients", coefficients_json(k)},
            {"potential", "V = alpha (1 - cos theta1) + beta (1 - cos theta2)"},
            {"saddle_energy",
             {{"1", to_decimal(model.saddle_energy(arm::one))},
              {"2", to_decimal(model.saddle_energy(arm::two))}}},
            {"maximum_energy", to_decimal(model.maximum_energy())},
            {"approximate_curve", curves}};
}

// ---- saddle-orbit families ------------------------------------------------------------------

/// The orbit options of the scene: the defaults, with [scene] orbit_integrator if given.
template <class Real>
orbit_options<Real> scene_orbit_options(const scene& s) {
    orbit_options<Real> options;
    if (!s.orbit_integrator.empty())
        options.integrator = parse_name<orbit_integrator>(s.orbit_integrator, "orbit_integrator");
    return options;
}

template <class Real>
void run_orbit_family(context& ctx, const plan_step& step) {
    const double_pendulum<Real> model = make_model<Real>(ctx.s.model);
    const arm a = arm_of(step.arm);
    const orbit_options<Real> options = scene_orbit_options<Real>(ctx.s);
    std::filesystem::path dir;
    if (!ctx.options.cache_dir.empty()) {
        dir = ctx.options.cache_dir / "saddle-orbits" / orbit_cache_key(model, options) /
              ("arm" + std::to_string(step.arm));
    }
    // cached orbits first
    std::vector<energy_level<Real>> missing;
    std::vector<std::string> missing_text;
    for (const std::string& text : step.energies) {
        const energy_level<Real> energy = parse_energy_level<Real>(text, "energy");
        if (recall_saddle_orbit(model, a, energy, options.method, options.integrator)) continue;
        const auto file = dir / ("E" + text + ".json");
        std::error_code ec;
        const bool present = !dir.empty() && std::filesystem::symlink_status(file, ec).type() !=
                                                 std::filesystem::file_type::not_found;
        // a folder, a device, a dangling link or a link loop is not an entry: recomputed (and
        // not overwritten)
        const bool regular = present && std::filesystem::is_regular_file(file, ec);
        if (present && !regular) {
            ++ctx.counters.orbit_cache_rejected;
            ctx.log << "  cache entry " << file.string()
                    << " is not a regular file; recomputing (the entry is left as it is)\n";
        }
        if (regular) {
            try {
                saddle_orbit<Real> o =
                    orbit_from_json<Real>(read_input_file(file, "cache entry"), file.string());
                const std::string problem = cached_orbit_problem(model, a, energy, o);
                if (problem.empty()) {
                    remember_saddle_orbit(model, o);
                    ++ctx.counters.orbit_cache_hits;
                    continue;
                }
                ++ctx.counters.orbit_cache_rejected;
                ctx.log << "  cache entry " << file.string() << " is invalid (" << problem
                        << "); recomputing\n";
            } catch (const input_error& e) {
                ++ctx.counters.orbit_cache_rejected;
                ctx.log << "  ignoring unreadable cache entry: " << e.what() << "; recomputing\n";
            }
        }
        missing.push_back(energy);
        missing_text.push_back(text);
    }
    json record = {{"arm", step.arm},
                   {"precision", precision_name<Real>()},
                   {"energies", step.energies.size()},
                   {"from_cache", step.energies.size() - missing.size()},
                   {"cache", dir.string()}};
    if (!missing.empty()) {
        ctx.log << "  continuing the family through " << missing.size() << " energies\n";
        const saddle_family<Real> family = continue_saddle_family(model, a, missing, options);
        ctx.counters.orbit_solves += family.orbits.size();
        for (const saddle_orbit<Real>& o : family.orbits) {
            remember_saddle_orbit(model, o);
            if (ctx.writes && !dir.empty() && o.status != orbit_status::not_converged) {
                std::size_t i = 0;
                while (i < missing.size() && (missing[i].value != o.energy ||
                                              missing[i].above(model.saddle_level(a)) != o.excess))
                    ++i;
                if (i < missing.size()) {
                    const auto file = dir / ("E" + missing_text[i] + ".json");
                    std::error_code ec;
                    const auto type = std::filesystem::symlink_status(file, ec).type();
                    // the cache only saves time: an entry that cannot be stored is a note
                    try {
                        if (type != std::filesystem::file_type::not_found &&
                            type != std::filesystem::file_type::regular)
                            throw std::runtime_error("'" + file.string() +
                                                     "' is not a regular file");
                        std::filesystem::create_directories(dir);
                        write_file_atomically(file, orbit_to_json(o));
                    } catch (const std::exception& e) {
                        ctx.log << "  note: the orbit was not cached: " << e.what() << "\n";
                    }
                }
            }
        }
        record["solved"] = family.orbits.size();
        record["continuation_steps"] = family.steps.size();
        record["halvings"] = family.halvings;
        if (!family.stop_reason.empty()) {
            record["stop_reason"] = family.stop_reason;
            ctx.log << "  the continuation stopped short: " << family.stop_reason << "\n";
        }
    }
    ctx.summary["orbit_families"].push_back(record);
}

/// orbits-arm<a>.csv (and orbit-curves-arm<a>.csv) for [orbits], from the remembered family.
template <class Real>
void write_orbit_tables(context& ctx, int arm_number) {
    const double_pendulum<Real> model = make_model<Real>(ctx.s.model);
    const arm a = arm_of(arm_number);
    const auto& spec = *ctx.s.orbits;
    std::ostringstream csv, curves;
    csv << "energy,period,action,flux,curve_flux,stability_index,multiplier,period_derivative,"
           "error_estimate_period,error_estimate_action,status\n";
    curves << "energy,theta1,theta2\n";
    const Real es = model.saddle_energy(a), emax = model.maximum_energy();
    const Real pi_r = boost::math::constants::pi<Real>();
    const std::vector<std::string> texts = energy_texts(spec.energies, "orbits.energies");
    const std::vector<energy_level<Real>> levels =
        energies_of<Real>(spec.energies, "orbits.energies");
    // energies with no row, and why: never dropped silently (a shared grid of both arms has
    // energies below arm 1's family; an energy above E_max has no saddle orbit)
    json& skipped = ctx.summary["orbits"]["skipped"];
    if (!skipped.is_array()) skipped = json::array();
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const energy_level<Real>& level = levels[i];
        const std::string& e = texts[i];  // the energy as the scene gives it (not rounded)
        if (!(level.above(model.saddle_level(a)) > 0 && level.below(model.maximum_level()) > 0)) {
            skipped.push_back({{"arm", std::to_string(arm_number)},
                               {"energy", e},
                               {"reason", "outside the arm's saddle-orbit family (" +
                                              to_decimal(es) + ", " + to_decimal(emax) + ")"}});
            continue;
        }
        const auto o = recall_saddle_orbit(model, a, level, orbit_method::periodic,
                                           scene_orbit_options<Real>(ctx.s).integrator);
        if (!o) {  // the continuation stopped short (its record in run.json says why)
            skipped.push_back({{"arm", std::to_string(arm_number)},
                               {"energy", e},
                               {"reason", "the family's continuation did not reach it"}});
            continue;
        }
        // the flux through the orbit's configuration curve by the general curve-flux quadrature:
        // an independent check of f3 = 2 F (which `flux` is, by definition)
        const saddle_curve<Real> curve = make_saddle_curve(model, *o);
        const Real through = curve_flux(model, level, curve).value;
        csv << e << "," << to_decimal(o->period) << "," << to_decimal(o->action) << ","
            << to_decimal(o->flux()) << "," << to_decimal(through) << ","
            << to_decimal(o->floquet.stability_index) << ","
            << (o->floquet.hyperbolic ? to_decimal(o->floquet.multiplier) : std::string()) << ","
            << to_decimal(o->period_derivative) << "," << to_decimal(o->error_estimate_period, 3)
            << "," << to_decimal(o->error_estimate_action, 3) << "," << to_string(o->status)
            << "\n";
        if (spec.curve_samples > 0) {
            const Real smax = curve.domain()[1];
            const int n = spec.curve_samples;
            for (int k = 0; k < n; ++k) {
                const Real s = -smax + 2 * smax * Real(k) / Real(n - 1 > 0 ? n - 1 : 1);
                const Real flip = pi_r + curve.offset(s);
                const Real th1 = a == arm::two ? s : flip, th2 = a == arm::two ? flip : s;
                curves << e << "," << to_decimal(th1) << "," << to_decimal(th2) << "\n";
            }
        }
    }
    ctx.write("orbits-arm" + std::to_string(arm_number) + ".csv", csv.str());
    if (spec.curve_samples > 0)
        ctx.write("orbit-curves-arm" + std::to_string(arm_number) + ".csv", curves.str());
}

// ---- predictions ----------------------------------------------------------------------------

/// The RMS relative differences of one arm's criteria's predicted rates from a reference
/// criterion's (the saddle orbit's), over the energies where both were evaluated strictly between
/// the arm's saddle energy and the maximum (paper Sec. 5.4: 13.46 % and 0.36 % for arm 2).
template <class Real>
void rate_differences_to(const double_pendulum<Real>& model,
                         const std::map<std::string, std::map<std::string, Real>>& values, arm a,
                         const criterion_definition& reference, json& out) {
    const std::string at = "@" + to_string(a);
    const auto ref = values.find(reference.rate_quantity + at);
    if (ref == values.end()) return;
    for (const criterion_definition& c : criteria_registry()) {
        if (c.is_reference || c.rate_quantity.empty()) continue;
        const auto other = values.find(c.rate_quantity + at);
        if (other == values.end()) continue;
        using std::sqrt;
        Real sum = 0;
        std::size_t n = 0;
        for (const auto& [text, v] : other->second) {
            const auto s = ref->second.find(text);
            const energy_level<Real> e = parse_energy_level<Real>(text, "energy");
            if (s == ref->second.end() || !(e.above(model.saddle_level(a)) > 0) ||
                !(e.below(model.maximum_level()) > 0) || !(s->second > 0))
                continue;
            const Real rel = v / s->second - 1;
            sum += rel * rel;
            ++n;
        }
        out.push_back(
            {{"arm", to_string(a)},
             {"criteria", json::array({c.name, reference.name})},
             {"energies", n},
             {"rms_relative", n ? json(to_decimal(Real(sqrt(sum / Real(n))))) : json(nullptr)}});
    }
}

/// rate_differences_to for each arm and reference criterion.
template <class Real>
json rate_differences(const double_pendulum<Real>& model,
                      const std::map<std::string, std::map<std::string, Real>>& values) {
    json out = json::array();
    for (const arm a : {arm::one, arm::two})
        for (const criterion_definition& reference : criteria_registry())
            if (reference.is_reference) rate_differences_to(model, values, a, reference, out);
    return out;
}

template <class Real>
void run_predictions(context& ctx, const plan_step& step) {
    const double_pendulum<Real> model = make_model<Real>(ctx.s.model);
    std::ostringstream csv;
    csv << "quantity,arm,energy,value,error_estimate,method\n";
    json skipped = json::array();
    std::map<std::string, std::map<std::string, Real>> values;  // entry -> energy text -> value
    for (const std::string& entry : step.quantities) {
        const auto at = entry.find('@');
        const std::string name = entry.substr(0, at);
        const arm a = at == std::string::npos ? arm::two : arm_named(entry.substr(at + 1)).value();
        const quantity& q = find_quantity(name);
        for (const std::string& text : step.energies) {
            const energy_level<Real> energy = parse_energy_level<Real>(text, "energy");
            try {
                // the scene's orbit integrator qualifies the orbit quantities' default method
                const quantity_value<Real> v =
                    q.evaluate(model, a, energy,
                               q.needs_saddle_orbit && !ctx.s.orbit_integrator.empty()
                                   ? q.methods.front() + "/" + ctx.s.orbit_integrator
                                   : std::string());
                ++ctx.counters.quantity_evaluations;
                values[entry][text] = v.value;
                const std::array<std::string, 2> printed = printed_value(v);
                csv << name << "," << (q.per_arm ? to_string(a) : "") << "," << text << ","
                    << printed[0] << "," << printed[1] << "," << csv_field(v.method) << "\n";
            } catch (const input_error& e) {
                skipped.push_back({{"quantity", entry}, {"energy", text}, {"reason", e.what()}});
            } catch (const budget_exceeded&) {  // the run's bound (execute_plan), not a finding
                throw;
            } catch (const std::runtime_error& e) {  // e.g. no multiplier of an elliptic orbit
                skipped.push_back({{"quantity", entry}, {"energy", text}, {"reason", e.what()}});
            }
        }
    }
    ctx.write("predictions.csv", csv.str());
    ctx.summary["predictions"] = {{"file", "predictions.csv"},
                                  {"skipped", skipped},
                                  {"rate_differences", rate_differences(model, values)}};
}

// ---- ensembles ------------------------------------------------------------------------------

/// The simulation request of [[ensemble]] `index` (its checkpoint and CSV directory set).
simulation_request ensemble_request(context& ctx, std::size_t index) {
    const ensemble_spec& x = ctx.s.ensembles[index];
    const std::string where =
        ctx.s.file.string() + ":" + std::to_string(x.line) + ": ensemble '" + x.name + "'";
    simulation_request request;
    try {
        request = ensemble_settings(x);  // checked by the loader: a refusal here is a defect
    } catch (const input_error& e) {
        throw input_error(where + ": " + e.what());
    }
    request.flip_arm = arm_of(x.arm);
    request.criteria = x.criteria;
    for (const std::string& text : energy_texts(x.energies, where + ": energies"))
        request.energies.emplace_back(text, parse_real<double>(text, where + ": energies"));
    request.options.threads = ctx.options.threads;
    request.options.stop = ctx.stop;
    request.csv_dir = ctx.s.output / ("ensemble-" + x.name);  // per-trajectory CSVs always (the
                                                              // report reads them)
    request.residence_times = x.residence_times;  // every crossing time: only where asked
    request.checkpoint_interval = ctx.options.checkpoint_interval;
    return request;
}

/// The step's ensembles on one set of trajectories (study/simulation.hpp): each trajectory
/// integrated once, each ensemble's result written as if it had run alone.
/// The step's requests: one per ensemble, sharing the step's checkpoint (an interrupted run
/// resumes where it stopped: finished trajectories are not integrated again; the checkpoint is
/// removed once the ensembles are complete) and the run's processes.
std::vector<simulation_request> ensemble_step_requests(context& ctx, const plan_step& step,
                                                       std::string& names) {
    std::vector<simulation_request> requests;
    for (std::size_t i : step.ensemble_indices) {
        requests.push_back(ensemble_request(ctx, i));
        names += (names.empty() ? "" : "+") + ctx.s.ensembles[i].name;
    }
    for (simulation_request& q : requests) {
        q.checkpoint = ctx.s.output / ("ensemble-" + names + ".checkpoint");
        q.group = ctx.options.group;
    }
    if (ctx.options.progress)  // the first request's serves the run (simulate)
        requests.front().progress = [&progress = ctx.options.progress,
                                     names](const simulation_progress& p) { progress(names, p); };
    return requests;
}

void run_ensemble(context& ctx, const plan_step& step) {
    const double_pendulum<double> model = make_model<double>(ctx.s.model);
    std::string names;
    const std::vector<simulation_request> requests = ensemble_step_requests(ctx, step, names);
    const std::filesystem::path checkpoint = requests.front().checkpoint;
    std::vector<study_result> results;
    try {
        results = *simulate(model, requests);
    } catch (const input_error& e) {  // the checkpoint, named as the scene has it
        if (e.field() != "checkpoint") throw;
        const ensemble_spec& x = ctx.s.ensembles[step.ensemble_indices.front()];
        throw input_error(ctx.s.file.string() + ":" + std::to_string(x.line) + ": ensemble '" +
                          x.name + "': its checkpoint " + e.detail() +
                          "; delete the file to start the ensemble afresh");
    }
    // what was integrated (once per energy of the step) and detected
    ctx.counters.trajectories += results.front().options.trajectories * step.energies.size();
    for (std::size_t r = 0; r < results.size(); ++r) {
        const study_result& result = results[r];
        const ensemble_spec& x = ctx.s.ensembles[step.ensemble_indices[r]];
        for (const energy_result& e : result.energies) {
            if (e.failed_trajectories > 0)
                ctx.log << "  warning: ensemble '" << x.name << "', E = " << e.label << ": "
                        << e.failed_trajectories
                        << " trajectories failed and are excluded from the statistics\n";
            for (const criterion_result& c : e.criteria)
                if (!criterion(c.statistics.criterion).is_level) ++ctx.counters.curve_criteria;
        }
        const std::string base = "ensemble-" + x.name;
        json out = study_json(result);
        out["model"] = model_parameters_json(model);  // as `flipflux simulate` writes it
        ctx.write(base + ".json", out.dump(2) + "\n");
        ctx.summary["ensembles"].push_back({{"name", x.name},
                                            {"file", base + ".json"},
                                            {"csv_dir", requests[r].csv_dir.string()},
                                            {"shared_with", names},
                                            {"residence_times", x.residence_times},
                                            {"histogram", x.histogram}});
        if (!x.census_of.empty()) ctx.summary["ensembles"].back()["census_of"] = x.census_of;
        if (!x.classification_check_of.empty())
            ctx.summary["ensembles"].back()["classification_check_of"] = x.classification_check_of;
    }
    // the results are on disk; the checkpoint goes when the whole run is complete (execute_plan):
    // a rerun of a run stopped later restores this step from it rather than integrating again
    ctx.checkpoints.push_back(checkpoint);
}

// ---- single trajectories ------------------------------------------------------------------

/// One [[trajectory]] at double by the ensemble's route: trajectory-<name>.csv (states) and
/// trajectory-<name>-events.csv, the files of `flipflux trajectory --out/--events`.
void run_trajectory(context& ctx, const plan_step& step) {
    const trajectory_spec& t = ctx.s.trajectories[step.ensemble_index];
    const std::string where =
        ctx.s.file.string() + ":" + std::to_string(t.line) + ": trajectory '" + t.name + "'";
    const double_pendulum<double> model = make_model<double>(ctx.s.model);
    trajectory_request<double> q;
    for (std::size_t k = 0; k < 4; ++k)
        q.state[k] = k < 2 ? parse_angle<double>(t.state[k], where + ": state")
                           : parse_real<double>(t.state[k], where + ": state");
    q.time = parse_real<double>(t.time, where + ": time");
    q.sample_interval = parse_real<double>(t.sample_interval, where + ": sample_interval");
    q.criteria = t.criteria;
    for (int a : t.arms)
        q.arms.push_back(arm_of(a));
    q.rtol = parse_real<double>(t.rtol, where + ": rtol");
    const trajectory_record<double> r = integrate_trajectory(model, q);
    for (const std::string& why : r.skipped)
        ctx.log << "  no flips possible for " << why << "\n";
    const std::string base = "trajectory-" + t.name;
    ctx.write(base + ".csv", trajectory_states_csv(r));
    ctx.write(base + "-events.csv", trajectory_events_csv(r));
    ++ctx.counters.trajectories;
    ctx.summary["trajectories"].push_back({{"name", t.name},
                                           {"states", base + ".csv"},
                                           {"events", base + "-events.csv"},
                                           {"energy", to_decimal(r.energy)},
                                           {"events_count", r.events.size()},
                                           {"max_energy_drift", to_decimal(r.max_energy_drift)},
                                           {"route", r.route},
                                           {"skipped", r.skipped}});
}

// ---- the saddle-orbit viewer ----------------------------------------------------------------

/// viewer.html from the families the plan's orbit-family steps continued (in the memo).
template <class Real>
void run_viewer(context& ctx) {
    const viewer_spec& v = *ctx.s.viewer;
    viewer_request request;
    request.arms.clear();
    for (int a : v.arms)
        request.arms.push_back(arm_of(a));
    request.energies = v.energies_per_arm;
    request.samples = v.samples;
    request.grid = v.grid;
    const viewer_data<Real> data = saddle_viewer_data(make_model<Real>(ctx.s.model), request,
                                                      scene_orbit_options<Real>(ctx.s));
    json record = {{"file", "viewer.html"}, {"families", json::array()}};
    for (const viewer_family<Real>& f : data.families) {
        record["families"].push_back({{"arm", to_string(f.flip_arm)},
                                      {"orbits", f.orbits.size()},
                                      {"stop_reason", f.stop_reason}});
        if (!f.stop_reason.empty())
            ctx.log << "  arm " << to_string(f.flip_arm) << ": " << f.stop_reason << "\n";
    }
    ctx.write("viewer.html", viewer_page(viewer_json(data),
                                         ctx.s.name + ": saddle orbits of the double pendulum"));
    ctx.summary["viewer"] = record;
}

}  // namespace

namespace {

/// The ranks of an MPI run meet here before rank 0's first ensemble step: rank 0 has then solved
/// (or read from its cache) every saddle orbit of the scene's families and predictions, and sends
/// those at double -- what the ensembles' saddle criterion recalls -- to every other rank, whose
/// memo then holds rank 0's bits. Returns the number of orbits sent.
std::size_t meet_before_the_ensembles(const run_options& options, const scene& s) {
    const double_pendulum<double> model = make_model<double>(s.model);
    const bool root = options.group->rank() == 0;
    const nlohmann::json sent = root ? remembered_orbit_records(model) : std::vector<std::string>{};
    const std::string text = options.group->broadcast(root ? sent.dump() : std::string());
    if (root) return sent.size();
    // what rank 0 sent is no user's input: a failure here is internal (printed by this rank)
    const std::string who = "rank " + std::to_string(options.group->rank());
    const nlohmann::json received = nlohmann::json::parse(text, nullptr, false);
    if (!received.is_array() ||
        !std::all_of(received.begin(), received.end(), [](const auto& r) { return r.is_string(); }))
        throw std::runtime_error(who + ": rank 0's orbits are not a JSON array of records");
    try {
        remember_orbit_records(model, received.get<std::vector<std::string>>(), "rank 0's orbits");
    } catch (const input_error& e) {
        throw std::runtime_error(who + ": " + e.what());
    }
    return received.size();
}

/// The run's CPU bound (run_options::max_seconds): a watch sets the flag the ensembles poll,
/// relaying the caller's (run_options::stop) until then. `stop` is what to poll: the flag, or the
/// caller's own without a bound.
struct run_bound {
    std::atomic<int> flag{0};
    const cpu_watch watch;
    const std::atomic<int>* const stop;
    /// the process's CPU time at which the bound is reached (0: no bound)
    const double deadline;
    explicit run_bound(const run_options& o)
        : watch(o.max_seconds, flag, cpu_bound_stop, o.stop),
          stop(o.max_seconds > 0 ? &flag : o.stop),
          deadline(o.max_seconds > 0 ? process_cpu_seconds() + o.max_seconds : 0) {}
};

/// Whether a step of this kind runs on the calling thread alone, through computations that check
/// the thread's CPU budget (core/budget.hpp: quadratures, integrators, Arb, a lone trajectory's
/// steps at double): the run's bound stops it there, not at its end. The ensembles poll the run's
/// flag themselves; the golden proofs and the accuracy harness run cells on OpenMP threads with
/// budgets of their own (max_seconds).
bool bounded_on_the_calling_thread(plan_step::kind k) {
    return k == plan_step::kind::orbit_family || k == plan_step::kind::predictions ||
           k == plan_step::kind::trajectory || k == plan_step::kind::viewer;
}

/// A rank other than 0 of `mpirun -np N flipflux run`: its share of the ensembles' trajectories.
/// It computes no family and no prediction: the saddle criterion's curves need rank 0's orbits
/// bit for bit, and rank 0 sends them (meet_before_the_ensembles). Then it joins each ensemble
/// step with the same requests as rank 0 (the collectives inside simulate() follow the same path;
/// rank 0 reads and writes the checkpoint and the CSVs), writing nothing.
run_counters join_ensembles(const scene& s, const plan& p, std::ostream& log,
                            const run_options& options) {
    context ctx{s, log, options, {}};
    ctx.writes = false;
    const run_bound bound(options);  // this rank's own
    ctx.stop = bound.stop;
    const double_pendulum<double> model = make_model<double>(s.model);
    bool met = false;
    for (const plan_step& step : p.steps) {
        if (step.what != plan_step::kind::ensemble) continue;
        if (!met) log << "  " << meet_before_the_ensembles(options, s) << " orbits from rank 0\n";
        met = true;
        std::string names;
        (void)simulate(model, ensemble_step_requests(ctx, step, names));  // rank 0's results
    }
    if (!met) (void)meet_before_the_ensembles(options, s);
    return ctx.counters;
}

/// One step of the plan (`seconds`: the run's so far, for the report's run.json).
void run_step(context& ctx, const plan_step& step, double seconds) {
    switch (step.what) {
        case plan_step::kind::orbit_family:
            dispatch(step.prec, [&]<class Real>() { run_orbit_family<Real>(ctx, step); });
            break;
        case plan_step::kind::predictions:
            dispatch(ctx.s.prec, [&]<class Real>() { run_predictions<Real>(ctx, step); });
            break;
        case plan_step::kind::ensemble:
            run_ensemble(ctx, step);
            break;
        case plan_step::kind::trajectory:
            run_trajectory(ctx, step);
            break;
        case plan_step::kind::viewer:
            dispatch(ctx.s.prec, [&]<class Real>() { run_viewer<Real>(ctx); });
            break;
        case plan_step::kind::golden:
            run_golden(ctx);
            break;
        case plan_step::kind::accuracy:
            run_accuracy(ctx);
            break;
        case plan_step::kind::report:
            run_report(ctx, seconds);
            break;
    }
}

/// Why the run stops (ctx.stop holds `signal`), `where` in the plan: what simulation_interrupted
/// says, naming the bound or the interruption, where it stopped and how to resume.
simulation_interrupted run_stopped(const context& ctx, int signal, const std::string& where,
                                   std::uint64_t saved,
                                   const std::string& rerun = "rerun the same command to resume") {
    const std::string cause =
        signal == cpu_bound_stop ? "stopped at its bound of " +
                                       to_shortest_decimal(ctx.options.max_seconds) + " CPU seconds"
                                 : "interrupted";
    std::string text = cause + " " + where;
    if (const std::size_t n = ctx.checkpoints.size(); n > 0)
        text += n == 1 ? std::string("; the finished ensemble step is kept in its checkpoint")
                       : "; the " + std::to_string(n) +
                             " finished ensemble steps are kept in their checkpoints";
    return simulation_interrupted(text + "; " + rerun, signal, saved);
}

/// `work`, when `bounded` (it runs on the calling thread alone, its CPU time about the
/// process's), with the rest of the run's CPU bound as that thread's budget and the run's stop
/// flag polled where it checks that budget, so that a long orbit family or prediction stops at the
/// bound or a signal, `where` in the plan, its work not kept.
template <class Work>
void within_bound(const context& ctx, const run_bound& bound, bool bounded,
                  const std::string& where, Work&& work) {
    try {
        std::optional<cpu_budget_scope> budget;
        if (bounded && bound.deadline > 0)
            budget.emplace(std::max(bound.deadline - process_cpu_seconds(), 1e-6));
        const stop_poll_scope poll(bounded ? ctx.stop : nullptr);
        work();
    } catch (const budget_exceeded&) {
        // the flag names the cause (a signal, or the bound); the thread's budget may end first,
        // before the watch sets the flag
        const int signal = ctx.stop != nullptr ? ctx.stop->load() : 0;
        if (!bounded || (signal == 0 && bound.deadline == 0)) throw;  // not the run's
        // at the bound, the step alone needs more than the rest of it: the same command would
        // stop there again
        const bool at_bound = signal == 0 || signal == cpu_bound_stop;
        throw run_stopped(ctx, at_bound ? cpu_bound_stop : signal,
                          where + ": its work so far is not kept", 0,
                          at_bound ? "rerun with a larger --max-seconds to finish it"
                                   : "rerun the same command to resume");
    }
}

}  // namespace

run_counters execute_plan(const scene& s, const plan& p, std::ostream& log,
                          const run_options& options) {
    if (options.group != nullptr && options.group->rank() != 0)
        return join_ensembles(s, p, log, options);
    context ctx{s, log, options, {}};
    const run_bound bound(options);  // the flag is also checked between steps
    ctx.stop = bound.stop;
    const auto start = std::chrono::steady_clock::now();
    const std::size_t misses_before = saddle_orbit_memo_misses();
    ctx.summary["scene"] = s.name;
    ctx.summary["scene_file"] = s.file.string();
    ctx.summary["precision"] = precision_name(s.prec);
    ctx.summary["git_commit"] = git_commit();
    ctx.summary["model"] =
        dispatch(s.prec, [&]<class Real>() { return model_json(make_model<Real>(s.model)); });
    ctx.summary["orbit_families"] = json::array();
    ctx.summary["ensembles"] = json::array();
    if (!s.trajectories.empty()) ctx.summary["trajectories"] = json::array();
    // the output directories before anything is computed (make_plan checked what it could
    // without creating them): a refusal names the scene's key, never a filesystem error after hours
    create_output_dir(s, s.output, s.output_line, "scene.output");
    check_output_entries(s, true);
    check_output_owner(s);
    if (s.golden) create_output_dir(s, s.golden->dir, s.golden->line, "golden.dir");
    if (s.accuracy && std::filesystem::path(s.accuracy->out).has_parent_path())
        create_output_dir(s, std::filesystem::path(s.accuracy->out).parent_path(), s.accuracy->line,
                          "accuracy.out");
    auto elapsed = [&] {
        return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    };
    // the orbit tables, once, after the last orbit family (the families come first in a plan)
    bool orbit_tables_written = !s.orbits;
    auto write_orbit_tables_once = [&] {
        if (orbit_tables_written) return;
        dispatch(s.prec, [&]<class Real>() {
            for (int a : s.orbits->arms)
                write_orbit_tables<Real>(ctx, a);
        });
        orbit_tables_written = true;
    };
    // each step's wall seconds (where a run's time goes: docs/scale.md)
    ctx.summary["step_seconds"] = json::array();
    bool met = options.group == nullptr;  // an MPI run's ranks meet before the first ensemble
    for (std::size_t i = 0; i < p.steps.size(); ++i) {
        const plan_step& step = p.steps[i];
        const std::string of = " of " + std::to_string(p.steps.size());
        if (const int signal = ctx.stop ? ctx.stop->load() : 0; signal != 0)
            throw run_stopped(ctx, signal,
                              i == 0 ? std::string("before its first step")
                                     : "after step " + std::to_string(i) + of + " (" +
                                           p.steps[i - 1].description + ")",
                              0);
        if (!met && step.what == plan_step::kind::ensemble) {
            log << "  " << meet_before_the_ensembles(options, s)
                << " orbits sent to the other ranks\n";
            met = true;
        }
        // (the orbit tables belong to the families before: written before this step's clock)
        if (step.what != plan_step::kind::orbit_family)
            within_bound(ctx, bound, true,
                         (i == 0 ? "before step 1" : "after step " + std::to_string(i)) + of +
                             ", writing the orbit tables",
                         write_orbit_tables_once);
        log << "- " << step.description << "\n";
        const double step_start = elapsed(), step_cpu_start = process_cpu_seconds();
        const std::string in_step =
            "in step " + std::to_string(i + 1) + of + " (" + step.description + ")";
        within_bound(ctx, bound, bounded_on_the_calling_thread(step.what), in_step, [&] {
            try {
                run_step(ctx, step, elapsed());
            } catch (const simulation_interrupted& e) {  // an ensemble's: its flag is ctx.stop
                throw run_stopped(ctx, e.signal(), in_step + ": " + e.kept(), e.saved());
            }
        });
        const double seconds = elapsed() - step_start;
        ctx.summary["step_seconds"].push_back(
            {{"step", step.description},
             {"seconds", seconds},
             {"cpu_seconds", process_cpu_seconds() - step_cpu_start}});
        log << "  (" << seconds << " s)\n";
    }
    within_bound(ctx, bound, true,
                 "after step " + std::to_string(p.steps.size()) + " of " +
                     std::to_string(p.steps.size()) + ", writing the orbit tables",
                 write_orbit_tables_once);
    if (!met) (void)meet_before_the_ensembles(options, s);
    // orbits solved one by one outside a family (e.g. beyond where a continuation stopped)
    ctx.counters.orbit_solves += saddle_orbit_memo_misses() - misses_before;
    ctx.summary["counters"] = {{"orbit_solves", ctx.counters.orbit_solves},
                               {"orbit_cache_hits", ctx.counters.orbit_cache_hits},
                               {"orbit_cache_rejected", ctx.counters.orbit_cache_rejected},
                               {"quantity_evaluations", ctx.counters.quantity_evaluations},
                               {"trajectories", ctx.counters.trajectories},
                               {"curve_criteria", ctx.counters.curve_criteria}};
    ctx.summary["seconds"] = elapsed();
    ctx.summary["cpu_seconds"] = process_cpu_seconds() - ctx.cpu_start;
    ctx.write("run.json", ctx.summary.dump(2) + "\n");
    // the run is complete: its ensemble steps' checkpoints go (a rerun computes it afresh)
    for (const std::filesystem::path& checkpoint : ctx.checkpoints)
        std::filesystem::remove(checkpoint);
    log << "done in " << ctx.summary["seconds"].get<double>() << " s\n";
    return ctx.counters;
}

}  // namespace flipflux
