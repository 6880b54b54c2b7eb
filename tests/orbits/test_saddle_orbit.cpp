// Saddle orbits: the centre-mode guess against the paper's closed forms, the shooting Jacobians
// against finite differences, the two formulations against each other, the small-orbit scaling
// F ~ (E - E_s) T_lin, the monodromy's structure, the stored orbit against direct integration,
// dT/dE against finite differences, continuation and bad input.
#include <cmath>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/integrators/gauss_legendre.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/orbits/shooting.hpp"
#include "pendulums.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

template <class Real>
class SaddleOrbitTyped : public test::real_test<Real> {};
TYPED_TEST_SUITE(SaddleOrbitTyped, real_types, real_name);

TYPED_TEST(SaddleOrbitTyped, LinearGuessIsThePapersCentreMode) {
    using Real = TypeParam;
    using std::abs;
    using std::sqrt;
    // egalitarian: omega^2 = sqrt 2 at both saddles (paper App. B), centre modes (1, 2 - sqrt 2)
    // at (0, pi) and (1, 2 + sqrt 2) at (pi, 0)
    const double_pendulum<Real> model;
    const Real t_lin = two_pi<Real>() / sqrt(sqrt(Real(2)));
    const double tol = 64 * static_cast<double>(eps<Real>());
    for (arm a : {arm::two, arm::one}) {
        const auto g = linear_guess(model, a);
        EXPECT_LE(relative_error(g.period, t_lin), tol);
        const Real a2 = a == arm::two ? 2 - sqrt(Real(2)) : 2 + sqrt(Real(2));
        // momentum of the mode's velocity (1, a2): l = M* (1, a2), M* = [[2, -1], [-1, 1]]
        const std::array<Real, 2> l{2 - a2, -1 + a2};
        const detail::shooting_setup<Real> setup(model, a, Real(1), 1);
        const auto l0 = setup.momentum(g.beta);
        EXPECT_LE(static_cast<double>(
                      abs(l0[0] * l[1] - l0[1] * l[0]) /
                      (sqrt(l0[0] * l0[0] + l0[1] * l0[1]) * sqrt(l[0] * l[0] + l[1] * l[1]))),
                  tol);
        EXPECT_GT(l0[0] * l[0] + l0[1] * l[1], 0);
    }
}

TEST(SaddleOrbit, ShootingJacobiansMatchFiniteDifferences) {
    // at a point near (not on) the orbit; the T column of the periodic residual is f(x(T)),
    // exact for the flow and O(tolerance) off for the discrete map whose differences we take
    const double_pendulum<double> model;
    for (arm a : {arm::two, arm::one}) {
        const double excess = 0.8;
        const detail::shooting_setup<double> setup(model, a, excess, 6);
        const double beta = a == arm::two ? 0.11 : 1.2, period = 6.0;
        const long steps = 200;
        const auto pr = detail::periodic_shooting(setup, beta, period, steps);
        const auto sr = detail::symmetric_shooting(setup, beta, period / 4, steps);
        const double h = 1e-6;
        for (int col = 0; col < 2; ++col) {
            const double db = col == 0 ? h : 0, dt = col == 1 ? h : 0;
            const auto pp = detail::periodic_shooting(setup, beta + db, period + dt, steps);
            const auto pm = detail::periodic_shooting(setup, beta - db, period - dt, steps);
            for (int i = 0; i < 4; ++i) {
                const double fd = (pp.r[i] - pm.r[i]) / (2 * h);
                EXPECT_NEAR(pr.jacobian[i][col], fd, 1e-6 * (1 + std::abs(fd)))
                    << "periodic row " << i << " col " << col;
            }
            const auto sp = detail::symmetric_shooting(setup, beta + db, (period + dt) / 4, steps);
            const auto sm = detail::symmetric_shooting(setup, beta - db, (period - dt) / 4, steps);
            for (int i = 0; i < 2; ++i) {
                const double fd = (sp.r[i] - sm.r[i]) / (2 * h);
                const double an = col == 0 ? sr.jacobian[i][0] : sr.jacobian[i][1] / 4;
                EXPECT_NEAR(an, fd, 1e-6 * (1 + std::abs(fd)))
                    << "symmetric row " << i << " col " << col;
            }
        }
    }
}

/// Parameter sets beyond the egalitarian pendulum.
std::vector<physical_parameters<double>> parameter_sets() {
    physical_parameters<double> heavy_top;  // heavy, short second link
    heavy_top.m2 = 3;
    heavy_top.L2 = 0.5;
    heavy_top.a2 = 0.5;
    const physical_parameters<double> rods = uniform_rods_parameters();
    return {physical_parameters<double>{}, heavy_top, rods};
}

TEST(SaddleOrbit, PeriodicAndSymmetricFormulationsGiveTheSameOrbit) {
    for (const auto& p : parameter_sets()) {
        const double_pendulum<double> model(p);
        for (arm a : {arm::two, arm::one}) {
            const double lo = model.saddle_energy(a), hi = model.maximum_energy();
            for (double f : {0.3, 0.8}) {
                const double E = lo + f * (hi - lo);
                const auto per = solve_saddle_orbit(model, a, E, {orbit_method::periodic});
                const auto sym = solve_saddle_orbit(model, a, E, {orbit_method::symmetric});
                ASSERT_EQ(per.status, orbit_status::converged) << E;
                ASSERT_EQ(sym.status, orbit_status::converged) << E;
                EXPECT_LE(relative_error(per.period, sym.period),
                          (per.error_estimate_period + sym.error_estimate_period) / per.period)
                    << "E = " << E << " arm " << int(a);
                EXPECT_LE(relative_error(per.action, sym.action),
                          (per.error_estimate_action + sym.error_estimate_action) / per.action)
                    << "E = " << E;
                EXPECT_NEAR(per.beta, sym.beta, 1e-12);
                EXPECT_GT(per.action, 0);
                EXPECT_NEAR(per.floquet.stability_index / sym.floquet.stability_index, 1.0, 1e-8);
                // the estimates are honest but not absurd
                EXPECT_LE(per.error_estimate_period / per.period, 1e-12);
                EXPECT_LE(per.error_estimate_action / per.action, 1e-12);
            }
        }
    }
}

