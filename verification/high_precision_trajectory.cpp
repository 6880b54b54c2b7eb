// Reference trajectories in high precision (study/trajectory.hpp, `flipflux trajectory
// --precision mp:50`): over T = 40 from chaotic initial states at E ~ 3.8 and E ~ 5.0, the flip
// events (every criterion with a curve there: upright and approx; both arms where both flip) and
// the final state at mp:50 agree with mp:80 (another precision, hence other stage counts, steps
// and rounding) to >= 40 digits: the same events in the same order, their times and the state
// at T. Too slow for CI (about a minute in the release build): label "verify".
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "flipflux/core/decimal.hpp"
#include "flipflux/study/trajectory.hpp"

namespace flipflux {
namespace {

struct text_record {
    std::vector<std::string> times, labels, final_state;
    double seconds = 0;
    std::string route;
};

text_record run(int digits, const char* state) {
    return dispatch(mp_precision(digits), [&]<class Real>() {
        trajectory_request<Real> q;
        std::string s = state;
        for (int i = 0; i < 4; ++i) {
            const std::size_t comma = s.find(',');
            q.state[static_cast<std::size_t>(i)] = parse_real<Real>(s.substr(0, comma), "state");
            s = comma == std::string::npos ? "" : s.substr(comma + 1);
        }
        q.time = 40;
        q.criteria = {"upright", "approx"};
        q.arms = {arm::one, arm::two};
        const auto start = std::chrono::steady_clock::now();
        const trajectory_record<Real> r = reference_trajectory(double_pendulum<Real>(), q);
        text_record t;
        t.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        t.route = r.route;
        for (const auto& e : r.events) {
            t.times.push_back(to_decimal(e.time));
            t.labels.push_back(to_string(e.flip_arm) + e.criterion + std::to_string(e.direction));
        }
        for (int i = 1; i <= 4; ++i)
            t.final_state.push_back(to_decimal(r.states.back()[static_cast<std::size_t>(i)]));
        return t;
    });
}

TEST(HighPrecisionTrajectory, EventsAndFinalStateAtMp50AgreeWithMp80) {
    for (const char* state : {"0.8,2.6,0.3,1.566", "1.9,2.2,0.5,1.113"}) {
        const text_record a = run(50, state), b = run(80, state);
        ASSERT_EQ(a.labels, b.labels) << state;
        ASSERT_GE(a.times.size(), 4u) << state;
        double digits = 1e9, state_digits = 1e9;  // the fewest agreeing digits
        for (std::size_t i = 0; i < a.times.size(); ++i)
            digits = std::min(digits, decimal_agreement(a.times[i], b.times[i], "time"));
        for (std::size_t i = 0; i < 4; ++i)
            state_digits =
                std::min(state_digits, decimal_agreement(a.final_state[i], b.final_state[i], "x"));
        std::printf(
            "state %s, T = 40: %zu events; mp:50 against mp:80: event times %.1f digits, "
            "final state %.1f digits (%.1f s at mp:50: %s; %.1f s at mp:80)\n",
            state, a.times.size(), digits, state_digits, a.seconds, a.route.c_str(), b.seconds);
        EXPECT_GE(digits, 40) << state;
        EXPECT_GE(state_digits, 40) << state;
    }
}

}  // namespace
}  // namespace flipflux
