// Fluxes through the upright surface and through dividing curves
// (include/flipflux/prediction/upright_flux.hpp, curve_flux.hpp): the paper's closed forms
// (values by mpmath), every route against every other, the power laws just above each saddle,
// the switch of closed form at E_max, huge energies, and curves with restricted domains, grazing
// zeros of K and several accessible pieces. (More: verification/prediction_routes.cpp.)
#include <boost/math/quadrature/gauss.hpp>
#include <stdexcept>
#include <string>

#include "flipflux/core/constants.hpp"
#include "flipflux/model/critical_points.hpp"
#include "flipflux/model/energy_level.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/prediction/curve_flux.hpp"
#include "flipflux/prediction/upright_flux.hpp"
#include "pendulums.hpp"

namespace flipflux {
namespace {

using test::convert;
using test::eps;
using test::reference_real;
using test::relative_error;
using test::target;
using test::to_reference;
using test::tolerance;

template <class Real>
class Fluxes : public test::real_test<Real> {};
TYPED_TEST_SUITE(Fluxes, test::real_types, test::real_name);

template <class T>
constexpr bool is_mp_v = has_variable_precision_v<T>;

// f1 of the egalitarian pendulum, arm 2, from the paper's eqs. (upright_arm_flux_incomplete_
// elliptic, upright_arm_flux_complete_elliptic) evaluated by mpmath 1.3.0 at 130 digits.
struct reference_value {
    const char *energy, *value;
};
const reference_value f1_paper[] = {
    {"3",
     "13.0015643667187278916091215130629372095847092301705713542930824365279328070099561823488192"
     "17986891163589341565"},
    {"5",
     "43.0033354043871178204092255903294828338055837192076008348255881556815788601699165841877215"
     "66965536907155487835"},
    {"6", "64"},
    {"10",
     "122.246329248886784572952386629486185341118963668712791074575893015910265638858557474117794"
     "86243911945030537529"},
};

TYPED_TEST(Fluxes, UprightFluxMatchesThePapersClosedForms) {
    using Real = TypeParam;
    const double_pendulum<Real> model;
    for (const auto& c : f1_paper) {
        const Real E = parse_real<Real>(c.energy, "E");
        const std::string expected = c.value;
        // NOTE: the 2-D momentum route in double only, the curve route up to quad (test time)
        std::vector methods{upright_flux_method::elliptic, upright_flux_method::integral};
        if (!is_mp_v<Real>) methods.push_back(upright_flux_method::curve);
        if (std::is_same_v<Real, double>) methods.push_back(upright_flux_method::momentum);
        for (upright_flux_method m : methods) {
            const Real f = upright_flux(model, arm::two, E, m).value;
            EXPECT_LE(relative_error(f, expected), tolerance<Real>(64))
                << "E " << c.energy << " " << to_string(m);
            EXPECT_LE(relative_error(f, expected), target<Real>());
        }
    }
}

TYPED_TEST(Fluxes, UprightRoutesAgreeForEveryPendulumAndArm) {
    using Real = TypeParam;
    if (is_mp_v<Real>) GTEST_SKIP() << "test time: MPFR in verification/prediction_routes.cpp";
    const bool full = std::is_same_v<Real, double>;  // NOTE: quad on a subset (test time)
    for (const auto& spec : test::model_specs()) {
        if (!full && spec.name != "light-first-link") continue;
        const double_pendulum<Real> model = test::make_model<Real>(spec);
        for (arm a : {arm::one, arm::two}) {
            if (!full && a == arm::one) continue;
            const Real es = model.saddle_energy(a), em = model.maximum_energy();
            for (const Real& E : {Real(es + (em - es) / 8), Real(es + (em - es) * 7 / 8),
                                  Real(2 * em), Real(1000000)}) {
                if (!full && E != es + (em - es) * 7 / 8) continue;
                const Real ref = upright_flux(model, a, E).value;
                for (upright_flux_method m :
                     {upright_flux_method::integral, upright_flux_method::curve,
                      upright_flux_method::momentum}) {
                    EXPECT_LE(relative_error(upright_flux(model, a, E, m).value, ref),
                              target<Real>())
                        << spec.name << " arm " << to_string(a) << " E " << E << " "
                        << to_string(m);
                }
                if (E < em) {
                    // DLMF 19.7.4 route, accurate away from E_s
                    EXPECT_LE(relative_error(upright_flux_reciprocal_modulus(model, a, E), ref),
                              target<Real>() * 10);
                }
            }
        }
    }
}

// The brief's hard case "just above a saddle": E = E_s + 10^-k written in decimal, with k beyond
// the working precision, so that E itself rounds to E_s. The distance E - E_s is carried from the
// decimal text (model/energy_level.hpp), and the fluxes follow their power laws in it: f1 =
// 4 pi sqrt(J/w) d (1 + d/(16 w)), f2 = 4 pi d / omega_centre (1 + O(d)); E - E_s computed from
// the rounded E would give 0. The reference d = 10^-k is parsed on its own (not carried).
TYPED_TEST(Fluxes, JustAboveASaddleTheDistanceComesFromTheDecimalInput) {
    using Real = TypeParam;
    using std::sqrt;
    const int k = full_digits(Real(1)) + 3;
    const Real d = parse_real<Real>("1e-" + std::to_string(k), "d");
    for (std::size_t i : {0, 2}) {  // critical levels with exact decimals: 2, 4, 6 and 1.5, 4, 5.5
        const auto& spec = test::model_specs()[i];
        const double_pendulum<Real> model = test::make_model<Real>(spec);
        for (arm a : {arm::two, arm::one}) {
            const std::string es = to_decimal(model.saddle_energy(a));
            ASSERT_EQ(parse_real<Real>(es, "E_s"), model.saddle_energy(a)) << es;
            // es + 10^-k as decimal text: the fraction padded to k digits, the last one a 1
            const auto point = es.find('.');
            const std::string fraction = point == std::string::npos ? "" : es.substr(point + 1);
            ASSERT_LT(fraction.size() + 1, static_cast<std::size_t>(k));
            const std::string text = es.substr(0, point) + "." + fraction +
                                     std::string(k - 1 - fraction.size(), '0') + "1";
            const energy_level<Real> E = parse_energy_level<Real>(text, "--energy");
            EXPECT_EQ(E.value, model.saddle_energy(a)) << text;  // Real cannot hold E
            const auto& k_ = model.coefficients();
            // upright_flux_near_saddle's J and w: those of the other (non-flipping) angle
            const Real J = a == arm::two ? k_.A : k_.B, w = a == arm::two ? k_.alpha : k_.beta;
            const Real series = 4 * pi<Real>() * sqrt(J / w) * d * (1 + d / (16 * w));
            for (upright_flux_method m :
                 {upright_flux_method::elliptic, upright_flux_method::integral})
                EXPECT_LE(relative_error(upright_flux(model, a, E, m).value, series),
                          tolerance<Real>(64))
                    << spec.name << " arm " << to_string(a) << " " << to_string(m);
            const critical_point<Real> saddle = flip_saddle(model, a);
            const Real f2 = approximate_saddle_flux(model, a, E).value;
            EXPECT_LE(relative_error(f2, Real(4 * pi<Real>() * d / saddle.modes[0].rate)),
                      tolerance<Real>(1024))
                << spec.name << " arm " << to_string(a);
        }
        // and just below the maximum: E_max - E = 10^-k, the distance the upright flux sees
        const std::string emax = to_decimal(model.maximum_energy());
        const energy_level<Real> top =
            parse_energy_level<Real>(emax + "e0", "--energy");  // exactly E_max: no residual
        EXPECT_EQ(top.residual, Real(0));
        const energy_level<Real> below(model.maximum_energy(), Real(-d));
        EXPECT_LE(relative_error(below.below(model.maximum_energy()), d), eps<Real>());
    }
}

// The same hard case for a pendulum whose critical energies are not dyadic: with g = 9.81,
// m2 = 0.45, L2 = 1.7 the saddle energy 2 g m2 L2 = 15.0093 is a decimal that no binary precision
// holds, and E = 15.0093 + 10^-k must still give E - E_s = 10^-k (the levels carry their exact
// decimals, model/model_text.hpp make_model), not 10^-k plus the rounding of the parameters'
// products (~eps E_s, regression: the flux was then off in its (digits - k + 17)th digit, or
// wholly wrong in double). The critical energies below were worked out by hand; exactly at a
// decimal saddle the flux is exactly 0, at the decimal maximum E_max - E is exactly 0.
TYPED_TEST(Fluxes, JustAboveTheDecimalSaddlesOfDecimalParameters) {
    using Real = TypeParam;
    using std::sqrt;
    const int k = full_digits(Real(1)) + 3;
    const Real d = parse_real<Real>("1e-" + std::to_string(k), "d");
    struct decimal_case {
        model_text model;
        std::string saddle2, saddle1, maximum;  // 2 g m2 a2, 2 g (m1 a1 + m2 L1), their sum
    };
    model_text point, rigid;
    point.m1 = "1.3", point.m2 = "0.45", point.L1 = "0.8", point.L2 = "1.7", point.g = "9.81";
    rigid.m1 = "0.1", rigid.m2 = "0.15", rigid.L1 = "0.18", rigid.L2 = "0.24", rigid.a1 = "0.09";
    rigid.a2 = "0.12", rigid.I1 = "0.00027", rigid.I2 = "0.00072", rigid.g = "9.81";
    for (const decimal_case& c : {decimal_case{point, "15.0093", "27.468", "42.4773"},
                                  decimal_case{rigid, "0.35316", "0.70632", "1.05948"}}) {
        const double_pendulum<Real> model = make_model<Real>(c.model);
        const auto& k_ = model.coefficients();
        for (arm a : {arm::two, arm::one}) {
            const std::string& es = a == arm::two ? c.saddle2 : c.saddle1;
            // es + 10^-k: es's fraction (es has a '.') padded to k digits, the last one a 1
            const std::size_t fraction = es.size() - es.find('.') - 1;
            const std::string text = es + std::string(k - 1 - fraction, '0') + "1";
            const energy_level<Real> E = parse_energy_level<Real>(text, "--energy");
            const Real J = a == arm::two ? k_.A : k_.B, w = a == arm::two ? k_.alpha : k_.beta;
            const Real series = 4 * pi<Real>() * sqrt(J / w) * d * (1 + d / (16 * w));
            for (upright_flux_method m :
                 {upright_flux_method::elliptic, upright_flux_method::integral}) {
                EXPECT_LE(relative_error(upright_flux(model, a, E, m).value, series),
                          tolerance<Real>(64))
                    << text << " arm " << to_string(a) << " " << to_string(m);
                EXPECT_EQ(upright_flux(model, a, parse_energy_level<Real>(es, "E"), m).value,
                          Real(0))
                    << es << " arm " << to_string(a) << " " << to_string(m);
            }
            const critical_point<Real> saddle = flip_saddle(model, a);
            EXPECT_LE(relative_error(approximate_saddle_flux(model, a, E).value,
                                     Real(4 * pi<Real>() * d / saddle.modes[0].rate)),
                      tolerance<Real>(1024))
                << text << " arm " << to_string(a);
        }
        EXPECT_EQ(parse_energy_level<Real>(c.maximum, "E").above(model.maximum_level()), Real(0));
        const energy_level<Real> below =
            parse_energy_level<Real>(decimal_difference(c.maximum, "1e-" + std::to_string(k)), "E");
        EXPECT_LE(relative_error(below.below(model.maximum_level()), d), eps<Real>()) << c.maximum;
    }
}

// Just above each saddle (E = E_s + 1e-12) every flux keeps its relative accuracy and follows its
// power law: f1 = 4 pi sqrt(J/w) d (1 + d/(16 w) + O(d^2)); through the approximate saddle curve
// f2 = 4 pi d sqrt(d^T M* d / d^T K* d) (1 + O(d)) = 4 pi d / omega_centre (its tangent is the
// centre mode).
TYPED_TEST(Fluxes, PowerLawsJustAboveTheSaddles) {
    using Real = TypeParam;
    using std::sqrt;
    for (std::size_t i : {0, 2}) {
        const auto& spec = test::model_specs()[i];
        const double_pendulum<Real> model = test::make_model<Real>(spec);
        for (arm a : {arm::two, arm::one}) {
            const Real d = Real(1) / 1000000000000;
            const Real E = model.saddle_energy(a) + d;
            const Real delta = E - model.saddle_energy(a);  // the d the pendulum sees
            const Real f1 = upright_flux(model, a, E).value;
            const Real f1_integral = upright_flux(model, a, E, upright_flux_method::integral).value;
            EXPECT_LE(relative_error(f1_integral, f1), tolerance<Real>(64)) << spec.name;
            EXPECT_LE(relative_error(f1, upright_flux_near_saddle(model, a, E)),
                      tolerance<Real>(64) + 1e-23)
                << spec.name;
            const sine_curve<Real> curve = approximate_saddle_curve(model, a);
            const curve_flux_result<Real> f2 = curve_flux(model, E, curve);
            ASSERT_EQ(f2.intervals.size(), 1u);
            const Real leading = near_saddle_flux(model, a, E, curve.amplitude);
            EXPECT_LE(relative_error(f2.value, leading), 1e-10) << spec.name;
            const critical_point<Real> saddle = flip_saddle(model, a);
            EXPECT_LE(relative_error(leading, 4 * pi<Real>() * delta / saddle.modes[0].rate),
                      tolerance<Real>(64));
            // the leading law is the minimum over slopes: the upright one is larger
            EXPECT_GT(near_saddle_flux(model, a, E, Real(0)), leading);
            if constexpr (std::is_same_v<Real, double>) {
                const Real f2m = curve_flux(model, E, curve, curve_flux_method::momentum).value;
                EXPECT_LE(relative_error(f2m, f2.value), target<Real>()) << spec.name;
            }
        }
    }
}

// E = E_max of decimal parameters (the compound bars: 2 (alpha + beta) = 1.05948 J, which Real
// holds to rounding only) is the maximum itself: the approximate curve touches K = 0 at its top,
// and a forbidden gap ~1e-(digits/2) wide that rounding opens there is that touch. Regression: the
// momentum route stalled there
// (> 20 s at mp:20, the golden check pass of compound-bars-si in mp:40). Both routes agree to the
// working precision, and neither does much more work than at a generic energy just below.
template <class Real>
void check_curve_flux_at_the_decimal_maximum(const std::string& where) {
    model_text t;
    t.m1 = "0.1", t.m2 = "0.15", t.L1 = "0.18", t.L2 = "0.24", t.a1 = "0.09", t.a2 = "0.12";
    t.I1 = "0.00027", t.I2 = "0.00072", t.g = "9.81";
    const double_pendulum<Real> model(parse_parameters<Real>(t));
    const energy_level<Real> top = parse_energy_level<Real>("1.05948", "E");
    const energy_level<Real> generic = parse_energy_level<Real>("1.0", "E");
    for (arm a : {arm::two, arm::one}) {
        const sine_curve<Real> curve = approximate_saddle_curve(model, a);
        const curve_flux_result<Real> k = curve_flux(model, top, curve);
        const curve_flux_result<Real> m =
            curve_flux(model, top, curve, curve_flux_method::momentum);
        // K vanishes quadratically at the top: sqrt(K) ~ |s - s_top| and the flux is well
        // conditioned (condition ~ 1)
        EXPECT_LE(relative_error(m.value, k.value), tolerance<Real>(64)) << where << to_string(a);
        const curve_flux_result<Real> near =
            curve_flux(model, generic, curve, curve_flux_method::momentum);
        EXPECT_LE(m.evaluations, 4 * near.evaluations) << where << " arm " << to_string(a);
        EXPECT_LE(k.evaluations, 4 * curve_flux(model, generic, curve).evaluations)
            << where << " arm " << to_string(a);
    }
}

TYPED_TEST(Fluxes, AtTheMaximumOfDecimalParametersTheCurveTouchesIt) {
    using Real = TypeParam;
    if constexpr (is_mp_v<Real>) {
        // where the rounding lands depends on the precision: mp:20 stalled, mp:50 did not
        for (int digits : {20, 30}) {
            const precision_scope scope(mp_precision(digits));
            check_curve_flux_at_the_decimal_maximum<Real>("mp:" + std::to_string(digits) + " ");
        }
    } else {
        check_curve_flux_at_the_decimal_maximum<Real>("");
    }
}

// The approximate curve's flux just above E_max, from the point-mass parameters alone (an
// independent route: 120 digits, Gauss-Legendre on pieces halving towards s = pi): the curve
// th_flip = pi + a sin s with a from the saddle's stable mode, det(K* - lambda M*) = 0; K = E - V
// on it; f = 8 int_0^pi sqrt(2 K Q) ds with Q = n^T adj(M) n (K and Q even in s).
struct point_masses {
    const char *m1, *m2, *L1, *L2;
};
reference_real approximate_flux_reference(const point_masses& p, arm a, const reference_real& E) {
    using R = reference_real;
    const R m1(p.m1), m2(p.m2), L1(p.L1), L2(p.L2);
    const R A = (m1 + m2) * L1 * L1, B = m2 * L2 * L2, C = m2 * L1 * L2;
    const R alpha = (m1 + m2) * L1, beta = m2 * L2, D0 = A * B - C * C;  // g = 1
    const bool two = a == arm::two;
    // lambda^2 D0 + lambda b - alpha beta = 0, b = A beta - alpha B (arm 2) or alpha B - A beta
    const R b = two ? R(A * beta - alpha * B) : R(alpha * B - A * beta);
    const R lambda = (-b + sqrt(b * b + 4 * D0 * alpha * beta)) / (2 * D0);
    const R amp = two ? R(lambda * C / (beta + lambda * B)) : R(lambda * C / (alpha + lambda * A));
    const R w_s = two ? alpha : beta, w_f = two ? beta : alpha;  // V's weights of s and flip
    const R J_s = two ? A : B, J_f = two ? B : A;  // M's diagonal entries of s and flip
    auto integrand = [&](const R& s) {
        const R h = amp * sin(s), hp = amp * cos(s);
        const R K = E - w_s * (1 - cos(s)) - w_f * (1 + cos(h));
        const R Q = J_s - 2 * C * cos(s - h) * hp + J_f * hp * hp;
        return K > 0 ? R(sqrt(2 * K * Q)) : R(0);
    };
    const R half_pi = boost::math::constants::half_pi<R>(), pi = boost::math::constants::pi<R>();
    R total = boost::math::quadrature::gauss<R, 30>::integrate(integrand, R(0), half_pi);
    R gap = half_pi;
    for (int k = 0; k < 130; ++k, gap /= 2)
        total += boost::math::quadrature::gauss<R, 30>::integrate(integrand, R(pi - gap),
                                                                  R(pi - gap / 2));
    return 8 * total;
}

// Just above E_max the sine curve's K has its minimum, ~ E - E_max, at s = pi, the seam of its
// domain [-pi, pi]: split there, its pieces met the branch points of sqrt(K) at pi +- i r,
// r ~ sqrt(E - E_max), and at quad the flux lost up to 6 digits beyond its error estimate (an
// independent mpmath audit: 7e-28 against an estimate of 3e-33 at E_max (1 + 1e-20)). Both
// routes keep the working precision within their estimates, for both arms of two pendulums.
TYPED_TEST(Fluxes, JustAboveTheMaximumTheCurvesSeamKeepsItsDigits) {
    using Real = TypeParam;
    if constexpr (is_mp_v<Real>) {
        GTEST_SKIP() << "double and quad: mp has the digits to spare here";
    } else {
        for (const point_masses& p :
             {point_masses{"1", "1", "1", "1"}, point_masses{"1.7", "0.3", "0.4", "2.2"}}) {
            model_text t;
            t.m1 = p.m1, t.m2 = p.m2, t.L1 = p.L1, t.L2 = p.L2;
            const double_pendulum<Real> model(parse_parameters<Real>(t));
            // E_max = V(pi, pi) = 2 (alpha + beta), alpha = (m1 + m2) L1, beta = m2 L2 (g = 1)
            const reference_real m1(p.m1), m2(p.m2), L1(p.L1), L2(p.L2);
            const reference_real E_max = 2 * ((m1 + m2) * L1 + m2 * L2);
            for (const char* excess : {"1e-14", "1e-20"}) {
                const reference_real E_ref = E_max * (1 + reference_real(excess));
                const std::string text = E_ref.str(45);
                const energy_level<Real> E = parse_energy_level<Real>(text, "E");
                for (arm a : {arm::two, arm::one}) {
                    const reference_real ref = approximate_flux_reference(p, a, E_ref);
                    for (curve_flux_method method :
                         {curve_flux_method::kinetic, curve_flux_method::momentum}) {
                        if (method == curve_flux_method::momentum && !std::is_same_v<Real, double>)
                            continue;  // (its nested quadrature at quad: verify's)
                        const curve_flux_result<Real> f =
                            curve_flux(model, E, approximate_saddle_curve(model, a), method);
                        const reference_real error = abs(to_reference(f.value) - ref);
                        const std::string where = std::string(p.m1) + "," + p.m2 + "," + p.L1 +
                                                  "," + p.L2 + " E = " + text + " arm " +
                                                  to_string(a);
                        EXPECT_LE(error, to_reference(f.error_estimate)) << where;
                        EXPECT_LE(error / ref, 1000 * to_reference(eps<Real>())) << where;
                    }
                }
            }
        }
    }
}

// A nearly singular mass matrix (C^2 / D0 = 182: a light long first link, a heavy short second
// one; found by an independent mpmath cross-check): M's eigenvalues differ by a factor of 4.5e5
// where cos(th1 - th2) = +-1, and the momentum route's integrand peaks in the direction of the
// small one. Written in the frame's quadratic form the integrand's q cancelled to lambda_min
// there and the flux at double was off by 1e-11 (E = 1000) and 1.8e-12 (E_max); written in M's
// eigenbasis it keeps the working precision. Reference: the kinetic route at quad (another
// formula, 17 more digits).
TEST(Fluxes, MomentumRouteKeepsItsDigitsForANearlySingularMassMatrix) {
    model_text t;
    t.m1 = "0.1", t.m2 = "10", t.L1 = "5", t.L2 = "0.2", t.a1 = "2.5", t.a2 = "0.1";
    t.I1 = "0", t.I2 = "0.0003", t.g = "20";
    const double_pendulum<double> model(parse_parameters<double>(t));
    const double_pendulum<quad> exact(parse_parameters<quad>(t));
    const auto& k = model.coefficients();
    ASSERT_GT(k.C * k.C / k.D0, 180.0);
    for (arm a : {arm::two, arm::one}) {
        const sine_curve<double> curve = approximate_saddle_curve(model, a);
        const sine_curve<quad> curve_q = approximate_saddle_curve(exact, a);
        for (const char* energy : {"300", "1000", "2050"}) {  // 2050 = E_max
            const curve_flux_result<quad> ref =
                curve_flux(exact, parse_energy_level<quad>(energy, "E"), curve_q);
            if (ref.value == 0) continue;  // arm 1 flips only near E_max here
            const curve_flux_result<double> m = curve_flux(
                model, parse_energy_level<double>(energy, "E"), curve, curve_flux_method::momentum);
            EXPECT_LE(relative_error(m.value, convert<double>(ref.value)), tolerance<double>(16))
                << "arm " << to_string(a) << " E " << energy;
            EXPECT_GE(m.error_estimate, std::abs(m.value - convert<double>(ref.value)))
                << "arm " << to_string(a) << " E " << energy;
        }
    }
}

// Regression (an independent cross-check, 2026-11-30): a lower link 2^20 times heavier makes Q =
// n^T adj(M) n along the approximate curve cancel from 2.8e5 to 0.125 near s = 0; tanh-sinh across
// that dip was 3x beyond its estimate at double and stopped at 16 digits at quad and mp:40. The
// quadrature is now split at the dip. Reference: the cross-check's own derivation (its Lagrangian,
// the curve's slope from the centre mode, mpmath at 30 digits, stable to 30 digits with 200 to 4000
// sub-intervals): 2500854.10600338396553738087.
TEST(Fluxes, KineticRouteKeepsItsDigitsWhereTheNormalWeightDips) {
    model_text t;
    t.m1 = "1", t.m2 = "1048576", t.L1 = "0.5", t.a1 = "0.25", t.I1 = "0.0625", t.L2 = "2";
    t.g = "0.0009765625";
    const double_pendulum<double> model(parse_parameters<double>(t));
    const double_pendulum<quad> exact(parse_parameters<quad>(t));
    const quad reference("2500854.10600338396553738087");
    const curve_flux_result<double> d =
        curve_flux(model, parse_energy_level<double>("51200.0048828125", "E"),
                   approximate_saddle_curve(model, arm::two));
    EXPECT_LE(std::abs(d.value - convert<double>(reference)), d.error_estimate);
    EXPECT_LE(relative_error(d.value, convert<double>(reference)), tolerance<double>(16));
    const curve_flux_result<quad> q =
        curve_flux(exact, parse_energy_level<quad>("51200.0048828125", "E"),
                   approximate_saddle_curve(exact, arm::two));
    // to the reference's 27 printed digits (quad's own estimate is below them; the old code's
    // relative error was 4.4e-17)
    EXPECT_LE(relative_error(q.value, reference), quad("1e-26"));
}

// At E_max the upright flux switches from the incomplete to the complete closed form.
TYPED_TEST(Fluxes, SwitchOfClosedFormAtTheMaximum) {
    using Real = TypeParam;
    using std::sqrt;
    const double_pendulum<Real> model = test::make_model<Real>(test::model_specs()[1]);
    for (arm a : {arm::two, arm::one}) {
        const Real em = model.maximum_energy();
        const Real delta = em - model.saddle_energy(a);
        const Real J = a == arm::two ? model.coefficients().A : model.coefficients().B;
        // at E_max both closed forms give 16 sqrt(2 J delta)
        const Real at = 16 * sqrt(2 * J * delta);
        EXPECT_LE(relative_error(upright_flux_incomplete_elliptic(model, a, em), at),
                  tolerance<Real>(16));
        EXPECT_LE(relative_error(upright_flux_complete_elliptic(model, a, em), at),
                  tolerance<Real>(16));
        const Real d = Real(1) / 1000000000000;
        for (const Real& E : {Real(em - d), Real(em + d)}) {
            const Real closed = upright_flux(model, a, E).value;
            const Real integral = upright_flux(model, a, E, upright_flux_method::integral).value;
            EXPECT_LE(relative_error(closed, integral), tolerance<Real>(64)) << "E " << E;
            // continuous: f1(E_max +- d) = f1(E_max) +- O(d)
            EXPECT_LE(relative_error(closed, at), 1e-11);
        }
    }
    EXPECT_THROW(
        upright_flux_incomplete_elliptic(model, arm::two, Real(2 * model.maximum_energy())),
        std::domain_error);
    EXPECT_THROW(upright_flux_complete_elliptic(model, arm::two, Real(1)), std::domain_error);
    EXPECT_THROW(upright_flux_reciprocal_modulus(model, arm::two, Real(0)), std::domain_error);
}

TYPED_TEST(Fluxes, HugeEnergy) {
    using Real = TypeParam;
    using std::sqrt;
    const double_pendulum<Real> model = test::make_model<Real>(test::model_specs()[2]);
    const Real E(1000000);
    for (arm a : {arm::two, arm::one}) {
        const Real f = upright_flux(model, a, E).value;
        EXPECT_LE(relative_error(upright_flux(model, a, E, upright_flux_method::integral).value, f),
                  tolerance<Real>(64));
        EXPECT_LE(relative_error(upright_flux(model, a, E, upright_flux_method::curve).value, f),
                  tolerance<Real>(64));
        // free rotation: f1 -> 16 sqrt(2 J E) E(0) = 8 pi sqrt(2 J E) as E -> infinity
        const Real J = a == arm::two ? model.coefficients().A : model.coefficients().B;
        EXPECT_LE(relative_error(f, 8 * pi<Real>() * sqrt(2 * J * E)), 1e-5);
        const Real f2 = approximate_saddle_flux(model, a, E).value;
        EXPECT_GT(f2, Real(0));
        if constexpr (std::is_same_v<Real, double>) {
            EXPECT_LE(
                relative_error(
                    approximate_saddle_flux(model, a, E, curve_flux_method::momentum).value, f2),
                target<Real>());
        }
    }
}

// f2 of the egalitarian pendulum, arm 2: the paper's eq. (approximate_saddle_flux) with K taken on
// the curve, by mpmath quad at 60 digits (good to ~45); with K(th1, pi), as the paper's box writes
// it, the value is 10.3548766538103974 at E = 3, 8% off (docs/errata.md).
TYPED_TEST(Fluxes, ApproximateSaddleFluxMatchesThePaperWithKOnTheCurve) {
    using Real = TypeParam;
    const double_pendulum<Real> model;
    const struct {
        const char *E, *f2;
    } cases[] = {{"3", "11.2457052730357908817916329596619059341160421761418"},
                 {"5", "39.2202436481270020304417834280153973011983874046514"}};
    for (const auto& c : cases) {
        const Real E = parse_real<Real>(c.E, "E");
        const std::string expected = c.f2;
        const double tol = std::max(tolerance<Real>(64), 1e-44);
        const curve_flux_result<Real> f2 = approximate_saddle_flux(model, arm::two, E);
        EXPECT_LE(relative_error(f2.value, expected), tol) << "E " << c.E;
        EXPECT_GT(relative_error(f2.value, "10.3548766538103974"), 0.05);
        if constexpr (std::is_same_v<Real, double>) {
            EXPECT_LE(
                relative_error(
                    approximate_saddle_flux(model, arm::two, E, curve_flux_method::momentum).value,
                    expected),
                tol);
        }
    }
    // the amplitudes: 2 - sqrt 2 (paper) and, for arm 1, 1 - 1/sqrt 2 (from the (pi, 0) centre
    // mode (1, 2 + sqrt 2), docs/theory.md)
    using std::sqrt;
    EXPECT_LE(relative_error(approximate_saddle_curve(model, arm::two).amplitude,
                             test::reference_real(2 - sqrt(test::reference_real(2)))),
              tolerance<Real>(16));
    EXPECT_LE(relative_error(approximate_saddle_curve(model, arm::one).amplitude,
                             test::reference_real(1 - 1 / sqrt(test::reference_real(2)))),
              tolerance<Real>(16));
}

/// A test curve: flip angle pi + A sin(s) + B sin(2 s) on [lo, hi].
template <class Real>
struct test_curve {
    arm a;
    Real A, B, lo, hi;
    arm flip_arm() const { return a; }
    Real offset(const Real& s) const {
        using std::sin;
        return A * sin(s) + B * sin(2 * s);
    }
    Real slope(const Real& s) const {
        using std::cos;
        return A * cos(s) + 2 * B * cos(2 * s);
    }
    std::array<Real, 2> domain() const { return {lo, hi}; }
};
static_assert(dividing_curve<test_curve<double>, double>);

TYPED_TEST(Fluxes, GeneralCurvesRespectDomainsZerosAndGrazing) {
    using Real = TypeParam;
    using std::asin;
    using std::sqrt;
    const double_pendulum<Real> model;
    // (1) a domain that is exactly the accessible piece gives the same flux as the full circle
    const Real E(3);
    const sine_curve<Real> sine = approximate_saddle_curve(model, arm::two);
    const curve_flux_result<Real> full = curve_flux(model, E, sine);
    ASSERT_EQ(full.intervals.size(), 1u);
    const test_curve<Real> cut{arm::two, sine.amplitude, Real(0), full.intervals[0][0],
                               full.intervals[0][1]};
    const curve_flux_result<Real> restricted = curve_flux(model, E, cut);
    EXPECT_LE(relative_error(restricted.value, full.value), tolerance<Real>(64));
    // and half of it gives half (the curve is odd, K even)
    const test_curve<Real> half{arm::two, sine.amplitude, Real(0), Real(0), pi<Real>()};
    EXPECT_LE(relative_error(curve_flux(model, E, half).value, full.value / 2),
              tolerance<Real>(64));
    // (2) the accessible piece of the upright curve: |s| < 2 asin(sqrt(delta / (2 alpha)))
    const curve_view<Real> upright_view{arm::two,
                                        {-pi<Real>(), pi<Real>()},
                                        [](const Real&) { return Real(0); },
                                        [](const Real&) { return Real(0); }};
    const auto pieces = accessible_intervals(model, E, upright_view);
    ASSERT_EQ(pieces.size(), 1u);
    const Real s_star = 2 * asin(sqrt((E - 2) / 4));
    EXPECT_LE(relative_error(pieces[0][1], s_star), tolerance<Real>(16));
    EXPECT_LE(relative_error(pieces[0][0], -s_star), tolerance<Real>(16));
    EXPECT_LE(relative_error(curve_kinetic_energy(model, E, upright_view, Real(1)),
                             E - model.potential(Real(1), pi<Real>())),
              tolerance<Real>(16));
    // (3) grazing: at E = E_max, K on the upright curve touches 0 at s = pi, here inside the
    // domain [0, 2 pi]
    const Real em = model.maximum_energy();
    const test_curve<Real> shifted{arm::two, Real(0), Real(0), Real(0), two_pi<Real>()};
    const curve_flux_result<Real> grazing = curve_flux(model, em, shifted);
    EXPECT_LE(relative_error(grazing.value, upright_flux(model, arm::two, em).value),
              tolerance<Real>(64));
    EXPECT_EQ(grazing.intervals.size(), 2u);  // split at the grazing point
    // (4) a wiggly curve that leaves and re-enters the allowed region: both routes agree
    const test_curve<Real> wiggly{arm::two, Real(3) / 2, Real(-9) / 4, -pi<Real>(), pi<Real>()};
    const curve_flux_result<Real> w = curve_flux(model, Real(3), wiggly);
    EXPECT_GE(w.intervals.size(), 2u);
    if constexpr (std::is_same_v<Real, double>) {
        EXPECT_LE(
            relative_error(curve_flux(model, Real(3), wiggly, curve_flux_method::momentum).value,
                           w.value),
            target<Real>());
    }
    // (5) a narrow accessible piece between two samples: just above the saddle
    const Real tiny = model.saddle_energy(arm::two) + Real(1) / 1000000;
    EXPECT_EQ(accessible_intervals(model, tiny, upright_view).size(), 1u);
    // (6) inaccessible curve: zero flux
    EXPECT_EQ(curve_flux(model, Real(1), sine).value, Real(0));
    EXPECT_TRUE(curve_flux(model, Real(1), sine).intervals.empty());
}

TYPED_TEST(Fluxes, BadInput) {
    using Real = TypeParam;
    const double_pendulum<Real> model;
    const Real nan = std::numeric_limits<Real>::quiet_NaN();
    EXPECT_THROW(upright_flux(model, arm::two, nan), std::domain_error);
    EXPECT_THROW(approximate_saddle_flux(model, arm::two, nan), std::domain_error);
    const test_curve<Real> empty{arm::two, Real(0), Real(0), Real(1), Real(1)};
    EXPECT_THROW(curve_flux(model, Real(3), empty), std::domain_error);
    // a tangent along the runaway direction has no finite near-saddle flux
    EXPECT_THROW(near_saddle_flux(model, arm::two, Real(3), Real(2)), std::domain_error);
    // below the saddle: zero
    EXPECT_EQ(upright_flux(model, arm::two, Real(2)).value, Real(0));
    EXPECT_EQ(upright_flux(model, arm::one, Real(3), upright_flux_method::integral).value, Real(0));
    EXPECT_EQ(to_string(upright_flux_method::momentum), "momentum");
    EXPECT_EQ(to_string(upright_flux_method::curve), "curve");
    EXPECT_EQ(to_string(upright_flux_method::integral), "integral");
    EXPECT_EQ(to_string(upright_flux_method::elliptic), "elliptic");
    EXPECT_EQ(to_string(curve_flux_method::kinetic), "kinetic");
    EXPECT_EQ(to_string(curve_flux_method::momentum), "momentum");
}

}  // namespace
}  // namespace flipflux
