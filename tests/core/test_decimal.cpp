#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iomanip>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

template <class Real>
class Decimal : public test::real_test<Real> {};
TYPED_TEST_SUITE(Decimal, real_types, real_name);

TYPED_TEST(Decimal, ParsesInWorkingPrecisionNotThroughDouble) {
    using Real = TypeParam;
    const Real x = parse_real<Real>("5.3", "--energy");
    const Real exact = Real(53) / 10;  // correctly rounded division in Real
    EXPECT_EQ(x, exact);
    if constexpr (!std::is_same_v<Real, double>) {
        // 5.3 through a double differs from 5.3 at the 17th digit: this would catch it.
        EXPECT_GT(relative_error(Real(5.3), exact), 1e-17);
    }
    EXPECT_EQ(parse_real<Real>("-1.25e-3", "x"), Real(-125) / 100000);
    EXPECT_EQ(parse_real<Real>("+.5", "x"), Real(1) / 2);
    EXPECT_EQ(parse_real<Real>("7.", "x"), Real(7));
}

// parse_difference: the distance of a decimal input to a Real that Real cannot hold by parsing the
// input first. References are powers of ten parsed on their own, and an exact binary expansion.
TYPED_TEST(Decimal, ParseDifferenceKeepsWhatRoundingTheInputLoses) {
    using Real = TypeParam;
    const int k = full_digits(Real(2)) + 3;  // beyond every digit Real holds (mp: guard digits too)
    const Real tiny = parse_real<Real>("1e-" + std::to_string(k), "x");
    const Real eps = std::numeric_limits<Real>::epsilon();
    const std::string above = "2." + std::string(k - 1, '0') + "1";  // 2 + 10^-k
    const std::string below = "1." + std::string(k, '9');            // 2 - 10^-k
    EXPECT_EQ(parse_real<Real>(above, "E"), Real(2));
    EXPECT_EQ(parse_real<Real>(below, "E"), Real(2));
    EXPECT_LE(relative_error(parse_difference<Real>(above, Real(2), "E"), tiny), eps);
    EXPECT_LE(relative_error(parse_difference<Real>(below, Real(2), "E"), Real(-tiny)), eps);
    EXPECT_EQ(parse_difference<Real>("0.5", Real(1) / 2, "E"), Real(0));
    EXPECT_EQ(parse_difference<Real>("-3.25", Real(1), "E"), Real(-17) / 4);
    if constexpr (std::is_same_v<Real, double>) {
        // 5.3 = 5.29999999999999982236431605997495353221893310546875
        // + 1.7763568394002504646778106689453125e-16
        EXPECT_EQ(parse_difference<double>("5.3", 5.3, "E"),
                  1.7763568394002504646778106689453125e-16);
    }
    EXPECT_THROW(parse_difference<Real>("nan", Real(2), "--energy"), input_error);
}

TYPED_TEST(Decimal, RoundTripsWithAllDigits) {
    using Real = TypeParam;
    random_reals rnd(7);
    for (int i = 0; i < 50; ++i) {
        const Real x = Real(rnd(-10, 10)) / 3 * pi<Real>() * Real(rnd(1, 1e6));
        // every digit (for mp: its guard digits too) round-trips exactly
        const std::string s = to_decimal(x, full_digits(x));
        EXPECT_EQ(parse_real<Real>(s, "x"), x) << s;
        // the output form (output_digits) agrees with x to its last digit
        EXPECT_GE(correct_digits(to_decimal(x), x), output_digits<Real>() - 1.5) << s;
    }
    EXPECT_EQ(to_decimal(Real(1) / 2), "0.5");
}

TYPED_TEST(Decimal, OutputDigitsMatchThePrecision) {
    using Real = TypeParam;
    const std::string s = to_decimal(Real(1) / 3);  // "0.333...3" with its last digit rounded
    ASSERT_EQ(s.substr(0, 2), "0.");
    const auto digits = static_cast<int>(s.size()) - 2;
    EXPECT_EQ(digits, output_digits<Real>());
    if constexpr (std::is_same_v<Real, double>) {
        EXPECT_EQ(digits, 17);
    } else if constexpr (std::is_same_v<Real, quad>) {
        EXPECT_EQ(digits, 36);
    }
}

