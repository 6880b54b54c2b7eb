// The criterion registry (study/criteria.hpp): a new criterion is one registration. A toy
// criterion registered here (a level f = pi + 2/5, and an alias of the upright arm) is listed,
// checked, detected by the ensembles and located by the reference trajectories at every
// precision, with no other change. The alias's flips equal the built-in upright criterion's on
// the same trajectories (the registry's plumbing against the built-in route); the level's events
// at double (the ensemble route) agree with those at quad (the Taylor route) to the double
// trajectory's accuracy, and lie on the level by a third route (quad Gauss-Legendre).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/integrators/gauss_legendre.hpp"
#include "flipflux/study/criteria.hpp"
#include "flipflux/study/trajectory.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

/// The toy criterion's curve: the flip angle at pi + 2/5 (a level, not a physical criterion).
template <class Real>
struct level_curve {
    arm a = arm::two;
    arm flip_arm() const { return a; }
    Real offset(const Real&) const { return Real(2) / 5; }
    Real slope(const Real&) const { return Real(0); }
    std::array<Real, 2> domain() const { return {-pi<Real>(), pi<Real>()}; }
};

// ---- the whole change a new criterion needs: one registration --------------------------------
struct make_level {
    template <class Real>
    level_curve<Real> operator()(const double_pendulum<Real>&, arm a, const Real&) const {
        return {a};
    }
};
struct make_alias {
    template <class Real>
    upright_curve<Real> operator()(const double_pendulum<Real>&, arm a, const Real&) const {
        return {a};
    }
};
const bool registered = [] {
    register_criterion(
        define_criterion<make_level>({.name = "toy-level",
                                      .help = "the flip angle at pi + 2/5 (a test's toy)",
                                      .rate_quantity = "",
                                      .needs_saddle_orbit = false,
                                      .is_reference = false,
                                      .is_level = false}));
    register_criterion(define_criterion<make_alias>({.name = "toy-upright",
                                                     .help = "the upright arm again (a test's toy)",
                                                     .rate_quantity = "",
                                                     .needs_saddle_orbit = false,
                                                     .is_reference = false,
                                                     .is_level = true}));
    return true;
}();
// ----------------------------------------------------------------------------------------------

TEST(CriterionRegistry, AToyCriterionIsListedAndChecked) {
    ASSERT_TRUE(registered);
    const std::vector<std::string> names = criterion_names();
    ASSERT_GE(names.size(), 5u);
    EXPECT_EQ(std::vector<std::string>(names.begin(), names.begin() + 3),
              (std::vector<std::string>{"upright", "approx", "saddle"}));
    EXPECT_NE(std::find(names.begin(), names.end(), "toy-level"), names.end());
    EXPECT_NO_THROW(check_criterion_name("toy-level"));
    EXPECT_EQ(criterion_named("TOY-Level"), std::optional<std::string>("toy-level"));
    EXPECT_EQ(default_criterion(), "upright");
    // no rate quantity: no prediction, and the name is in every list of names
    const double_pendulum<double> m;
    EXPECT_FALSE(criterion_prediction(m, arm::two, "toy-level", 5).has_value());
    EXPECT_NE(criterion_name_list().find("toy-level"), std::string::npos);
    try {
        check_criterion_name("nope", "criteria");
        ADD_FAILURE() << "an unknown criterion was accepted";
    } catch (const input_error& e) {
        EXPECT_EQ(e.field(), "criteria");
        EXPECT_NE(e.detail().find("toy-level"), std::string::npos) << e.what();
    }
    // a taken name is refused
    EXPECT_THROW(
        register_criterion(define_criterion<make_level>({"upright", "", "", false, false, false})),
        std::logic_error);
}

TEST(CriterionRegistry, AnAliasOfTheUprightArmFlipsAsTheUprightArmDoes) {
    const double_pendulum<double> m;
    ensemble_options o;
    o.energy = 5;
    o.trajectories = 24;
    o.time = 40;
    o.seed = 11;
    o.chaos = false;
    const ensemble_result r = run_ensemble(
        m, o,
        {make_criterion(m, arm::two, "upright", 5), make_criterion(m, arm::two, "toy-upright", 5)});
    std::size_t total = 0;
    for (const trajectory_result& t : r.trajectories) {
        EXPECT_EQ(t.flips(0), t.flips(1)) << "trajectory " << t.index;
        EXPECT_EQ(t.crossing_times[0], t.crossing_times[1]) << "trajectory " << t.index;
        total += t.flips(0);
    }
    EXPECT_GT(total, 10u);
}

