// Phase volume and configuration-space densities (include/flipflux/prediction/phase_volume.hpp):
// the elliptic 1-D reduction against the 2-D quadrature and the closed form, the kink at E_max and
// the harmonic limit with their leading power laws, the marginals and the CDF.
// (More energies, pendulums and precisions: verification/prediction_routes.cpp.)
#include <stdexcept>

#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/constants.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/prediction/phase_volume.hpp"
#include "flipflux/quadrature/quadrature.hpp"
#include "pendulums.hpp"

namespace flipflux {
namespace {

using test::convert;
using test::eps;
using test::relative_error;
using test::target;
using test::tolerance;

template <class Real>
class PhaseVolume : public test::real_test<Real> {};
TYPED_TEST_SUITE(PhaseVolume, test::real_types, test::real_name);

// 16 pi^2 E(-1) by mpmath 1.3.0 (120 digits).
const char* const omega_egalitarian_max =
    "301.6307272929579491278041858189564673289868134930415803493231794541102518930997723177695100"
    "239061635259975231883";

TYPED_TEST(PhaseVolume, ClosedFormAtTheMaximumIsSixteenPiSquaredE) {
    using Real = TypeParam;
    const double_pendulum<Real> model;
    const Real six(6);
    const std::string expected = omega_egalitarian_max;
    for (phase_volume_method m : {phase_volume_method::closed_form, phase_volume_method::elliptic,
                                  phase_volume_method::quadrature_2d}) {
        const prediction_result<Real> r = phase_volume(model, six, m);
        EXPECT_LE(relative_error(r.value, expected), tolerance<Real>(16)) << to_string(m);
        EXPECT_LE(relative_error(r.value, expected), target<Real>()) << to_string(m);
    }
    EXPECT_LE(relative_error(phase_volume_above_maximum(model), expected), tolerance<Real>(16));
    // above the maximum Omega no longer depends on E
    const Real huge(1000000);
    EXPECT_LE(relative_error(phase_volume(model, huge).value, expected), tolerance<Real>(16));
    EXPECT_LE(relative_error(phase_volume(model, huge, phase_volume_method::quadrature_2d).value,
                             expected),
              tolerance<Real>(16));
}

// Omega(E_max - d) = Omega_max - 4 pi^2 sqrt(D0 / (alpha beta)) d (1 + O(d)): the forbidden
// ellipse around (pi, pi) has area 2 pi d / sqrt(alpha beta) and sqrt(det M) = sqrt(D0) there.
TYPED_TEST(PhaseVolume, KinkAtTheMaximumFollowsItsPowerLaw) {
    using Real = TypeParam;
    using std::sqrt;
    for (std::size_t i : {0, 2}) {
        const auto& spec = test::model_specs()[i];
        const double_pendulum<Real> model = test::make_model<Real>(spec);
        const auto& k = model.coefficients();
        const Real d = Real(1) / 1000000000000;  // 1e-12
        const Real below = model.maximum_energy() - d;
        const Real omega_max = phase_volume_above_maximum(model);
        const prediction_result<Real> r = phase_volume(model, below);
        const Real slope = 4 * pi<Real>() * pi<Real>() * sqrt(k.D0 / (k.alpha * k.beta));
        const Real ratio = (omega_max - r.value) / (slope * d);
        // the difference of two O(1) numbers carries their rounding, magnified by 1/(slope d)
        const double tol =
            static_cast<double>(16 * eps<Real>() * omega_max / (slope * d)) + 100 * 1e-12;
        EXPECT_LE(relative_error(ratio, "1"), tol) << spec.name;
        // the 2-D route agrees with the elliptic one just below the kink (double, quad)
        if constexpr (std::is_same_v<Real, double> || std::is_same_v<Real, quad>) {
            EXPECT_LE(
                relative_error(phase_volume(model, below, phase_volume_method::quadrature_2d).value,
                               r.value),
                target<Real>())
                << spec.name;
        }
        // and Omega is continuous through E_max
        const Real above = model.maximum_energy() + d;
        EXPECT_LE(relative_error(phase_volume(model, above).value, omega_max), tolerance<Real>(16));
    }
}

// Small E: the harmonic limit Omega = 4 pi^2 sqrt(D0 / (alpha beta)) E (1 + O(E)).
TYPED_TEST(PhaseVolume, HarmonicLimit) {
    using Real = TypeParam;
    using std::sqrt;
    const double_pendulum<Real> model = test::make_model<Real>(test::model_specs()[1]);
    const auto& k = model.coefficients();
    const Real E = Real(1) / 1000000000;  // 1e-9
    const Real harmonic = 4 * pi<Real>() * pi<Real>() * sqrt(k.D0 / (k.alpha * k.beta)) * E;
    EXPECT_LE(relative_error(phase_volume(model, E).value, harmonic), 1e-8);
    EXPECT_GT(phase_volume(model, E).value, Real(0));
}

TYPED_TEST(PhaseVolume, RoutesAgreeForEveryPendulum) {
    using Real = TypeParam;
    if constexpr (has_variable_precision_v<Real>) {
        GTEST_SKIP() << "the 2-D route at MPFR precision is in verification/prediction_routes";
    } else {
        // NOTE: quad on a subset for test time; the full grid is in verification/
        const bool full = std::is_same_v<Real, double>;
        for (const auto& spec : test::model_specs()) {
            if (!full && spec.name != "rigid-links") continue;
            const double_pendulum<Real> model = test::make_model<Real>(spec);
            const Real e_max = model.maximum_energy();
            for (int i : {1, 3, 5, 7}) {
                if (!full && (i == 1 || i == 7)) continue;
                const Real E = e_max * i / 8;
                const Real a = phase_volume(model, E).value;
                const Real b = phase_volume(model, E, phase_volume_method::quadrature_2d).value;
                EXPECT_LE(relative_error(a, b), target<Real>()) << spec.name << " E " << E;
            }
        }
    }
}

// Against mp:50 (for double and quad); mp itself is checked against the closed form above and
// across routes and precisions in verification/.
TYPED_TEST(PhaseVolume, HigherPrecisionReference) {
    using Real = TypeParam;
    if constexpr (has_variable_precision_v<Real>) {
        GTEST_SKIP() << "test time: MPFR against a higher precision in "
                        "verification/prediction_routes.cpp";
    } else {
        const double_pendulum<Real> model = test::make_model<Real>(test::model_specs()[2]);
        const Real E = model.maximum_energy() * 5 / 8;
        const prediction_result<Real> r = phase_volume(model, E);
        const std::string e_text = to_decimal(E, full_digits(E));
        const std::string expected = test::in_mp(50, [&] {
            const double_pendulum<mp> reference = test::make_model<mp>(test::model_specs()[2]);
            return to_decimal(phase_volume(reference, parse_real<mp>(e_text, "E")).value);
        });
        EXPECT_LE(relative_error(r.value, expected), target<Real>());
        EXPECT_LE(relative_error(r.value, expected), tolerance<Real>(64));
        EXPECT_GT(r.evaluations, 0u);
        EXPECT_GT(r.error_estimate, Real(0));
    }
}

// The bars of data/golden/compound-bars-si (decimal parameters, not binary) at E = 2 alpha =
// 0.70632, the arm-1 saddle level. From the decimal texts (make_model, parse_energy_level) E is
// exactly at the level, where the half-width is analytic: no more work than nearby. From the
// rounded parameters and a Real E, the level lies a genuine 1e-(digits) off E: a square-root
// branch point of the half-width ~1e-(digits/2) from the quadrature's path, which the graded
// quadrature resolves with ~log(1/eps) more pieces (in double and quad; mp's ~50 pieces are left
// to verification for test time). Reference: the Arb enclosure, `eval omega --energy 0.70632
// --precision mp:80 --certify` (radius 5.5e-81). Condition of the Real route: Omega's derivative
// is log-singular at the level, so the parameters' rounding costs ~log(1/eps) ulps.
TYPED_TEST(PhaseVolume, AnEnergyAtASaddleLevelOfDecimalParametersIsThatLevel) {
    using Real = TypeParam;
    using std::log;
    model_text t;
    t.m1 = "0.1", t.m2 = "0.15", t.L1 = "0.18", t.L2 = "0.24", t.a1 = "0.09", t.a2 = "0.12";
    t.I1 = "0.00027", t.I2 = "0.00072", t.g = "9.81";
    const std::string expected =
        "0.578887516875970341629898769786514113189077638733678881329032773023104616208028226";
    const double condition = -std::log(static_cast<double>(eps<Real>()));
    const double_pendulum<Real> exact = make_model<Real>(t);
    const double_pendulum<Real> rounded(parse_parameters<Real>(t));
    const energy_level<Real> E = parse_energy_level<Real>("0.70632", "E");
    const prediction_result<Real> nearby = phase_volume(exact, parse_real<Real>("0.7", "E"));
    for (const phase_volume_method m :
         {phase_volume_method::elliptic, phase_volume_method::quadrature_2d}) {
        SCOPED_TRACE(to_string(m));
        const bool mp = has_variable_precision_v<Real>;
        if (mp && m == phase_volume_method::quadrature_2d) continue;  // in verification
        const prediction_result<Real> r = phase_volume(exact, E, m);
        EXPECT_LE(relative_error(r.value, expected), tolerance<Real>(16));
        if (m == phase_volume_method::elliptic) {
            EXPECT_LE(r.evaluations, 2 * nearby.evaluations);
        }
        if (mp) continue;
        const prediction_result<Real> inexact = phase_volume(rounded, E.value, m);
        EXPECT_LE(relative_error(inexact.value, expected), tolerance<Real>(16 * condition));
    }
}

// Just above a saddle Omega's derivative is log-singular (~330 at E = 2 + 1e-14, paper's
// pendulum), so Omega needs E's distance to the level to full relative precision. Regression: an
// energy within 16 eps E_max of a level was moved onto it, and Omega at E = 2 + 1e-14 was off by
// 3.2e-12 against an error estimate of 2.1e-13 in double (quad likewise). Reference: the Arb
// enclosure of the decimal inputs (certified/, an independent route). Two pendulums (the paper's;
// point masses with decimal parameters, levels 15.0093, 27.468 and 42.4773), each saddle level and
// E_max, at distances inside the old snap (~10 eps) and far below the precision (eps^2, where the
// half-width's branch point is ~eps from the quadrature's path). The value must lie within its
// own error estimate of the proven one.
TYPED_TEST(PhaseVolume, JustAboveASaddleOmegaFollowsTheExactDistanceToTheLevel) {
    using Real = TypeParam;
    using std::abs;
    model_text decimal_pendulum;
    decimal_pendulum.m1 = "1.3", decimal_pendulum.m2 = "0.45", decimal_pendulum.L1 = "0.8";
    decimal_pendulum.L2 = "1.7", decimal_pendulum.g = "9.81";
    const int digits = static_cast<int>(-std::log10(static_cast<double>(eps<Real>())));
    const std::string tiny = "1e-" + std::to_string(digits - 1),
                      tinier = "1e-" + std::to_string(2 * digits);
    struct level {
        model_text model;
        const char* value;
        bool from_below;
    };
    for (const level& l :
         {level{model_text{}, "2", false}, level{model_text{}, "4", false},
          level{model_text{}, "6", true}, level{decimal_pendulum, "15.0093", false},
          level{decimal_pendulum, "27.468", false}, level{decimal_pendulum, "42.4773", true}}) {
        // test time (~5 s a case at mp, ~1 s in quad): mp checks arm 2's saddle of the paper's
        // pendulum, quad every level, each at the distance inside the old snap; double both
        const bool mp = has_variable_precision_v<Real>, quad = std::is_same_v<Real, flipflux::quad>;
        if (mp && std::string(l.value) != "2") continue;
        const double_pendulum<Real> model = make_model<Real>(l.model);
        for (const std::string& d : {tiny, tinier}) {
            if ((mp || quad) && d == tinier) continue;
            const std::string E =
                l.from_below ? decimal_difference(l.value, d, "E") : decimal_sum(l.value, d, "E");
            SCOPED_TRACE("E = " + E);
            const prediction_result<Real> r = phase_volume(model, parse_energy_level<Real>(E, "E"));
            const certified_enclosure ref =
                certified_value("omega", l.model, arm::two, E, digits + 5);
            const Real err = abs(r.value - parse_real<Real>(ref.mid, "mid"));
            EXPECT_LE(err, r.error_estimate) << "value " << to_decimal(r.value) << ", proven "
                                             << ref.mid << " +/- " << ref.radius;
            EXPECT_LE(relative_error(r.value, ref.mid), tolerance<Real>(16));
        }
    }
}

TYPED_TEST(PhaseVolume, OutsideTheDomain) {
    using Real = TypeParam;
    const double_pendulum<Real> model;
    EXPECT_EQ(phase_volume(model, Real(0)).value, Real(0));
    EXPECT_EQ(phase_volume(model, Real(-1), phase_volume_method::quadrature_2d).value, Real(0));
    EXPECT_THROW(phase_volume(model, Real(5), phase_volume_method::closed_form), std::domain_error);
    EXPECT_THROW(phase_volume(model, std::numeric_limits<Real>::quiet_NaN()), std::domain_error);
    EXPECT_EQ(to_string(phase_volume_method::elliptic), "elliptic");
    EXPECT_EQ(to_string(phase_volume_method::quadrature_2d), "quadrature-2d");
    EXPECT_EQ(to_string(phase_volume_method::closed_form), "closed-form");
}

// rho_i(x) = integral of 2 pi sqrt(det M) over the allowed interval of the other angle, checked by
// tanh-sinh in mp:100 over [-t, t] (t from allowed_half_width, itself checked against V = E).
TYPED_TEST(PhaseVolume, MarginalDensitiesMatchQuadratureOfTheDensity) {
    using Real = TypeParam;
    using std::cos;
    using std::sqrt;
    const double_pendulum<Real> model = test::make_model<Real>(test::model_specs()[2]);
    const Real E = model.maximum_energy() * 5 / 8;
    test::random_reals rnd(7);
    for (configuration_angle which : {configuration_angle::theta1, configuration_angle::theta2}) {
        for (int i = 0; i < 4; ++i) {
            const Real x = Real(rnd(-3.1, 3.1));
            const Real t = allowed_half_width(model, E, which, x);
            const Real rho = marginal_density(model, E, which, x);
            if (t == 0) {
                EXPECT_EQ(rho, Real(0));
                continue;
            }
            // the boundary: V(x, t) = E (unless the whole circle is allowed)
            const Real V = which == configuration_angle::theta1 ? model.potential(x, t)
                                                                : model.potential(t, x);
            if (t < pi<Real>()) {
                EXPECT_LE(abs(V - E), 64 * eps<Real>() * E);
            }
            const std::string x_text = to_decimal(x, full_digits(x)),
                              t_text = to_decimal(t, full_digits(t));
            // the marginal and the density at (x, 0) in mp:100
            const auto [expected, inside_expected] = test::in_mp(100, [&] {
                const double_pendulum<mp> ref = test::make_model<mp>(test::model_specs()[2]);
                const mp X = parse_real<mp>(x_text, "x"), T = parse_real<mp>(t_text, "t");
                auto f = [&](const mp& y) -> mp {
                    return which == configuration_angle::theta1 ? ref.mass_determinant(X, y)
                                                                : ref.mass_determinant(y, X);
                };
                auto g = [&](const mp& y, const mp&, const mp&) -> mp {
                    return two_pi<mp>() * sqrt(f(y));
                };
                return std::pair{to_decimal(tanh_sinh_integrate<mp>(g, -T, T).value),
                                 to_decimal(mp(two_pi<mp>() * sqrt(f(mp(0)))))};
            });
            EXPECT_LE(relative_error(rho, expected), tolerance<Real>(64)) << "x " << x;
            // the density itself: inside, on and outside the allowed region
            const Real inside = which == configuration_angle::theta1
                                    ? configuration_density(model, E, x, Real(0))
                                    : configuration_density(model, E, Real(0), x);
            EXPECT_LE(relative_error(inside, inside_expected), tolerance<Real>(8));
        }
    }
    EXPECT_EQ(configuration_density(model, E, pi<Real>(), pi<Real>()), Real(0));
    const double_pendulum<Real> egal;
    // on the boundary V = E exactly: V(0, pi/2 rounded)... use E = V at a point
    const Real e_on = egal.potential(Real(1), Real(2));
    EXPECT_LE(relative_error(configuration_density(egal, e_on, Real(1), Real(2)),
                             two_pi<Real>() * sqrt(egal.mass_determinant(Real(1), Real(2))) / 2),
              tolerance<Real>(8));
}

TYPED_TEST(PhaseVolume, MarginalsNormaliseToOmegaAndTheCdfIsConsistent) {
    using Real = TypeParam;
    const double_pendulum<Real> model;
    const Real E = Real(7) / 2;
    const Real omega = phase_volume(model, E).value;
    // Omega = 2 * integral_0^pi rho_2: the theta2 marginal is an independent 1-D reduction
    const prediction_result<Real> half =
        marginal_cdf(model, E, configuration_angle::theta2, Real(0));
    EXPECT_LE(relative_error(half.value, "0.5"), tolerance<Real>(4));
    if (has_variable_precision_v<Real>) return;  // NOTE: test time; the rest runs in double, quad
    EXPECT_EQ(marginal_cdf(model, E, configuration_angle::theta1, pi<Real>()).value, Real(1));
    EXPECT_EQ(marginal_cdf(model, E, configuration_angle::theta1, Real(-pi<Real>())).value,
              Real(0));
    // cdf at x: integral_{-pi}^{x} rho_1 / Omega, with the integral done by tanh-sinh here
    const Real x = Real(1) / 3;
    auto rho1 = [&](const Real& y, const Real&, const Real&) -> Real {
        return marginal_density(model, E, configuration_angle::theta1, y);
    };
    // rho_1 has kinks where the support changes: integrate over [0, x] (x below the first kink)
    const Real part = tanh_sinh_integrate<Real>(rho1, Real(0), x).value;
    const prediction_result<Real> cdf = marginal_cdf(model, E, configuration_angle::theta1, x);
    EXPECT_LE(relative_error(cdf.value, Real(Real(1) / 2 + part / omega)), tolerance<Real>(64));
    EXPECT_LE(relative_error(marginal_cdf(model, E, configuration_angle::theta1, Real(-x)).value,
                             Real(Real(1) / 2 - part / omega)),
              tolerance<Real>(64));
    EXPECT_GT(cdf.evaluations, 0u);
    EXPECT_THROW(marginal_cdf(model, E, configuration_angle::theta1, Real(4)), std::domain_error);
    EXPECT_THROW(marginal_cdf(model, Real(0), configuration_angle::theta1, Real(1)),
                 std::domain_error);
    // periodicity and evenness of the marginal
    const Real a = marginal_density(model, E, configuration_angle::theta2, Real(1));
    EXPECT_LE(
        relative_error(
            marginal_density(model, E, configuration_angle::theta2, Real(1 + 4 * pi<Real>())), a),
        tolerance<Real>(64));
    EXPECT_EQ(marginal_density(model, E, configuration_angle::theta2, Real(-1)), a);
    EXPECT_EQ(marginal_density(model, Real(-1), configuration_angle::theta2, Real(1)), Real(0));
}

}  // namespace
}  // namespace flipflux
