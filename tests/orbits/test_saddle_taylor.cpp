// The saddle frame's Taylor recurrences (orbits/saddle_taylor.hpp) against independent routes:
// coefficients 1 and 2 from saddle_frame::rhs_and_jacobian (x_1 = f, x_2 = J f / 2, Phi_1 = J),
// coefficient 3 from central differences of J f along the flow, the Taylor shot against the
// Gauss-Legendre shot (state, action, Phi), and the saddle orbit solved with either integrator.
#include <cmath>
#include <string>
#include <utility>

#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/orbits/saddle_taylor.hpp"
#include "flipflux/orbits/shooting.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

template <class Real>
class SaddleTaylor : public test::real_test<Real> {};
TYPED_TEST_SUITE(SaddleTaylor, real_types, real_name);

template <class Real>
using matrix4 = std::array<std::array<Real, 4>, 4>;

template <class Real>
std::array<Real, 4> times(const matrix4<Real>& J, const std::array<Real, 4>& v) {
    std::array<Real, 4> r;
    for (int i = 0; i < 4; ++i) {
        r[i] = 0;
        for (int j = 0; j < 4; ++j)
            r[i] += J[i][j] * v[j];
    }
    return r;
}

/// A generic state away from the saddle (both arms).
template <class Real>
std::array<Real, 4> some_state() {
    return {Real(3) / 10, Real(-2) / 5, Real(7) / 10, Real(-1) / 2};
}

TYPED_TEST(SaddleTaylor, LowCoefficientsMatchRhsAndJacobian) {
    using Real = TypeParam;
    using std::abs;
    // (every coefficient at the working precision: an order-6 expansion graded for its own
    // tolerance would carry ~ 80 bits)
    const taylor::graded_precision_scope uniform(false);
    // unequal point masses (m1 = 1, m2 = 3, L1 = 1, L2 = 0.75, g = 9.75): every coefficient nonzero
    physical_parameters<Real> par;
    par.m2 = 3;
    par.L2 = par.a2 = Real(3) / 4;
    par.g = Real(39) / 4;
    const double_pendulum<Real> model(par);
    const double tol = 256 * static_cast<double>(eps<Real>());
    for (arm a : {arm::one, arm::two}) {
        const saddle_frame<Real> frame(model, a);
        const auto x = some_state<Real>();
        std::array<Real, 4> f;
        matrix4<Real> J;
        const Real lw = frame.rhs_and_jacobian(x, f, J);
        const auto Jf = times(J, f);
        const int p = 6;
        taylor_integrator<Real, 21> ti(p);
        saddle_taylor_flow<Real, 4> flow(frame, p);
        std::array<Real, 21> y{};
        for (int k = 0; k < 4; ++k)
            y[k] = x[k];
        for (int i = 0; i < 4; ++i)
            y[5 + 5 * i] = 1;
        ASSERT_TRUE(ti.expand(flow, y));
        const auto& c = ti.jet();
        for (int i = 0; i < 4; ++i) {
            EXPECT_LE(static_cast<double>(abs(c[i][1] - f[i])), tol) << i;
            EXPECT_LE(static_cast<double>(abs(c[i][2] - Jf[i] / 2)), tol) << i;
            for (int j = 0; j < 4; ++j)
                EXPECT_LE(static_cast<double>(abs(c[5 + 4 * i + j][1] - J[i][j])), tol) << i << j;
        }
        EXPECT_LE(static_cast<double>(abs(c[4][1] - lw)), tol);
        // the two-column flow carries the same last two columns
        taylor_integrator<Real, 13> t2(p);
        saddle_taylor_flow<Real, 2> flow2(frame, p);
        std::array<Real, 13> y2{};
        for (int k = 0; k < 4; ++k)
            y2[k] = x[k];
        y2[5 + 2 * 2 + 0] = 1;
        y2[5 + 2 * 3 + 1] = 1;
        ASSERT_TRUE(t2.expand(flow2, y2));
        for (int i = 0; i < 4; ++i)
            for (int j = 0; j < 2; ++j)
                for (int k = 0; k <= p; ++k)
                    EXPECT_EQ(t2.jet()[5 + 2 * i + j][k], c[5 + 4 * i + 2 + j][k]);
    }
}