template <class Real>
void check_small_orbit(arm a) {
    using std::abs;
    // E = E_s + 1e-8: F = T_lin (dE + a dE^2 / 2 + b dE^3 / 3) and T = T_lin (1 + a dE + b dE^2)
    // (from dF/dE = T), so F / (dE T_lin) - 1 = (T / T_lin - 1) / 2 - b dE^2 / 6: both sides are
    // O(1e-9) numbers that agree to O(1e-17) + rounding
    const double_pendulum<Real> model;
    const Real dE = Real(1) / 100000000;
    const Real E = model.saddle_energy(a) + dE;
    orbit_options<Real> options;
    options.method = orbit_method::symmetric;
    const auto o = solve_saddle_orbit(model, a, E, options);
    ASSERT_EQ(o.status, orbit_status::converged);
    const Real t_lin = linear_guess(model, a).period;
    // NOTE: the excess actually computed with (E_s + 1e-8 rounded to Real, minus E_s)
    const Real lhs = o.action / (o.excess * t_lin) - 1;
    const Real rhs = (o.period / t_lin - 1) / 2;
    EXPECT_GT(abs(rhs), Real(1e-11));  // the nonlinear correction is resolved
    EXPECT_LE(static_cast<double>(abs(lhs - rhs)), 256 * static_cast<double>(eps<Real>()) + 1e-15)
        << "lhs " << to_decimal(lhs) << " rhs " << to_decimal(rhs);
    // the orbit is tiny: turning point at distance ~ sqrt(dE)
    EXPECT_LT(static_cast<double>(abs(o.turning_points[0][0] - o.saddle[0]) +
                                  abs(o.turning_points[0][1] - o.saddle[1])),
              1e-3);
    EXPECT_LE(static_cast<double>(o.energy_error), 1e-12);
}

TEST(SaddleOrbit, SmallOrbitsScaleWithTheLinearPeriodAtDouble) {
    check_small_orbit<double>(arm::two);
    check_small_orbit<double>(arm::one);
}

TEST(SaddleOrbit, SmallOrbitsScaleWithTheLinearPeriodAtQuad) {
    check_small_orbit<quad>(arm::two);
    check_small_orbit<quad>(arm::one);
}

// E = E_s + 10^-20 given in decimal: E rounds to E_s at double, the orbit is the one of
// E - E_s = 10^-20 (model/energy_level.hpp): F = (E - E_s) T_lin (1 + O(E - E_s)), T = T_lin.
TEST(SaddleOrbit, JustAboveTheSaddleTheExcessComesFromTheDecimalInput) {
    const double_pendulum<double> model;
    for (arm a : {arm::two, arm::one}) {
        const std::string text =
            a == arm::two ? "2.00000000000000000001" : "4.00000000000000000001";
        const energy_level<double> E = parse_energy_level<double>(text, "--energy");
        ASSERT_EQ(E.value, model.saddle_energy(a));
        orbit_options<double> options;
        options.method = orbit_method::symmetric;
        const auto o = solve_saddle_orbit(model, a, E, options);
        ASSERT_EQ(o.status, orbit_status::converged);
        const double t_lin = linear_guess(model, a).period;
        EXPECT_NEAR(o.excess, 1e-20, 4 * eps<double>() * 1e-20);
        EXPECT_NEAR(o.period / t_lin, 1, 64 * eps<double>());
        EXPECT_NEAR(o.action / (1e-20 * t_lin), 1, 64 * eps<double>());
    }
}

TEST(SaddleOrbit, MonodromyHasTwoUnitMultipliersAndAReciprocalPair) {
    const double_pendulum<double> model;
    for (arm a : {arm::two, arm::one}) {
        const double E = a == arm::two ? 3.5 : 5.0;
        for (auto m : {orbit_method::periodic, orbit_method::symmetric}) {
            const auto o = solve_saddle_orbit(model, a, E, {m});
            const auto& f = o.floquet;
            double norm = 0;
            for (const auto& row : o.monodromy)
                for (double v : row)
                    norm = std::max(norm, std::abs(v));
            // a Jordan block: the unit pair is resolved to sqrt(eps |M|)
            EXPECT_LE(f.unit_deviation, 100 * std::sqrt(eps<double>() * norm));
            EXPECT_LE(f.determinant_deviation, 1e4 * eps<double>() * norm * norm);
            EXPECT_TRUE(f.hyperbolic);
            EXPECT_GT(f.multiplier, 1);
            EXPECT_NEAR(std::abs(f.eigenvalues[3]) / f.multiplier, 1.0, 1e-9);
            EXPECT_NEAR(std::abs(f.eigenvalues[0]) * f.multiplier, 1.0, 1e-6);
            EXPECT_EQ(f.angle, 0);
        }
    }
    // an elliptic monodromy (a rotation block) and the analysis of the trace
    const double c = std::cos(0.3), s = std::sin(0.3);
    const std::array<std::array<double, 4>, 4> rot{
        {{1, 0.5, 0, 0}, {0, 1, 0, 0}, {0, 0, c, -s}, {0, 0, s, c}}};
    const auto e = floquet_analysis(rot);
    EXPECT_FALSE(e.hyperbolic);
    EXPECT_NEAR(e.angle, 0.3, 1e-14);
    EXPECT_EQ(e.multiplier, 1);
}