struct quad_flow {
    const double_pendulum<quad>* m;
    void operator()(const std::array<quad, 4>& x, std::array<quad, 4>& dx) const { dx = m->rhs(x); }
};

TEST(CriterionRegistry, AToyLevelIsFoundAtDoubleAndQuadOnTheLevel) {
    const phase_point<double> x0{2.5, 3.0, 1.2, 1.0};
    const double T = 8;
    trajectory_request<double> qd;
    qd.state = x0;
    qd.time = T;
    qd.criteria = {"toy-level"};
    qd.arms = {arm::one, arm::two};
    qd.rtol = 1e-13;
    const trajectory_record<double> d = integrate_trajectory(double_pendulum<double>{}, qd);
    trajectory_request<quad> qq;
    qq.state = {x0[0], x0[1], x0[2], x0[3]};
    qq.time = T;
    qq.criteria = qd.criteria;
    qq.arms = qd.arms;
    const double_pendulum<quad> mq;
    const trajectory_record<quad> q = integrate_trajectory(mq, qq);
    ASSERT_GE(q.events.size(), 2u);
    ASSERT_EQ(d.events.size(), q.events.size());
    for (std::size_t i = 0; i < q.events.size(); ++i) {
        EXPECT_EQ(d.events[i].criterion, "toy-level");
        EXPECT_EQ(d.events[i].flip_arm, q.events[i].flip_arm);
        EXPECT_EQ(d.events[i].direction, q.events[i].direction);
        // double at rtol 1e-13 over T = 8: event times to ~1e-10 (a margin of 100 over the
        // state error's growth on this trajectory)
        EXPECT_NEAR(d.events[i].time, static_cast<double>(q.events[i].time), 1e-9) << i;
        // a third route: quad Gauss-Legendre (order 32, steps <= 1/64) to the quad event time;
        // the flip angle is pi + 2/5 (mod 2 pi) there to ~1e-25
        std::array<quad, 4> x = qq.state;
        const quad t = q.events[i].time;
        const long n = std::max(1L, static_cast<long>(std::ceil(static_cast<double>(t) * 64)));
        gauss_legendre<quad, 4> gl(16);
        gl.integrate(quad_flow{&mq}, x, t / n, n);
        const quad f = q.events[i].flip_arm == arm::two ? x[1] : x[0];
        const quad two_pi = 2 * pi<quad>();
        const quad r = f - pi<quad>() - quad(2) / 5;
        const quad off = r - two_pi * boost::multiprecision::round(r / two_pi);
        EXPECT_LT(static_cast<double>(boost::multiprecision::abs(off)), 1e-22) << i;
    }
}

// A criterion on the saddle orbit exists only below the potential's maximum E_max (the family
// ends there); the others have no ceiling. At a pendulum whose E_max is not the egalitarian one
// (m1 = 2, m2 = 1, L1 = 1, L2 = 0.5, g = 1: E_max = 2 (m1 + m2) L1 + 2 m2 L2 = 7 from the potential
// by hand), an energy above it is refused naming the energy and the criterion; below it the
// criterion is made.
TEST(CriterionRegistry, ASaddleOrbitCriterionEndsAtTheMaximumEnergy) {
    const double_pendulum<double> m(physical_parameters<double>{
        .m1 = 2, .m2 = 1, .L1 = 1, .L2 = 0.5, .a1 = 1, .a2 = 0.5, .g = 1});
    ASSERT_EQ(m.maximum_energy(), 7.0);
    EXPECT_EQ(criterion_ceiling(m, arm::two, "saddle"), 7.0);
    EXPECT_EQ(criterion_ceiling(m, arm::one, "saddle"), 7.0);
    EXPECT_EQ(criterion_ceiling(m, arm::two, "upright"), std::numeric_limits<double>::infinity());
    EXPECT_EQ(criterion_ceiling(m, arm::two, "approx"), std::numeric_limits<double>::infinity());
    for (const double e : {7.0, 9.5}) {
        try {
            (void)make_criterion(m, arm::two, "saddle", e);
            ADD_FAILURE() << "E = " << e << " was not refused";
        } catch (const input_error& err) {
            const std::string what = err.what();
            EXPECT_NE(what.find("is at or above the maximum energy 7, where criterion 'saddle' of "
                                "arm 2 has no saddle orbit"),
                      std::string::npos)
                << what;
        }
    }
    EXPECT_EQ(make_criterion(m, arm::two, "upright", 9.5).name, "upright");
    EXPECT_EQ(make_criterion(m, arm::two, "saddle", 6.5).name, "saddle");
}

}  // namespace
}  // namespace flipflux::test
