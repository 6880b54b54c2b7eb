// flipflux trajectory --state TH1,TH2,L1,L2 --time T [--precision P] [--criteria ...]
// [--arm 1|2|both] [--events FILE] [--out FILE] [--sample-interval DT] [--rtol R] [--method M]
// [--route default|ensemble|reference]: one trajectory from a canonical state with its flip events
// (study/trajectory.hpp), for checking a simulator's integrator and flip detector. Events CSV:
// time,arm,criterion,direction (on stdout without
// --events); states CSV (--out): t,theta1,theta2,l1,l2,energy_drift at t = 0, every sample time
// and t = T, angles unwrapped. Files are written atomically, after the whole computation.
#include <algorithm>
#include <cstdio>
#include <string>
#include <type_traits>
#include <vector>

#include "common.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/settings.hpp"
#include "flipflux/study/simulation.hpp"
#include "flipflux/study/trajectory.hpp"
#include "flipflux/study/trajectory_files.hpp"

namespace flipflux::cli {
namespace {

struct trajectory_state {
    std::string state, time, criteria = criterion_name_list(","), arms = "both", events, out,
                             sample_interval = "0", rtol = "1e-12", method = "dop853",
                             route = "default", taylor_order = "0";
    model_options model;
    precision_option precision;
    time_bound_option bound;
};

template <class Real>
phase_point<Real> parse_state(const std::string& text) {
    phase_point<Real> x{};
    std::size_t pos = 0, i = 0;
    while (pos <= text.size()) {
        const std::size_t comma = std::min(text.find(',', pos), text.size());
        if (i == 4) break;
        const std::string item = text.substr(pos, comma - pos);
        if (i < 2) {  // angles: beyond 1e6 rad reduced exactly modulo 2 pi (docs/limits.md)
            x[i] = parse_angle<Real>(item, "--state");
            if (is_decimal_number(item) && decimal_agreement(item, "0") < -6)
                std::fprintf(
                    stderr,
                    "flipflux: note: --state: theta%zu = %s is reduced exactly modulo 2 pi "
                    "to %s\n",
                    i + 1, one_line(item).c_str(), to_decimal(x[i]).c_str());
            ++i;
        } else {
            x[i++] = parse_real<Real>(item, "--state");
        }
        pos = comma + 1;
    }
    if (i != 4 || pos <= text.size())
        throw input_error("--state: '" + text + "' is not four numbers TH1,TH2,L1,L2");
    return x;
}

// --taylor-order's text as an order (the study refuses one out of range or without taylor; a
// huge number stays out of range here)
int parse_taylor_order(const std::string& text, integration_method method, double rtol) {
    const int order = static_cast<int>(
        std::min<std::uint64_t>(parse_unsigned(text, "--taylor-order", false), 1u << 20));
    if (const std::string p = taylor_order_problem(order, method, rtol, text); !p.empty())
        throw input_error("--taylor-order: " + p);
    return order;
}

std::vector<arm> parse_arms(const std::string& text) {
    if (text == "both") return {arm::one, arm::two};
    return {parse_arm(text, "--arm")};
}

void write(const std::string& path, const std::string& text) {
    write_file_atomically(path, text);
}

template <class Real>
void run(const trajectory_state& s) {
    const double_pendulum<Real> model = make_model<Real>(s.model);
    trajectory_request<Real> q;
    q.state = parse_state<Real>(s.state);
    q.time = parse_real<Real>(s.time, "--time");
    q.criteria = parse_criterion_list(s.criteria, "--criteria");
    q.arms = parse_arms(s.arms);
    q.sample_interval = parse_real<Real>(s.sample_interval, "--sample-interval");
    q.rtol = parse_real<double>(s.rtol, "--rtol");
    q.method = resolved_method(parse_name<integration_method>(s.method, "--method"), q.rtol);
    q.taylor_order = parse_taylor_order(s.taylor_order, q.method, q.rtol);
    if (s.route != "default" && s.route != "ensemble" && s.route != "reference" &&
        s.route != "taylor")
        throw input_error("--route: '" + s.route +
                          "' is not a route (default, ensemble, reference, taylor)");
    if (s.route == "ensemble" && !std::is_same_v<Real, double>)
        throw input_error("--route: 'ensemble' integrates in double only (--precision double)");
    // the outputs before the integration (minutes at mp:N): refused first, with one line
    if (!s.out.empty()) check_output_file(s.out, "--out");
    if (!s.events.empty()) check_output_file(s.events, "--events");
    if (!s.out.empty() && !s.events.empty() && [](const std::string& a, const std::string& b) {
            namespace fs = std::filesystem;
            std::error_code ec;
            return fs::weakly_canonical(fs::absolute(a, ec), ec) ==
                   fs::weakly_canonical(fs::absolute(b, ec), ec);
        }(s.out, s.events))
        throw input_error("--events: '" + s.events + "' is also the --out file; give two files");
    const trajectory_record<Real> r = s.route == "reference" ? reference_trajectory(model, q)
                                      : s.route == "taylor"  ? taylor_trajectory(model, q)
                                                             : integrate_trajectory(model, q);
    for (const std::string& why : r.skipped)
        std::fprintf(stderr, "flipflux: note: no flips possible for %s\n", why.c_str());
    const std::string events = trajectory_events_csv(r);
    if (!s.out.empty()) write(s.out, trajectory_states_csv(r));
    if (s.events.empty())
        print(events);
    else
        write(s.events, events);
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<trajectory_state>();
    CLI::App* sub = app.add_subcommand(
        "trajectory",
        "Integrate one trajectory from a canonical state and list its flip events (time, arm, "
        "criterion, direction): the ensemble's integrator and detectors, for checking a "
        "simulator");
    sub->add_option("--state", s->state,
                    "initial state TH1,TH2,L1,L2: angles from the downward vertical, conjugate "
                    "momenta l = dL/d(theta dot)")
        ->required();
    sub->add_option("--time", s->time, "integration time T (> 0)")->required();
    sub->add_option("--criteria", s->criteria,
                    "comma-separated flip criteria: " + criterion_name_list())
        ->capture_default_str();
    sub->add_option("--arm", s->arms, "the arm whose flips are detected: 1, 2 or both")
        ->capture_default_str();
    sub->add_option("--events", s->events,
                    "write the events CSV (time,arm,criterion,direction) to FILE instead of "
                    "stdout");
    sub->add_option("--out", s->out,
                    "write the states CSV (t,theta1,theta2,l1,l2,energy_drift; angles unwrapped) "
                    "to FILE");
    sub->add_option("--sample-interval", s->sample_interval,
                    "state every DT in --out (0: only t = 0 and t = T)")
        ->capture_default_str();
    sub->add_option("--rtol", s->rtol,
                    "relative (and absolute) tolerance of the integrator at double (the same "
                    "integrator and detectors as simulate, whose default is 1e-10: one trajectory "
                    "compared event by event needs the tighter one, ensemble statistics do not)")
        ->capture_default_str();
    sub->add_option(
           "--method", s->method,
           "the ensemble route's integrator: dop853, dopri5, taylor (rtol down to eps) or auto "
           "(taylor below rtol 1e-10)")
        ->capture_default_str();
    sub->add_option("--taylor-order", s->taylor_order,
                    "the ensemble route's Taylor order (--method taylor, or auto below rtol "
                    "1e-10; 0: the order of least modelled cost at --rtol, docs/scale.md)")
        ->capture_default_str();
    add_model_options(*sub, s->model);
    add_precision_option(*sub, s->precision);
    add_time_bound_option(*sub, s->bound);
    sub->add_option("--route", s->route,
                    "default (double: the ensemble's; quad, mp:N: taylor), ensemble, reference "
                    "(Gauss-Legendre, events polished to full precision: the independent check "
                    "of taylor), or taylor (Taylor series, events on each step's polynomial; "
                    "much faster at many digits)")
        ->capture_default_str();
    sub->callback([s] {
        const precision p = parse_precision(s->precision.text);
        // no pilots (the run writes its files): the CPU budget alone bounds it
        bounded_dispatch(p, s->bound, false, [&]<class Real>() { run<Real>(*s); });
    });
});

}  // namespace
}  // namespace flipflux::cli