TEST(SaddleOrbit, StoredOrbitAgreesWithDirectIntegration) {
    const double_pendulum<double> model;
    const double E = 4.2;
    const auto o = solve_saddle_orbit(model, arm::two, E, {orbit_method::periodic});
    ASSERT_EQ(o.status, orbit_status::converged);
    const double T = o.period;
    // t = 0 and T: the start; T/4: the turning point, momenta zero
    const auto x0 = orbit_state(model, o, 0.0), xT = orbit_state(model, o, T);
    for (int i = 0; i < 4; ++i) {
        EXPECT_NEAR(x0[i], o.start[i], 1e-15);
        EXPECT_NEAR(xT[i], o.start[i], 1e-12);
    }
    const auto tp = orbit_state(model, o, T / 4);
    EXPECT_NEAR(tp[0], o.turning_points[0][0], 1e-13);
    EXPECT_NEAR(tp[1], o.turning_points[0][1], 1e-13);
    EXPECT_NEAR(tp[2], 0, 1e-12);
    EXPECT_NEAR(tp[3], 0, 1e-12);
    const auto tp2 = orbit_state(model, o, 3 * T / 4);
    EXPECT_NEAR(tp2[0], o.turning_points[1][0], 1e-12);
    EXPECT_NEAR(tp2[1], o.turning_points[1][1], 1e-12);
    // any time: against a direct integration of the absolute equations (the model's rhs)
    struct absolute_flow {
        const double_pendulum<double>* m;
        void operator()(const std::array<double, 4>& x, std::array<double, 4>& dx) const {
            dx = m->rhs(x);
        }
    };
    for (double frac : {0.13, 0.37, 0.5, 0.61, 0.88, 1.3, -0.2}) {
        const double t = frac * T;
        std::array<double, 4> x = o.start;
        gauss_legendre<double, 4> gl(6);
        const long n = 400;
        gl.integrate(absolute_flow{&model}, x, t / n, n);
        const auto y = orbit_state(model, o, t);
        for (int i = 0; i < 4; ++i)
            EXPECT_NEAR(y[i], x[i], 1e-9) << "t/T = " << frac << " component " << i;
        EXPECT_NEAR(model.hamiltonian(y), E, 1e-13);
    }
    saddle_orbit<double> empty;
    EXPECT_THROW(orbit_state(model, empty, 1.0), std::invalid_argument);
}

TEST(SaddleOrbit, PeriodDerivativeMatchesFiniteDifferences) {
    const double_pendulum<double> model;
    for (auto m : {orbit_method::periodic, orbit_method::symmetric}) {
        for (double E : {2.5, 5.5}) {
            const double h = 1e-5;
            const auto o = solve_saddle_orbit(model, arm::two, E, {m});
            const auto p = solve_saddle_orbit(model, arm::two, E + h, {m});
            const auto q = solve_saddle_orbit(model, arm::two, E - h, {m});
            const double fd = (p.period - q.period) / (2 * h);
            EXPECT_NEAR(o.period_derivative / fd, 1.0, 1e-7) << E;
            // and dF/dE = T, by the same differences
            EXPECT_NEAR((p.action - q.action) / (2 * h) / o.period, 1.0, 1e-8) << E;
        }
    }
}

// Scaling every mass by lambda scales E, E_s, the momenta and the action by lambda and leaves
// the angles and the period unchanged (torques and inertias scale alike). The reference is the
// unscaled pendulum. With lambda = 4^20 the model's coefficients scale by powers of two, exactly,
// but the double stage's iterates do not quite (the momentum rows' weights and scales round
// differently: its continuation points differ in the last bits from the seventh step on), so the
// period is within two ulp (the same bits until the continuation's steps were refined by the
// action identity, 2026-11-30, one ulp apart since); with lambda = 1e9 and 1e12 (not powers of
// two) within 1e-13. Before
// the residual rows were weighted (shooting_setup::row_weight) the momentum rows' rounding floor
// grew as eps lambda^1/2 and the double period at lambda = 2^40 was 1.7e-9 off.
TEST(SaddleOrbit, HeavyPendulumsKeepTheirDigits) {
    const double E = 4;  // E_s = 2 for arm 2 of the egalitarian pendulum
    const double_pendulum<double> model;
    for (orbit_method m : {orbit_method::periodic, orbit_method::symmetric}) {
        const saddle_orbit<double> o = solve_saddle_orbit(model, arm::two, E, {m});
        ASSERT_NE(o.status, orbit_status::not_converged);
        for (double lambda : {0x1p40, 1e9, 1e12}) {
            physical_parameters<double> p;
            p.m1 = lambda;
            p.m2 = lambda;
            const double_pendulum<double> heavy(p);
            const saddle_orbit<double> h = solve_saddle_orbit(heavy, arm::two, E * lambda, {m});
            ASSERT_NE(h.status, orbit_status::not_converged) << lambda << h.double_stage;
            if (lambda == 0x1p40) {
                EXPECT_LE(std::abs(h.period - o.period), 2 * eps<double>() * o.period);
                EXPECT_LE(std::abs(h.action / lambda - o.action), 4 * eps<double>() * o.action);
            }
            EXPECT_LE(std::abs(h.period - o.period), 1e-13 * o.period) << lambda;
            EXPECT_LE(std::abs(h.action / lambda - o.action), 1e-13 * o.action) << lambda;
            EXPECT_LE(h.error_estimate_period, 1e-12 * o.period) << lambda;
        }
    }
}

