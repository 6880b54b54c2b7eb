// Flip detection (ensemble/flip_detector.hpp):
//   - on prescribed analytic paths (exact dense output): a grazing double crossing inside one
//     step with both ends on the same side, its near miss, several 2 pi levels in one step, a
//     restricted-domain curve (crossings outside the domain do not count), arm 1, a crossing at
//     a step boundary counted once; each with and without the dense output's rates and angle
//     bounds (Newton's method and the enclosure test against TOMS 748 and the samples alone);
//   - offset_bounds against the curves sampled on any range of the other angle;
//   - on real dynamics: a brake orbit whose apex lies 1e-8 beyond the curve (two crossings
//     ~1e-4 apart inside one step) or before it (none); a crossing in the first step and one
//     at the very end; counts at high energy (many turns, angles reduced every step) against a
//     brute-force count on an unreduced integration; crossing times against an independent
//     integration landing on them, and DOP853 against DOPRI5;
//   - the lanes' quiet tests against the detectors: no step the RK lanes' lets pass is one they
//     examine; the prefilter's reach, on which both rest, is the levels within the bound and
//     monotone in the range and the bound.
#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <random>
#include <vector>

#include "ensemble_support.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/ensemble/fast_trig.hpp"
#include "flipflux/ensemble/flip_detector.hpp"

namespace flipflux::test {
namespace {

constexpr double pi = std::numbers::pi;

/// A linear curve h(s) = slope * s on a restricted domain (satisfies dividing_curve).
struct linear_curve {
    arm a = arm::two;
    double k = 0.2;
    std::array<double, 2> dom{-0.5, 0.5};
    arm flip_arm() const { return a; }
    double offset(double s) const { return k * s; }
    double slope(double) const { return k; }
    std::array<double, 2> domain() const { return dom; }
};
static_assert(dividing_curve<linear_curve, double>);

// A prescribed configuration path th(t) with velocities w(t); momenta l = M(th) w.
struct path {
    std::function<std::array<double, 4>(double)> q;  // (th1, th2, w1, w2)
};

// With `rated`, it also gives the angles' rates (the path's own derivative: Newton's method on
// the crossings) and their bounds over the current step (from 4001 points and widened by 1e-9:
// the enclosure test before the samples), as the RK lanes' dense output does.
class path_interpolant final : public step_interpolant {
  public:
    path_interpolant(const double_pendulum<double>& m, path p, bool rated = false)
        : m_(m), p_(std::move(p)), rated_(rated) {}
    std::array<double, 4> state(double t) const override {
        const auto q = p_.q(t);
        const auto l = m_.momenta(q[0], q[1], q[2], q[3]);
        return {q[0], q[1], l[0], l[1]};
    }
    bool angles_and_rates(double t, std::array<double, 2>& q,
                          std::array<double, 2>& dq) const override {
        if (!rated_) return false;
        const auto y = p_.q(t);
        q = {y[0], y[1]};
        dq = {y[2], y[3]};
        return true;
    }
    bool angle_bounds(std::array<std::array<double, 2>, 2>& r) const override {
        if (!rated_) return false;
        for (std::size_t i = 0; i < 2; ++i)
            r[i] = {std::numeric_limits<double>::infinity(),
                    -std::numeric_limits<double>::infinity()};
        for (int j = 0; j <= 4000; ++j) {
            const auto y = p_.q(j == 4000 ? t1_ : t0_ + (t1_ - t0_) * (j / 4000.0));
            for (std::size_t i = 0; i < 2; ++i)
                r[i] = {std::min(r[i][0], y[i] - 1e-9), std::max(r[i][1], y[i] + 1e-9)};
        }
        return true;
    }
    void set_step(double t0, double t1) {
        t0_ = t0;
        t1_ = t1;
    }

