// The request checks both trajectory routes share (study/trajectory.hpp); private to src/study.
#pragma once

#include <cmath>
#include <string>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/trajectory.hpp"

namespace flipflux::detail {

template <class Real>
void check_trajectory_request(const trajectory_request<Real>& q) {
    using std::isfinite;
    for (const Real& x : q.state)
        if (!isfinite(x))
            throw input_error::about("state",
                                     "'" + to_shortest_decimal(x) + "' is not a finite number");
    if (!isfinite(q.time) || !(q.time > 0))
        throw input_error::about("time",
                                 "'" + to_shortest_decimal(q.time) + "' is invalid (must be > 0)");
    if (!isfinite(q.sample_interval) || q.sample_interval < 0)
        throw input_error::about("sample_interval", "'" + to_shortest_decimal(q.sample_interval) +
                                                        "' is invalid (must be >= 0)");
    if (q.sample_interval > 0 && q.time / q.sample_interval > 1e8)
        throw input_error::about("sample_interval", "'" + to_shortest_decimal(q.sample_interval) +
                                                        "' gives more than 1e8 samples");
    if (!(q.rtol > 0) || !(q.rtol <= 0.1))
        throw input_error::about(
            "rtol", "'" + to_shortest_decimal(q.rtol) + "' is invalid (must be in (0, 0.1])");
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

/// Why criterion `name` of arm `a` cannot flip at `energy` (at or below the arm's saddle energy).
template <class Real>
std::string below_threshold(arm a, const std::string& name, const Real& energy,
                            const Real& threshold) {
    return "arm " + to_string(a) + " " + name + ": E = " + to_decimal(energy) +
           " is at or below the arm's saddle energy " + to_decimal(threshold);
}

/// The arms in the events' order: arm 1 first.
inline std::vector<arm> ordered_arms(std::vector<arm> arms) {
    std::sort(arms.begin(), arms.end(),
              [](arm a, arm b) { return a == arm::one && b == arm::two; });
    return arms;
}

}  // namespace flipflux::detail