// Arm 2 of a point-mass pendulum (m1 = 0.5124, m2 = 2.05, L1 = 1.66, L2 = 0.486, g = 9.81) has
// another periodic orbit close to its saddle orbit near E = 71.55: before the continuation's steps
// were checked by the action identity dF/dE = T, a step from E - E_s = 38.8 to the target at
// E = 71.6 landed on it (T = 3.2773 against the family's 3.1030, F = 138.53 against 136.88) and
// every energy from 71.6 to 72.9 reported that orbit, with estimates of 1e-9. The check: the
// orbits at 71.5 and 71.6 obey the identity (F's difference within |dT| dE / 2 of the trapezoid,
// T being monotone between them), both methods, and T has no jump.
TEST(SaddleOrbit, ContinuationStaysOnItsFamilyWhereAnotherOrbitIsNear) {
    const double_pendulum<double> model(point_mass_parameters(0.5124, 2.05, 1.66, 0.486, 9.81));
    for (orbit_method m : {orbit_method::symmetric, orbit_method::periodic}) {
        const saddle_orbit<double> lo = solve_saddle_orbit(model, arm::two, 71.5, {m});
        const saddle_orbit<double> hi = solve_saddle_orbit(model, arm::two, 71.6, {m});
        ASSERT_NE(lo.status, orbit_status::not_converged) << lo.double_stage;
        ASSERT_NE(hi.status, orbit_status::not_converged) << hi.double_stage;
        const double dE = 0.1, trapezoid = dE * (lo.period + hi.period) / 2;
        EXPECT_LE(std::abs(hi.action - lo.action - trapezoid),
                  dE * std::abs(hi.period - lo.period) / 2 + 1e-9 * hi.action);
        EXPECT_LE(std::abs(hi.period - lo.period), 0.01 * lo.period);
    }
}

// A pendulum whose arm-2 family stopped at E - E_s = 190.494 (E = 728.65) with "step size fell
// below 1e-07": there steps_for_tolerance chose 8 steps per quarter orbit instead of ~1000. With
// 4, 8 and 16 steps the Gauss-Legendre stages converge to another solution of their implicit
// equations, the same for all three, so the three runs agreed to 1e-9 at an observed order of 2
// (the "rounding floor" verdict) while all of them were ~0.3 off; the Newton iteration on those
// steps could not converge. Each verdict now stands only when the next triple (2n, 4n, 8n) gives
// one too. In pendulum E's geometry with m2 = 1024 (arm 2, E - E_s = 55.7586) the other solution
// held for 4 to 32 steps (4, 8 and 16 splitting a step whose stage iteration failed) and the
// confirmation alone did not see it: a run that splits a step gives no verdict.
physical_parameters<double> heavy_second_arm_family_params() {
    return point_mass_parameters(0.1793, 31.6, 0.44, 0.868, 9.81);
}

TEST(SaddleOrbit, StepCountIsNotFooledByCoarseRunsThatAgreeWithEachOther) {
    model_text t;  // pendulum E's geometry with m2 = 1024 (every parameter exact in binary)
    t.m1 = "1", t.m2 = "1024", t.L1 = "0.5", t.a1 = "0.25", t.I1 = "0.0625";
    t.L2 = t.a2 = "2", t.I2 = "0", t.g = "1";
    const physical_parameters<double> pendulum_e_geometry = parse_parameters<double>(t);
    struct shot_case {
        physical_parameters<double> p;
        double excess, beta, period;
    };
    for (const shot_case& c : {shot_case{heavy_second_arm_family_params(), 190.4940213680882,
                                         0.38618825969963883, 1.4203250802756493},
                               shot_case{pendulum_e_geometry, 55.758568954737598,
                                         0.23640741766989562, 1.3286492257761193}}) {
        const double_pendulum<double> model(c.p);
        const detail::shooting_setup<double> setup(model, arm::two, c.excess, 6);
        const double quarter = c.period / 4;
        const auto x0 = setup.start(c.beta);
        const std::array<double, 5> y0{x0[0], x0[1], x0[2], x0[3], 0.0};
        const double lscale = std::max(std::abs(x0[2]), std::abs(x0[3]));
        const std::array<double, 5> scale{lscale, lscale, lscale, lscale, c.excess};
        const auto est = steps_for_tolerance<double, 5>(orbit_flow<double>{&setup.frame}, y0,
                                                        quarter, 1e-12, 6, scale, 4);
        // the reference: 4096 steps (the method's error there is at rounding, ~1e-14)
        gauss_legendre<double, 5> gl(6);
        auto run = [&](long n) {
            std::array<double, 5> y = y0;
            EXPECT_TRUE(gl.integrate(orbit_flow<double>{&setup.frame}, y, quarter / n, n).success);
            return y;
        };
        const auto ref = run(4096), got = run(est.steps);
        double err = 0;
        for (std::size_t k = 0; k < 5; ++k)
            err = std::max(err, std::abs(got[k] - ref[k]) / scale[k]);
        EXPECT_GE(est.steps, 64) << c.excess << ": coarse runs taken for converged";
        EXPECT_LE(err, 1e-10) << c.excess << ": " << est.steps << " steps";
    }
}