  private:
    const double_pendulum<double>& m_;
    path p_;
    bool rated_ = false;
    double t0_ = 0, t1_ = 0;
};

// Runs a detector over [t0, t1] split into `steps` equal steps of the path (`rated`: see
// path_interpolant).
std::vector<crossing> detect(const double_pendulum<double>& m, flip_detector_base& d, path p,
                             double t0, double t1, int steps, bool rated = false) {
    const pendulum_flow flow(m);
    path_interpolant interp(m, p, rated);
    std::vector<crossing> out;
    auto x0 = interp.state(t0), f0 = flow(0, x0);
    d.start(x0, f0);
    for (int i = 0; i < steps; ++i) {
        const double a = t0 + (t1 - t0) * i / steps, b = t0 + (t1 - t0) * (i + 1) / steps;
        const auto x1 = interp.state(b), f1 = flow(0, x1);
        interp.set_step(a, b);
        const std::size_t before = out.size();
        d.step({a, b, x0, f0, x1, f1, interp}, out);
        for (std::size_t k = before; k < out.size(); ++k) {  // a step's crossings lie in it
            EXPECT_GE(out[k].time, a);
            EXPECT_LE(out[k].time, b);
        }
        x0 = x1;
        f0 = f1;
    }
    return out;
}

TEST(FlipDetector, GrazingDoubleCrossingInsideOneStep) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    for (const bool rated : {false, true})
        for (double delta : {1e-6, 1e-10, -1e-6, -1e-10}) {
            // th2 = pi + delta - (t - 0.5)^2: an apex delta beyond the upright line at t = 0.5
            path p{[delta](double t) {
                return std::array<double, 4>{0.3 + 0.1 * t, pi + delta - (t - 0.5) * (t - 0.5), 0.1,
                                             -2 * (t - 0.5)};
            }};
            auto d = make_flip_detector(upright_curve<double>{arm::two}, flow);
            const auto c = detect(m, *d, p, 0, 1, 1, rated);
            if (delta < 0) {
                EXPECT_TRUE(c.empty()) << delta;
            } else {
                ASSERT_EQ(c.size(), 2u) << delta;
                // rounding of phi (~ulp(pi)) divided by the slope phi' = 2 sqrt(delta) there
                const double tol = 8 * eps<double>() * pi / (2 * std::sqrt(delta)) + 1e-15;
                EXPECT_NEAR(c[0].time, 0.5 - std::sqrt(delta), tol) << delta;
                EXPECT_NEAR(c[1].time, 0.5 + std::sqrt(delta), tol) << delta;
                EXPECT_EQ(c[0].direction, 1);
                EXPECT_EQ(c[1].direction, -1);
                EXPECT_NEAR(c[0].s, 0.3 + 0.1 * c[0].time, 1e-15);
            }
            EXPECT_EQ(d->examined_steps(), 1);
        }
}

// The detectors of one trajectory share a step's examination samples (step_view::samples): the
// same crossings, bit for bit, as each evaluating its own, whichever detector examines first, and
// fewer evaluations of the dense output; with the dense output's rates and angle bounds too (the
// bounds asked once per step when shared).
void expect_shared_samples_give_the_same_bits(bool rated) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    // th2 oscillates about pi while th1 drifts: crossings of the upright line and of the line
    // th2 = pi + 0.2 th1 in the same steps, some grazing
    path p{[](double t) {
        return std::array<double, 4>{-0.4 + 0.1 * t, pi + 0.3 * std::sin(7 * t) + 0.01 * t, 0.1,
                                     2.1 * std::cos(7 * t) + 0.01};
    }};
    class counting final : public step_interpolant {
      public:
        explicit counting(const step_interpolant& d) : d_(d) {}
        std::array<double, 4> state(double t) const override {
            ++calls;
            return d_.state(t);
        }
        bool angles_and_rates(double t, std::array<double, 2>& q,
                              std::array<double, 2>& dq) const override {
            return d_.angles_and_rates(t, q, dq);
        }
        bool angle_bounds(std::array<std::array<double, 2>, 2>& r) const override {
            ++bounds_calls;
            return d_.angle_bounds(r);
        }
        mutable long calls = 0, bounds_calls = 0;

      private:
        const step_interpolant& d_;
    };
    path_interpolant base(m, p, rated);
    long bounds_own = 0, bounds_shared = 0;
    auto run = [&](bool share, bool reversed, long& calls) {
        std::vector<std::unique_ptr<flip_detector_base>> ds;
        ds.push_back(make_flip_detector(upright_curve<double>{arm::two}, flow));
        ds.push_back(make_flip_detector(linear_curve{}, flow));
        if (reversed) std::swap(ds[0], ds[1]);
        const counting interp(base);
        std::vector<std::vector<crossing>> out(2);
        auto x0 = base.state(0.0), f0 = flow(0, x0);
        for (auto& d : ds)
            d->start(x0, f0);
        const int steps = 40;
        for (int i = 0; i < steps; ++i) {
            const double a = 3.0 * i / steps, b = 3.0 * (i + 1) / steps;
            const auto x1 = base.state(b), f1 = flow(0, x1);
            step_samples samples;
            base.set_step(a, b);
            step_view v{a, b, x0, f0, x1, f1, interp};
            if (share) v.samples = &samples;
            for (std::size_t k = 0; k < 2; ++k)
                ds[k]->step(v, out[reversed ? 1 - k : k]);
            x0 = x1;
            f0 = f1;
        }
        calls = interp.calls;
        (share ? bounds_shared : bounds_own) = interp.bounds_calls;
        return out;
    };
    long own = 0, shared = 0, shared_reversed = 0;
    const auto a = run(false, false, own);
    const auto b = run(true, false, shared);
    const auto c = run(true, true, shared_reversed);
    for (std::size_t k = 0; k < 2; ++k) {
        ASSERT_GE(a[k].size(), 4u) << k;
        for (const auto* other : {&b, &c}) {
            ASSERT_EQ((*other)[k].size(), a[k].size()) << k;
            for (std::size_t j = 0; j < a[k].size(); ++j) {
                EXPECT_EQ((*other)[k][j].time, a[k][j].time) << k << " " << j;
                EXPECT_EQ((*other)[k][j].direction, a[k][j].direction);
                EXPECT_EQ((*other)[k][j].s, a[k][j].s);
            }
        }
    }
    EXPECT_LT(shared, own);
    EXPECT_EQ(shared_reversed, shared);
    if (rated) {
        EXPECT_GT(bounds_shared, 0);
        EXPECT_LE(bounds_shared, 40);  // at most once per step
        EXPECT_LT(bounds_shared, bounds_own);
    }
}

