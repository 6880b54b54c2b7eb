// One trajectory with its flip events (study/trajectory.hpp, `flipflux trajectory`): the events
// lie on their criterion's curve and have the right direction, checked by an independent route
// (the symplectic Gauss-Legendre integrator in quad precision); every crossing on a fine quad
// grid is reported once; a grazing flip (two crossings close in time) is found as two events;
// bad input is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <sstream>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/ensemble/taylor_ensemble.hpp"
#include "flipflux/integrators/gauss_legendre.hpp"
#include "flipflux/study/trajectory.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

constexpr double pi = std::numbers::pi;

struct quad_flow {
    const double_pendulum<quad>* m;
    void operator()(const std::array<quad, 4>& x, std::array<quad, 4>& dx) const { dx = m->rhs(x); }
};

/// The state at time t from x0 by 16-stage Gauss-Legendre (order 32) in quad with steps <= 1/32:
/// 30 digits over the short times used here, independent of the double integrator under test.
std::array<quad, 4> quad_state(const phase_point<double>& x0, double t) {
    static const double_pendulum<quad> m;
    std::array<quad, 4> x{x0[0], x0[1], x0[2], x0[3]};
    const long n = std::max(1L, static_cast<long>(std::ceil(t * 32)));
    gauss_legendre<quad, 4> gl(16);
    gl.integrate(quad_flow{&m}, x, quad(t) / n, n);
    return x;
}

/// Distance of an angle from pi modulo 2 pi.
double from_upright(quad th) {
    const quad k = boost::multiprecision::round((th - boost::math::constants::pi<quad>()) /
                                                (2 * boost::math::constants::pi<quad>()));
    return static_cast<double>(th - boost::math::constants::pi<quad>() -
                               2 * k * boost::math::constants::pi<quad>());
}

// Every upright event of both arms: the flip angle is pi (mod 2 pi) there, to the accuracy the
// double trajectory has at that time, and it moves in the event's direction. The tolerance is
// derived, not chosen: e(t), the measured distance of the double trajectory's state at the event
// from the quad one (it grows with the Lyapunov exponent), bounds the angle's error, and an event
// time located to a few ulp adds |theta'| * 8 ulp(t).
TEST(Trajectory, EventsLieOnTheCurveByAnIndependentRoute) {
    const double_pendulum<double> m;
    for (const phase_point<double> x0 :
         {phase_point<double>{0.3, 2.9, 0.5, 0.8}, phase_point<double>{2.5, 3.0, 1.2, 1.0},
          phase_point<double>{2.2, -2.5, 0.5, 1.1}}) {
        trajectory_request<double> q;
        q.state = x0;
        q.time = 12;
        q.criteria = {"upright"};
        q.arms = {arm::one, arm::two};
        const trajectory_record<double> r = integrate_trajectory(m, q);
        ASSERT_GE(r.events.size(), 2u) << "E = " << r.energy;
        for (std::size_t i = 1; i < r.events.size(); ++i)
            EXPECT_LE(r.events[i - 1].time, r.events[i].time);
        for (const flip_event<double>& e : r.events) {
            const std::array<quad, 4> exact = quad_state(x0, e.time);
            trajectory_request<double> to = q;
            to.time = e.time;
            const trajectory_record<double> at = integrate_trajectory(m, to);
            const auto& last = at.states.back();
            double err = 0;
            for (int k = 0; k < 4; ++k)
                err = std::max(err, std::abs(last[1 + k] - static_cast<double>(exact[k])));
            const int flip = e.flip_arm == arm::two ? 1 : 0;
            const std::array<quad, 4> rate = double_pendulum<quad>().rhs(exact);
            const double speed = std::abs(static_cast<double>(rate[flip]));
            const double tol =
                4 * err + speed * 8 * std::numeric_limits<double>::epsilon() * e.time + 1e-15;
            std::printf("arm %s t = %.6f residual %.2e err %.2e tol %.2e\n",
                        to_string(e.flip_arm).c_str(), e.time, std::abs(from_upright(exact[flip])),
                        err, tol);
            EXPECT_LE(std::abs(from_upright(exact[flip])), tol)
                << "arm " << to_string(e.flip_arm) << " t = " << e.time << " err " << err;
            EXPECT_EQ(e.direction, rate[flip] > 0 ? 1 : -1) << "t = " << e.time;
        }
    }
}

