// The fast double-precision flow (ensemble/pendulum_flow.hpp) against the precision-templated
// model evaluated in 120 digits (an independent implementation: different trigonometric
// formulation, Jacobian written separately), and its tangent map against finite differences of
// two nearby trajectories.
#include <cmath>

#include "ensemble_support.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/integrators/explicit_rk.hpp"

namespace flipflux::test {
namespace {

TEST(PendulumFlow, MatchesTheModelInHighPrecision) {
    random_reals rnd(21);
    double worst = 0;
    for (int trial = 0; trial < 40; ++trial) {
        const auto p =
            trial == 0 ? physical_parameters<double>{} : random_parameters(rnd, trial % 2 == 0);
        const double_pendulum<double> md(p);
        const double_pendulum<reference_real> mq(convert_parameters<reference_real>(p));
        const pendulum_flow flow(md);
        for (int point = 0; point < 5; ++point) {
            const phase_point<double> x{rnd(-3.2, 3.2), rnd(-3.2, 3.2), rnd(-4, 4), rnd(-4, 4)};
            const phase_point<reference_real> xq{reference_real(x[0]), reference_real(x[1]),
                                                 reference_real(x[2]), reference_real(x[3])};
            const auto f = flow(0, x);
            const auto fq = mq.rhs(xq);
            const auto jq = mq.rhs_jacobian(xq);
            const std::array<double, 4> v{rnd(-1, 1), rnd(-1, 1), rnd(-1, 1), rnd(-1, 1)};
            const auto tg = flow.tangent({x[0], x[1], x[2], x[3], v[0], v[1], v[2], v[3]});
            double scale = 0, jscale = 0;
            for (int i = 0; i < 4; ++i) {
                scale = std::max(scale, std::abs(static_cast<double>(fq[i])));
                for (int j = 0; j < 4; ++j)
                    jscale = std::max(jscale, std::abs(static_cast<double>(jq[i][j])));
            }
            for (int i = 0; i < 4; ++i) {
                const double e = std::abs(f[i] - static_cast<double>(fq[i])) / scale;
                worst = std::max(worst, e);
                EXPECT_LT(e, 64 * eps<double>()) << "rhs component " << i;
                EXPECT_EQ(tg[i], f[i]);
                reference_real jv = 0;
                for (int j = 0; j < 4; ++j)
                    jv += jq[i][j] * reference_real(v[j]);
                EXPECT_LT(std::abs(tg[4 + i] - static_cast<double>(jv)),
                          256 * eps<double>() * jscale)
                    << "tangent component " << i;
            }
            const auto w = flow.velocities(x);
            EXPECT_NEAR(w[0], f[0], 4 * eps<double>() * scale);
            EXPECT_NEAR(w[1], f[1], 4 * eps<double>() * scale);
            const double H = static_cast<double>(mq.hamiltonian(xq));
            EXPECT_NEAR(flow.hamiltonian(x), H, 32 * eps<double>() * std::max(1.0, H));
        }
    }
    std::printf("worst relative rhs error %.3g eps\n", worst / eps<double>());
}

// v(t) of the variational equations equals (x(t; x0 + e v0) - x(t; x0 - e v0)) / (2 e) to
// O(e^2) + rounding / e: an independent check of the whole tangent flow over a time span.
TEST(PendulumFlow, TangentMatchesFiniteDifferencesOfTrajectories) {
    const double_pendulum<double> m(lopsided_parameters());
    const pendulum_flow flow(m);
    rk_options o;
    o.rtol = o.atol = 1e-13;
    const phase_point<double> x0{0.3, 2.9, 0.4, -0.2};
    const std::array<double, 4> v0{0.6, -0.3, 0.5, 0.55};
    const double T = 2, e = 1e-5;
    auto end_of = [&](const phase_point<double>& start) {
        explicit_rk<dormand_prince_853, 4, pendulum_flow> rk(flow, o);
        rk.initialize(0, start);
        rk.integrate(T, [](auto&) {});
        return rk.x();
    };
    phase_point<double> plus = x0, minus = x0;
    for (int i = 0; i < 4; ++i) {
        plus[i] += e * v0[i];
        minus[i] -= e * v0[i];
    }
    const auto xp = end_of(plus), xm = end_of(minus);
    o.controlled_components = 4;
    explicit_rk<dormand_prince_853, 8, pendulum_tangent_rhs> rk(pendulum_tangent_rhs{flow}, o);
    rk.initialize(0, {x0[0], x0[1], x0[2], x0[3], v0[0], v0[1], v0[2], v0[3]});
    rk.integrate(T, [](auto&) {});
    for (int i = 0; i < 4; ++i) {
        const double fd = (xp[i] - xm[i]) / (2 * e);
        EXPECT_NEAR(rk.x()[4 + i], fd, 1e-6 * (1 + std::abs(fd))) << i;
    }
}

}  // namespace
}  // namespace flipflux::test
