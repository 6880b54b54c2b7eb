#include "flipflux/core/constants.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

template <class Real>
class Decimal : public ::testing::Test {};
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

TYPED_TEST(Decimal, RoundTripsWithAllDigits) {
    using Real = TypeParam;
    random_reals rnd(7);
    for (int i = 0; i < 50; ++i) {
        const Real x = Real(rnd(-10, 10)) / 3 * pi<Real>() * Real(rnd(1, 1e6));
        const std::string s = to_decimal(x);
        EXPECT_EQ(parse_real<Real>(s, "x"), x) << s;
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
    if constexpr (std::is_same_v<Real, double> || std::is_same_v<Real, quad>) {
        EXPECT_THROW((void)parse_real<Real>("1e99999", "--energy"), input_error);
    }
}

TEST(Precision, ParsesNamesAndRoundsDigitsUp) {
    EXPECT_EQ(parse_precision("double"), precision::double_);
    EXPECT_EQ(parse_precision("quad"), precision::quad);
    EXPECT_EQ(parse_precision("mp:1"), precision::mp50);
    EXPECT_EQ(parse_precision("mp:50"), precision::mp50);
    EXPECT_EQ(parse_precision("mp:51"), precision::mp100);
    EXPECT_EQ(parse_precision("mp:100"), precision::mp100);
    for (const char* bad : {"float", "mp:", "mp:0", "mp:101", "mp:-3", "mp:5x", "MP:50", ""}) {
        EXPECT_THROW(parse_precision(bad), input_error) << bad;
    }
    EXPECT_EQ(decimal_digits(precision::double_), 15);
    EXPECT_EQ(decimal_digits(precision::quad), 33);
    EXPECT_GE(decimal_digits(precision::mp50), 50);
    EXPECT_GE(decimal_digits(precision::mp100), 100);
    EXPECT_EQ(precision_name(precision::mp100), "mp:100");
}

}  // namespace
}  // namespace flipflux::test