TEST(FlipDetector, SharedExaminationSamplesGiveTheSameBits) {
    for (const bool rated : {false, true})
        expect_shared_samples_give_the_same_bits(rated);
}

TEST(FlipDetector, SeveralLevelsInOneStepAndStepBoundaries) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    // th2 = pi - 0.1 + 20 t on [0, 1]: levels 0, 2 pi, 4 pi, 6 pi at t = (0.1 + 2 pi k) / 20
    path p{[](double t) { return std::array<double, 4>{0.2, pi - 0.1 + 20 * t, 0.0, 20.0}; }};
    for (const bool rated : {false, true})
        for (int steps : {1, 3, 7}) {
            auto d = make_flip_detector(upright_curve<double>{arm::two}, flow);
            const auto c = detect(m, *d, p, 0, 1, steps, rated);
            ASSERT_EQ(c.size(), 4u) << steps;
            for (int k = 0; k < 4; ++k) {
                EXPECT_NEAR(c[k].time, (0.1 + 2 * pi * k) / 20, 1e-14);
                EXPECT_EQ(c[k].direction, 1);
            }
        }
    // a path that reaches the level exactly at a step end and continues: counted once
    path q{[](double t) { return std::array<double, 4>{0.0, pi - 0.5 + t, 0.0, 1.0}; }};
    auto d = make_flip_detector(upright_curve<double>{arm::two}, flow);
    const auto c = detect(m, *d, q, 0, 1, 2);  // step end at t = 0.5 where th2 = pi exactly
    ASSERT_EQ(c.size(), 1u);
    EXPECT_NEAR(c[0].time, 0.5, 1e-15);
}

TEST(FlipDetector, RestrictedDomainCountsOnlyInside) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    for (const bool rated : {false, true}) {
        for (double s0 : {0.3, 0.7, -0.45, -0.55}) {
            // crossing the line th2 = pi + 0.2 th1 at th1 = s0, moving in th2 only
            path p{[s0](double t) {
                return std::array<double, 4>{s0, pi + 0.2 * s0 - 0.5 + t, 0.0, 1.0};
            }};
            auto d = make_flip_detector(linear_curve{}, flow);
            const auto c = detect(m, *d, p, 0, 1, 3, rated);
            EXPECT_EQ(c.size(), std::abs(s0) <= 0.5 ? 1u : 0u) << s0;
        }
        // crossing while moving along s out of the domain: the crossing is at s = 0.45, counted
        path p{[](double t) {
            return std::array<double, 4>{0.4 + 0.1 * t, pi + 0.2 * (0.4 + 0.1 * t) - 0.5 + t, 0.1,
                                         1.02};
        }};
        auto d = make_flip_detector(linear_curve{}, flow);
        const auto c = detect(m, *d, p, 0, 1, 2, rated);
        ASSERT_EQ(c.size(), 1u);
        EXPECT_NEAR(c[0].s, 0.45, 1e-12);
        EXPECT_NEAR(c[0].time, 0.5, 1e-14);  // 0.2 (0.4 + 0.1 t) - 0.5 + t = 0.2 s at t = 0.5
    }
    // a domain longer than 2 pi is refused
    EXPECT_THROW(make_flip_detector(linear_curve{arm::two, 0.1, {-4, 4}}, flow),
                 std::invalid_argument);
    EXPECT_THROW(make_flip_detector(linear_curve{arm::two, 0.1, {1, 1}}, flow),
                 std::invalid_argument);
}

