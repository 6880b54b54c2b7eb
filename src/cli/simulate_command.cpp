// flipflux simulate: Monte Carlo ensembles (paper Sec. 5-6), a thin layer over
// ensemble/simulation.hpp: parses the options and prints the study's JSON report (with the model).
#include <charconv>

#include "common.hpp"
#include "flipflux/ensemble/simulation.hpp"

namespace flipflux::cli {
namespace {

struct simulate_state {
    std::string energy, arm_text = "2", criteria = "upright,approx,saddle", trajectories, time,
                        seed = "0", rtol = "1e-10", threads = "0", csv_dir, method = "dop853",
                        chaos_threshold = "0.05", first_index = "0", bins = "0",
                        sample_interval = "0";
    bool no_chaos = false;
    model_options model;
};

std::uint64_t parse_unsigned(const std::string& text, const std::string& option, bool positive) {
    std::uint64_t v = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, v);
    if (text.empty() || r.ec != std::errc() || r.ptr != end || (positive && v == 0))
        throw input_error(option + ": '" + text + "' is invalid (expected " +
                          (positive ? "a positive" : "a non-negative") + " integer)");
    return v;
}

double parse_positive(const std::string& text, const std::string& option) {
    const double v = parse_real<double>(text, option);
    if (!(v > 0)) throw input_error(option + ": '" + text + "' is invalid (must be > 0)");
    return v;
}

json run(const simulate_state& s) {
    simulation_request q;
    q.flip_arm = parse_arm(s.arm_text);
    const double_pendulum<double> model(parse_parameters<double>(s.model));
    q.energies = parse_energy_list(s.energy);
    q.criteria = parse_criterion_list(s.criteria);
    ensemble_options& o = q.options;
    o.trajectories = parse_unsigned(s.trajectories, "--trajectories", true);
    o.time = parse_positive(s.time, "--time");
    o.seed = parse_unsigned(s.seed, "--seed", false);
    o.first_index = parse_unsigned(s.first_index, "--first-index", false);
    o.rtol = parse_positive(s.rtol, "--rtol");
    o.threads = static_cast<int>(
        std::min<std::uint64_t>(parse_unsigned(s.threads, "--threads", false), 4096));
    o.method = parse_integration_method(s.method, "--method");
    o.chaos = !s.no_chaos;
    o.chaos_threshold = parse_positive(s.chaos_threshold, "--chaos-threshold");
    o.sample_interval = parse_real<double>(s.sample_interval, "--sample-interval");
    q.bins = parse_unsigned(s.bins, "--bins", false);
    q.csv_dir = s.csv_dir;
    json out = simulate(model, q);
    out["model"] = parameters_json(model);
    return out;
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<simulate_state>();
    CLI::App* sub = app.add_subcommand(
        "simulate",
        "Monte Carlo ensemble at one or more energies: microcanonical initial conditions, "
        "trajectories (DOP853 or DOPRI5 at double), flips of each criterion, statistics as JSON "
        "(and CSV with --csv-dir).");
    sub->add_option("--energy", s->energy,
                    "energy E, a list E1,E2,... or a range FROM:TO:STEP (inclusive)")
        ->required();
    sub->add_option("--arm", s->arm_text, "the arm whose flips are counted: 1 or 2")
        ->capture_default_str();
    sub->add_option("--criteria", s->criteria,
                    "comma-separated flip criteria: upright, approx, saddle")
        ->capture_default_str();
    sub->add_option("--trajectories", s->trajectories, "number of trajectories per energy (> 0)")
        ->required();
    sub->add_option("--time", s->time, "integration time T per trajectory (> 0)")->required();
    sub->add_option("--seed", s->seed, "random seed (non-negative integer)")->capture_default_str();
    sub->add_option("--first-index", s->first_index,
                    "index of the first trajectory (split runs across processes)")
        ->capture_default_str();
    sub->add_option("--rtol", s->rtol, "relative (and absolute) tolerance of the integrator")
        ->capture_default_str();
    sub->add_option("--method", s->method, "integrator: dop853 or dopri5")->capture_default_str();
    sub->add_option("--threads", s->threads, "OpenMP threads (0: all available)")
        ->capture_default_str();
    sub->add_option("--chaos-threshold", s->chaos_threshold,
                    "Lyapunov threshold for 'chaotic', in units of sqrt(alpha/A)")
        ->capture_default_str();
    sub->add_flag("--no-chaos", s->no_chaos,
                  "skip the variational equations (no chaotic/regular classification)");
    sub->add_option("--bins", s->bins, "histogram bins (0: square-root rule)")
        ->capture_default_str();
    sub->add_option("--sample-interval", s->sample_interval,
                    "store every trajectory's state at this time interval (needs --csv-dir)")
        ->capture_default_str();
    sub->add_option("--csv-dir", s->csv_dir,
                    "write per-trajectory rates, residence times and histograms as CSV here");
    add_model_options(*sub, s->model);
    sub->callback([s] { print(run(*s).dump(2) + "\n"); });
});

}  // namespace
}  // namespace flipflux::cli