TEST(SaddleOrbit, FamilyOfAHeavySecondArmPassesWhereCoarsePilotRunsAgreed) {
    const double_pendulum<double> model(heavy_second_arm_family_params());
    // E = 730 lies beyond the old stop; the reference is the quad solve's period
    // (1.42531863364656566099282113857810871, error estimate 9.2e-27), 2026-11-30
    const saddle_orbit<double> o = solve_saddle_orbit(model, arm::two, 730.0);
    ASSERT_NE(o.status, orbit_status::not_converged) << o.double_stage;
    EXPECT_NEAR(o.period, 1.42531863364656566099282113857810871, 1e-13);
    EXPECT_LE(std::abs(o.period - 1.42531863364656566099282113857810871), o.error_estimate_period);
}

// Very unstable orbits at double, where the periodic residual's rounding floor eps |mu| is large:
// the periodic period's error estimate must still cover its actual error (found by a randomized
// sweep of the command line, 2026-12-01: the estimates were 11x and 10x below the errors). The
// references are the quad solves' periods (`eval period --precision quad`, error estimates
// 2.07e-32 and 1.12e-30), a higher precision, and the symmetric formulation's double solution,
// an independent formulation.
TEST(SaddleOrbit, PeriodicErrorEstimatesCoverTheRoundingFloorOfVeryUnstableOrbits) {
    struct unstable_case {
        physical_parameters<double> p;
        arm a;
        double energy;
        double quad_period;
        double min_multiplier;
    };
    physical_parameters<double> converged;  // |mu| = 9.0e10: the periodic iteration converges
    converged.m1 = 0.6268, converged.m2 = 1.522, converged.L1 = converged.a1 = 4.369;
    converged.L2 = converged.a2 = 0.9752, converged.g = 4.816;
    physical_parameters<double> stalled;  // |mu| = 1.7e14: it stalls at its rounding floor
    stalled.m1 = 1, stalled.m2 = 0.05, stalled.L1 = stalled.a1 = 1;
    stalled.L2 = stalled.a2 = 10, stalled.g = 0.5;
    const unstable_case cases[] = {
        {converged, arm::two, 41.42421294592, 6.14986159015852869002189429737476252, 1e10},
        {stalled, arm::one, 1.5, 45.958977251458681414934759897835382, 1e13}};
    for (const unstable_case& c : cases) {
        const double_pendulum<double> model(c.p);
        const auto per = solve_saddle_orbit(model, c.a, c.energy, {orbit_method::periodic});
        const auto sym = solve_saddle_orbit(model, c.a, c.energy, {orbit_method::symmetric});
        ASSERT_NE(per.status, orbit_status::not_converged) << per.double_stage;
        ASSERT_EQ(sym.status, orbit_status::converged) << sym.double_stage;
        ASSERT_GT(std::abs(per.floquet.multiplier), c.min_multiplier);
        const double error = std::abs(per.period - c.quad_period);
        EXPECT_LE(error, per.error_estimate_period) << "E = " << c.energy;
        // honest but not absurd: within 100x of the actual error
        EXPECT_LE(per.error_estimate_period, 100 * error) << "E = " << c.energy;
        // the symmetric formulation (amplification ~ |mu|^(1/4)) is accurate here
        EXPECT_LE(std::abs(sym.period - c.quad_period), sym.error_estimate_period);
        EXPECT_LE(sym.error_estimate_period, 1e-12 * sym.period);
    }
}

// A light long first link, a heavy short second one (docs/limits.md): with the step counts of the
// coarse runs that agreed with each other, the arm-1 continuation of the build of 19fb772
// converged to the family's orbit traversed several times (T, F exactly 3x and the multiplier
// cubed at E = 2016, 0.68655753476589909, exit 0 with an estimate of 3e-15; 5x at 2035), and the
// build of 805a25e (the action check) failed at 2035 (bench/results/orbit_step_count_fix.txt).
// The references are the quad solves' periods, 2026-11-30.
TEST(SaddleOrbit, ArmOneOfALightLongFirstLinkIsTheFundamentalOrbit) {
    model_text t;
    t.m1 = "0.1", t.m2 = "10", t.L1 = "5", t.L2 = "1", t.a1 = "2.5", t.a2 = "0.5";
    t.I1 = "0", t.I2 = "0.0003", t.g = "20";
    const double_pendulum<double> model(parse_parameters<double>(t));
    for (const auto& [energy, quad] : {std::pair{2016.0, 0.22885251158863303870113414282637327},
                                       std::pair{2035.0, 0.452681557110620144544428278512551111}}) {
        const saddle_orbit<double> o = solve_saddle_orbit(model, arm::one, energy);
        ASSERT_NE(o.status, orbit_status::not_converged) << energy << ": " << o.double_stage;
        EXPECT_NEAR(o.period, quad, 1e-13) << energy;
        EXPECT_LE(std::abs(o.period - quad), o.error_estimate_period) << energy;
    }
}