TYPED_TEST(Decimal, RejectsAnythingButAFiniteDecimal) {
    using Real = TypeParam;
    for (const char* bad : {"", "nan", "NaN", "inf", "-inf", "infinity", "abc", "1e", "1.2.3", " 1",
                            "1 ", "0x1p3", "--1", "1e+", ".", "e5", "1e1234567"}) {
        try {
            (void)parse_real<Real>(bad, "--energy");
            ADD_FAILURE() << "accepted '" << bad << "'";
        } catch (const input_error& e) {
            const std::string msg = e.what();
            EXPECT_NE(msg.find("--energy"), std::string::npos) << msg;
            EXPECT_NE(msg.find(std::string("'") + bad + "'"), std::string::npos) << msg;
            EXPECT_EQ(msg.find('\n'), std::string::npos);
        }
    }
    if constexpr (!has_variable_precision_v<Real>) {
        EXPECT_THROW((void)parse_real<Real>("1e99999", "--energy"), input_error);
    }
}

TEST(Precision, ParsesNamesAndAnyDigits) {
    EXPECT_EQ(parse_precision("double"), precision{real_kind::double_});
    EXPECT_EQ(parse_precision("quad"), precision{real_kind::quad});
    for (int n : {1, 2, 49, 50, 51, 80, 100, 101, 300, 1000, 10000, max_mp_digits}) {
        const precision p = parse_precision("mp:" + std::to_string(n));
        EXPECT_EQ(p, mp_precision(n));
        EXPECT_EQ(decimal_digits(p), n);
        EXPECT_EQ(precision_name(p), "mp:" + std::to_string(n));
    }
    for (const char* bad : {"float", "mp:", "mp", "mp:0", "mp:-3", "mp:abc", "mp:1000001", "mp:5x",
                            "mp:+5", "mp:1e3", "MP:50", "double:2", "quad:", ""}) {
        EXPECT_THROW(parse_precision(bad), input_error) << bad;
    }
    try {
        parse_precision("mp:1000001", "--precision");
        ADD_FAILURE() << "no error";
    } catch (const input_error& e) {
        const std::string msg = e.what();
        EXPECT_NE(msg.find("--precision: 'mp:1000001'"), std::string::npos) << msg;
        EXPECT_EQ(msg.find('\n'), std::string::npos);
    }
    EXPECT_EQ(decimal_digits(precision{real_kind::double_}), 15);
    EXPECT_EQ(decimal_digits(precision{real_kind::quad}), 33);
    EXPECT_EQ(mp_working_digits(1), mp_min_working_digits);
    EXPECT_EQ(mp_working_digits(100), 100 + mp_guard_digits);
    // lists: ordered by digits, repeats dropped
    const std::vector<precision> list =
        parse_precision_list("mp:300,double,mp:50,quad,double", "x");
    ASSERT_EQ(list.size(), 4u);
    EXPECT_EQ(list[0], precision{real_kind::double_});
    EXPECT_EQ(list[1], precision{real_kind::quad});
    EXPECT_EQ(list[2], mp_precision(50));
    EXPECT_EQ(list[3], mp_precision(300));
    EXPECT_THROW(parse_precision_list("", "x"), input_error);
    EXPECT_THROW(parse_precision_list("double,mp:0", "x"), input_error);
}

// n doubles of random bit patterns (xorshift64: every kind of value, NaNs and infinities too).
std::vector<double> random_bit_patterns(int n) {
    std::vector<double> out;
    std::uint64_t bits = 0x9E3779B97F4A7C15ull;
    for (int i = 0; i < n; ++i) {
        bits ^= bits << 13;
        bits ^= bits >> 7;
        bits ^= bits << 17;
        double x;
        std::memcpy(&x, &bits, sizeof x);
        out.push_back(x);
    }
    return out;
}

