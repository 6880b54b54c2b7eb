// Elliptic integrals E(phi|m), F(phi|m), E(m), K(m) (include/flipflux/special/elliptic.hpp)
// against three independent references: values computed with mpmath 1.3.0 (ellipe, ellipf,
// ellipk at 70 digits), direct tanh-sinh quadrature of the defining integral in mp:100, and DLMF's
// imaginary- and reciprocal-modulus transformations evaluated with Boost's ellint_1/ellint_2 (which
// take the modulus k and apply only for 0 <= k^2 sin^2 phi < 1).
#include <algorithm>
#include <boost/math/special_functions/ellint_1.hpp>
#include <boost/math/special_functions/ellint_2.hpp>
#include <boost/math/special_functions/ellint_rd.hpp>
#include <boost/math/special_functions/ellint_rf.hpp>
#include <boost/math/special_functions/next.hpp>
#include <cstdio>
#include <stdexcept>

#include "flipflux/core/constants.hpp"
#include "flipflux/quadrature/quadrature.hpp"
#include "flipflux/special/elliptic.hpp"
#include "support.hpp"

namespace flipflux {
namespace {

using test::convert;
using test::eps;
using test::relative_error;

template <class Real>
class Elliptic : public test::real_test<Real> {};
TYPED_TEST_SUITE(Elliptic, test::real_types, test::real_name);

template <class Real>
Real R(const char* text) {
    return parse_real<Real>(text, "test");
}

/// c eps of Real (the references are computed in 100 digits or more).
template <class Real>
double tolerance(double c) {
    return c * static_cast<double>(eps<Real>());
}

/// E(phi|m) by tanh-sinh quadrature of sqrt(1 - m sin^2 u) in mp:100, split at multiples of
/// pi/2 (where sqrt(1 - sin^2 u) = |cos u| has its kinks when m = 1), as decimal text.
std::string e_by_quadrature(const std::string& phi_text, const std::string& m_text) {
    return test::in_mp(100, [&] {
        using std::abs;
        using std::sin;
        using std::sqrt;
        const mp phi = parse_real<mp>(phi_text, "phi"), m = parse_real<mp>(m_text, "m");
        auto f = [&](const mp& u, const mp&, const mp&) -> mp {
            const mp s = sin(u);
            const mp d = 1 - m * s * s;
            return d > 0 ? sqrt(d) : mp(0);
        };
        std::vector<mp> p{mp(0)};
        const mp step = half_pi<mp>();
        const mp target = abs(phi);
        while (p.back() + step < target)
            p.push_back(p.back() + step);
        p.push_back(target);
        const mp v = tanh_sinh_integrate_pieces<mp>(f, p).value;
        return to_decimal(phi < 0 ? mp(-v) : v);
    });
}

struct mpmath_case {
    const char *phi, *m, *value;
};
// mpmath.ellipe(phi, m) at 70 digits (inputs exactly representable in double).
const mpmath_case mpmath_e[] = {
    {"1.25", "-3",
     "1.7886980007014390259151870616591636352444507435346571531873784498193365569104943468270160011"
     "456684367129512507"},
    {"0.5", "4",
     "0.4018194805534948653088910160972210227798828286323500729712391389777333494934817646536615387"
     "6970320367989534231"},
    {"7", "0.75",
     "5.5171292345676972923608610890046944263414471753491670120722594742944820915916663816462129836"
     "175487647799676174"},
    {"-2.5", "-1000000",
     "-1801."
     "1485634696251253566996469782682705408870117455509518931662941599784801985945935666846915"
     "194044448875990233"},
    {"1.5", "0", "1.5"},
    {"3", "1",
     "1.8588799919401327778992551971918897201530667357477344158481173587675779900329855280887178271"
     "465501362495863271"},
    {"-10", "-1",
     "-12."
     "064284079205484607269758738845488898956595698856469044024677907362283573343346932883368352"
     "584407952046814039"},
    {"0.125", "0.5",
     "0.1248375576047894033559274800232039925103912809109592267168759310521340457688620958826624545"
     "0926016537639569579"},
    {"100", "-0.25",
     "106.00987221783960293350803939944613331368901828513354207178681763116927881465314773904555975"
     "344996320495345218"},
    // phi = pi/2 rounded to double, m = 1 - 2^-53: the corner where the Carlson terms cancel
    {"1.5707963267948965579989817342720925807952880859375",
     "0.99999999999999988897769753748434595763683319091796875",
     "1.0000000000000010688502657583019236445727426553688838053557263484273731492972681076274618432"
     "7414262493031043"},
};

TYPED_TEST(Elliptic, IncompleteSecondKindMatchesMpmath) {
    using Real = TypeParam;
    double worst = 0;
    for (const auto& c : mpmath_e) {
        const Real value = elliptic_e(R<Real>(c.phi), R<Real>(c.m));
        const double err = relative_error(value, std::string(c.value));
        worst = std::max(worst, err);
        // NOTE: 64 eps covers the corner m -> 1, phi -> pi/2, where the two Carlson terms are
        // each ~ log(1/cos phi) ~ 37 and cancel to 1.
        EXPECT_LE(err, 64 * static_cast<double>(eps<Real>())) << "phi " << c.phi << " m " << c.m;
    }
    ::testing::Test::RecordProperty("worst_relative_error", std::to_string(worst));
}

TYPED_TEST(Elliptic, CompleteAndFirstKindMatchMpmath) {
    using Real = TypeParam;
    const double tol = 16 * static_cast<double>(eps<Real>());
    EXPECT_LE(relative_error(elliptic_e(Real(-1)),
                             std::string("1."
                                         "91009889451385600895238104108572164595498380"
                                         "7323637360540248328373597900607164960533"
                                         "0905447256112414110214889")),
              tol);
    EXPECT_LE(
        relative_error(elliptic_k(Real(1) / 2),
                       std::string("1."
                                   "854074677301371918433850347195260046217598823521766905585928"
                                   "045056021776838119978357"
                                   "271861650371897277771871")),
        tol);
    EXPECT_LE(
        relative_error(elliptic_f(R<Real>("1.25"), Real(-3)),
                       std::string("0."
                                   "915766948798575060740100419173648567481908842432039520102132"
                                   "910037110254470023289705"
                                   "32334543594065926759062563")),
        tol);
    EXPECT_LE(
        relative_error(elliptic_f(R<Real>("0.5"), Real(4)),
                       std::string("0."
                                   "677417538203930386580891364645540813208927669811008158617960"
                                   "111371864017983053244725"
                                   "36634252457378915819841952")),
        tol);
    EXPECT_EQ(elliptic_e(Real(1)), Real(1));
    EXPECT_LE(relative_error(elliptic_e(Real(0)), half_pi<test::reference_real>()), tol);
}

TYPED_TEST(Elliptic, BoundaryOfTheRealDomainMatchesMpmath) {
    using Real = TypeParam;
    const double tol = 16 * static_cast<double>(eps<Real>());
    // m sin^2 phi = 1 exactly: sin phi = 1/2, m = 4, and sin phi = 1/1000, m = 10^6.
    const Real e4 = elliptic_e_carlson(Real(1) / 2, Real(3) / 4, Real(0), Real(4));
    EXPECT_LE(
        relative_error(e4, std::string("0."
                                       "40629888645996024661278504728321678779952216344283035482"
                                       "1658826141497900219061130698"
                                       "4006005620903488621669239")),
        tol);
    const Real s = Real(1) / 1000;
    const Real e6 = elliptic_e_carlson(s, Real(1 - s * s), Real(0), Real(1000000));
    EXPECT_LE(
        relative_error(
            e6,
            std::string(
                "0."
                "000785398261572255549854783574760113532827306679411090369496154288139522863970508"
                "32158552008489545469989804426398")),
        tol);
    // through elliptic_e with phi = asin(1/sqrt m) rounded: d may come out an ulp below 0
    using std::asin;
    EXPECT_LE(relative_error(elliptic_e(asin(Real(1) / 2), Real(4)), e4), tol);
    // F is finite on the boundary for m > 1
    const Real f4 = elliptic_f_carlson(Real(1) / 2, Real(3) / 4, Real(0), Real(4));
    EXPECT_TRUE(f4 > Real(0) && f4 < Real(1));
}

// DLMF 19.7.5 (imaginary modulus), k^2 = -m > 0, kappa = k / sqrt(1 + k^2):
//   E(phi, ik) = sqrt(1 + k^2) [E(theta, kappa) - kappa^2 sin(theta) cos(theta) /
//                sqrt(1 - kappa^2 sin^2 theta)],  sin theta = sqrt(1 + k^2) sin phi / sqrt(1 + k^2
//                sin^2 phi),
// for 0 <= phi <= pi/2.
TYPED_TEST(Elliptic, NegativeParameterMatchesImaginaryModulusTransformation) {
    using Real = TypeParam;
    using std::asin;
    using std::cos;
    using std::sin;
    using std::sqrt;
    test::random_reals rnd(19);
    double worst = 0;
    for (int i = 0; i < 12; ++i) {
        const Real phi = Real(rnd(0.01, 1.57));
        const Real k2 = Real(rnd(0.001, 50));  // m = -k2
        // the transformation, evaluated in 120 digits (it cancels near phi = pi/2, kappa -> 1)
        using ref = test::reference_real;
        const ref p = test::to_reference(phi), K2 = test::to_reference(k2);
        const ref kappa = sqrt(K2 / (1 + K2));
        const ref sp = sin(p);
        const ref theta = asin(sqrt(1 + K2) * sp / sqrt(1 + K2 * sp * sp));
        const ref st = sin(theta), ct = cos(theta);
        const ref expected = (boost::math::ellint_2(kappa, theta) -
                              kappa * kappa * st * ct / sqrt(1 - kappa * kappa * st * st)) *
                             sqrt(1 + K2);
        const double err = relative_error(elliptic_e(phi, Real(-k2)), expected);
        worst = std::max(worst, err);
        EXPECT_LE(err, tolerance<Real>(16)) << "phi " << phi << " m " << -k2;
    }
    ::testing::Test::RecordProperty("worst_relative_error", std::to_string(worst));
}

// DLMF 19.7.4 (reciprocal modulus), m > 1, sin beta = sqrt(m) sin phi:
//   E(phi|m) = sqrt(m) E(beta|1/m) - ((m - 1)/sqrt(m)) F(beta|1/m).
TYPED_TEST(Elliptic, ParameterAboveOneMatchesReciprocalModulusTransformation) {
    using Real = TypeParam;
    using std::asin;
    using std::sin;
    using std::sqrt;
    test::random_reals rnd(23);
    for (int i = 0; i < 12; ++i) {
        const Real m = Real(rnd(1.01, 200));
        const Real phi_max = asin(1 / sqrt(m));
        const Real phi = phi_max * Real(rnd(0.05, 0.999));
        // the transformation in 120 digits (its two terms ~ sqrt(m) phi cancel)
        using ref = test::reference_real;
        const ref M = test::to_reference(m), p = test::to_reference(phi);
        const ref k = 1 / sqrt(M);
        const ref beta = asin(sqrt(M) * sin(p));
        const ref expected = sqrt(M) * boost::math::ellint_2(k, beta) -
                             (M - 1) / sqrt(M) * boost::math::ellint_1(k, beta);
        EXPECT_LE(relative_error(elliptic_e(phi, m), expected), tolerance<Real>(16))
            << "phi " << phi << " m " << m;
    }
}

// The Legendre relation E(m) K(1-m) + E(1-m) K(m) - K(m) K(1-m) = pi/2 (DLMF 19.7.1).
TYPED_TEST(Elliptic, LegendreRelation) {
    using Real = TypeParam;
    for (const char* text : {"0.001", "0.25", "0.5", "0.875", "0.999999"}) {
        const Real m = R<Real>(text), mc = 1 - m;
        const Real lhs = elliptic_e_complete(m, mc) * elliptic_k_complete(mc, m) +
                         elliptic_e_complete(mc, m) * elliptic_k_complete(m, mc) -
                         elliptic_k_complete(m, mc) * elliptic_k_complete(mc, m);
        EXPECT_LE(relative_error(lhs, half_pi<test::reference_real>()),
                  64 * static_cast<double>(eps<Real>()))
            << "m " << text;
    }
}

TYPED_TEST(Elliptic, QuasiPeriodicityAndOddness) {
    using Real = TypeParam;
    const Real m = R<Real>("-0.75"), phi = R<Real>("0.625");
    for (int k : {-3, -1, 1, 2, 5}) {
        const Real shifted = elliptic_e(Real(phi + k * pi<Real>()), m);
        const Real expected = elliptic_e(phi, m) + 2 * k * elliptic_e(m);
        EXPECT_LE(relative_error(shifted, expected), 16 * static_cast<double>(eps<Real>()));
    }
    EXPECT_EQ(elliptic_e(Real(-phi), m), -elliptic_e(phi, m));
    EXPECT_EQ(elliptic_e(Real(0), m), Real(0));
    EXPECT_LE(relative_error(elliptic_f(Real(phi + 2 * pi<Real>()), m),
                             elliptic_f(phi, m) + 4 * elliptic_k(m)),
              16 * static_cast<double>(eps<Real>()));
}

// Against the defining integral on a grid covering m < 0, 0 <= m <= 1, m > 1 and |phi| > pi/2.
// mp is checked on a few points only (its quadrature reference is the expensive part).
TYPED_TEST(Elliptic, MatchesQuadratureOfTheDefiningIntegral) {
    using Real = TypeParam;
    const bool mp = has_variable_precision_v<Real>;
    const std::vector<std::pair<const char*, const char*>> grid = {
        {"0.75", "-50"}, {"2.25", "-2"},     {"-4.5", "-0.0001"}, {"1", "0.0000001"},
        {"1.5", "0.9"},  {"5.5", "0.999"},   {"0.3", "10"},       {"0.0625", "200"},
        {"9", "1"},      {"-1.25", "0.375"}, {"1.5625", "1"},     {"3.125", "-1000"}};
    double worst = 0;
    std::size_t n = 0;
    for (const auto& [phi_text, m_text] : grid) {
        if (mp && ++n > 4) break;
        const Real phi = R<Real>(phi_text), m = R<Real>(m_text);
        const std::string reference =
            e_by_quadrature(to_decimal(phi, full_digits(phi)), to_decimal(m, full_digits(m)));
        const double err = relative_error(elliptic_e(phi, m), reference);
        worst = std::max(worst, err);
        EXPECT_LE(err, tolerance<Real>(32)) << "phi " << phi_text << " m " << m_text;
    }
    ::testing::Test::RecordProperty("worst_relative_error", std::to_string(worst));
}

TYPED_TEST(Elliptic, HardCases) {
    using Real = TypeParam;
    using std::sqrt;
    const double tol = 64 * static_cast<double>(eps<Real>());
    // m -> 0: E(phi|m) ~ phi - m (2 phi - sin 2 phi)/8
    const Real tiny = std::numeric_limits<Real>::min() * 1024;
    EXPECT_LE(relative_error(elliptic_e(Real(1), tiny), Real(1)), tol);
    // m -> 1 from below with the complement given exactly: E(m) = 1 + (mc/4)(ln(16/mc) - 1) + ...
    const Real mc = Real(1) / (Real(1) * 1024 * 1024 * 1024 * 1024 * 1024 * 1024);
    const Real e = elliptic_e_complete(Real(1 - mc), mc);
    using std::log;
    const Real series = 1 + mc / 4 * (log(16 / mc) - 1);
    EXPECT_LE(relative_error(e, series), tol + 1e-35);
    // phi -> pi/2 from below is continuous with the complete integral
    const Real m = R<Real>("0.5");
    const Real near = elliptic_e(Real(half_pi<Real>() - sqrt(eps<Real>())), m);
    EXPECT_LE(relative_error(near, elliptic_e(m)), 2 * static_cast<double>(sqrt(eps<Real>())));
    // large |m|: E(pi/2|-M) ~ sqrt(M) for M -> infinity (E = sqrt(1+M) E(M/(1+M)) -> sqrt(M))
    const Real big = Real(1) * 1000000 * 1000000;
    EXPECT_LE(relative_error(elliptic_e(Real(-big)), sqrt(big)), 1e-10);
}

// The edge m -> 1 of the complete E and the turning point m sin^2 = 1 with cos^2 -> 0 of the
// incomplete one (f1 just below and above E_max): E = 1 there, but the Carlson form
// R_F - m R_D / 3 subtracts two terms that grow like log(1/mc), which cost ~25 eps at mc = 1e-21
// (regression). References: mpmath 1.3.0 ellipe at 150 digits; tolerance 8 eps.
TYPED_TEST(Elliptic, NoCancellationAtTheEdgeOfTheDomain) {
    using Real = TypeParam;
    using std::sqrt;
    struct edge {
        const char *mc, *complete,
            *turning;  // mc (= c2), E(1 - mc), E(asin(sqrt(1 - c2)) | 1/(1 - c2))
    };
    for (const edge& e :
         {edge{"1e-9", "1.000000005623963641796159464617503660393892291170269011074568146408348",
               "0.999999994376036356829099624089868403785585232039669299309309561463279"},
          edge{"1e-21", "1.000000000000000000012531718918778685150516277278145630664912727687474",
               "0.999999999999999999987468281081221314849480621042124674663799641320282"},
          edge{"1e-40", "1.00000000000000000000000000000000000000234689981105004021495971466683",
               "0.9999999999999999999999999999999999999976531001889499597850402853331698"}}) {
        const Real mc = R<Real>(e.mc), s = sqrt(Real(1 - mc));
        EXPECT_LE(relative_error(elliptic_e_complete(Real(1 - mc), mc), std::string(e.complete)),
                  tolerance<Real>(8))
            << "mc " << e.mc;
        EXPECT_LE(relative_error(elliptic_e_carlson(s, mc, Real(0), Real(1 / (s * s))),
                                 std::string(e.turning)),
                  tolerance<Real>(8))
            << "c2 " << e.mc;
    }
}

/// Carlson's R_F and R_D (special/elliptic.hpp's carlson_rf_rd: shared duplication, series of
/// order ~ sqrt(bits)) against Boost.Math's ellint_rf / ellint_rd (order-5/7 tails, separate
/// duplications), at arguments with a zero, a tiny one, widely spread and near-equal ones.
template <class Real>
void expect_carlson_matches_boost(double c) {
    const char* args[][3] = {
        {"0", "0.5", "1"},     {"0.25", "1.75", "1"},   {"1e-30", "2", "1"},
        {"3", "0", "1"},       {"0.999", "1.001", "1"}, {"100", "0.001", "1"},
        {"0.7", "0.2", "3.5"}, {"1", "1", "1"},         {"5e6", "2e-6", "0.01"}};
    for (const auto& a : args) {
        const Real x = R<Real>(a[0]), y = R<Real>(a[1]), z = R<Real>(a[2]);
        const auto rfd = carlson_rf_rd(x, y, z);
        EXPECT_LE(relative_error(rfd[0], boost::math::ellint_rf(x, y, z)), tolerance<Real>(c))
            << a[0] << ", " << a[1] << ", " << a[2];
        EXPECT_LE(relative_error(rfd[1], boost::math::ellint_rd(x, y, z)), tolerance<Real>(c))
            << a[0] << ", " << a[1] << ", " << a[2];
    }
}

TYPED_TEST(Elliptic, CarlsonRfRdMatchesBoost) {
    using Real = TypeParam;
    expect_carlson_matches_boost<Real>(16);
    // R_F(x, x, x) = x^(-1/2), R_D(x, x, x) = x^(-3/2) (DLMF 19.20.1, 19.20.18)
    const Real x = R<Real>("2.5");
    using std::sqrt;
    const auto same = carlson_rf_rd(x, x, x);
    EXPECT_LE(relative_error(same[0], Real(1 / sqrt(x))), tolerance<Real>(4));
    EXPECT_LE(relative_error(same[1], Real(1 / (x * sqrt(x)))), tolerance<Real>(4));
    const Real inf = std::numeric_limits<Real>::infinity();
    EXPECT_THROW(carlson_rf_rd(Real(0), Real(0), Real(1)), std::domain_error);
    EXPECT_THROW(carlson_rf_rd(Real(1), Real(1), Real(0)), std::domain_error);
    EXPECT_THROW(carlson_rf_rd(Real(-1), Real(1), Real(1)), std::domain_error);
    EXPECT_THROW(carlson_rf_rd(inf, Real(1), Real(1)), std::domain_error);
}

/// |elliptic_e_sum(t, y) - (E(t + y|m) + E(t - y|m))| / (|E(t + y)| + |E(t - y)| + 1), the
/// reference in mp:60 at the same (exactly converted) t, y and m.
template <class Real>
double sum_error(const Real& t, const Real& y, const Real& m, const Real& complete) {
    const Real got = elliptic_e_sum(t, y, m, complete);
    const precision_scope scope(mp_precision(60));
    const mp mt = convert<mp>(t), my = convert<mp>(y), mm = convert<mp>(m);
    const mp u = elliptic_e(mp(mt + my), mm), v = elliptic_e(mp(mt - my), mm);
    return std::abs(static_cast<double>(convert<mp>(got) - (u + v))) /
           static_cast<double>(abs(u) + abs(v) + 1);
}

/// elliptic_e_sum in Real against the two-integral sum E(t + y|m) + E(t - y|m) in mp:60 at the
/// same (exactly converted) t and y: a grid of t in [0, pi], y in [0, pi/2] dense enough that the
/// sum's amplitude sigma passes every half period (the neighbours decided by the sign of
/// cos sigma), m from 0 to the m1 = 0.1 pendulum's -10; error relative to |E(u)| + |E(v)|.
template <class Real>
void expect_sum_matches_two_integrals(double tolerance_eps) {
    double worst = 0;
    for (const char* m_text : {"0", "-0.0625", "-0.5", "-1", "-4", "-10"}) {
        const Real m = parse_real<Real>(m_text, "m");
        const Real complete = elliptic_e_complete(m, Real(1 - m));
        for (int i = 0; i <= 48; ++i)
            for (int j = 0; j <= 24; ++j) {
                const Real t = pi<Real>() * i / 48 + (i % 5 == 1 ? Real(1e-9) : Real(0));
                const Real y = pi<Real>() / 2 * j / 24 + (j % 7 == 3 ? Real(3e-7) : Real(0));
                const double error = sum_error(t, y, m, complete);
                worst = std::max(worst, error);
                ASSERT_LE(error, tolerance_eps * static_cast<double>(eps<Real>()))
                    << "t = " << static_cast<double>(t) << ", y = " << static_cast<double>(y)
                    << ", m = " << m_text;
            }
    }
    std::printf("elliptic_e_sum: worst error %.2f eps\n", worst / static_cast<double>(eps<Real>()));
}

TEST(EllipticSum, AdditionTheoremMatchesTwoIntegralsAtDoubleAndQuad) {
    expect_sum_matches_two_integrals<double>(16);
    expect_sum_matches_two_integrals<quad>(16);
}

/// At y = 0 the sum's amplitude is sigma = 2t exactly, so t = (2j + 1) pi/4 puts sigma on the
/// boundary between the half periods j and j + 1. Within +-40 ulp of it t rounds to one double,
/// so the double estimate of F(u) + F(v) picks one neighbour for all 81 points, and on the far
/// side of the boundary only the sign of cos sigma gives the right one (a wrong pick is off by
/// about 2 E(m)). Negative j: negative half periods. Also at y = 0.3 (sigma then not 2t: the
/// boundary found by bisection in mp:60 on F(t + y) + F(t - y) = (2j + 1) K).
template <class Real>
void expect_boundaries_decided(const char* m_text, double tolerance_eps) {
    const Real m = parse_real<Real>(m_text, "m");
    const Real complete = elliptic_e_complete(m, Real(1 - m));
    for (int j = -3; j <= 3; ++j)
        for (const char* y_text : {"0", "0.3"}) {
            const Real y = parse_real<Real>(y_text, "y");
            Real centre;
            {
                const precision_scope scope(mp_precision(60));
                const mp mm = convert<mp>(m), my = convert<mp>(y);
                const mp target = (2 * j + 1) * elliptic_k(mm);
                mp lo = (2 * j + 1) * pi<mp>() / 4 - 1, hi = lo + 2;  // F increases with t
                for (int it = 0; it < 220; ++it) {
                    const mp mid = (lo + hi) / 2;
                    (elliptic_f(mp(mid + my), mm) + elliptic_f(mp(mid - my), mm) < target ? lo
                                                                                          : hi) =
                        mid;
                }
                centre = convert<Real>(mp((lo + hi) / 2));
            }
            Real t = centre;
            for (int step = 0; step < 40; ++step)
                t = boost::math::float_prior(t);
            for (int step = 0; step <= 80; ++step, t = boost::math::float_next(t)) {
                const double error = sum_error(t, y, m, complete);
                ASSERT_LE(error, tolerance_eps * static_cast<double>(eps<Real>()))
                    << "j = " << j << ", y = " << y_text << ", step " << step << ", m = " << m_text;
            }
        }
}

TEST(EllipticSum, HalfPeriodBoundariesAreDecidedByTheSignOfTheCosine) {
    for (const char* m : {"0", "-1", "-10"}) {
        expect_boundaries_decided<double>(m, 16);
        expect_boundaries_decided<quad>(m, 16);
    }
}

TEST(EllipticHighPrecision, CarlsonRfRdMatchesBoostAtMp300AndMp1000) {
    // the series' order grows with the digits (19 at mp:100, 33 at mp:300, 58 at mp:1000)
    for (int digits : {300, 1000}) {
        const precision_scope scope(mp_precision(digits));
        expect_carlson_matches_boost<mp>(16);
    }
}

TYPED_TEST(Elliptic, OutsideTheDomainThrows) {
    using Real = TypeParam;
    const Real nan = std::numeric_limits<Real>::quiet_NaN();
    EXPECT_THROW(elliptic_e(nan, Real(0)), std::domain_error);
    EXPECT_THROW(elliptic_e(Real(1), nan), std::domain_error);
    EXPECT_THROW(elliptic_e(Real(1), Real(4)), std::domain_error);  // 4 sin^2(1) > 1
    EXPECT_THROW(elliptic_e(Real(3), Real(2)), std::domain_error);  // |phi| > pi/2 with m > 1
    EXPECT_THROW(elliptic_e(Real(2)), std::domain_error);           // complete needs m <= 1
    EXPECT_THROW(elliptic_k(Real(1)), std::domain_error);
    EXPECT_THROW(elliptic_f(half_pi<Real>(), Real(1)), std::domain_error);
    EXPECT_THROW(elliptic_f(Real(4), Real(1)), std::domain_error);
    EXPECT_THROW(elliptic_e_carlson(Real(1) / 2, Real(-1), Real(0), Real(1)), std::domain_error);
    EXPECT_THROW(elliptic_f_carlson(Real(1), Real(0), Real(0), Real(1)), std::domain_error);
    EXPECT_THROW(elliptic_e_complete(Real(1), Real(-1)), std::domain_error);
    EXPECT_THROW(elliptic_k_complete(Real(1), Real(0)), std::domain_error);
}

}  // namespace
}  // namespace flipflux
