// The files of one trajectory (study/trajectory.hpp), as `flipflux trajectory` and a scene's
// [[trajectory]] write them, every number with all the digits of its precision:
//   events CSV: time,arm,criterion,direction (direction +1: the flip angle increases through the
//               criterion's curve), in time order;
//   states CSV: t,theta1,theta2,l1,l2,energy_drift at t = 0, every sample time and t = T, the
//               angles unwrapped, energy_drift = H(x(t)) - H(x0).
#pragma once

#include <string>

#include "flipflux/core/decimal.hpp"
#include "flipflux/study/trajectory.hpp"

namespace flipflux {

template <class Real>
std::string trajectory_events_csv(const trajectory_record<Real>& r) {
    std::string s = "time,arm,criterion,direction\n";
    for (const flip_event<Real>& e : r.events)
        s += to_decimal(e.time) + "," + to_string(e.flip_arm) + "," + e.criterion + "," +
             (e.direction > 0 ? "1" : "-1") + "\n";
    return s;
}

template <class Real>
std::string trajectory_states_csv(const trajectory_record<Real>& r) {
    std::string s = "t,theta1,theta2,l1,l2,energy_drift\n";
    for (const auto& x : r.states) {
        for (std::size_t i = 0; i < x.size(); ++i)
            s += (i ? "," : "") + to_decimal(x[i]);
        s += "\n";
    }
    return s;
}

}  // namespace flipflux