TEST(SaddleTaylorQuad, ThirdCoefficientMatchesDifferencesOfTheJacobian) {
    using Real = quad;
    using std::abs;
    // x_3 = (J' f + J J f) / 6, J' f = d/dh J(x + h f) f at h = 0 (central differences, h^2 error)
    // (every coefficient at quad: an order-4 expansion graded for its own tolerance computes
    // coefficients 1..3 in the double tail)
    const taylor::graded_precision_scope uniform(false);
    const double_pendulum<Real> model;
    const Real h = Real(1) / 10000000000LL;
    for (arm a : {arm::one, arm::two}) {
        const saddle_frame<Real> frame(model, a);
        const auto x = some_state<Real>();
        std::array<Real, 4> f, fp, fm;
        matrix4<Real> J, Jp, Jm;
        frame.rhs_and_jacobian(x, f, J);
        std::array<Real, 4> xp, xm;
        for (int i = 0; i < 4; ++i) {
            xp[i] = x[i] + h * f[i];
            xm[i] = x[i] - h * f[i];
        }
        frame.rhs_and_jacobian(xp, fp, Jp);
        frame.rhs_and_jacobian(xm, fm, Jm);
        const auto Jf = times(J, f), JJf = times(J, Jf), Jpf = times(Jp, f), Jmf = times(Jm, f);
        taylor_integrator<Real, 5> ti(4);
        saddle_taylor_flow<Real> flow(frame, 4);
        ASSERT_TRUE(ti.expand(flow, std::array<Real, 5>{x[0], x[1], x[2], x[3], Real(0)}));
        for (int i = 0; i < 4; ++i) {
            const Real ref = ((Jpf[i] - Jmf[i]) / (2 * h) + JJf[i]) / 6;
            EXPECT_LE(static_cast<double>(abs(ti.jet()[i][3] - ref)), 1e-17) << i;
        }
    }
}

/// The coefficients of two order-p expansions of the state at y: the flow as built (graded
/// precision on: at quad the double tail) and the same flow with every coefficient at quad.
template <bool Action>
struct quad_expansions {
    static constexpr std::size_t N = Action ? 5 : 4;
    using flow = saddle_taylor_flow<quad, 0, Action>;
    taylor_integrator<quad, N> tail, uniform;
    int split = 0, uniform_split = 0;
    int tail_coefficients = 0;  ///< of the tail's expansion
    quad_expansions(const saddle_frame<quad>& frame, int p, const std::array<quad, N>& y)
        : tail(p), uniform(p) {
        flow f(frame, p);
        split = f.split();
        EXPECT_TRUE(tail.expand(f, y));
        tail_coefficients = f.tail_coefficients();
        const taylor::graded_precision_scope off(false);
        flow g(frame, p);
        uniform_split = g.split();
        EXPECT_TRUE(uniform.expand(g, y));
    }
};

/// Checks the tail's expansion at x against the all-quad one; returns how many coefficients the
/// tail computed.
template <bool Action>
int expect_tail_within_its_share(const saddle_frame<quad>& frame, const std::array<quad, 4>& x,
                                 const std::string& what) {
    using std::abs;
    using std::pow;
    constexpr std::size_t N = quad_expansions<Action>::N;
    std::array<quad, N> y{};
    for (std::size_t i = 0; i < 4; ++i)
        y[i] = x[i];
    const quad tol = eps<quad>();
    const int p = taylor_order_for(tol);
    const quad_expansions<Action> e(frame, p, y);
    EXPECT_EQ(e.split, p - 12) << what;  // 2 (p - 1 - k) / ln 2 + 20 <= 53 from k = p - 12 on
    EXPECT_EQ(e.uniform_split, p + 1) << what;
    std::array<quad, N> scale;
    for (std::size_t i = 0; i < N; ++i)
        scale[i] = 1 + abs(y[i]);
    const quad h = e.uniform.step_size(tol, scale);
    for (std::size_t i = 0; i < N; ++i) {
        const auto& a = e.tail.jet()[i];
        const auto& b = e.uniform.jet()[i];
        for (int k = 0; k <= p; ++k) {
            const auto K = static_cast<std::size_t>(k);
            if (k < e.split) {
                EXPECT_EQ(a[K], b[K]) << what << ": component " << i << ", coefficient " << k;
                continue;
            }
            // the tail coefficient's share of the step: at most 2^-12 of the tolerance (design:
            // ~ 2^-20 and below for a component whose scale fits its coefficients; the action
            // starting at 0 at momenta 1e4 gives ~ 2^-15.5; an error of 2^-40 relative to
            // coefficient p - 12 of a state component would exceed it)
            EXPECT_LE(static_cast<double>(abs(a[K] - b[K]) * pow(h, k) / scale[i]),
                      static_cast<double>(tol) * 0x1p-12)
                << what << ": component " << i << ", coefficient " << k;
        }
        EXPECT_LE(
            static_cast<double>(abs(e.tail.evaluate(h)[i] - e.uniform.evaluate(h)[i]) / scale[i]),
            4 * static_cast<double>(tol))
            << what << ": component " << i;
    }
    return e.tail_coefficients;
}