// Every upright crossing of arm 2 on a fine grid of the quad trajectory (the flip angle's
// 2 pi-period level changes between grid points) is one event, none missing, none twice.
TEST(Trajectory, EveryCrossingIsReportedOnce) {
    const double_pendulum<double> m;
    const phase_point<double> x0{0.0, 3.0, 0.0, 1.0};
    trajectory_request<double> q;
    q.state = x0;
    q.time = 10;
    q.criteria = {"upright"};
    q.arms = {arm::two};
    const trajectory_record<double> r = integrate_trajectory(m, q);
    const double_pendulum<quad> mq;
    std::array<quad, 4> x{x0[0], x0[1], x0[2], x0[3]};
    gauss_legendre<quad, 4> gl(12);
    auto level = [](quad th) {
        return static_cast<long>(boost::multiprecision::floor(
            (th - boost::math::constants::pi<quad>()) / (2 * boost::math::constants::pi<quad>())));
    };
    long crossings = 0, previous = level(x[1]);
    const long n = 2000;  // h = 1/200: the angle moves < 0.05 per step, no double crossing
    for (long k = 0; k < n; ++k) {
        gl.integrate(quad_flow{&mq}, x, quad(q.time) / n, 1);
        const long now = level(x[1]);
        crossings += std::abs(now - previous);
        previous = now;
    }
    EXPECT_GT(crossings, 0);
    std::printf("%ld crossings on the quad grid, %zu events\n", crossings, r.events.size());
    EXPECT_EQ(static_cast<long>(r.events.size()), crossings);
}

// A state on the curve at t = 0 (theta2 equal to the working precision's pi) is not a crossing in
// either direction, by every route: crossings are counted in (0, T]. Before, the ensemble route
// reported a flip at t = 0 and the reference and Taylor routes one at t = -1e-35 (quad) when the
// arm left the curve downwards, and none when it left upwards. A state a little off the curve
// still has its crossing, at t = delta / |theta2'| to first order, after the start.
template <class Real, class Route>
void check_start_on_the_curve(Route route, const char* name) {
    const double_pendulum<Real> m;
    const Real pi_r = boost::math::constants::pi<Real>();
    const Real delta = Real(1) / 1000000;
    for (const double l2 : {-0.5, 0.5}) {
        trajectory_request<Real> q;
        q.time = 1;
        q.criteria = {"upright"};
        q.arms = {arm::two};
        q.state = {Real(3) / 10, pi_r, Real(0), Real(l2)};
        EXPECT_TRUE(route(m, q).events.empty()) << name << " l2 = " << l2;
        // off the curve by delta on the side the arm leaves from: one crossing, towards pi
        q.state[1] = l2 < 0 ? pi_r + delta : pi_r - delta;
        const trajectory_record<Real> r = route(m, q);
        ASSERT_EQ(r.events.size(), 1u) << name << " l2 = " << l2;
        const double speed = std::abs(static_cast<double>(m.rhs(q.state)[1]));
        const double t = static_cast<double>(r.events[0].time);
        EXPECT_EQ(r.events[0].direction, l2 < 0 ? -1 : 1) << name;
        // theta2' changes by O(t) over the step to the crossing: a relative 1e-5 covers it
        EXPECT_NEAR(t, 1e-6 / speed, 1e-5 * 1e-6 / speed) << name << " l2 = " << l2;
    }
}