TEST(FlipDetector, ArmOneCurvesUseTheFirstAngle) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    const sine_curve<double> curve = approximate_saddle_curve(m, arm::one);
    // centre mode (1, 2 + sqrt 2) in (th1, th2): th1 - pi = sin(th2) / (2 + sqrt 2)
    ASSERT_NEAR(curve.amplitude, 1 - std::sqrt(0.5), 1e-15);
    // th1 decreasing through pi + A sin(th2) at th2 = 0.1, then continuing 2 pi further down
    path p{[](double t) { return std::array<double, 4>{4 - 8 * t, 0.1, -8.0, 0.0}; }};
    for (const bool rated : {false, true}) {
        auto d = make_flip_detector(curve, flow);
        const auto c = detect(m, *d, p, 0, 1, 4, rated);
        const double level = pi + curve.offset(0.1);
        ASSERT_EQ(c.size(), 2u);
        EXPECT_NEAR(c[0].time, (4 - level) / 8, 1e-14);
        EXPECT_NEAR(c[1].time, (4 - level + 2 * pi) / 8, 1e-14);
        EXPECT_EQ(c[0].direction, -1);
        EXPECT_EQ(d->flip_arm(), arm::one);
    }
}

// offset_bounds against the curve sampled on 2001 points of each range of s (reduced around the
// domain's centre, kept where it lies in the domain): they enclose it, no more than a bin's
// variation wider, and a range that never meets the domain is reported as such. Curves: the
// approximate saddle curve (the whole circle), a restricted linear one, the upright arm (h = 0).
template <class Curve>
void expect_offset_bounds(const Curve& curve, double width_slack) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    const flip_detector<Curve> d(curve, flow);
    const std::array<double, 2> dom = curve.domain();
    const double c = (dom[0] + dom[1]) / 2;
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> start(-20, 20), width(0, 7);
    int met = 0, missed = 0;
    for (int trial = 0; trial < 3000; ++trial) {
        const double slo = start(rng), shi = slo + (trial % 3 == 0 ? 0.05 : 1) * width(rng);
        double lo = std::numeric_limits<double>::infinity(), hi = -lo;
        for (int j = 0; j <= 2000; ++j) {
            const double s = slo + (shi - slo) * (j / 2000.0);
            const double r = s - 2 * pi * std::round((s - c) / (2 * pi));
            if (r < dom[0] || r > dom[1]) continue;
            lo = std::min(lo, curve.offset(r));
            hi = std::max(hi, curve.offset(r));
        }
        double hmin = 0, hmax = 0;
        const bool any = d.offset_bounds(slo, shi, hmin, hmax);
        if (lo > hi) {  // no sample in the domain: either answer, bounds not checked
            missed += any ? 0 : 1;
            continue;
        }
        ++met;
        ASSERT_TRUE(any) << slo << " " << shi;
        EXPECT_LE(hmin, lo) << slo << " " << shi;
        EXPECT_GE(hmax, hi) << slo << " " << shi;
        EXPECT_LE(lo - hmin, width_slack) << slo << " " << shi;
        EXPECT_LE(hmax - hi, width_slack) << slo << " " << shi;
    }
    EXPECT_GT(met, 1000);
    if (dom[1] - dom[0] < pi) {
        EXPECT_GT(missed, 100);
    }
}

TEST(FlipDetector, OffsetBoundsEncloseTheCurveOverAnyRangeOfS) {
    const double_pendulum<double> m;
    const sine_curve<double> approx = approximate_saddle_curve(m, arm::two);
    // a bin is 2 pi / 64 wide: h = A sin s varies by at most A 2 pi / 64 < 0.06 across one
    expect_offset_bounds(approx, 0.07);
    // bins of 1 / 64: 0.2 / 64 = 0.003 of variation
    expect_offset_bounds(linear_curve{}, 0.004);
    expect_offset_bounds(upright_curve<double>{arm::two}, 0.0);
}

// ---- real dynamics ---------------------------------------------------------------------------

ensemble_options tight(double T) {
    ensemble_options o;
    o.time = T;
    o.rtol = 1e-12;
    o.chaos = false;
    o.keep_crossings = true;
    return o;
}

trajectory_result simulate(const double_pendulum<double>& m, const phase_point<double>& x0,
                           const ensemble_options& o,
                           const std::vector<std::shared_ptr<flip_detector_base>>& ds) {
    std::vector<flip_detector_base*> raw;
    for (const auto& d : ds)
        raw.push_back(d.get());
    return simulate_trajectory(m, x0, o, 0, raw);
}

// The state that reaches `apex` (at rest) after time tau: integrate from the apex and reverse
// the momenta (time-reversal symmetry).
phase_point<double> towards_apex(const double_pendulum<double>& m, const phase_point<double>& apex,
                                 double tau) {
    const pendulum_flow flow(m);
    rk_options ro;
    ro.rtol = ro.atol = 1e-13;
    explicit_rk<dormand_prince_853, 4, pendulum_flow> rk(flow, ro);
    rk.initialize(0, apex);
    rk.integrate(tau, [](auto&) {});
    const auto x = rk.x();
    return {x[0], x[1], -x[2], -x[3]};
}