TEST(SaddleTaylorQuad, DoubleTailCoefficientsStayWithinTheirShareOfTheStep) {
    // the double tail (coefficients k >= p - 12 of a quad expansion in double) against the same
    // expansion with every coefficient at quad (graded precision off), with and without the
    // action, for both arms, at ordinary and high energies (momenta up to 1e6: the coefficients
    // grow like rho^-k past 2^400 before the order, where the tail turns itself off mid-way)
    physical_parameters<quad> unequal;
    unequal.m2 = 3;
    unequal.L2 = unequal.a2 = quad(3) / 4;
    int partial = 0;  // expansions whose tail turned itself off past the split
    for (const auto& par : {physical_parameters<quad>{}, unequal}) {
        const double_pendulum<quad> model(par);
        for (arm a : {arm::one, arm::two}) {
            const saddle_frame<quad> frame(model, a);
            for (const double l : {0.0, 1.0, 7.0, 1e2, 1e4, 1e6}) {
                const std::array<quad, 4> x{quad(3) / 10, quad(-2) / 5, quad(l) + quad(7) / 10,
                                            quad(-l) / 2 - quad(1) / 2};
                const std::string what =
                    "arm " + std::to_string(static_cast<int>(a)) + ", l = " + std::to_string(l);
                for (const int n :
                     {expect_tail_within_its_share<true>(frame, x, what + " (action)"),
                      expect_tail_within_its_share<false>(frame, x, what)}) {
                    // the tail runs to the order (12 coefficients) at ordinary momenta
                    if (l <= 7) {
                        EXPECT_EQ(n, 12) << what;
                    }
                    if (n > 0 && n < 12) ++partial;
                }
            }
        }
    }
    EXPECT_GT(partial, 0);  // the fallback from inside the tail was exercised
}

TEST(SaddleTaylorQuad, DoubleTailStandsAsideOutsideDoublesRange) {
    // masses of 1e150 and of 1e-150 at quad (A B - C^2 ~ 1e+-300, beyond 2^+-400): the expansion
    // is the uniform one bit for bit
    for (const char* mass : {"1e150", "1e-150"}) {
        physical_parameters<quad> par;
        par.m1 = par.m2 = quad(mass);
        const double_pendulum<quad> model(par);
        const saddle_frame<quad> frame(model, arm::two);
        const quad l = par.m1 / 2;  // angular velocities of order 1
        const int p = taylor_order_for(eps<quad>());
        const quad_expansions<false> e(frame, p, {quad(1) / 3, quad(2), l, -l / 5});
        ASSERT_EQ(e.split, p - 12);
        EXPECT_EQ(e.tail_coefficients, 0) << mass;  // turned off at the split
        for (std::size_t i = 0; i < 4; ++i)
            for (int k = 0; k <= p; ++k)
                ASSERT_EQ(e.tail.jet()[i][static_cast<std::size_t>(k)],
                          e.uniform.jet()[i][static_cast<std::size_t>(k)])
                    << mass << ": " << i << ", " << k;
    }
}