TEST(Trajectory, AStateOnTheCurveAtTheStartIsNotACrossing) {
    check_start_on_the_curve<double>(
        [](const auto& m, const auto& q) { return integrate_trajectory(m, q); }, "ensemble");
    check_start_on_the_curve<double>(
        [](const auto& m, const auto& q) { return reference_trajectory(m, q); }, "reference");
    check_start_on_the_curve<quad>(
        [](const auto& m, const auto& q) { return reference_trajectory(m, q); }, "quad reference");
    check_start_on_the_curve<quad>(
        [](const auto& m, const auto& q) { return taylor_trajectory(m, q); }, "quad taylor");
}

// A grazing flip: arm 2 rises towards upright and falls back. Bisection on the initial momentum
// l2 finds where the number of upright events in a short time changes from 0 to 2; just beyond
// it the two events are close in time, opposite in direction, and both on the curve.
TEST(Trajectory, GrazingFlipIsTwoEvents) {
    const double_pendulum<double> m;
    auto events = [&](double l2) {
        trajectory_request<double> q;
        q.state = {0.3, 2.6, 0.0, l2};
        q.time = 2.5;
        q.criteria = {"upright"};
        q.arms = {arm::two};
        return integrate_trajectory(m, q).events;
    };
    double lo = 0.0, hi = 1.5;  // lo: no flip; hi: at least one
    ASSERT_TRUE(events(lo).empty());
    ASSERT_FALSE(events(hi).empty());
    for (int i = 0; i < 60 && hi - lo > 1e-12; ++i) {
        const double mid = (lo + hi) / 2;
        (events(mid).empty() ? lo : hi) = mid;
    }
    const auto e = events(hi);
    ASSERT_EQ(e.size(), 2u) << "l2 = " << hi;
    std::printf("grazing: l2 = %.17g, events at %.17g and %.17g (gap %.3g)\n", hi, e[0].time,
                e[1].time, e[1].time - e[0].time);
    EXPECT_EQ(e[0].direction, 1);
    EXPECT_EQ(e[1].direction, -1);
    EXPECT_LT(e[1].time - e[0].time, 0.05);
    for (const flip_event<double>& x : e) {
        const std::array<quad, 4> exact = quad_state({0.3, 2.6, 0.0, hi}, x.time);
        EXPECT_LE(std::abs(from_upright(exact[1])), 1e-9) << x.time;
    }
}