TEST(FlipDetector, GrazingBrakeOrbitOfRealDynamics) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    const double tau = 1.0, th1 = 0.3;
    const sine_curve<double> approx = approximate_saddle_curve(m, arm::two);
    for (double delta : {1e-8, -1e-8}) {
        for (int which = 0; which < 2; ++which) {
            const double offset = which == 0 ? 0.0 : approx.offset(th1);
            const phase_point<double> apex{th1, pi + offset + delta, 0, 0};
            // phi'' at the apex (at rest: th'' = M^-1 l', and phi'' = th2'' - h'(th1) th1'')
            const auto f = flow(0, apex);
            const auto acc = flow.velocities({apex[0], apex[1], f[2], f[3]});
            const double slope = which == 0 ? 0.0 : approx.slope(th1);
            const double phi2 = acc[1] - slope * acc[0];
            ASSERT_LT(phi2, 0);  // a maximum: the trajectory comes up to the apex and falls back
            const phase_point<double> x0 = towards_apex(m, apex, tau);
            std::vector<std::shared_ptr<flip_detector_base>> ds;
            if (which == 0)
                ds.push_back(make_flip_detector(upright_curve<double>{arm::two}, flow));
            else
                ds.push_back(make_flip_detector(approx, flow));
            const trajectory_result r = simulate(m, x0, tight(2 * tau), ds);
            const auto& c = r.crossings[0];
            if (delta < 0) {
                EXPECT_TRUE(c.empty()) << which;
                continue;
            }
            ASSERT_EQ(c.size(), 2u) << which;
            // symmetric about tau, separated by 2 sqrt(2 delta / |phi''|)
            EXPECT_NEAR(0.5 * (c[0].time + c[1].time), tau, 1e-7);
            const double expected = 2 * std::sqrt(2 * delta / -phi2);
            EXPECT_NEAR(c[1].time - c[0].time, expected, 0.01 * expected);
            EXPECT_EQ(c[0].direction, 1);
            EXPECT_EQ(c[1].direction, -1);
            EXPECT_GE(r.steps, 10);
        }
    }
}

TEST(FlipDetector, CrossingsInTheFirstAndLastStep) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    // first step: th2 = pi - 1e-9 moving up at th2' = 1
    const auto l = m.momenta(0.0, pi - 1e-9, 0.0, 1.0);
    const phase_point<double> x0{0.0, pi - 1e-9, l[0], l[1]};
    std::vector<std::shared_ptr<flip_detector_base>> ds{
        make_flip_detector(upright_curve<double>{arm::two}, flow)};
    const trajectory_result r = simulate(m, x0, tight(3), ds);
    ASSERT_GE(r.crossings[0].size(), 1u);
    EXPECT_NEAR(r.crossings[0][0].time, 1e-9, 1e-15);
    EXPECT_EQ(r.crossings[0][0].direction, 1);
    // last step: end just after / just before a later crossing
    const microcanonical_sampler sampler(m, 5.0);
    const phase_point<double> y0 = sampler.sample(3, 0);
    const trajectory_result full = simulate(m, y0, tight(60), ds);
    ASSERT_GE(full.crossings[0].size(), 2u);
    const double tc = full.crossings[0][1].time;
    const trajectory_result after = simulate(m, y0, tight(tc + 1e-7), ds);
    const trajectory_result before = simulate(m, y0, tight(tc - 1e-7), ds);
    ASSERT_EQ(after.crossings[0].size(), 2u);
    EXPECT_NEAR(after.crossings[0][1].time, tc, 1e-10);
    EXPECT_EQ(before.crossings[0].size(), 1u);
    EXPECT_EQ(after.end_time, tc + 1e-7);
}