TYPED_TEST(SaddleTaylor, ShotAgreesWithGaussLegendre) {
    using Real = TypeParam;
    using std::abs;
    using std::max;
    // a quarter of the saddle orbit's linear period from the saddle at E - E_s = 1, both
    // integrators at their working accuracy: state, action and Phi agree to the tolerance times
    // the growth of Phi over the shot
    // NOTE: not at mp: the Gauss-Legendre side needs ~30 stages there (seconds at -O0); mp's
    // integration is checked by Mp60AgreesWithGaussLegendreAtQuad and verify_orbits_taylor
    if constexpr (has_variable_precision_v<Real>) GTEST_SKIP() << "see the NOTE";
    const double_pendulum<Real> model;
    for (arm a : {arm::one, arm::two}) {
        const auto guess = linear_guess(model, a);
        const Real tol = 64 * eps<Real>();
        // (more stages than the solver's: the steps are longer than its)
        const int stages = std::is_same_v<Real, double> ? 12 : std::is_same_v<Real, quad> ? 24 : 32;
        const detail::shooting_setup<Real> gl(model, a, Real(1), stages);
        const detail::shooting_setup<Real> ty(model, a, Real(1), 0, orbit_integrator::taylor,
                                              taylor_order_for(tol));
        const auto x0 = gl.start(guess.beta);
        // equal steps of T / 128 for both (within the Taylor series' Jorba-Zou step); at mp a
        // shorter shot keeps the Gauss-Legendre side cheap
        const bool mp_type = has_variable_precision_v<Real>;
        const Real tau = guess.period / (mp_type ? 128 : 16);
        const long n = mp_type ? 1 : 8;
        const auto eg = detail::integrate_variational(gl, x0, tau, n);
        const auto et = detail::integrate_variational(ty, x0, tau, n);
        const auto e2 = detail::integrate_variational(ty, x0, tau, n, 2);
        ASSERT_TRUE(eg.success && et.success && e2.success);
        Real growth = 1;
        for (const auto& row : eg.phi)
            for (const Real& v : row)
                growth = max(growth, abs(v));
        const double bound = 1024 * static_cast<double>(tol * growth);
        for (int i = 0; i < 4; ++i) {
            EXPECT_LE(static_cast<double>(abs(eg.x[i] - et.x[i])), bound) << i;
            for (int j = 0; j < 4; ++j) {
                EXPECT_LE(static_cast<double>(abs(eg.phi[i][j] - et.phi[i][j])), bound) << i << j;
                EXPECT_EQ(e2.phi[i][j], j < 2 ? Real(0) : et.phi[i][j]);
            }
        }
        EXPECT_LE(static_cast<double>(abs(eg.action - et.action)), bound);
        const auto sg = detail::integrate_state(gl, x0, tau, n);
        const auto st = detail::integrate_state(ty, x0, tau, n);
        for (int i = 0; i < 4; ++i)
            EXPECT_LE(static_cast<double>(abs(sg.x[i] - st.x[i])), bound) << i;
        const auto mg = detail::quarter_extent(gl, guess.beta, tau, n);
        const auto mt = detail::quarter_extent(ty, guess.beta, tau, n);
        EXPECT_LE(static_cast<double>(abs(mg[0] - mt[0]) + abs(mg[1] - mt[1])), bound);
    }
}

/// An orbit's T, F and stability index by one integrator (symmetric shooting: the cheaper one).
template <class Real>
saddle_orbit<Real> orbit_by(arm a, const Real& energy, orbit_integrator integrator,
                            orbit_method method = orbit_method::symmetric) {
    orbit_options<Real> options;
    options.method = method;
    options.integrator = integrator;
    return solve_saddle_orbit(double_pendulum<Real>(), a, energy, options);
}

TEST(SaddleTaylorOrbit, AgreesWithGaussLegendreAtQuad) {
    using std::abs;
    using std::sqrt;
    // T and F agree within the sum of the two error estimates, the stability index
    // within 64 eps |mu|^(1/4) relative (the quarter orbit's amplification, docs/theory.md)
    const quad e = std::numeric_limits<quad>::epsilon();
    // (arm 1's recurrences are checked by LowCoefficientsMatchRhsAndJacobian and the shots)
    for (const auto& [a, E] : {std::pair{arm::two, quad(3)}}) {
        const auto t = orbit_by(a, E, orbit_integrator::taylor);
        const auto g = orbit_by(a, E, orbit_integrator::gauss_legendre);
        ASSERT_EQ(t.status, orbit_status::converged) << t.double_stage;
        ASSERT_EQ(g.status, orbit_status::converged) << g.double_stage;
        EXPECT_EQ(t.integrator, orbit_integrator::taylor);
        EXPECT_EQ(t.order, taylor_order_for(64 * e));
        EXPECT_EQ(g.integrator, orbit_integrator::gauss_legendre);
        EXPECT_LE(abs(t.period - g.period), t.error_estimate_period + g.error_estimate_period);
        EXPECT_LE(abs(t.action - g.action), t.error_estimate_action + g.error_estimate_action);
        EXPECT_LE(t.error_estimate_period / t.period, 16384 * e);
        const quad mu = abs(g.floquet.multiplier);
        EXPECT_LE(abs(t.floquet.stability_index - g.floquet.stability_index) / mu,
                  64 * e * sqrt(sqrt(mu)));
        // the periodic formulation by Taylor: the monodromy from half the period, squared
        const auto tp = orbit_by(a, E, orbit_integrator::taylor, orbit_method::periodic);
        ASSERT_EQ(tp.status, orbit_status::converged) << tp.double_stage;
        EXPECT_LE(abs(tp.period - g.period), tp.error_estimate_period + g.error_estimate_period);
        EXPECT_LE(abs(tp.floquet.stability_index - g.floquet.stability_index) / mu, 2 * e * mu);
        // the orbit's states between the stored ones come from the Taylor polynomial
        const double_pendulum<quad> model;
        const auto x = orbit_state(model, t, t.period / 7);
        const auto y = orbit_state(model, g, g.period / 7);
        for (int i = 0; i < 4; ++i)
            EXPECT_LE(abs(x[i] - y[i]), 1e-28) << i;
        // the saddle curve's root finder runs on the Taylor polynomials (dense output)
        if (a == arm::two) {
            const auto ct = make_saddle_curve(model, t), cg = make_saddle_curve(model, g);
            const quad s = ct.domain()[1] * 3 / 5;
            EXPECT_LE(abs(ct.offset(s) - cg.offset(s)), 1e-28);
            EXPECT_LE(abs(ct.domain()[1] - cg.domain()[1]), 1e-28);
        }
    }
}

