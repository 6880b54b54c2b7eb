// One trajectory with its flip events (include/flipflux/study/trajectory.hpp).
#include "flipflux/study/trajectory.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/study/criteria.hpp"

namespace flipflux {
namespace {

void check(const trajectory_request& q) {
    for (double x : q.state)
        if (!std::isfinite(x))
            throw input_error::about("state", "'" + to_decimal(x) + "' is not a finite number");
    if (!std::isfinite(q.time) || !(q.time > 0))
        throw input_error::about("time", "'" + to_decimal(q.time) + "' is invalid (must be > 0)");
    if (!std::isfinite(q.sample_interval) || q.sample_interval < 0)
        throw input_error::about(
            "sample_interval", "'" + to_decimal(q.sample_interval) + "' is invalid (must be >= 0)");
    if (q.sample_interval > 0 && q.time / q.sample_interval > 1e8)
        throw input_error::about("sample_interval", "'" + to_decimal(q.sample_interval) +
                                                        "' gives more than 1e8 samples");
    if (!(q.rtol > 0) || !(q.rtol <= 0.1))
        throw input_error::about("rtol",
                                 "'" + to_decimal(q.rtol) + "' is invalid (must be in (0, 0.1])");
    if (q.criteria.empty()) throw input_error::about("criteria", "no criterion given");
    for (std::size_t i = 0; i < q.criteria.size(); ++i) {
        check_criterion_name(q.criteria[i]);
        for (std::size_t j = 0; j < i; ++j)
            if (q.criteria[j] == q.criteria[i])
                throw input_error::about("criteria", "'" + q.criteria[i] + "' is given twice");
    }
    if (q.arms.empty()) throw input_error::about("arms", "no arm given");
    if (q.arms.size() == 2 && q.arms[0] == q.arms[1])
        throw input_error::about("arms", "arm " + to_string(q.arms[0]) + " is given twice");
}

}  // namespace

trajectory_record integrate_trajectory(const double_pendulum<double>& model,
                                       const trajectory_request& q) {
    check(q);
    trajectory_record out;
    out.energy = model.hamiltonian(q.state);
    // the criteria, arm 1 first; those that cannot flip at this energy are skipped
    struct detected {
        arm flip_arm;
        std::string name;
        ensemble_criterion criterion;
    };
    std::vector<detected> list;
    std::vector<arm> arms = q.arms;
    std::sort(arms.begin(), arms.end(),
              [](arm a, arm b) { return a == arm::one && b == arm::two; });
    for (const arm a : arms)
        for (const std::string& name : q.criteria) {
            const double threshold = criterion_threshold(model, a, name);
            if (!(out.energy > threshold)) {
                out.skipped.push_back(
                    "arm " + to_string(a) + " " + name + ": E = " + to_decimal(out.energy) +
                    " is at or below the arm's saddle energy " + to_decimal(threshold));
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
    o.chaos = false;
    o.keep_crossings = true;
    o.sample_interval = q.sample_interval > 0 ? q.sample_interval : q.time;
    o.unwrapped_angles = true;
    o.trajectories = 1;
    std::vector<std::unique_ptr<flip_detector_base>> owned;
    std::vector<flip_detector_base*> detectors;
    for (const detected& d : list) {
        owned.push_back(d.criterion.detector->clone());
        detectors.push_back(owned.back().get());
    }
    const trajectory_result r = simulate_trajectory(model, q.state, o, 0, detectors);
    out.status = r.status;
    out.steps = r.steps;
    out.rejected_steps = r.rejected_steps;
    out.max_energy_drift = r.max_energy_drift;
    if (r.status != rk_status::ok)
        throw std::runtime_error("trajectory: the integration failed at t = " +
                                 to_decimal(r.end_time) + " (" + to_string(r.status) + ")");
    // events in time order; for equal times arm 1 first, then the criteria's order (stable sort)
    for (std::size_t c = 0; c < list.size(); ++c)
        for (const crossing& x : r.crossings[c])
            out.events.push_back({x.time, list[c].flip_arm, list[c].name, x.direction});
    std::stable_sort(out.events.begin(), out.events.end(),
                     [](const flip_event& a, const flip_event& b) { return a.time < b.time; });
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