// A light second arm (a rigid first link): the arm-2 family's swing of theta2 grows with E until
// it reaches the vertical opposite the saddle's (|delta2| = pi) at E - E_s = 5.2529; beyond it
// the family's orbits leave the saddle's strip and are no saddle orbits. The continuation used to
// end in "no convergence" there (a scan of random pendulums, bench/results/orbit_family_scan_*);
// it now names the family's end, and the end is checked on the orbit solved there: its quarter's
// largest |delta2| (at the turning point, a sample of the stored quarter) is pi.
TEST(SaddleOrbit, AFamilyThatLeavesItsStripNamesItsEnd) {
    model_text t;
    t.m1 = "0.1792", t.m2 = "0.101", t.L1 = "1.98", t.a1 = "0.991", t.I1 = "0.05868";
    t.L2 = t.a2 = "0.586", t.I2 = "0", t.g = "9.81";
    const double_pendulum<double> model(parse_parameters<double>(t));
    const double es = model.saddle_energy(arm::two);
    const saddle_orbit<double> beyond = solve_saddle_orbit(model, arm::two, 6.55);
    ASSERT_EQ(beyond.status, orbit_status::not_converged);
    ASSERT_TRUE(std::isfinite(beyond.family_end)) << beyond.double_stage;
    EXPECT_EQ(beyond.family_end_angle, 2);
    auto swing = [&](double excess) {
        const saddle_orbit<double> o = solve_saddle_orbit(model, arm::two, es + excess);
        EXPECT_NE(o.status, orbit_status::not_converged) << excess << ": " << o.double_stage;
        double m = 0;
        for (const auto& q : o.quarter)
            m = std::max(m, std::abs(q[1]));
        return m;
    };
    EXPECT_NEAR(swing(beyond.family_end), pi<double>(), 1e-6);
    EXPECT_LT(swing(0.99 * beyond.family_end), pi<double>() - 1e-3);
    try {
        throw_not_converged(model, arm::two, parse_energy_level<double>("6.55", "energy"), beyond,
                            "saddle orbit");
        FAIL();
    } catch (const input_error& e) {
        EXPECT_EQ(e.field(), "energy");
        const std::string w = e.what();
        EXPECT_NE(w.find("'6.55' lies beyond the end of the arm-2 saddle-orbit family"),
                  std::string::npos)
            << w;
        EXPECT_NE(w.find("theta2"), std::string::npos) << w;
    }
}

// Every rejected step of a continuation is recorded with its reason, one per halving.
template <class Family>
void expect_rejections_recorded(const Family& fam) {
    int rejected = 0;
    for (const auto& st : fam.steps)
        if (!st.accepted) {
            ++rejected;
            EXPECT_FALSE(st.note.empty());
        }
    EXPECT_EQ(rejected, fam.halvings);
}

TEST(SaddleOrbit, ContinuationReachesBothFamiliesAndRecordsItsSteps) {
    const double_pendulum<double> model;
    const auto fam2 = continue_saddle_family(
        model, arm::two, std::vector<double>{2.1, 3, 4, 5, 5.9}, {orbit_method::symmetric});
    ASSERT_EQ(fam2.orbits.size(), 5u);
    EXPECT_TRUE(fam2.stop_reason.empty());
    EXPECT_GE(fam2.steps.size(), 5u);
    for (std::size_t i = 1; i < fam2.orbits.size(); ++i) {
        EXPECT_GT(fam2.orbits[i].action, fam2.orbits[i - 1].action);  // dF/dE = T > 0
        EXPECT_GT(fam2.orbits[i].period, fam2.orbits[i - 1].period);
    }
    EXPECT_NEAR(fam2.highest_excess, 3.9, 1e-12);
    const auto fam1 = continue_saddle_family(model, arm::one, std::vector<double>{4.001, 5, 5.99});
    ASSERT_EQ(fam1.orbits.size(), 3u);
    expect_rejections_recorded(fam1);
    expect_rejections_recorded(fam2);
    // a single orbit from the family agrees with a direct solve
    const auto direct = solve_saddle_orbit(model, arm::one, 5.0);
    EXPECT_NEAR(direct.period, fam1.orbits[1].period, 1e-12 * direct.period);
}

// Arm 1's family continued to a millionth below E_max (where the period diverges): it gets there,
// halving its steps on the way, each rejected step recorded with its reason. (66 steps: 52 s of
// CI's instrumented build, so left to `verify`, CMakePresets.json's ci test preset.)
TEST(SaddleOrbit, ArmOneContinuationReachesAMillionthBelowTheMaximum) {
    const double_pendulum<double> model;
    const auto fam1 =
        continue_saddle_family(model, arm::one, std::vector<double>{4.001, 5, 5.999999});
    ASSERT_EQ(fam1.orbits.size(), 3u);
    EXPECT_TRUE(fam1.stop_reason.empty());
    for (std::size_t i = 1; i < fam1.orbits.size(); ++i)
        EXPECT_GT(fam1.orbits[i].period, fam1.orbits[i - 1].period);
    expect_rejections_recorded(fam1);
    EXPECT_GT(fam1.halvings, 0);
}