TEST(SaddleTaylorOrbit, Mp60AgreesWithGaussLegendreAtQuad) {
    // mp:60: quad's Newton, then the chord iteration in mp (the ladder), against the independent
    // route at quad: T and F to quad's error estimate
    const auto g = orbit_by(arm::two, quad(3), orbit_integrator::gauss_legendre);
    ASSERT_EQ(g.status, orbit_status::converged);
    const precision_scope scope(mp_precision(60));
    const auto t = orbit_by(arm::two, mp(3), orbit_integrator::taylor);
    ASSERT_EQ(t.status, orbit_status::converged) << t.double_stage;
    EXPECT_NE(t.double_stage.find("chord"), std::string::npos) << t.double_stage;
    using std::abs;
    EXPECT_LE(abs(t.period - convert<mp>(g.period)), convert<mp>(2 * g.error_estimate_period));
    EXPECT_LE(abs(t.action - convert<mp>(g.action)), convert<mp>(2 * g.error_estimate_action));
    // its own estimate is at mp:60's level
    EXPECT_LE(t.error_estimate_period / t.period, mp(1) / mp("1e55"));
}

TEST(SaddleTaylorOrbit, GradedPrecisionAgreesWithUniformAtMp) {
    // coefficient k of the jet at ~ 2 (p - 1 - k) / ln 2 + 64 bits (integrators/taylor.hpp) against
    // every coefficient at the working precision: the orbit of arm 1 at E = 5 in mp:140
    // (above 4 x quad's digits: the chord iteration with refreshed Jacobians and the order
    // ladder), T and F within the uniform solve's error estimates
    const precision_scope scope(mp_precision(140));
    const auto graded = orbit_by(arm::one, mp(5), orbit_integrator::taylor);
    saddle_orbit<mp> uniform;
    {
        const taylor::graded_precision_scope off(false);
        uniform = orbit_by(arm::one, mp(5), orbit_integrator::taylor);
    }
    ASSERT_EQ(graded.status, orbit_status::converged) << graded.double_stage;
    ASSERT_EQ(uniform.status, orbit_status::converged) << uniform.double_stage;
    using std::abs;
    EXPECT_LE(abs(graded.period - uniform.period), uniform.error_estimate_period);
    EXPECT_LE(abs(graded.action - uniform.action), uniform.error_estimate_action);
    // (the index's rounding error is ~ eps |mu|, |mu| ~ 1e3 here: 1e-120 leaves a margin of 1e10)
    EXPECT_LE(abs(graded.floquet.stability_index - uniform.floquet.stability_index),
              mp("1e-120") * abs(uniform.floquet.stability_index));
    EXPECT_LE(uniform.error_estimate_period / uniform.period, mp("1e-135"));
    // the grading is active: the last coefficient of an expansion carries ~ 64 bits, the first
    // the working precision
    const saddle_frame<mp> frame(double_pendulum<mp>(), arm::one);
    const int p = taylor_order_for(mp(64 * eps<mp>()));
    taylor_integrator<mp, 5> ti(p);
    saddle_taylor_flow<mp> flow(frame, p);
    const auto x = some_state<mp>();
    ASSERT_TRUE(ti.expand(flow, std::array<mp, 5>{x[0], x[1], x[2], x[3], mp(0)}));
    EXPECT_EQ(mpfr_get_prec(ti.jet()[2][0].backend().data()), binary_digits<mp>());
    EXPECT_LE(mpfr_get_prec(ti.jet()[2][static_cast<std::size_t>(p)].backend().data()), 64 + 64);
}

}  // namespace
}  // namespace flipflux::test