// Grazes closer than the working precision can resolve (found by an independent cross-check,
// 2026-11-30: the reference route at double threw "a refining step did not converge" or reported
// one crossing of the pair). The states come from an independent route (a 100-digit Taylor
// integration in mpmath, backwards from a state where arm 2's angle has its extremum pi + delta,
// angular velocity 0, at t = 2), for delta = 1e-18, 1e-25, 1e-35. The crossings are then at
// 2 -+ d with d = sqrt(2 delta / kappa) (kappa the angle's curvature there: a parabola). Checked:
//   - double, both high-precision routes, T = 2.5, 3, 4: no error, an even number of upright events
//   (0 or 2:
//     a graze below the precision may or may not cross), each within 1e-7 (about the square root
//     of epsilon) of t = 2;
//   - quad, reference route, delta = 1e-18 and 1e-25: two events, up then down, their midpoint
//     within delta + 1e-20 of 2 (the time of the extremum by construction; the curve's cubic term
//     moves the midpoint by O(d^2) = O(delta): measured 0.3 delta);
//   - mp:40, Taylor route, every delta: two events, midpoint within delta + 1e-30 of 2, and
//     d / sqrt(delta) the same for the three deltas to 1e-6 (the parabola's law, an independent
//     check of d).
TEST(Trajectory, GrazesBelowThePrecisionGiveEvenCounts) {
    const char* states[3][4] = {{"-1.705058285280586323415314195069738546352723660726364731",
                                 "0.9791784635827180592550793771130652433290531052105214763",
                                 "-0.3635552282077075447117598690030461928078397727210428431",
                                 "0.9643564339157965975695871618300611081595955102024745197"},
                                {"-1.705058285280586323032757703761515286376030154240826956",
                                 "0.9791784635827180500099594515981089043428941458364024870",
                                 "-0.3635552282077075547194778340862319619257396658448506258",
                                 "0.9643564339157966087751650063150864188563892796580148236"},
                                {"-1.705058285280586323032757665505862333813969631493779021",
                                 "0.9791784635827180500099585270860239940899732013870639058",
                                 "-0.3635552282077075547194788348581284473567845359705907845",
                                 "0.9643564339157966087751661268729828110927789725470795148"}};
    const double deltas[3] = {1e-18, 1e-25, 1e-35};
    auto run = [&]<class Real>(int which, bool taylor, double time = 4) {
        trajectory_request<Real> q;
        for (int i = 0; i < 4; ++i)
            q.state[static_cast<std::size_t>(i)] = parse_real<Real>(states[which][i], "state");
        q.time = time;
        q.criteria = {"upright"};
        q.arms = {arm::two};
        const double_pendulum<Real> m;
        return taylor ? taylor_trajectory(m, q) : reference_trajectory(m, q);
    };
    for (int which = 0; which < 3; ++which)
        for (const bool taylor : {false, true})
            for (const double time : {2.5, 3.0, 4.0}) {  // other steps, other roundings
                const auto r = run.template operator()<double>(which, taylor, time);
                EXPECT_EQ(r.events.size() % 2, 0u)
                    << deltas[which] << (taylor ? " taylor" : "") << ", T = " << time;
                for (const auto& e : r.events)
                    EXPECT_LE(std::abs(e.time - 2), 1e-7) << deltas[which];
            }
    // the pair's half gap d, after checking two events, up then down, their midpoint within
    // delta + tol of t = 2 (NaN when the count is not two)
    auto pair_gap = [&](const auto& r, int which, double tol) {
        EXPECT_EQ(r.events.size(), 2u) << deltas[which];
        if (r.events.size() != 2) return std::nan("");
        EXPECT_EQ(r.events[0].direction, 1);
        EXPECT_EQ(r.events[1].direction, -1);
        EXPECT_LE(static_cast<double>(abs((r.events[0].time + r.events[1].time) / 2 - 2)),
                  deltas[which] + tol);
        return static_cast<double>(r.events[1].time - r.events[0].time) / 2;
    };
    for (int which = 0; which < 2; ++which)
        pair_gap(run.template operator()<quad>(which, false), which, 1e-20);
    double law = 0;
    dispatch(parse_precision("mp:40"), [&]<class Real>() {
        for (int which = 0; which < 3; ++which) {
            const double d = pair_gap(run.template operator()<Real>(which, true), which, 1e-30);
            const double ratio = d / std::sqrt(deltas[which]);
            if (which == 0) law = ratio;
            EXPECT_NEAR(ratio, law, 1e-6 * law) << deltas[which];
        }
    });
}

// The states: t = 0 is the initial state, t = T is last, angles are unwrapped (continuous), the
// drift column is small; a criterion that cannot flip at the energy is listed, not an error.
TEST(Trajectory, StatesAreUnwrappedAndCriteriaBelowTheirThresholdAreSkipped) {
    const double_pendulum<double> m;
    trajectory_request<double> q;
    q.state = {0.3, 2.9, 0.5, 0.8};  // E ~ 2.94: arm 1 cannot flip
    q.time = 10;
    q.sample_interval = 0.01;
    q.criteria = {"upright", "saddle"};
    q.arms = {arm::one, arm::two};
    const trajectory_record<double> r = integrate_trajectory(m, q);
    ASSERT_EQ(r.skipped.size(), 2u);
    EXPECT_NE(r.skipped[0].find("arm 1 upright"), std::string::npos) << r.skipped[0];
    EXPECT_EQ(r.states.front()[0], 0.0);
    EXPECT_EQ(r.states.front()[2], 2.9);
    EXPECT_EQ(r.states.back()[0], 10.0);
    ASSERT_EQ(r.states.size(), 1001u);
    for (std::size_t i = 1; i < r.states.size(); ++i) {
        EXPECT_LT(std::abs(r.states[i][2] - r.states[i - 1][2]), 0.5) << r.states[i][0];
        EXPECT_LT(std::abs(r.states[i][5]), 1e-9);
    }
    // arm 2 flips: its angle leaves [-pi, pi] unwrapped
    double widest = 0;
    for (const auto& s : r.states)
        widest = std::max(widest, std::abs(s[2]));
    EXPECT_GT(widest, pi);
    EXPECT_GT(r.events.size(), 0u);
    // bad input names the field
    trajectory_request<double> bad = q;
    bad.state[2] = std::numeric_limits<double>::infinity();
    EXPECT_THROW(integrate_trajectory(m, bad), input_error);
    bad = q;
    bad.time = -1;
    EXPECT_THROW(integrate_trajectory(m, bad), input_error);
    bad = q;
    bad.criteria = {"upright", "upright"};
    EXPECT_THROW(integrate_trajectory(m, bad), input_error);
}

