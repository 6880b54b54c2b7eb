// flipflux validate CANDIDATE.csv [--golden DIR] [--pendulum NAME] [--rtol X] [--allow-missing]
//     [--require-all] [--verbose]
// flipflux validate --ensemble CANDIDATE.csv [--pilot P] [--seed S] [model options]
// flipflux validate --trajectories CANDIDATE.csv [--reference EVENTS.csv] [--state NAME]
//     [--states STATES.csv] [--reference-states FILE] [--time-tol DT] [--state-tol DX] [--until T]
//     [--criteria LIST]
#include <cctype>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>

#include "common.hpp"
#include "flipflux/core/names.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/validation/candidate_pendulum.hpp"
#include "flipflux/validation/paired_check.hpp"
#include "flipflux/validation/simulator_check.hpp"
#include "flipflux/validation/trajectory_check.hpp"
#include "flipflux/validation/validate.hpp"
#include "simulate_request.hpp"

namespace flipflux::cli {
namespace {

struct validate_state {
    std::string candidate, golden, rtol = "1e-12";
    bool allow_missing = false, verbose = false, require_all = false, paired = false;
    std::string pendulum;
    std::string ensemble, pilot = "1000", seed = "1", variance = "auto";
    std::string trajectories, reference, state, time_tol = "1e-6", until = "0", criteria;
    std::string states, reference_states, state_tol = "0";
    model_options model;
    bool model_given = false;  ///< any of --m1 ... --g on the command line
};

/// The pendulum the validation is about: declared by the files (`# pendulum:` lines, in the
/// candidate and, for --trajectories, the reference) or by the model options; every declaration
/// given must name the same parameters. nullopt when nothing declares one.
std::optional<model_text> declared_pendulum_of(const validate_state& s,
                                               const std::vector<std::string>& files,
                                               std::string& who) {
    std::optional<model_text> out;
    if (s.model_given) {
        (void)parse_parameters<double>(s.model);  // a malformed option is named as the option
        out = s.model;
        who = "the model options";
    }
    for (const std::string& f : files) {
        const std::optional<declared_pendulum> d = read_declared_pendulum(f);
        if (!d) continue;
        if (out && !same_parameters(*out, d->parameters))
            throw input_error(d->where + ": pendulum: " + parameters_text(d->parameters) +
                              " is not the pendulum of " + who + " (" + parameters_text(*out) +
                              ")");
        if (!out) {
            out = d->parameters;
            who = d->where;
        }
    }
    return out;
}

/// The golden set of a named pendulum: the folder NAME under the golden data (one path component,
/// holding golden.csv); input_error listing the sets there otherwise.
std::string golden_set_of(const std::string& golden, const std::string& name) {
    namespace fs = std::filesystem;
    if (name == "egalitarian") return golden;  // the paper's pendulum: the top-level set
    std::string known;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(golden, ec))
        if (e.is_directory() && fs::exists(e.path() / "golden.csv"))
            known += (known.empty() ? "" : ", ") + e.path().filename().string();
    if (!is_plain_name(name) || !fs::exists(fs::path(golden) / name / "golden.csv"))
        throw input_error("--pendulum: '" + name + "' has no golden set under '" + golden +
                          "' (sets: egalitarian, the default" +
                          (known.empty() ? "" : ", " + known) + ")");
    return (fs::path(golden) / name).string();
}

void validate_ensemble(const validate_state& s) {
    std::string who;
    const std::optional<model_text> declared = declared_pendulum_of(s, {s.ensemble}, who);
    const bool from_file = declared && !s.model_given;
    const double_pendulum<double> model = [&] {
        try {
            return make_model<double>(declared.value_or(s.model));
        } catch (const input_error& e) {
            if (!from_file) throw;
            throw input_error(who + ": pendulum: " + e.what());  // the file's value, not an option
        }
    }();
    if (s.paired) {
        const paired_check_report r = check_paired_ensemble(model, s.ensemble, {});
        print(format_paired_check(r));
        if (!r.passed()) exit_status() = 1;
        return;
    }
    ensemble_check_options o;
    o.pilot_trajectories = parse_unsigned(s.pilot, "--pilot", true);
    o.seed = parse_unsigned(s.seed, "--seed", false);
    o.pilot_variance_always = s.variance == "pilot";
    const ensemble_check_report r = check_simulated_ensemble(model, s.ensemble, o);
    print(format_ensemble_check(r));
    if (!r.passed()) exit_status() = 1;
}

void validate_trajectories(const validate_state& s) {
    std::string reference = s.reference;
    if (reference.empty() && !s.state.empty()) {
        // the reference trajectories of the golden data flipflux was built or installed with
        const std::filesystem::path golden = find_share_path("golden");
        if (!golden.empty()) reference = (golden / "trajectories" / "events.csv").string();
    }
    if (reference.empty())
        throw input_error(
            "--trajectories: needs --reference FILE (or --state NAME of the golden data's "
            "reference trajectories)");
    std::string who;
    std::vector<std::string> declaring{s.trajectories, reference};
    if (!s.states.empty()) declaring.push_back(s.states);
    (void)declared_pendulum_of(s, declaring, who);  // they must agree
    event_comparison_options o;
    o.name = option_name;
    o.time_tolerance = parse_real<double>(s.time_tol, "--time-tol");
    o.until = parse_real<double>(s.until, "--until");
    if (!(o.time_tolerance > 0))
        throw input_error("--time-tol: '" + s.time_tol + "' must be positive");
    if (!(o.until >= 0)) throw input_error("--until: '" + s.until + "' must be >= 0");
    o.state_tolerance = parse_real<double>(s.state_tol, "--state-tol");
    if (!(o.state_tolerance >= 0))
        throw input_error("--state-tol: '" + s.state_tol + "' must be >= 0");
    o.state = s.state;
    o.candidate_states = s.states;
    o.reference_states = s.reference_states;
    if (!s.reference_states.empty() && s.states.empty())
        throw input_error("--reference-states: needs the candidate's --states");
    for (std::size_t pos = 0; pos < s.criteria.size();) {
        const std::size_t comma = std::min(s.criteria.find(',', pos), s.criteria.size());
        const std::string name = s.criteria.substr(pos, comma - pos);
        check_criterion_name(criterion_named(name).value_or(name), "--criteria");  // a typo
        o.criteria.push_back(*criterion_named(name));  // would compare nothing and pass
        pos = comma + 1;
    }
    const event_comparison c = compare_flip_events(s.trajectories, reference, o);
    print(format_event_comparison(c, o));
    if (c.differs) exit_status() = 1;
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<validate_state>();
    CLI::App* sub = app.add_subcommand(
        "validate",
        "Compare another implementation's values (CSV: quantity, arm, energy, value) with the "
        "golden data, a simulator's ensemble flip counts with the predicted rates (--ensemble), "
        "or its flip events with reference events (--trajectories); exit status 1 when any row "
        "fails (docs/validating.md)");
    sub->add_option("candidate", s->candidate, "the candidate CSV file (golden-data values)");
    sub->add_option("--golden", s->golden,
                    "the golden-data directory [default: the installation's, share/flipflux/golden "
                    "beside the executable or in ../share]");
    sub->add_option("--rtol", s->rtol, "relative tolerance per row")->capture_default_str();
    sub->add_option("--pendulum", s->pendulum,
                    "the golden set of this pendulum (a folder under the golden data, e.g. "
                    "unequal-point-masses; its parameters are in its provenance.json) [default: "
                    "egalitarian, the paper's]");
    sub->add_flag("--verbose", s->verbose, "list every row, the ok and missing ones too");
    sub->add_flag("--require-all", s->require_all,
                  "candidate rows the golden set lacks (unmatched) fail the validation");
    sub->add_flag("--allow-missing", s->allow_missing,
                  "accept a candidate that covers only some energies of a quantity");
    sub->add_option("--ensemble", s->ensemble,
                    "a simulator's ensemble results (CSV: criterion, arm, energy, trajectories, "
                    "time, flips[, flips_sq]) to test against the predicted rates");
    sub->add_flag("--paired", s->paired,
                  "--ensemble: the candidate lists its trajectories one by one (CSV: energy, "
                  "theta1, theta2, l1, l2, time, arm, flips[, criterion, trajectory]); flipflux "
                  "integrates the same initial states and compares the counts pair by pair (the "
                  "recommended ensemble check, docs/validating.md)");
    sub->add_option("--pilot", s->pilot,
                    "--ensemble rows without flips_sq: trajectories of flipflux's pilot ensemble "
                    "that bounds the count variance")
        ->capture_default_str();
    sub->add_option("--seed", s->seed, "seed of the pilot ensembles")->capture_default_str();
    sub->add_option("--variance", s->variance,
                    "--ensemble: whose spread of the counts the z-scores use: auto (the "
                    "candidate's flips_sq where given, else the pilot's bound) or pilot (always "
                    "flipflux's pilot: the spread of a correct simulator, which a wrong one's "
                    "wider scatter cannot inflate; costs the pilot ensembles)")
        ->capture_default_str();
    sub->add_option("--trajectories", s->trajectories,
                    "a simulator's flip events of one trajectory (CSV: time, arm, direction and "
                    "criterion, upright when absent) to compare with --reference: the criteria "
                    "it reports, up to the common horizon (with a golden --state and a "
                    "double-precision candidate, up to the double horizon, where chaos starts "
                    "to part any double run from the reference)");
    sub->add_option("--states", s->states,
                    "--trajectories: the candidate's states (CSV: t, theta1, theta2, l1, l2) to "
                    "compare at the reference's sample times (the golden states.csv with --state)");
    sub->add_option("--reference-states", s->reference_states,
                    "--trajectories: the reference states (flipflux trajectory --out) [default "
                    "with --state: the golden states.csv]");
    sub->add_option("--state-tol", s->state_tol,
                    "absolute tolerance of each state component, angles modulo 2 pi (0: "
                    "--time-tol)")
        ->capture_default_str();
    sub->add_option("--reference", s->reference,
                    "reference events (flipflux trajectory --events, or the golden data's "
                    "trajectories/events.csv with --state; default with --state: the golden "
                    "data beside the executable)");
    sub->add_option("--state", s->state, "the reference trajectory's name (a `state` column)");
    sub->add_option("--time-tol", s->time_tol, "absolute tolerance of event times")
        ->capture_default_str();
    sub->add_option("--until", s->until,
                    "compare only events and states before this time (0: the inferred horizon)")
        ->capture_default_str();
    sub->add_option("--criteria", s->criteria,
                    "--trajectories: compare these criteria (comma-separated, any case) [default: "
                    "those the candidate reports]");
    add_model_options(*sub, s->model);
    sub->callback([s, sub] {
        for (const parameter_field& f : parameter_fields)
            s->model_given =
                s->model_given || sub->get_option("--" + std::string(f.name))->count() > 0;
        const int modes = !s->candidate.empty() + !s->ensemble.empty() + !s->trajectories.empty();
        if (modes != 1)
            throw input_error(
                "validate: give exactly one of CANDIDATE, --ensemble FILE, --trajectories FILE");
        for (const char* o : {"--states", "--reference-states", "--state-tol"})
            if (sub->get_option(o)->count() > 0 && s->trajectories.empty())
                throw input_error(std::string(o) + ": only with --trajectories");
        if (sub->get_option("--state-tol")->count() > 0 && s->states.empty())
            throw input_error("--state-tol: needs the candidate's --states");
        if (s->variance != "auto" && s->variance != "pilot")
            throw input_error("--variance: '" + s->variance + "' is not auto or pilot");
        for (const char* o : {"--pilot", "--seed", "--variance"}) {
            if (sub->get_option(o)->count() > 0 && s->ensemble.empty())
                throw input_error(std::string(o) + ": only with --ensemble");
            if (sub->get_option(o)->count() > 0 && s->paired)
                throw input_error(std::string(o) +
                                  ": not with --paired (flipflux integrates the candidate's own "
                                  "states; no pilot ensemble)");
        }
        if (s->paired && s->ensemble.empty())
            throw input_error("--paired: needs --ensemble FILE (the candidate's trajectories)");
        if (!s->ensemble.empty()) return validate_ensemble(*s);
        if (!s->trajectories.empty()) return validate_trajectories(*s);
        const double rtol = parse_real<double>(s->rtol, "--rtol");
        if (!(rtol > 0 && rtol < 1)) {
            throw input_error("--rtol: '" + s->rtol + "' must be in (0, 1)");
        }
        std::string golden = s->golden;
        if (golden.empty()) {
            golden = find_share_path("golden").string();
            if (golden.empty())
                throw input_error(
                    "--golden: no golden data beside the executable (share/flipflux/golden or "
                    "../share/flipflux/golden); give the directory");
        }
        std::string who;
        if (const std::optional<model_text> p = declared_pendulum_of(*s, {s->candidate}, who)) {
            const golden_set set = golden_set_for(golden, *p, who);
            if (!s->pendulum.empty() && s->pendulum != set.name)
                throw input_error("--pendulum: '" + s->pendulum +
                                  "' is not the set of the pendulum of " + who + " (" +
                                  parameters_text(*p) + "): that is '" + set.name + "'");
            std::fprintf(stderr, "flipflux: note: golden set '%s' (%s), the pendulum of %s\n",
                         set.name.c_str(), set.dir.string().c_str(), who.c_str());
            golden = set.dir.string();
        } else if (!s->pendulum.empty()) {
            golden = golden_set_of(golden, s->pendulum);
        }
        const validation_report r =
            validate_candidate(s->candidate, golden, rtol, s->allow_missing, s->require_all);
        print(format_report(r, rtol, s->verbose,
                            ": --verbose lists them, --allow-missing accepts them"));
        if (!r.passed()) exit_status() = 1;
    });
});

}  // namespace
}  // namespace flipflux::cli
