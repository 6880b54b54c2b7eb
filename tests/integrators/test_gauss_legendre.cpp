// Gauss-Legendre integrator: the tableau against independent facts (Boost's Legendre zeros, the
// simplifying assumptions B(2s), C(s), the symplecticity condition), the observed order on the
// Kepler problem (exact reference: the orbit closes after 2 pi), long-time energy behaviour, time
// reversibility, the variational equations against finite differences of the numerical flow,
// step-count selection and failure handling.
#include <boost/math/special_functions/legendre.hpp>
#include <cmath>

#include "flipflux/core/constants.hpp"
#include "flipflux/integrators/gauss_legendre.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

template <class Real>
class GaussLegendre : public test::real_test<Real> {};
TYPED_TEST_SUITE(GaussLegendre, real_types, real_name);

/// The stage counts whose order is tested at a type: all up to 6 at double and 10 at quad, a
/// spread at MPFR (slow, and the coverage build runs this at -O0).
template <class Real>
std::vector<int> tested_stages() {
    if constexpr (std::is_same_v<Real, double>)
        return {1, 2, 3, 4, 5, 6};
    else if constexpr (std::is_same_v<Real, quad>)
        return {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    else
        return {2, 7, 12};
}

template <class Real>
int max_tested_stages() {
    return tested_stages<Real>().back();
}

TYPED_TEST(GaussLegendre, TableauMatchesBoostZerosAndOrderConditions) {
    using Real = TypeParam;
    using std::abs;
    const double e = static_cast<double>(eps<Real>());
    for (int s = 1; s <= max_tested_stages<Real>(); ++s) {
        const auto& t = gauss_legendre_tableau_of<Real>(s);
        ASSERT_EQ(t.stages, s);
        // Boost returns the non-negative zeros, increasing
        const std::vector<Real> z = boost::math::legendre_p_zeros<Real>(s);
        for (std::size_t k = 0; k < z.size(); ++k) {
            const Real mine = t.roots[static_cast<std::size_t>(s) - z.size() + k];
            EXPECT_LE(static_cast<double>(abs(mine - z[k])), 8 * e) << "s = " << s << " k = " << k;
        }
        const double tol = 64 * s * s * e;
        // B(2s): sum b_i c_i^(k-1) = 1/k
        for (int k = 1; k <= 2 * s; ++k) {
            Real sum = 0;
            for (int i = 0; i < s; ++i)
                sum += t.b[i] * pow(t.c[i], k - 1);
            EXPECT_LE(static_cast<double>(abs(sum * k - 1)), tol) << "B s=" << s << " k=" << k;
        }
        for (int i = 0; i < s; ++i) {
            // C(s): sum_j a_ij c_j^(k-1) = c_i^k / k
            for (int k = 1; k <= s; ++k) {
                Real sum = 0;
                for (int j = 0; j < s; ++j)
                    sum += t.A(i, j) * pow(t.c[j], k - 1);
                EXPECT_LE(static_cast<double>(abs(sum - pow(t.c[i], k) / k)), tol)
                    << "C s=" << s << " i=" << i << " k=" << k;
            }
            // symplecticity: b_i a_ij + b_j a_ji = b_i b_j
            for (int j = 0; j < s; ++j)
                EXPECT_LE(static_cast<double>(
                              abs(t.b[i] * t.A(i, j) + t.b[j] * t.A(j, i) - t.b[i] * t.b[j])),
                          tol);
        }
        // d A = b
        for (int j = 0; j < s; ++j) {
            Real sum = 0;
            for (int i = 0; i < s; ++i)
                sum += t.d[i] * t.A(i, j);
            EXPECT_LE(static_cast<double>(abs(sum - t.b[j])), tol * s);
        }
    }
    EXPECT_THROW(gauss_legendre_tableau_of<Real>(0), std::invalid_argument);
    EXPECT_THROW(gauss_legendre_tableau_of<Real>(max_gauss_legendre_stages + 1),
                 std::invalid_argument);
    EXPECT_EQ(&gauss_legendre_tableau_of<Real>(3), &gauss_legendre_tableau_of<Real>(3));  // cached
}

/// Kepler problem, unit mass parameter: period 2 pi for semi-major axis 1.
template <class Real>
struct kepler {
    void operator()(const std::array<Real, 4>& x, std::array<Real, 4>& dx) const {
        using std::sqrt;
        const Real r2 = x[0] * x[0] + x[1] * x[1];
        const Real r3 = r2 * sqrt(r2);
        dx = {x[2], x[3], -x[0] / r3, -x[1] / r3};
    }
    static Real energy(const std::array<Real, 4>& x) {
        using std::sqrt;
        return (x[2] * x[2] + x[3] * x[3]) / 2 - 1 / sqrt(x[0] * x[0] + x[1] * x[1]);
    }
    static std::array<Real, 4> start(const Real& e) {
        using std::sqrt;
        return {1 - e, Real(0), Real(0), sqrt((1 + e) / (1 - e))};
    }
};

/// Kepler with its variational equations: x (4) then Phi (4x4 row-major).
template <class Real>
struct kepler_variational {
    void operator()(const std::array<Real, 20>& x, std::array<Real, 20>& dx) const {
        using std::sqrt;
        const Real r2 = x[0] * x[0] + x[1] * x[1];
        const Real r = sqrt(r2), r3 = r2 * r, r5 = r3 * r2;
        dx[0] = x[2];
        dx[1] = x[3];
        dx[2] = -x[0] / r3;
        dx[3] = -x[1] / r3;
        // J = [[0, I], [G, 0]], G = -I/r^3 + 3 q q^T / r^5
        const Real g11 = -1 / r3 + 3 * x[0] * x[0] / r5, g12 = 3 * x[0] * x[1] / r5,
                   g22 = -1 / r3 + 3 * x[1] * x[1] / r5;
        for (int col = 0; col < 4; ++col) {
            const Real p0 = x[4 + 0 * 4 + col], p1 = x[4 + 1 * 4 + col];
            const Real p2 = x[4 + 2 * 4 + col], p3 = x[4 + 3 * 4 + col];
            dx[4 + 0 * 4 + col] = p2;
            dx[4 + 1 * 4 + col] = p3;
            dx[4 + 2 * 4 + col] = g11 * p0 + g12 * p1;
            dx[4 + 3 * 4 + col] = g12 * p0 + g22 * p1;
        }
    }
};

template <class Real>
Real max_distance(const std::array<Real, 4>& a, const std::array<Real, 4>& b) {
    using std::abs;
    Real d = 0;
    for (int k = 0; k < 4; ++k)
        if (abs(a[k] - b[k]) > d) d = abs(a[k] - b[k]);
    return d;
}

/// Global error after `periods` Kepler periods with n steps per period (the reference is exact:
/// the orbit closes).
template <class Real>
Real kepler_period_error(int s, long n, const Real& e, int periods = 1) {
    gauss_legendre<Real, 4> gl(s);
    auto x = kepler<Real>::start(e);
    const auto x0 = x;
    const auto r = gl.integrate(kepler<Real>{}, x, two_pi<Real>() / n, n * periods);
    EXPECT_TRUE(r.success);
    return max_distance(x, x0);
}

TYPED_TEST(GaussLegendre, ObservedOrderIsTwiceTheStageCount) {
    using Real = TypeParam;
    using std::log2;
    // e = 0.2 over several periods: the phase error grows linearly, which lifts the errors above
    // the rounding floor (1e4 eps) for a wider window of step sizes
    const Real e = Real(1) / 5;
    const int periods = std::is_same_v<Real, double> ? 20 : 1;
    const Real floor = 1e4 * eps<Real>();
    for (int s : tested_stages<Real>()) {
        // the asymptotic regime: error below 1e-4 and at least 16 steps per period for the high
        // orders (whose errors are tiny before the asymptotic regime); then halve the step while
        // above the floor
        long n = s >= 7 ? 16 : s >= 4 ? 8 : 4;
        Real err = kepler_period_error<Real>(s, n, e, periods);
        while (err > Real(1) / 10000) {
            n *= 2;
            err = kepler_period_error<Real>(s, n, e, periods);
        }
        int checked = 0;
        for (int k = 0; k < 2; ++k) {
            const Real err2 = kepler_period_error<Real>(s, 2 * n, e, periods);
            if (err2 < floor) break;
            const double p = static_cast<double>(log2(err / err2));
            EXPECT_NEAR(p, 2 * s, 1.0)
                << "s = " << s << ", steps per period " << n << " -> " << 2 * n;
            ++checked;
            err = err2;
            n *= 2;
        }
        EXPECT_GE(checked, 1) << "s = " << s << ": no step pair above the rounding floor";
    }
}

TYPED_TEST(GaussLegendre, EnergyErrorStaysBoundedOverLongTimes) {
    using Real = TypeParam;
    using std::abs;
    // 300 periods at double/quad, 30 at MPFR (slow at -O0); s = 2, 20 steps per period: a
    // visible O(h^4) energy oscillation that must not drift
    const long periods = std::is_same_v<Real, double> || std::is_same_v<Real, quad> ? 300 : 15;
    const long per = 40;
    const Real e = Real(1) / 2;
    gauss_legendre<Real, 4> gl(2);
    auto x = kepler<Real>::start(e);
    const Real h0 = kepler<Real>::energy(x);
    Real early = 0, late = 0;
    gl.integrate(kepler<Real>{}, x, two_pi<Real>() / per, periods * per,
                 [&](long k, const std::array<Real, 4>& y) {
                     const Real d = abs(kepler<Real>::energy(y) - h0);
                     if (k <= per * periods / 10) {
                         if (d > early) early = d;
                     } else if (d > late) {
                         late = d;
                     }
                 });
    // bounded oscillation: the last 90 % show the same amplitude as the first 10 %
    EXPECT_LE(static_cast<double>(late), 1.5 * static_cast<double>(early));
    EXPECT_GT(static_cast<double>(early), 0.0);
}

TYPED_TEST(GaussLegendre, RoundoffInEnergyGrowsLikeARandomWalk) {
    using Real = TypeParam;
    using std::abs;
    using std::sqrt;
    // 6 stages, tiny steps: truncation far below rounding, so the energy error is rounding only
    const int s = std::is_same_v<Real, double> ? 6 : 8;
    const long steps = std::is_same_v<Real, double> ? 20000
                       : std::is_same_v<Real, quad> ? 2000
                                                    : 400;
    const Real e = Real(1) / 10;
    gauss_legendre<Real, 4> gl(s);
    auto x = kepler<Real>::start(e);
    const Real h0 = kepler<Real>::energy(x);
    gl.integrate(kepler<Real>{}, x, two_pi<Real>() / 200, steps);
    const double drift = static_cast<double>(abs(kepler<Real>::energy(x) - h0) / abs(h0));
    // a random walk: ~ eps sqrt(steps); a systematic drift would be ~ eps * steps
    EXPECT_LE(drift, 20 * static_cast<double>(eps<Real>()) * std::sqrt(double(steps)));
}

TYPED_TEST(GaussLegendre, IntegrationIsTimeReversible) {
    using Real = TypeParam;
    const Real e = Real(6) / 10;
    for (int s : {1, 3, 6}) {
        gauss_legendre<Real, 4> gl(s);
        const long n = std::is_same_v<Real, double> || std::is_same_v<Real, quad> ? 300 : 60;
        auto x = kepler<Real>::start(e);
        const auto x0 = x;
        const Real h = Real(3) / 100;
        ASSERT_TRUE(gl.integrate(kepler<Real>{}, x, h, n).success);
        ASSERT_TRUE(gl.integrate(kepler<Real>{}, x, -h, n).success);
        EXPECT_LE(static_cast<double>(max_distance(x, x0)),
                  400 * static_cast<double>(eps<Real>()) * std::sqrt(double(n)))
            << "s = " << s;
    }
}

TYPED_TEST(GaussLegendre, VariationalEquationsGiveTheJacobianOfTheNumericalFlow) {
    using Real = TypeParam;
    using std::abs;
    // central differences of the numerical flow in Real with step delta: error ~ delta^2 + eps /
    // delta; the method commutes with differentiation, so the agreement is that of the differences
    const int s = 4;
    const long n = 40;
    const Real h = Real(1) / 10;
    const Real e = Real(1) / 2;
    std::array<Real, 20> xv{};
    const auto x0 = kepler<Real>::start(e);
    for (int k = 0; k < 4; ++k)
        xv[k] = x0[k];
    for (int k = 0; k < 4; ++k)
        xv[4 + 5 * k] = 1;
    gauss_legendre<Real, 20> glv(s);
    ASSERT_TRUE(glv.integrate(kepler_variational<Real>{}, xv, h, n).success);
    using std::cbrt;
    const Real delta = cbrt(eps<Real>());
    double worst = 0;
    for (int col = 0; col < 4; ++col) {
        auto xp = x0, xm = x0;
        xp[col] += delta;
        xm[col] -= delta;
        gauss_legendre<Real, 4> gl(s);
        gl.integrate(kepler<Real>{}, xp, h, n);
        gl.integrate(kepler<Real>{}, xm, h, n);
        for (int row = 0; row < 4; ++row) {
            const Real fd = (xp[row] - xm[row]) / (2 * delta);
            const Real an = xv[4 + row * 4 + col];
            worst = std::max(worst, static_cast<double>(abs(fd - an) / (1 + abs(an))));
        }
    }
    EXPECT_LE(worst, 1e4 * static_cast<double>(delta * delta));
}

TYPED_TEST(GaussLegendre, StepCountReachesTheRequestedTolerance) {
    using Real = TypeParam;
    const Real e = Real(1) / 5;
    const auto x0 = kepler<Real>::start(e);
    const std::array<Real, 4> scale{1, 1, 1, 1};
    const int s = std::is_same_v<Real, double> ? 6 : 10;
    using std::max;
    for (const Real& tol : {Real(1) / 1000000, max(Real(sqrt(eps<Real>()) * 100), Real(1e-24))}) {
        const auto est =
            steps_for_tolerance<Real, 4>(kepler<Real>{}, x0, two_pi<Real>(), tol, s, scale);
        ASSERT_TRUE(est.asymptotic);
        const Real err = kepler_period_error<Real>(s, est.steps, e);
        EXPECT_LE(static_cast<double>(err), 4 * static_cast<double>(tol)) << est.steps;
        // not wastefully many: the error is within a few digits of the tolerance
        EXPECT_GE(static_cast<double>(err), 1e-4 * static_cast<double>(tol)) << est.steps;
    }
}

/// dx = x^2 blows up at t = 1: large steps make the stage iteration diverge.
template <class Real>
struct blow_up {
    void operator()(const std::array<Real, 1>& x, std::array<Real, 1>& dx) const {
        dx[0] = x[0] * x[0];
    }
};

TYPED_TEST(GaussLegendre, FailedStageIterationSplitsTheStepOrFails) {
    using Real = TypeParam;
    gauss_legendre<Real, 1> gl(2);
    std::array<Real, 1> x{Real(1)};
    // one step of 0.9 towards the singularity at t = 1: the iteration cannot converge
    EXPECT_FALSE(gl.step(blow_up<Real>{}, x, Real(9) / 10));
    EXPECT_EQ(x[0], Real(1));
    // integrate splits it into smaller pieces and follows the exact 1 / (1 - t)
    const auto r = gl.integrate(blow_up<Real>{}, x, Real(9) / 10, 1);
    EXPECT_TRUE(r.success);
    EXPECT_GT(r.statistics.split_steps, 0);
    using std::abs;
    EXPECT_LE(static_cast<double>(abs(x[0] - 10) / 10), 5e-2);
    // a right-hand side that returns NaN cannot be integrated at all
    struct nan_rhs {
        void operator()(const std::array<Real, 1>&, std::array<Real, 1>& dx) const {
            dx[0] = std::numeric_limits<Real>::quiet_NaN();
        }
    };
    std::array<Real, 1> y{Real(1)};
    EXPECT_FALSE(gl.integrate(nan_rhs{}, y, Real(1) / 10, 3).success);
}

}  // namespace
// The tableau cache is keyed by the working precision: 16 stages at mp:300 after mp:30 are
// exact to 300 digits (a tableau frozen at mp:30 would give ~40).
TEST(GaussLegendreCache, FollowsTheWorkingPrecision) {
    for (int digits : {30, 300}) {
        test::in_mp(digits, [&] {
            const auto& t = gauss_legendre_tableau_of<mp>(16);
            const std::vector<mp> z = boost::math::legendre_p_zeros<mp>(16);
            for (std::size_t k = 0; k < z.size(); ++k)
                EXPECT_LE(abs(t.roots[16 - z.size() + k] - z[k]), 16 * epsilon<mp>())
                    << "mp:" << digits << " k " << k;
            mp sum = 0;
            for (int i = 0; i < 16; ++i)
                sum += t.b[i];
            EXPECT_LE(abs(sum - 1), 64 * epsilon<mp>()) << "mp:" << digits;
        });
    }
}

}  // namespace flipflux::test