// The reference route (Gauss-Legendre, events polished by Newton with exact-length steps) in two
// precisions: quad and mp:20 (about 30 working digits) give the same events, their times agreeing
// to within the coarser one's epsilon times the growth of errors along the trajectory (bounded by
// e^(lambda T) <= 1e3 for T = 5 and lambda <= 1.4, the largest finite-time exponent seen).
TEST(Trajectory, ReferenceRouteAgreesAcrossPrecisions) {
    const char* state[] = {"2.5", "3.0", "1.2", "1.0"};
    auto run = [&](const precision& p) {
        return dispatch(p, [&]<class Real>() {
            trajectory_request<Real> q;
            for (int i = 0; i < 4; ++i)
                q.state[static_cast<std::size_t>(i)] = parse_real<Real>(state[i], "state");
            q.time = 5;
            q.criteria = {"upright", "approx"};
            q.arms = {arm::one, arm::two};
            const trajectory_record<Real> r = reference_trajectory(double_pendulum<Real>(), q);
            std::vector<std::pair<std::string, std::string>> out;
            for (const auto& e : r.events)
                out.emplace_back(to_string(e.flip_arm) + e.criterion + std::to_string(e.direction),
                                 to_decimal(e.time));
            out.emplace_back("theta2(T)", to_decimal(r.states.back()[2]));
            return out;
        });
    };
    const auto a = run(parse_precision("quad")), b = run(parse_precision("mp:20"));
    ASSERT_EQ(a.size(), b.size());
    ASSERT_GE(a.size(), 6u);  // 5 events and the final angle
    const double eps20 =
        std::pow(10.0, -static_cast<double>(decimal_digits(parse_precision("mp:20"))));
    for (std::size_t i = 0; i < a.size(); ++i) {
        EXPECT_EQ(a[i].first, b[i].first) << i;
        EXPECT_LE(decimal_relative_error(a[i].second, b[i].second, "t"), 1e3 * eps20)
            << a[i].first << ": " << a[i].second << " vs " << b[i].second;
    }
}

