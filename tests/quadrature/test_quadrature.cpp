// The quadrature layer (include/flipflux/quadrature/quadrature.hpp): known integrals with endpoint
// singularities at every precision, endpoint distances, error estimates that bound the actual
// error, the fixed and adaptive Gauss-Kronrod rules, nesting, and thread safety under OpenMP.
#include <omp.h>

#include <boost/math/special_functions/bessel.hpp>
#include <boost/math/special_functions/legendre.hpp>
#include <stdexcept>

#include "flipflux/core/constants.hpp"
#include "flipflux/quadrature/quadrature.hpp"
#include "support.hpp"

namespace flipflux {
namespace {

using test::eps;
using test::relative_error;

template <class Real>
class Quadrature : public test::real_test<Real> {};
TYPED_TEST_SUITE(Quadrature, test::real_types, test::real_name);

TYPED_TEST(Quadrature, TanhSinhIntegratesEndpointSingularitiesToRounding) {
    using Real = TypeParam;
    using std::sqrt;
    const double tol = 8 * static_cast<double>(eps<Real>());
    // int_0^1 sqrt(1 - x) dx = 2/3, with the distance to b (no cancellation in 1 - x)
    auto f = [](const Real&, const Real&, const Real& to_b) -> Real { return sqrt(to_b); };
    const quadrature_result<Real> a = tanh_sinh_integrate<Real>(f, Real(0), Real(1));
    EXPECT_LE(relative_error(a.value, test::reference_real(2) / 3), tol);
    EXPECT_GE(a.error_estimate, abs(a.value - Real(2) / 3));  // a conservative estimate
    EXPECT_GT(a.evaluations, 0u);
    EXPECT_GT(a.levels, 0u);
    // int_{-1}^{1} dx / sqrt(1 - x^2) = pi: both endpoints singular, distances used
    auto g = [](const Real& x, const Real& to_a, const Real& to_b) -> Real {
        return 1 / sqrt(x < 0 ? to_a * (2 - to_a) : to_b * (2 - to_b));
    };
    const quadrature_result<Real> b = tanh_sinh_integrate<Real>(g, Real(-1), Real(1));
    EXPECT_LE(relative_error(b.value, pi<test::reference_real>()), tol);
    // the distances agree with x to the rounding of x (they are more accurate than x - a near a)
    auto h = [](const Real& x, const Real& to_a, const Real& to_b) -> Real {
        using std::abs;
        EXPECT_LE(abs(to_a - (x - 2)), 8 * eps<Real>());
        EXPECT_LE(abs(to_a + to_b - 3), 8 * eps<Real>());
        return x;
    };
    EXPECT_LE(relative_error(tanh_sinh_integrate<Real>(h, Real(2), Real(5)).value,
                             test::reference_real(21) / 2),
              tol);
}

// The estimate does not depend on the interval's size: int_0^w sqrt((w - x)(w + x)) dx = pi w^2 / 4
// with w = 2^k is the same integral for every k, every abscissa and value scaled by a power of two
// (exactly), so the relative estimate is the same to the bit at every width. Boost 1.74 returns
// its level difference in the units of [-1, 1] (not scaled back by w / 2 as the integral and L1
// are): its estimate then grew as w^(-3/2) towards small widths (a relative 3.8 at w = 1e-12 for a
// value good to 2e-16) and shrank below the actual error beyond w = 2.
TYPED_TEST(Quadrature, TanhSinhEstimateDoesNotDependOnTheIntervalsSize) {
    using Real = TypeParam;
    using std::ldexp;
    using std::sqrt;
    auto relative_estimate = [](int k, Real& actual) {
        const Real w = ldexp(Real(1), k);
        auto f = [&](const Real& x, const Real&, const Real& to_b) -> Real {
            return sqrt(to_b * (x + w));
        };
        // a loose tolerance: the rule stops after a few levels, with a level difference well
        // above the rounding floor eps L1, so that the difference's scaling is what is tested
        quadrature_options<Real> o;
        o.relative_tolerance = sqrt(sqrt(eps<Real>()));
        const quadrature_result<Real> r = tanh_sinh_integrate<Real>(f, Real(0), w, o);
        const Real exact = pi<Real>() * w * w / 4;
        actual = abs(r.value - exact) / exact;
        return Real(r.error_estimate / r.value);
    };
    Real actual_one = 0;
    const Real at_one = relative_estimate(0, actual_one);
    EXPECT_GT(at_one, 16 * eps<Real>());  // not the rounding floor alone
    EXPECT_GE(at_one, actual_one);        // covers the actual error
    for (const int k : {-60, -40, -20, -3, 1, 2, 3, 10, 40}) {
        Real actual = 0;
        EXPECT_EQ(relative_estimate(k, actual), at_one) << "width 2^" << k;
        EXPECT_EQ(actual, actual_one) << "width 2^" << k;
    }
}
TYPED_TEST(Quadrature, SineSquaredClenshawCurtisConvergesOrDeclines) {
    using Real = TypeParam;
    using std::exp;
    using std::sqrt;
    const double tol = 8 * static_cast<double>(eps<Real>());
    // int_{-1}^{1} sqrt(1 - x^2) dx = pi / 2: the substitution makes it a trigonometric
    // polynomial in u, entire in the rule's variable: 63 evaluations (32 and 64 intervals) at
    // double and quad, 127 at 50 digits
    auto g = [](const Real&, const Real& to_a, const Real& to_b) -> Real {
        return sqrt(to_a * to_b);
    };
    const auto a = sine_squared_clenshaw_curtis<Real>(g, Real(-1), Real(1), 256);
    ASSERT_TRUE(a.has_value());
    EXPECT_LE(relative_error(a->value, pi<test::reference_real>() / 2), tol);
    EXPECT_EQ(a->evaluations, has_variable_precision_v<Real> ? 127u : 63u);
    // int_{-1}^{1} e^x sqrt(1 - x^2) dx = pi I_1(1) (Boost's Bessel function as reference)
    auto h = [](const Real& x, const Real& to_a, const Real& to_b) -> Real {
        return exp(x) * sqrt(to_a * to_b);
    };
    const auto b = sine_squared_clenshaw_curtis<Real>(h, Real(-1), Real(1), 256);
    ASSERT_TRUE(b.has_value());
    const test::reference_real exact =
        pi<test::reference_real>() * boost::math::cyl_bessel_i(1, test::reference_real(1));
    EXPECT_LE(relative_error(b->value, exact), tol);
    EXPECT_GE(b->error_estimate, abs(b->value - Real(exact)));
    EXPECT_LE(b->error_estimate, 100 * abs(b->value - Real(exact)) + 8 * eps<Real>() * b->l1_norm);
    // a pole 1e-9 beyond b: no rule up to 256 intervals converges, and the caller is told so
    auto near = [](const Real&, const Real&, const Real& to_b) -> Real {
        return 1 / (to_b + Real(1e-9));
    };
    EXPECT_FALSE(sine_squared_clenshaw_curtis<Real>(near, Real(0), Real(1), 256).has_value());
    EXPECT_EQ(sine_squared_clenshaw_curtis<Real>(near, Real(1), Real(1), 256)->value, Real(0));
    EXPECT_THROW(sine_squared_clenshaw_curtis<Real>(near, Real(0), Real(1), 96), std::domain_error);
    EXPECT_THROW(sine_squared_clenshaw_curtis<Real>(near, Real(0), Real(1), 16), std::domain_error);
}

TYPED_TEST(Quadrature, PiecesAndEmptyIntervals) {
    using Real = TypeParam;
    using std::abs;
    using std::sin;
    auto f = [](const Real& x, const Real&, const Real&) -> Real { return abs(sin(x)); };
    const std::vector<Real> p{Real(0), pi<Real>(), two_pi<Real>(), Real(3 * pi<Real>())};
    const quadrature_result<Real> r = tanh_sinh_integrate_pieces<Real>(f, p);
    EXPECT_LE(relative_error(r.value, test::reference_real(6)),
              8 * static_cast<double>(eps<Real>()));
    EXPECT_EQ(tanh_sinh_integrate<Real>(f, Real(1), Real(1)).value, Real(0));
    EXPECT_THROW(tanh_sinh_integrate<Real>(f, Real(2), Real(1)), std::domain_error);
    EXPECT_THROW(tanh_sinh_integrate<Real>(f, Real(0), std::numeric_limits<Real>::infinity()),
                 std::domain_error);
}

// int_0^pi exp(cos x) dx = pi I_0(1) (Boost's Bessel function as reference).
TYPED_TEST(Quadrature, GaussKronrodAdaptiveAndFixed) {
    using Real = TypeParam;
    using std::cos;
    using std::exp;
    auto f = [](const Real& x) -> Real { return exp(cos(x)); };
    const Real expected = pi<Real>() * boost::math::cyl_bessel_i(0, Real(1));
    const double tol = 16 * static_cast<double>(eps<Real>());
    const quadrature_result<Real> a = gauss_kronrod_integrate<Real>(f, Real(0), pi<Real>());
    EXPECT_LE(relative_error(a.value, expected), tol);
    EXPECT_GT(a.evaluations, 0u);
    // exp(cos z) is entire: any strip works; use the panels for a strip of half-width 1
    const std::size_t panels = kronrod_panels(pi<Real>(), Real(1));
    ASSERT_GT(panels, 0u);
    const quadrature_result<Real> b = gauss_kronrod_fixed<Real>(f, Real(0), pi<Real>(), panels);
    EXPECT_LE(relative_error(b.value, expected), tol);
    EXPECT_EQ(b.evaluations, panels * 61);
    // panel counts grow with precision and shrink with the strip
    EXPECT_GE(kronrod_panels(pi<Real>(), Real(1) / 2), panels);
    EXPECT_EQ(kronrod_panels(pi<Real>(), Real(0)), 0u);
    EXPECT_EQ(kronrod_panels(Real(0), Real(1)), 1u);
    EXPECT_EQ(kronrod_panels(pi<Real>(), Real(1) / 1000000, 8), 0u);
    EXPECT_EQ(gauss_kronrod_integrate<Real>(f, Real(1), Real(1)).value, Real(0));
    EXPECT_THROW(gauss_kronrod_integrate<Real>(f, Real(1), Real(0)), std::domain_error);
    EXPECT_THROW(gauss_kronrod_fixed<Real>(f, Real(0), Real(1), 0), std::domain_error);
}

// int_0^1 int_0^x sqrt(x - y) dy dx = int_0^1 (2/3) x^(3/2) dx = 4/15.
TYPED_TEST(Quadrature, NestedIntegralPropagatesInnerResults) {
    using Real = TypeParam;
    using std::sqrt;
    auto inner = [](const Real& x, const Real&, const Real&) {
        return tanh_sinh_integrate<Real>(
            [](const Real&, const Real&, const Real& to_b) -> Real { return sqrt(to_b); }, Real(0),
            x);
    };
    const quadrature_result<Real> r = nested_integrate<Real>(inner, Real(0), Real(1));
    EXPECT_LE(relative_error(r.value, test::reference_real(4) / 15),
              16 * static_cast<double>(eps<Real>()));
    EXPECT_GT(r.evaluations, 100u);
    EXPECT_GE(r.error_estimate, abs(r.value - Real(4) / 15));
}

// A shared tanh-sinh object gives wrong answers under OpenMP while it adds levels (TOOLCHAIN.md):
// every thread must get exactly the serial answer.
TYPED_TEST(Quadrature, ThreadSafeUnderOpenMP) {
    using Real = TypeParam;
    using std::sqrt;
    const int n = has_variable_precision_v<Real> ? 8 : 32;
    std::vector<Real> serial(n), parallel(n);
    auto integral = [](int i) {
        const Real c = Real(i + 1) / 7;
        return tanh_sinh_integrate<Real>(
                   [&c](const Real& x, const Real&, const Real& to_b) -> Real {
                       return sqrt(to_b) / (c + x * x);
                   },
                   Real(0), Real(1))
            .value;
    };
    for (int i = 0; i < n; ++i)
        serial[i] = integral(i);
#pragma omp parallel for num_threads(4) schedule(dynamic)
    for (int i = 0; i < n; ++i)
        parallel[i] = integral(i);
    for (int i = 0; i < n; ++i)
        EXPECT_EQ(parallel[i], serial[i]) << i;
}

// The integrators' caches follow mp's working precision: tanh-sinh abscissas and the Gauss-Kronrod
// rule are built per precision, so 400 digits after 40 (and 40 again after 400) are each
// accurate to their own precision. With a cache frozen at its first precision the mp:400 results
// would carry ~50 digits.
TEST(QuadratureCaches, FollowTheWorkingPrecision) {
    using std::exp;
    using std::sqrt;
    const std::string two_thirds = "0." + std::string(600, '6') + "7";
    for (int digits : {40, 400, 40}) {
        test::in_mp(digits, [&] {
            const int working = mp_working_digits(digits);
            auto f = [](const mp&, const mp&, const mp& to_b) -> mp { return sqrt(to_b); };
            const mp a = tanh_sinh_integrate<mp>(f, mp(0), mp(1)).value;
            EXPECT_GE(test::correct_digits(a, two_thirds), working - 3) << "mp:" << digits;
            auto g = [](const mp& x) -> mp { return exp(x); };
            const mp b = gauss_kronrod_integrate<mp>(g, mp(0), mp(1)).value;
            const mp e1 = exp(mp(1)) - 1;
            EXPECT_GE(test::correct_digits(b, e1), 0.74 * working) << "mp:" << digits;
            const mp c = gauss_kronrod_fixed<mp>(g, mp(0), mp(1), 4).value;
            // four fixed panels: the 61-point rule's truncation error is ~1e-256 here
            EXPECT_GE(test::correct_digits(c, e1), std::min(working - 3, 250)) << "mp:" << digits;
            // the rule itself: Gauss nodes are zeros of P_30, weights sum to 2
            const gauss_kronrod_rule<mp>& rule = gauss_kronrod_61<mp>();
            ASSERT_EQ(rule.abscissa.size(), 31u);
            ASSERT_EQ(rule.gauss_weights.size(), 15u);
            mp kronrod_sum = rule.kronrod_weights[0], gauss_sum = 0;
            for (std::size_t i = 1; i < 31; ++i) {
                kronrod_sum += 2 * rule.kronrod_weights[i];
                if (i % 2 == 1) {
                    gauss_sum += 2 * rule.gauss_weights[i / 2];
                    EXPECT_LE(abs(boost::math::legendre_p(30, rule.abscissa[i])),
                              1000 * epsilon<mp>());
                }
            }
            EXPECT_LE(abs(kronrod_sum - 2), 100 * epsilon<mp>());
            EXPECT_LE(abs(gauss_sum - 2), 100 * epsilon<mp>());
        });
    }
}

// The tabulated rule of the fixed types is Boost's: the computed rule (as mp builds it) agrees
// with it to the type's precision at double and quad.
TEST(QuadratureCaches, ComputedRuleMatchesBoostsTablesInQuad) {
    const gauss_kronrod_rule<quad>& q = gauss_kronrod_61<quad>();
    const auto [x, w] = test::in_mp(40, [] {
        const gauss_kronrod_rule<mp>& r = gauss_kronrod_61<mp>();
        std::vector<std::string> xs, ws;
        for (std::size_t i = 0; i < r.abscissa.size(); ++i) {
            xs.push_back(to_decimal(r.abscissa[i], 45));
            ws.push_back(to_decimal(r.kronrod_weights[i], 45));
        }
        return std::pair{xs, ws};
    });
    for (std::size_t i = 1; i < x.size(); ++i) {
        EXPECT_LE(relative_error(q.abscissa[i], x[i]), 4 * static_cast<double>(eps<quad>())) << i;
        EXPECT_LE(relative_error(q.kronrod_weights[i], w[i]), 8 * static_cast<double>(eps<quad>()))
            << i;
    }
}

}  // namespace
}  // namespace flipflux