// A double's decimal text (std::to_chars, the fast path of ensemble CSVs) is the iostream's (the
// reference: printf's %.*g through the C++ stream, as every other type is printed), for
// every number of digits and values of every kind: subnormals, powers of ten, halfway cases,
// signed zeros, infinities, NaN and random bit patterns.
TEST(Decimal, DoubleTextEqualsTheStreams) {
    std::vector<double> values = {0.0,
                                  -0.0,
                                  1.0,
                                  0.1,
                                  -2.5,
                                  0.5e-5,
                                  1e16,
                                  9.999999999999999e22,
                                  123456789012345678.0,
                                  std::numeric_limits<double>::denorm_min(),
                                  std::numeric_limits<double>::min(),
                                  std::numeric_limits<double>::max(),
                                  std::numeric_limits<double>::infinity(),
                                  -std::numeric_limits<double>::infinity(),
                                  std::numeric_limits<double>::quiet_NaN()};
    for (const double x : random_bit_patterns(2000))
        values.push_back(x);
    for (const double x : values)
        for (int digits = 1; digits <= 40; ++digits) {
            std::ostringstream stream;
            stream << std::setprecision(digits) << x;
            ASSERT_EQ(to_decimal(x, digits), stream.str()) << digits << " digits";
        }
    EXPECT_EQ(to_decimal(0.1), "0.10000000000000001");  // all of a double's 17 digits
}

// A value echoed in a message (to_shortest_decimal) has the fewest significant digits that read
// back as it: as many as std::to_chars's shortest round-trip form in scientific notation (an
// independent route: the Ryu-style shortest representation of the standard library) for typed
// values and random bit patterns, and at quad and mp:30 a typed decimal comes back as typed.
TEST(Decimal, ShortestDecimalReadsBackAndHasTheFewestDigits) {
    EXPECT_EQ(to_shortest_decimal(-0.1), "-0.1");
    EXPECT_EQ(to_shortest_decimal(0.0), "0");
    // fixed notation as typed from 1e-4 to 1e18 ('50', not '5e+01'), scientific beyond
    for (const auto& [x, text] :
         std::vector<std::pair<double, std::string>>{{50.0, "50"},
                                                     {1500.0, "1500"},
                                                     {-1500.0, "-1500"},
                                                     {2050.5, "2050.5"},
                                                     {1e6, "1000000"},
                                                     {123456.789, "123456.789"},
                                                     {1e17, "100000000000000000"},
                                                     {1.5e18, "1.5e+18"},
                                                     {0.00025, "0.00025"},
                                                     {-0.0001, "-0.0001"},
                                                     {2.5e-5, "2.5e-05"}})
        EXPECT_EQ(to_shortest_decimal(x), text);
    EXPECT_EQ(to_shortest_decimal(std::numeric_limits<double>::infinity()),
              to_decimal(std::numeric_limits<double>::infinity()));
    auto significant = [](std::string t) {  // significant digits of a decimal text
        const std::size_t e = t.find_first_of("eE");
        if (e != std::string::npos) t = t.substr(0, e);
        std::string d;
        for (const char c : t)
            if (c >= '0' && c <= '9') d += c;
        const std::size_t first = d.find_first_not_of('0');
        if (first == std::string::npos) return 1;
        d = d.substr(first);
        const std::size_t last = d.find_last_not_of('0');
        return static_cast<int>(last + 1);
    };
    std::vector<double> values = {0.1, -2.5e-7, 1.0 / 3, 5.3, 1e300, 123456.789};
    for (const double x : random_bit_patterns(2000))
        if (std::isfinite(x)) values.push_back(x);
    EXPECT_EQ(to_shortest_decimal(std::numeric_limits<double>::denorm_min()),
              to_decimal(std::numeric_limits<double>::denorm_min()));  // parse_real refuses it
    for (const double x : values) {
        if (std::abs(x) < std::numeric_limits<double>::min()) continue;  // as above
        const std::string t = to_shortest_decimal(x);
        ASSERT_EQ(parse_real<double>(t, "x"), x) << t;
        char buffer[64];
        const auto r =
            std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::scientific);
        EXPECT_EQ(significant(t), significant(std::string(buffer, r.ptr))) << t;
    }
    EXPECT_EQ(to_shortest_decimal(parse_real<quad>("-0.1", "x")), "-0.1");
    EXPECT_EQ(to_shortest_decimal(parse_real<quad>("2050", "x")), "2050");
    EXPECT_EQ(to_shortest_decimal(parse_real<quad>("2.000000000000000000000001", "x")),
              "2.000000000000000000000001");
    dispatch(parse_precision("mp:30"), [&]<class Real>() {
        if constexpr (has_variable_precision_v<Real>) {
            EXPECT_EQ(to_shortest_decimal(parse_real<Real>("5.3", "x")), "5.3");
            EXPECT_EQ(to_shortest_decimal(parse_real<Real>("-1.25e-40", "x")), "-1.25e-40");
        }
    });
}