// The Taylor route (Taylor series, events on each step's polynomial) against the Gauss-Legendre
// reference route, both in quad, from a chaotic state over T = 3 with every curve criterion
// (upright and approx, both arms; 4 events, a pair 5.5e-3 apart): two integrators that share only
// the event-location code give the same events, times and final state within quad's epsilon
// times the growth of errors (e^(lambda T) <= 1e3 for T <= 5, lambda <= 1.4, as above) times
// |x| <= 10. (T = 3 keeps it cheap at -O0: the Gauss-Legendre side dominates.)
TEST(Trajectory, TaylorRouteAgreesWithTheGaussLegendreRoute) {
    const double_pendulum<quad> m;
    trajectory_request<quad> q;
    q.state = {quad(2.5), quad(3), quad("1.2"), quad(1)};
    q.time = 3;
    q.criteria = {"upright", "approx"};
    q.arms = {arm::one, arm::two};
    const trajectory_record<quad> a = taylor_trajectory(m, q), b = reference_trajectory(m, q);
    ASSERT_EQ(a.events.size(), b.events.size());
    ASSERT_EQ(a.events.size(), 4u);
    const double tol = 1e3 * 10 * static_cast<double>(std::numeric_limits<quad>::epsilon());
    for (std::size_t i = 0; i < a.events.size(); ++i) {
        EXPECT_EQ(a.events[i].flip_arm, b.events[i].flip_arm) << i;
        EXPECT_EQ(a.events[i].criterion, b.events[i].criterion) << i;
        EXPECT_EQ(a.events[i].direction, b.events[i].direction) << i;
        EXPECT_LE(static_cast<double>(abs(a.events[i].time - b.events[i].time)), tol) << i;
    }
    for (std::size_t k = 1; k <= 4; ++k)
        EXPECT_LE(static_cast<double>(abs(a.states.back()[k] - b.states.back()[k])), tol) << k;
    EXPECT_NE(a.route.find("taylor"), std::string::npos) << a.route;
    EXPECT_LE(static_cast<double>(a.max_energy_drift), tol);
    // the default route at quad (issue 42): the Taylor one, Gauss-Legendre its independent check
    const trajectory_record<quad> d = integrate_trajectory(m, q);
    EXPECT_EQ(d.route, a.route);
    ASSERT_EQ(d.events.size(), a.events.size());
    EXPECT_EQ(d.events.back().time, a.events.back().time);
}

// The ensemble route (double) against the reference route (quad): the same events, each time
// within what the double trajectory's own error allows there (its state error against the quad
// one divided by the crossing speed, as in EventsLieOnTheCurveByAnIndependentRoute).
TEST(Trajectory, EnsembleRouteAgreesWithTheReferenceRoute) {
    const double_pendulum<double> m;
    const double_pendulum<quad> mq;
    trajectory_request<double> q;
    q.state = {2.5, 3.0, 1.2, 1.0};
    q.time = 8;
    q.criteria = {"upright", "approx"};
    q.arms = {arm::one, arm::two};
    trajectory_request<quad> qq;
    qq.state = {2.5, 3.0, 1.2, 1.0};
    qq.time = 8;
    qq.criteria = q.criteria;
    qq.arms = q.arms;
    const trajectory_record<double> r = ensemble_trajectory(m, q);
    const trajectory_record<quad> ref = reference_trajectory(mq, qq);
    ASSERT_EQ(r.events.size(), ref.events.size());
    for (std::size_t i = 0; i < r.events.size(); ++i) {
        const flip_event<double>& e = r.events[i];
        EXPECT_EQ(e.flip_arm, ref.events[i].flip_arm) << i;
        EXPECT_EQ(e.criterion, ref.events[i].criterion) << i;
        EXPECT_EQ(e.direction, ref.events[i].direction) << i;
        const std::array<quad, 4> exact = quad_state(q.state, e.time);
        trajectory_request<double> to = q;
        to.time = e.time;
        const trajectory_record<double> at = ensemble_trajectory(m, to);
        const auto& last = at.states.back();
        double err = 0;
        for (int k = 0; k < 4; ++k)
            err = std::max(err, std::abs(last[1 + k] - static_cast<double>(exact[k])));
        const std::array<quad, 4> rate = mq.rhs(exact);
        const int flip = e.flip_arm == arm::two ? 1 : 0;
        const double speed = std::abs(static_cast<double>(rate[flip]));
        EXPECT_LE(std::abs(e.time - static_cast<double>(ref.events[i].time)),
                  8 * err / speed + 16 * std::numeric_limits<double>::epsilon() * e.time)
            << e.criterion << " arm " << to_string(e.flip_arm) << " t = " << e.time;
    }
}