TEST(SaddleOrbit, BadEnergiesAreInputErrors) {
    const double_pendulum<double> model;
    for (double E : {2.0, 1.5, 6.0, 7.0, -1.0, std::nan("")}) {
        EXPECT_THROW(solve_saddle_orbit(model, arm::two, E), input_error) << E;
        EXPECT_THROW(refine_saddle_orbit(model, arm::two, E, {0.1, 6.0}), input_error);
    }
    EXPECT_THROW(solve_saddle_orbit(model, arm::one, 4.0), input_error);
    EXPECT_THROW(solve_saddle_orbit(model, arm::one, 3.0), input_error);
    try {
        solve_saddle_orbit(model, arm::one, 3.5);
        FAIL();
    } catch (const input_error& e) {
        EXPECT_EQ(e.field(), "energy") << e.what();
        EXPECT_NE(std::string(e.what()).find("arm-1"), std::string::npos);
    }
    EXPECT_THROW(continue_saddle_family(model, arm::two, std::vector<double>{3, 2.5}), input_error);
    EXPECT_THROW(continue_saddle_family(model, arm::two, std::vector<double>{3, 6.5}), input_error);
    EXPECT_THROW(parse_name<orbit_method>("ceres", "method"), input_error);
    EXPECT_EQ(parse_name<orbit_method>("symmetric", "method"), orbit_method::symmetric);
    EXPECT_EQ(to_string(orbit_method::periodic), "periodic");
    EXPECT_EQ(to_string(orbit_status::stalled), "stalled");
    EXPECT_EQ(to_string(orbit_status::not_converged), "not converged");
    EXPECT_EQ(to_string(orbit_status::converged), "converged");
}

// A not-converged orbit whose double stage reported `stage`.
saddle_orbit<double> failed_with(const std::string& stage) {
    saddle_orbit<double> o;
    o.status = orbit_status::not_converged;
    o.double_stage = stage;
    return o;
}

// An orbit that did not converge is the user's energy's fault within 1e-6 (E_max - E_s) of E_max
// (the period diverges there; each precision's continuation stops short): an input_error naming
// the energy, E_max and E_max - E, carried from the decimal. Elsewhere it stays a runtime error.
// (LimitsCommand.SaddleOrbitsTooCloseToTheMaximumAreRefused runs a real case end to end.)
TEST(SaddleOrbit, NoConvergenceJustBelowTheMaximumIsTheEnergysFault) {
    const double_pendulum<double> model;
    try {
        throw_not_converged(model, arm::two, parse_energy_level<double>("5.9999999999", "energy"),
                            failed_with("the stage"), "saddle orbit");
        FAIL();
    } catch (const input_error& e) {
        EXPECT_EQ(e.field(), "energy") << e.what();
        const std::string w = e.what();
        EXPECT_NE(w.find("'5.9999999999' is too close to E_max = 6"), std::string::npos) << w;
        EXPECT_NE(w.find("E_max - E = 1e-10"), std::string::npos) << w;
        EXPECT_NE(w.find("the stage"), std::string::npos) << w;
    }
    // 4e-6 below E_max is 1e-6 of (E_max - E_s) = 4: beyond it the failure is not the energy's
    for (const char* e : {"5.99999", "4"}) {
        try {
            throw_not_converged(model, arm::two, parse_energy_level<double>(e, "energy"),
                                failed_with("s"), "w");
            FAIL();
        } catch (const input_error& x) {
            ADD_FAILURE() << e << ": " << x.what();
        } catch (const std::runtime_error& x) {
            EXPECT_NE(std::string(x.what()).find("no convergence"), std::string::npos);
        }
    }
}

// A pendulum whose arm-2 saddle orbits are far too unstable for shooting (found by an independent
// cross-check: a light long first link, a heavy short second one): the continuation fails at the
// first orbit next to the saddle, and the failure names the cause instead of "no convergence".
// The multiplier's estimate exp(lambda 2 pi / omega_c) is checked against the saddle's modes
// from the coefficients by hand: M* = [[A, -C], [-C, B]], K* = diag(alpha, -beta) at (0, pi), so
// x = W^2 solves D0 x^2 + (A beta - alpha B) x - alpha beta = 0.
TEST(SaddleOrbit, OrbitsTooUnstableForShootingNameTheirMultiplier) {
    model_text t;
    t.m1 = "0.1", t.m2 = "10", t.L1 = "5", t.L2 = "0.2", t.a1 = "2.5", t.a2 = "0.1";
    t.I1 = "0", t.I2 = "0.0003", t.g = "20";
    const double_pendulum<double> model(parse_parameters<double>(t));
    const auto& k = model.coefficients();
    const double b = k.A * k.beta - k.alpha * k.B,
                 disc = std::sqrt(b * b + 4 * k.D0 * k.alpha * k.beta);
    const double x_centre = (-b + disc) / (2 * k.D0), x_growth = (-b - disc) / (2 * k.D0);
    const double log10_mu =
        std::sqrt(-x_growth) * 2 * pi<double>() / std::sqrt(x_centre) / std::log(10.0);
    ASSERT_GT(log10_mu, 254);
    ASSERT_LT(log10_mu, 255);  // printed as 1e255
    // NOTE: the continuation's failure itself (solve_saddle_orbit: 3 s in the release build,
    // 170 s in CI's instrumented one) is measured in bench/results/unstable_orbits_scan.txt; here
    // the failure's report, from the stage text it would carry
    const energy_level<double> level = parse_energy_level<double>("41", "energy");
    try {
        throw_not_converged(model, arm::two, level, failed_with("the stage"), "saddle orbit");
        FAIL();
    } catch (const input_error& e) {
        const std::string w = e.what();
        EXPECT_EQ(w.find("saddle orbit at E = 41 (arm 2): the pendulum's saddle orbits for this "
                         "arm are too unstable to be found by shooting"),
                  0u)
            << w;
        EXPECT_NE(w.find("about 1e255"), std::string::npos) << w;
        EXPECT_NE(w.find("the stage"), std::string::npos) << w;
    }
    // the same pendulum's arm-1 saddle is barely unstable (multiplier ~ 1.07 near it): a failure
    // there is not blamed on instability
    try {
        throw_not_converged(model, arm::one, parse_energy_level<double>("2014", "energy"),
                            failed_with("the stage"), "saddle orbit");
        FAIL();
    } catch (const input_error& e) {
        ADD_FAILURE() << e.what();
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find("no convergence"), std::string::npos) << e.what();
    }
}