// mp:N prints N + 2 significant digits, computes with mp_working_digits(N), and parses its input
// in that precision.
TEST(Precision, MpPrintsTheRequestedDigitsPlusTwo) {
    for (int n : {1, 7, 50, 123, 1000}) {
        const precision_scope scope(mp_precision(n));
        const mp third = mp(1) / 3;
        const std::string text = to_decimal(third);
        EXPECT_EQ(text, "0." + std::string(static_cast<std::size_t>(n + 2), '3')) << "mp:" << n;
        EXPECT_EQ(static_cast<int>(third.precision()), mp_working_digits(n));
        // every working digit is there: 1/3 - 0.333...3 (working digits) is below 1e-(W)
        const std::string all = to_decimal(third, full_digits(third));
        EXPECT_GE(decimal_agreement(all, "0." + std::string(2000, '3')), mp_working_digits(n) - 1);
    }
}

// Decimal comparisons do not depend on the working precision: 1000-digit texts compared exactly.
TEST(Precision, DecimalComparisonsUseEveryDigit) {
    const std::string a = "1." + std::string(999, '0') + "1", b = "1";
    EXPECT_NEAR(decimal_agreement(a, b), 1000, 1e-9);
    EXPECT_EQ(decimal_agreement(b, b), std::numeric_limits<double>::infinity());
    EXPECT_EQ(decimal_relative_error(a, b), 0.0);  // 1e-1000 is below double's range
    EXPECT_NEAR(decimal_relative_error("1.5", "1"), 0.5, 1e-15);
    EXPECT_NEAR(decimal_agreement("0.001", "0"), 3, 1e-12);  // absolute when the reference is 0
    EXPECT_EQ(round_decimal("3.14159", 3), "3.14");
    EXPECT_EQ(round_decimal("0.25", 1), "0.2");           // ties to even, as MPFR rounds
    EXPECT_EQ(round_decimal("-2.5e-300", 1), "-3e-300");  // 2.5e-300 is not a tie in binary
    EXPECT_EQ(round_decimal("1." + std::string(60, '9'), 5), "2");
    // a text with fewer digits than asked for is returned as it is, not padded with the binary
    // noise of its conversion (regression: "35.2" to 50 digits gave 35.20000000000000000000001058)
    EXPECT_EQ(round_decimal("35.2", 50), "35.2");
    EXPECT_EQ(round_decimal("-0.00125", 40), "-0.00125");
    EXPECT_EQ(round_decimal("7e-300", 100), "7e-300");
    EXPECT_EQ(round_decimal("0", 10), "0");
    EXPECT_EQ(round_decimal("100", 50), "100");
    EXPECT_THROW(decimal_agreement("1", "abc"), input_error);
}

// Exact decimal arithmetic (for the distance of a decimal energy to a critical level that is a
// product of decimal parameters): the results checked against sums and products worked by hand.
// The sign of a decimal text, exactly: a zero written any way, and sizes no binary precision holds.
TEST(Decimal, SignOfADecimalText) {
    EXPECT_EQ(decimal_sign("1e-999999"), 1);
    EXPECT_EQ(decimal_sign("-0.0000000000000000000000001"), -1);
    EXPECT_EQ(decimal_sign("+3"), 1);
    for (const char* zero : {"0", "-0", "+0.000", "0e999999", "-0.0E-5", ".0"})
        EXPECT_EQ(decimal_sign(zero), 0) << zero;
    EXPECT_EQ(decimal_sign("00.010e-3"), 1);  // a zero before the first nonzero digit
    EXPECT_EQ(decimal_sign("-9E9"), -1);
}