// Many turns: counts with angle reduction against a brute-force count of level changes of the
// unreduced crossing function sampled finely on an independent (unreduced) integration.
TEST(FlipDetector, ManyTurnsAreCountedModuloTwoPi) {
    const double_pendulum<double> m(lopsided_parameters());
    const pendulum_flow flow(m);
    const double E = 6 * m.maximum_energy();
    const microcanonical_sampler sampler(m, E);
    const double T = 15;
    for (std::uint64_t i = 0; i < 3; ++i) {
        const phase_point<double> x0 = sampler.sample(8, i);
        const std::array<sine_curve<double>, 2> curves{approximate_saddle_curve(m, arm::two),
                                                       approximate_saddle_curve(m, arm::one)};
        std::vector<std::shared_ptr<flip_detector_base>> ds;
        for (const auto& c : curves)
            ds.push_back(make_flip_detector(c, flow));
        ensemble_options o = tight(T);
        const trajectory_result r = simulate(m, x0, o, ds);
        rk_options ro;
        ro.rtol = ro.atol = 1e-12;
        explicit_rk<dormand_prince_853, 4, pendulum_flow> rk(flow, ro);
        rk.initialize(0, x0);
        auto phi = [&](const std::array<double, 4>& x, int c) {
            const arm a = curves[c].flip_arm();
            const auto q = curve_coordinates(a, x[0], x[1]);
            return q[1] - pi - curves[c].offset(q[0]);
        };
        std::array<long, 2> count{}, level{};
        for (int c = 0; c < 2; ++c)
            level[c] = static_cast<long>(std::floor(phi(x0, c) / (2 * pi)));
        long turns = 0;
        rk.integrate(T, [&](auto& s) {
            for (int j = 1; j <= 64; ++j) {
                const auto x = s.dense(s.t_previous() + (s.t() - s.t_previous()) * j / 64);
                for (int c = 0; c < 2; ++c) {
                    const long lv = static_cast<long>(std::floor(phi(x, c) / (2 * pi)));
                    count[c] += std::abs(lv - level[c]);
                    level[c] = lv;
                }
            }
        });
        turns = static_cast<long>(std::abs(rk.x()[1] - x0[1]) / (2 * pi));
        EXPECT_GT(turns, 5) << "the test needs fast rotation";
        for (int c = 0; c < 2; ++c) {
            EXPECT_EQ(static_cast<long>(r.crossing_times[c].size()), count[c]) << c;
            // alternating directions within each turn are consistent with the net winding
            long net = 0;
            for (const crossing& x : r.crossings[c])
                net += x.direction;
            EXPECT_LE(std::abs(net), count[c]);
        }
    }
}

// step_is_quiet (the lanes' test that lets a step pass without calling the detectors) against
// the detectors themselves: on random cubic paths whose flip angle comes near pi, 0 and 2 pi
// plus or minus the curve's bound, every step it calls quiet is one the detector neither
// examines nor finds a crossing in (so the outputs are those of calling it); and it is not
// vacuous: it calls most steps quiet, and the detector examines some of the others.
TEST(FlipDetector, QuietStepsAreOnesNoDetectorExamines) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    std::mt19937_64 rng(20261130);
    std::uniform_real_distribution<double> u(-1, 1);
    long quiet = 0, loud = 0, examined_loud = 0;
    for (int trial = 0; trial < 20000; ++trial) {
        const double h = 0.01 + 0.3 * (u(rng) + 1) / 2;
        const double amplitude = trial % 3 == 0 ? 0.0 : 0.5 * (u(rng) + 1);
        const int level = static_cast<int>(std::floor(3 * (u(rng) + 1) / 2)) - 1;  // -1, 0, 1
        // th2 = c0 + c1 t + c2 t^2 + c3 t^3 passing within a few tenths of pi + 2 pi level +- A
        const double c0 =
            pi + 2 * pi * level + (1.1 * amplitude + 0.05 + 0.6 * u(rng)) * (u(rng) < 0 ? -1 : 1);
        const double c1 = 3 * u(rng), c2 = 4 * u(rng), c3 = 6 * u(rng);
        const double a0 = 2 * u(rng), a1 = 2 * u(rng);
        path p{[=](double t) {
            return std::array<double, 4>{a0 + a1 * t, c0 + t * (c1 + t * (c2 + t * c3)), a1,
                                         c1 + t * (2 * c2 + t * 3 * c3)};
        }};
        const path_interpolant interp(m, p);
        const auto x0 = interp.state(0), x1 = interp.state(h);
        const auto f0 = flow(0, x0), f1 = flow(0, x1);
        std::shared_ptr<flip_detector_base> d =
            amplitude == 0 ? make_flip_detector(upright_curve<double>{arm::two}, flow)
                           : make_flip_detector(sine_curve<double>{arm::two, amplitude}, flow);
        const bool is_quiet = step_is_quiet({-1.0, d->prefilter_bound()}, h, x0, f0, x1, f1);
        d->start(x0, f0);
        std::vector<crossing> out;
        d->step({0, h, x0, f0, x1, f1, interp}, out);
        if (is_quiet) {
            ++quiet;
            EXPECT_EQ(d->examined_steps(), 0) << trial;
            EXPECT_TRUE(out.empty()) << trial;
        } else {
            ++loud;
            examined_loud += d->examined_steps();
        }
    }
    EXPECT_GT(quiet, 5000);
    EXPECT_GT(loud, 2000);
    EXPECT_GT(examined_loud, 500);
    // after a skipped step the detector starts the next one from the view's x0, f0: th2 = pi -
    // 0.15 + t passes pi at t = 0.15, inside the step after the skipped one
    path p{[](double t) { return std::array<double, 4>{0.1, pi - 0.15 + t, 0.0, 1.0}; }};
    const path_interpolant interp(m, p);
    const auto x0 = interp.state(0), x1 = interp.state(0.1), x2 = interp.state(0.2);
    const auto f0 = flow(0, x0), f1 = flow(0, x1), f2 = flow(0, x2);
    auto d = make_flip_detector(upright_curve<double>{arm::two}, flow);
    d->start(x0, f0);
    d->skip_step();
    std::vector<crossing> out;
    ASSERT_EQ(d->step({0.1, 0.2, x1, f1, x2, f2, interp}, out), 1);
    EXPECT_NEAR(out[0].time, 0.15, 8 * eps<double>() * pi);  // rounding of phi over slope 1
    EXPECT_EQ(out[0].direction, 1);
}