// The ensemble route's Taylor order: the automatic one (ensemble_taylor_order) or the one asked
// for, named in the route; either way the state at T = 2 is the quad reference route's to the
// tolerance's order (1e-12 asked; 1e-10 allowed over the two time units).
TEST(Trajectory, EnsembleRouteNamesTheTaylorOrderItUses) {
    const double_pendulum<double> m;
    trajectory_request<double> q;
    q.state = {0.4, 2.8, 0.9, 1.0};
    q.time = 2;
    q.criteria = {"upright"};
    q.arms = {arm::two};
    q.rtol = 1e-12;
    q.method = integration_method::taylor;
    const std::array<quad, 4> exact = quad_state(q.state, 2.0);
    for (const int order : {0, 8}) {
        q.taylor_order = order;
        const trajectory_record<double> r = ensemble_trajectory(m, q);
        const int used = order > 0 ? order : ensemble_taylor_order(q.rtol, false);
        EXPECT_EQ(r.route, "ensemble (taylor, order " + std::to_string(used) + ", rtol " +
                               to_decimal(q.rtol) + ")");
        for (int k = 0; k < 4; ++k)
            EXPECT_NEAR(r.states.back()[1 + k], static_cast<double>(exact[k]), 1e-10)
                << "order " << used << " component " << k;
    }
    q.taylor_order = 1;
    EXPECT_THROW(ensemble_trajectory(m, q), input_error);
    q.taylor_order = 12;
    q.method = integration_method::dop853;
    EXPECT_THROW(ensemble_trajectory(m, q), input_error);
}

TEST(CliTrajectory, WritesEventsAndStatesAndRefusesBadInput) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::path(::testing::TempDir()) / "flipflux_trajectory_cli";
    fs::create_directories(dir);
    const auto ok = run_flipflux(
        "trajectory --state 0.3,2.9,0.5,0.8 --time 10 --arm 2 "
        "--criteria upright --sample-interval 1 --out " +
        (dir / "s.csv").string());
    ASSERT_EQ(ok.status, 0) << ok.err;
    EXPECT_EQ(ok.out.rfind("time,arm,criterion,direction\n", 0), 0u) << ok.out;
    const std::string states = read_text(dir / "s.csv");
    EXPECT_EQ(
        states.rfind("t,theta1,theta2,l1,l2,energy_drift\n0,0.29999999999999999,2.8999999999999999",
                     0),
        0u)
        << states;
    EXPECT_NE(ok.out.find(",2,upright,"), std::string::npos) << ok.out;
    std::istringstream lines(states);
    std::string line;
    int rows = 0;
    while (std::getline(lines, line)) {
        EXPECT_EQ(std::count(line.begin(), line.end(), ','), 5) << line;
        ++rows;
    }
    EXPECT_EQ(rows, 12);  // header, t = 0, 1, ..., 10
    for (const std::string bad :
         {"--state 0.4,2.8,0.9 --time 10", "--state 0.4,2.8,0.9,nan --time 10",
          "--state 0.4,2.8,0.9,x --time 10", "--state 0.4,2.8,0.9,1,2 --time 10",
          "--state 0.4,2.8,0.9,1 --time -1", "--state 0.4,2.8,0.9,1 --time 1 --arm 3",
          "--state 0.4,2.8,0.9,1 --time 1 --route ensemble --precision quad",
          "--state 0.4,2.8,0.9,1 --time 1 --route fast",
          "--state 0.4,2.8,0.9,1 --time 1 --method taylor --taylor-order 1",
          "--state 0.4,2.8,0.9,1 --time 1 --method taylor --taylor-order 99999999999999999999",
          "--state 0.4,2.8,0.9,1 --time 1 --method taylor --taylor-order -3",
          "--state 0.4,2.8,0.9,1 --time 1 --method dop853 --taylor-order 12"}) {
        const auto r = run_flipflux("trajectory " + bad + " --events " + (dir / "e.csv").string());
        EXPECT_EQ(r.status, 2) << bad << ": " << r.err;
        EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
        EXPECT_FALSE(fs::exists(dir / "e.csv")) << bad;
    }
    fs::remove_all(dir);
}

}  // namespace
}  // namespace flipflux::test