TEST(Decimal, ExactSumsDifferencesAndProducts) {
    EXPECT_EQ(decimal_product("9.81", "0.45"), "4.4145e0");
    EXPECT_EQ(decimal_product("-0.12", "250"), "-3e1");
    EXPECT_EQ(decimal_product("1.7e-3", "2E+5"), "3.4e2");
    EXPECT_EQ(decimal_sum("15.0093", "1e-40"),
              "1.50093" + std::string(35, '0') + "1e1");  // 15.0093 + 1e-40: 42 digits
    EXPECT_EQ(decimal_difference("15.0093" + std::string(30, '0') + "1", "15.0093"), "1e-35");
    EXPECT_EQ(decimal_difference("0.1", "0.10"), "0");
    EXPECT_EQ(decimal_difference("1", "1.5"), "-5e-1");
    EXPECT_EQ(decimal_sum("+2.5", "-0.5"), "2e0");
    EXPECT_EQ(decimal_product("1e-999999", "10"), "1e-999998");
    // every digit: 0.1 + 0.2 is 0.3, not binary's 0.30000000000000004
    EXPECT_EQ(decimal_sum("0.1", "0.2"), "3e-1");
    EXPECT_THROW(decimal_product("1e-999999", "1e-5"), input_error);  // beyond the range
    EXPECT_THROW(decimal_sum("1", "nan"), input_error);
    EXPECT_THROW(decimal_difference("0x10", "1"), input_error);
}

// The one grid rule (CLI --energy FROM:TO:STEP and scene {from, to, step}): the decimals the user
// meant, whatever the binary value of FROM + i STEP; TO exactly as given.
TEST(DecimalGrid, GivesTheDecimalsMeant) {
    const std::vector<std::string> g = decimal_grid("2.1", "5.9", "0.1", "energy");
    ASSERT_EQ(g.size(), 39u);
    EXPECT_EQ(g[0], "2.1");
    EXPECT_EQ(g[1], "2.2");  // 2.1 + 0.1 in binary is 2.2000000000000002
    EXPECT_EQ(g[8], "2.9");
    EXPECT_EQ(g[38], "5.9");
    const std::vector<std::string> fine =
        decimal_grid("1", "1.000000000000000000000000000002", "1e-30", "energy");
    ASSERT_EQ(fine.size(), 3u);
    EXPECT_EQ(fine[1], "1.000000000000000000000000000001");
    EXPECT_EQ(decimal_grid("4", "4", "0.5", "energy"), std::vector<std::string>{"4"});
}

TEST(DecimalGrid, RefusesWhatIsNotAGrid) {
    const auto field_of = [](const char* from, const char* to, const char* step, long max) {
        try {
            (void)decimal_grid(from, to, step, "energy", max);
        } catch (const input_error& e) {
            EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos);
            return e.field() + ": " + e.detail();
        }
        return std::string("accepted");
    };
    EXPECT_NE(field_of("2", "5", "0.7", 100).find("not a multiple"), std::string::npos);
    EXPECT_NE(field_of("2", "5", "0", 100).find("step '0' must be > 0"), std::string::npos);
    EXPECT_NE(field_of("2", "5", "-1", 100).find("must be > 0"), std::string::npos);
    EXPECT_NE(field_of("5", "4", "0.1", 100).find("below from"), std::string::npos);
    EXPECT_NE(field_of("2", "x", "0.1", 100).find("to 'x' is not a finite"), std::string::npos);
    EXPECT_NE(field_of("0", "1", "0.001", 1000).find("more than 1000 values"), std::string::npos);
    EXPECT_EQ(field_of("0", "1", "0.001", 1001), "accepted");
    EXPECT_EQ(field_of("2", "5", "0", 100).rfind("energy: ", 0), 0u);
}

}  // namespace
}  // namespace flipflux::test