// The quiet test as the RK lanes run it, on a vector of steps (detail::quiet_reach on v8d, v4d and
// v2d, the rounding lane by lane), against the scalar test written out here as it was before it
// was shared (std::min, std::max, std::abs, within_reach's subtraction of bound + pi): the same
// verdict in every lane, on random steps, on steps whose end sits on the reach's edges (values
// near pi + 2 pi k +- bound, where a rounding decides) and on signed zeros.
template <class V>
void expect_lane_quiet_tests_match(std::mt19937_64& rng) {
    constexpr int W = lanes_of<V>;
    std::uniform_real_distribution<double> u(-1, 1);
    auto literal = [](double bound, double h, double p0, double p1, double w0, double w1) {
        const double m0 = h * w0, m1 = h * w1;
        const double b1 = p0 + m0 / 3, b2 = p1 - m1 / 3;
        const double lo = std::min(std::min(p0, p1), std::min(b1, b2));
        const double hi = std::max(std::max(p0, p1), std::max(b1, b2));
        const double d2a = std::abs(6 * (p1 - p0) - 4 * m0 - 2 * m1);
        const double d2b = std::abs(-6 * (p1 - p0) + 2 * m0 + 4 * m1);
        const double margin =
            0.25 * (std::abs(p1 - p0) + std::abs(m0) + std::abs(m1)) + 0.125 * std::max(d2a, d2b) +
            64 * std::numeric_limits<double>::epsilon() * (1 + std::abs(lo) + std::abs(hi)) + 1e-9;
        double a = lo - margin, b = hi + margin;
        a -= bound + pi;
        b += bound - pi;
        return std::ceil(a * (1 / (2 * pi))) > std::floor(b * (1 / (2 * pi)));
    };
    long quiet = 0, loud = 0;
    for (int trial = 0; trial < 4000; ++trial) {
        const double bound = trial % 4 == 0 ? 0.0 : 0.8 * (u(rng) + 1);
        V h, p0, p1, w0, w1;
        for (int l = 0; l < W; ++l) {
            h[l] = 0.02 + 0.1 * (u(rng) + 1);
            w0[l] = 2 * u(rng);
            w1[l] = 2 * u(rng);
            const double k = std::round(3 * u(rng));
            p0[l] = pi + 2 * pi * k + 2 * u(rng);
            p1[l] = p0[l] + h[l] * (w0[l] + w1[l]) / 2;
            if (trial % 5 == 1) {
                // the end's reach exactly on pi + 2 pi k - bound - margin (a rounding decides)
                const double edge = pi + 2 * pi * k - bound;
                p0[l] = p1[l] = edge + (l % 3 - 1) * 1e-9;
                w0[l] = w1[l] = 0;
            }
            if (trial % 7 == 2 && l % 2 == 0) {
                p0[l] = -0.0;
                w0[l] = -0.0;
                w1[l] = 0.0;
            }
        }
        V a, b;
        detail::quiet_reach(bound, h, p0, p1, w0, w1, a, b);
        for (int l = 0; l < W; ++l) {
            const bool lane_quiet = std::ceil(a[l]) > std::floor(b[l]);
            const bool expected = literal(bound, h[l], p0[l], p1[l], w0[l], w1[l]);
            EXPECT_EQ(lane_quiet, expected) << "W " << W << " trial " << trial << " lane " << l;
            EXPECT_EQ(step_is_quiet({-1.0, bound}, h[l], {0, p0[l], 0, 0}, {0, w0[l], 0, 0},
                                    {0, p1[l], 0, 0}, {0, w1[l], 0, 0}),
                      expected);
            (expected ? quiet : loud) += 1;
        }
    }
    EXPECT_GT(quiet, 1000);  // not vacuous: both verdicts occur often
    EXPECT_GT(loud, 1000);
}

TEST(FlipDetector, LaneQuietTestIsTheScalarOne) {
    std::mt19937_64 rng(20261203);
    expect_lane_quiet_tests_match<v8d>(rng);
    expect_lane_quiet_tests_match<v4d>(rng);
    expect_lane_quiet_tests_match<v2d>(rng);
}