TEST(SaddleOrbit, TheContinuationStaysOnTheFamilyOfARigidPendulum) {
    model_text t;
    t.m1 = "0.7", t.m2 = "1.9", t.L1 = "1.3", t.L2 = "0.8", t.a1 = "0.5", t.a2 = "0.45";
    t.I1 = "0.11", t.I2 = "0.07", t.g = "2.3";
    const double_pendulum<double> model(parse_parameters<double>(t));
    const std::vector<std::pair<const char*, double>> reference{
        {"12.5", 5.61264684877506347331308639301921559674},
        {"12.8", 5.68987874965374943731086250084380072066},
        {"16.888095", 12.9560476918484325686676023891585579623}};
    for (const auto& [energy, period] : reference) {
        const saddle_orbit<double> orbit =
            solve_saddle_orbit<double>(model, arm::two, parse_energy_level<double>(energy, "E"));
        ASSERT_NE(orbit.status, orbit_status::not_converged) << energy << orbit.double_stage;
        EXPECT_LE(std::abs(orbit.period - period), orbit.error_estimate_period) << energy;
        EXPECT_LE(std::abs(orbit.period - period), 1e-12 * period) << energy;
    }
}

TEST(SaddleOrbit, HopelessGuessesAreReportedNotThrown) {
    const double_pendulum<double> model;
    // a direction far from the orbit's and a wrong period: Ceres does not find a zero
    for (auto m : {orbit_method::periodic, orbit_method::symmetric}) {
        const auto o = refine_saddle_orbit(model, arm::two, 5.5, {2.0, 1.0}, {m});
        EXPECT_EQ(o.status, orbit_status::not_converged);
        EXPECT_FALSE(o.double_stage.empty());
    }
}

// Regression (issue 20): at E = E_max - 1e-6 the periodic shooting's residual has a rounding
// floor eps |mu| (|mu| ~ 1e26) above the orbit's scale in double: the default method failed
// with "no convergence" (arm 2) or reached a root with T < 0 (arm 1). The symmetric solution is
// reported instead, and it must agree with the quad orbit (symmetric shooting with 10 and 14
// Gauss-Legendre stages, which agree to 4e-30: verify_orbits_precision JustBelowTheMaximum)
// within the solver's error estimate.
TEST(SaddleOrbit, PeriodicMethodJustBelowTheMaximumReportsTheSymmetricOrbit) {
    const double_pendulum<double> model;
    const struct {
        arm a;
        double quad_period;
    } cases[] = {{arm::two, 39.3672933893950783395628681287972145},
                 {arm::one, 38.1122293126956412818619081185069069}};
    for (const auto& c : cases) {
        const auto o = solve_saddle_orbit(model, c.a, 6 - 1e-6, {orbit_method::periodic});
        ASSERT_NE(o.status, orbit_status::not_converged) << o.double_stage;
        EXPECT_EQ(o.method, orbit_method::symmetric) << o.double_stage;
        EXPECT_NE(o.double_stage.find("symmetric solution is reported"), std::string::npos);
        EXPECT_GT(o.action, 0);
        EXPECT_LE(std::abs(o.period - c.quad_period), o.error_estimate_period)
            << "arm " << to_string(c.a) << ": T = " << o.period;
        // the estimate is honest, not vacuous: the period's condition number E |dT/dE| / T is
        // ~4e5 here, so a few 1e-10 relative is what double can give
        EXPECT_LE(o.error_estimate_period / o.period, 1e-8);
    }
}

// Regression (found by the light-upper-arm golden set): the Gauss-Legendre step estimate of the
// quarter orbit, started from 4 steps, took a pre-asymptotic agreement of 4, 8 and 16 steps for
// convergence and chose 8 steps at E = 5.65 (arm 2), an error of 1e-5 in the period. The pilot
// now starts at 16 steps. Reference: the orbit in mp:40 with the Taylor integrator (another
// integrator, another precision), where periodic and symmetric shooting agree to all 42 printed
// digits (`flipflux eval period|action --arm 2 --energy 5.65 --m1 0.1 --L2 2 --precision mp:40
// --method periodic|symmetric`). Tolerance: 4096 eps, the quarter-orbit integration's rounding
// amplified by the orbit's instability (its error estimate is ~1e-12).
TEST(SaddleOrbit, GaussLegendreStepsAreAsymptoticForALightUpperArm) {
    physical_parameters<double> p;
    p.m1 = 0.1;
    p.L2 = 2;
    p.a2 = 2;
    const auto d =
        solve_saddle_orbit(double_pendulum<double>(p), arm::two, 5.65, {orbit_method::periodic});
    ASSERT_EQ(d.status, orbit_status::converged);
    const double tol = 4096 * std::numeric_limits<double>::epsilon();
    EXPECT_LE(relative_error(d.period, "7.28340655583798875008185236371620332594207"), tol);
    EXPECT_LE(relative_error(d.action, "8.59556620809818067996926440759948672535336"), tol);
}

}  // namespace
}  // namespace flipflux::test
