// Reference trajectories in high precision (study/trajectory.hpp, `flipflux trajectory
// --precision mp:50`): over T = 40 from chaotic initial states at E ~ 3.8 and E ~ 5.0, the flip
// events (every criterion with a curve there: upright and approx; both arms where both flip) and
// the final state at mp:50 agree with mp:80 (another precision, hence other stage counts, steps
// and rounding) to >= 40 digits: the same events in the same order, their times and the state
// at T. Too slow for CI (about a minute in the release build): label "verify".
//
// And against an independent route (issue 15's target: ">= 40 digits against an independent
// high-precision route"): the Taylor-series integrator (integrators/taylor.hpp, with the
// recurrences of orbits/saddle_taylor.hpp: series arithmetic, written apart from the
// Gauss-Legendre route's right-hand side and its event location) in mp:80, with adaptive
// Jorba-Zou steps to tolerance 1e-80 landing exactly on each mp:50 event time: at every upright
// event the flip angle is pi (mod 2 pi) to within |theta'| 1e-40 max(t, 1) (the event time is
// right to 40 digits) and moves in the event's direction, and the mp:50 state at T = 40 agrees
// with the Taylor state to 40 digits. (The approximate criterion's events are located by the
// same code on the same dense output as the upright ones; their times are checked against mp:80
// above.)
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>

#include "flipflux/core/decimal.hpp"
#include "flipflux/integrators/taylor.hpp"
#include "flipflux/orbits/saddle_taylor.hpp"
#include "flipflux/study/trajectory.hpp"

namespace flipflux {
namespace {

struct text_record {
    std::vector<std::string> times, labels, final_state, arms, criteria, directions;
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
            t.arms.push_back(to_string(e.flip_arm));
            t.criteria.push_back(e.criterion);
            t.directions.push_back(std::to_string(e.direction));
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

// The Taylor route in Real from the decimal state: the state (theta1, theta2, l1, l2) at each of
// the increasing times, by Jorba-Zou steps (tolerance 10^-digits) cut to land on each time. The
// arm-2 saddle frame is only a shift of the angles (delta1 = theta1, delta2 = theta2 - pi), so
// its recurrences integrate any trajectory.
template <class Real>
std::vector<std::array<Real, 4>> taylor_states(const char* state, const std::vector<Real>& times,
                                               int digits) {
    const double_pendulum<Real> model;
    const saddle_frame<Real> frame(model, arm::two);
    const Real tol = pow(Real(10), -digits);
    const int order = taylor_order_for(tol);
    saddle_taylor_flow<Real, 0> f(frame, order);
    taylor_integrator<Real, 5> ti(order);
    std::array<Real, 5> x{};
    std::string s = state;
    for (std::size_t i = 0; i < 4; ++i) {
        const std::size_t comma = s.find(',');
        x[i] = parse_real<Real>(s.substr(0, comma), "state");
        s = comma == std::string::npos ? "" : s.substr(comma + 1);
    }
    x[1] -= pi<Real>();
    const std::array<Real, 5> scale{1, 1, 1, 1, 1};
    std::vector<std::array<Real, 4>> out;
    Real t = 0;
    for (const Real& target : times) {
        while (t < target) {
            if (!ti.expand(f, x)) throw std::runtime_error("Taylor expansion not finite");
            Real h = ti.step_size(tol, scale);
            if (t + h > target) h = target - t;
            if (!ti.step(f, x, h)) throw std::runtime_error("Taylor step failed");
            t += h;
        }
        out.push_back({x[0], x[1] + pi<Real>(), x[2], x[3]});
    }
    return out;
}

TEST(HighPrecisionTrajectory, Mp50AgreesWithAnIndependentTaylorRouteInMp80) {
    for (const char* state : {"0.8,2.6,0.3,1.566", "1.9,2.2,0.5,1.113"}) {
        const text_record a = run(50, state);
        const auto start = std::chrono::steady_clock::now();
        dispatch(mp_precision(80), [&]<class Real>() {
            std::vector<Real> times;
            std::vector<std::size_t> upright;
            for (std::size_t i = 0; i < a.times.size(); ++i) {
                if (a.criteria[i] != "upright") continue;
                upright.push_back(i);
                times.push_back(parse_real<Real>(a.times[i], "time"));
            }
            times.push_back(Real(40));
            ASSERT_GE(upright.size(), 2u) << state;
            const auto states = taylor_states<Real>(state, times, 80);
            const double_pendulum<Real> model;
            double worst_digits = 1e9;
            for (std::size_t j = 0; j < upright.size(); ++j) {
                const std::array<Real, 4>& y = states[j];
                const int k = a.arms[upright[j]] == "2" ? 1 : 0;
                const Real off = y[static_cast<std::size_t>(k)] - pi<Real>();
                const Real wrapped = off - 2 * pi<Real>() * round(off / (2 * pi<Real>()));
                const Real speed = model.rhs({y[0], y[1], y[2], y[3]})[static_cast<std::size_t>(k)];
                const Real t = times[j];
                // the time error the angle's offset means: |offset| / |theta'|
                const Real dt = abs(wrapped) / abs(speed);
                const double d = static_cast<double>(-log10(dt / (t > 1 ? t : Real(1))));
                worst_digits = std::min(worst_digits, d);
                EXPECT_GE(d, 40) << state << " event " << upright[j]
                                 << " t = " << a.times[upright[j]];
                EXPECT_EQ(a.directions[upright[j]], speed > 0 ? "1" : "-1")
                    << state << " t = " << a.times[upright[j]];
            }
            double state_digits = 1e9;
            for (std::size_t i = 0; i < 4; ++i)
                state_digits = std::min(
                    state_digits,
                    decimal_agreement(a.final_state[i], to_decimal(states.back()[i]), "state"));
            EXPECT_GE(state_digits, 40) << state;
            std::printf(
                "state %s, T = 40: %zu upright events: mp:50 event times against the Taylor route "
                "in mp:80: >= %.1f digits; final state %.1f digits (%.1f s)\n",
                state, upright.size(), worst_digits, state_digits,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
        });
    }
}

}  // namespace
}  // namespace flipflux