// The prefilter's reach (detail::within_reach), on which both lanes' quiet tests rest: levels
// pi + 2 pi n are reached exactly when the range widened by the bound holds one, and a wider
// range or a larger bound never reaches fewer (what makes a test with the widest bound of a
// trajectory's detectors, ranges_are_quiet, safe for each of them).
TEST(FlipDetector, PrefilterReachIsTheLevelsWithinTheBoundAndMonotone) {
    using detail::within_reach;
    EXPECT_FALSE(within_reach(pi - 0.1, pi - 0.05, 0));
    EXPECT_TRUE(within_reach(pi - 0.1, pi + 0.01, 0));
    EXPECT_TRUE(within_reach(pi - 0.3, pi - 0.25, 0.3));
    EXPECT_FALSE(within_reach(pi - 0.3, pi - 0.25, 0.2));
    EXPECT_TRUE(within_reach(-pi - 0.05, -pi + 0.05, 0));  // the level -pi
    EXPECT_FALSE(within_reach(-pi + 0.2, -pi + 0.3, 0.1));
    EXPECT_TRUE(within_reach(5 * pi + 0.15, 5 * pi + 0.2, 0.2));  // the level 5 pi
    std::mt19937_64 rng(20261201);
    std::uniform_real_distribution<double> u(0, 1);
    long reached = 0, not_reached = 0;
    for (int i = 0; i < 200000; ++i) {
        const double lo = -8 + 16 * u(rng), hi = lo + 0.3 * u(rng), b = 0.6 * u(rng);
        // a slightly wider range and bound (down to a rounding's difference)
        const double wider = i % 2 == 0 ? 1e-3 * u(rng) : std::ldexp(u(rng), -50);
        const bool r = within_reach(lo, hi, b);
        (r ? reached : not_reached)++;
        if (r) {
            EXPECT_TRUE(within_reach(lo - wider, hi, b)) << lo << " " << hi << " " << b;
            EXPECT_TRUE(within_reach(lo, hi + wider, b)) << lo << " " << hi << " " << b;
            EXPECT_TRUE(within_reach(lo, hi, b + wider)) << lo << " " << hi << " " << b;
        }
        // exactly: some level pi + 2 pi n within [lo - b, hi + b] (checked away from its ends)
        const double n_lo = std::ceil((lo - b - pi) / (2 * pi)),
                     n_hi = std::floor((hi + b - pi) / (2 * pi));
        const double edge =
            std::min(std::abs(lo - b - pi - 2 * pi * std::round((lo - b - pi) / (2 * pi))),
                     std::abs(hi + b - pi - 2 * pi * std::round((hi + b - pi) / (2 * pi))));
        if (edge > 1e-12) {
            EXPECT_EQ(r, n_lo <= n_hi) << lo << " " << hi << " " << b;
        }
        const std::array<std::array<double, 2>, 2> ranges{{{0.0, 0.0}, {lo, hi}}};
        EXPECT_EQ(ranges_are_quiet({-1.0, b}, ranges), !r);
    }
    EXPECT_GT(reached, 10000);
    EXPECT_GT(not_reached, 20000);
}

TEST(FlipDetector, CrossingTimesAreAccurate) {
    const double_pendulum<double> m;
    const pendulum_flow flow(m);
    const microcanonical_sampler sampler(m, 4.5);
    const phase_point<double> x0 = sampler.sample(12, 5);
    const sine_curve<double> approx = approximate_saddle_curve(m, arm::two);
    auto make = [&] {
        return std::vector<std::shared_ptr<flip_detector_base>>{
            make_flip_detector(upright_curve<double>{arm::two}, flow),
            make_flip_detector(approx, flow)};
    };
    ensemble_options o = tight(20);
    const trajectory_result a = simulate(m, x0, o, make());
    o.method = integration_method::dopri5;
    const trajectory_result b = simulate(m, x0, o, make());
    for (int c = 0; c < 2; ++c) {
        ASSERT_GE(a.crossing_times[c].size(), 2u);
        ASSERT_EQ(a.crossing_times[c].size(), b.crossing_times[c].size());
        for (std::size_t i = 0; i < a.crossing_times[c].size(); ++i)
            EXPECT_NEAR(a.crossing_times[c][i], b.crossing_times[c][i], 1e-7);
    }
    // landing exactly on each crossing time, the crossing function vanishes there
    for (int c = 0; c < 2; ++c) {
        for (const crossing& x : a.crossings[c]) {
            rk_options ro;
            ro.rtol = ro.atol = 1e-13;
            explicit_rk<dormand_prince_853, 4, pendulum_flow> rk(flow, ro);
            rk.initialize(0, x0);
            rk.integrate(x.time, [](auto&) {});
            const auto y = rk.x();
            const double h = c == 0 ? 0.0 : approx.offset(y[0]);
            const double phi = std::remainder(y[1] - pi - h, 2 * pi);
            EXPECT_LT(std::abs(phi), 1e-8) << "criterion " << c << " t = " << x.time;
        }
    }
}

}  // namespace
}  // namespace flipflux::test
