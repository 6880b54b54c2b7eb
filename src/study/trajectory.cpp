// One trajectory with its flip events by the ensemble's route (include/flipflux/study/
// trajectory.hpp).
#include "flipflux/study/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/ensemble/taylor_ensemble.hpp"
#include "flipflux/study/criteria.hpp"
#include "trajectory_checks.hpp"

namespace flipflux {

void check_trajectory_request(const trajectory_request<double>& q) {
    detail::check_trajectory_request(q);
}

trajectory_record<double> ensemble_trajectory(const double_pendulum<double>& model,
                                              const trajectory_request<double>& q) {
    detail::check_trajectory_request(q);
    if (const std::string p = rtol_problem(q.rtol, "", q.method); !p.empty())
        throw input_error::about("rtol", p);
    if (const std::string p = taylor_order_problem(q.taylor_order, q.method, q.rtol); !p.empty())
        throw input_error::about("taylor_order", p);
    trajectory_record<double> out;
    out.energy = model.hamiltonian(q.state);
    check_trajectory_work(model, out.energy, q.time, "time");
    // the criteria, arm 1 first; those that cannot flip at this energy are skipped
    struct detected {
        arm flip_arm;
        std::string name;
        ensemble_criterion criterion;
    };
    std::vector<detected> list;
    for (const arm a : detail::ordered_arms(q.arms))
        for (const std::string& name : q.criteria) {
            const double threshold = criterion_threshold(model, a, name);
            if (!(out.energy > threshold)) {
                out.skipped.push_back(detail::below_threshold(a, name, out.energy, threshold));
                continue;
            }
            try {
                list.push_back({a, name, make_criterion(model, a, name, out.energy)});
            } catch (const input_error& e) {
                out.skipped.push_back("arm " + to_string(a) + " " + name + ": " + e.detail());
            }
        }
    ensemble_options o;
    o.energy = out.energy;
    o.time = q.time;
    o.rtol = q.rtol;
    o.atol = q.rtol;
    o.method = q.method;
    o.taylor_order = q.taylor_order;
    o.chaos = false;
    o.keep_crossings = true;
    o.sample_interval = q.sample_interval > 0 ? q.sample_interval : q.time;
    o.unwrapped_angles = true;
    o.trajectories = 1;
    const integration_method method = resolved_method(q.method, q.rtol);
    out.route = "ensemble (" + to_string(method) +
                (method == integration_method::taylor
                     ? ", order " + std::to_string(ensemble_taylor_order(o))
                     : std::string()) +
                ", rtol " + to_decimal(q.rtol) + ")";
    std::vector<std::unique_ptr<flip_detector_base>> owned;
    std::vector<flip_detector_base*> detectors;
    for (const detected& d : list) {
        owned.push_back(d.criterion.detector->clone());
        detectors.push_back(owned.back().get());
    }
    const trajectory_result r = simulate_trajectory(model, q.state, o, 0, detectors);
    out.steps = r.steps;
    out.max_energy_drift = r.max_energy_drift;
    if (r.status != rk_status::ok)
        throw std::runtime_error("trajectory: the integration failed at t = " +
                                 to_decimal(r.end_time) + " (" + to_string(r.status) + ")");
    // events in time order; for equal times arm 1 first, then the criteria's order (stable sort)
    for (std::size_t c = 0; c < list.size(); ++c)
        for (const crossing& x : r.crossings[c])
            out.events.push_back({x.time, list[c].flip_arm, list[c].name, x.direction});
    std::stable_sort(
        out.events.begin(), out.events.end(),
        [](const flip_event<double>& a, const flip_event<double>& b) { return a.time < b.time; });
    // the states: the samples (t = 0 and every interval) and t = T unless it was sampled
    const pendulum_flow flow(model);
    const double h0 = flow.hamiltonian_absolute(q.state);
    auto add = [&](double t, const phase_point<double>& x) {
        out.states.push_back({t, x[0], x[1], x[2], x[3], flow.hamiltonian_absolute(x) - h0});
    };
    for (const auto& s : r.samples)
        add(s[0], {s[1], s[2], s[3], s[4]});
    if (out.states.empty() || out.states.back()[0] != r.end_time) add(r.end_time, r.final_state);
    return out;
}

}  // namespace flipflux
