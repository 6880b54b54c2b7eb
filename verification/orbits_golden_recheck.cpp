// Golden data's second check of ill-conditioned rows (src/quantities/golden.cpp, pass 3), run for
// real: the light upper arm's saddle-orbit multipliers in mp:60, certified against mp:30 and, for
// a row that check leaves short of its cap (30 digits), again against mp:45. The multiplier of arm
// 1 near E_max (~5e30) is such a row: the periodic shooting's mp:30 value is good to ~18 digits
// only. The reference is the committed mp:100 set (data/golden/light-upper-arm, 50 digits, each
// row proven by an Arb enclosure), not the code under test. ~280 CPU-s: label "verify".
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>
#include <tuple>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/model/energy_level.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/output/golden_files.hpp"
#include "flipflux/quantities/golden.hpp"
#include "flipflux/quantities/registry.hpp"
#include "support.hpp"

namespace flipflux {
namespace {

TEST(GoldenRecheck, IllConditionedRowsAreCertifiedAgainInAHigherPrecision) {
    model_text light;
    light.m1 = "0.1";
    light.L2 = "2";
    std::map<std::tuple<std::string, std::string>, golden_row> reference;
    for (golden_row& r : parse_golden_csv(test::read_text(
             std::string(FLIPFLUX_SOURCE_DIR) + "/data/golden/light-upper-arm/golden.csv")))
        if (r.quantity == "multiplier") reference[{r.arm, r.energy}] = r;
    ASSERT_GE(reference.size(), 12u);

    golden_options options;
    options.model = light;
    options.pendulum = "light-upper-arm";
    options.quantities = {"multiplier"};
    options.value_precision = mp_precision(60);
    options.jobs = 2;
    const precision check = golden_check_precision(options.value_precision);
    const int cap = decimal_digits(check);
    ASSERT_EQ(cap, 30);
    ASSERT_TRUE(golden_recheck_precision(options.value_precision).has_value());
    const std::vector<golden_row> rows = generate_golden(options);
    ASSERT_EQ(rows.size(), reference.size());

    // every row: its value agrees with the proven mp:100 one to the digits it is certified to,
    // |value - ref| <= 10^-d |ref| before the value is rounded to d digits, plus the rounding's
    // half unit of the d-th digit (<= 5 10^-d relative)
    for (const golden_row& r : rows) {
        const auto ref = reference.find({r.arm, r.energy});
        ASSERT_NE(ref, reference.end()) << r.arm << " " << r.energy;
        EXPECT_GE(r.digits, 1);
        EXPECT_GE(decimal_agreement(r.value, ref->second.value), r.digits - std::log10(6.0))
            << "arm " << r.arm << " E " << r.energy << ": " << r.value << " certified to "
            << r.digits << " digits, against " << ref->second.value;
    }

    // the ill-conditioned row: what the mp:30 check alone would certify (the periodic shooting's
    // value in mp:30 against the reference), and what the recheck certified
    const auto row = std::find_if(rows.begin(), rows.end(), [](const golden_row& r) {
        return r.arm == "1" && r.energy == "6.196";
    });
    ASSERT_NE(row, rows.end());
    const std::string at_check = dispatch(check, [&]<class Real>() {
        const double_pendulum<Real> model = make_model<Real>(light);
        const quantity_value<Real> v =
            find_quantity("multiplier")
                .evaluate(model, arm::one, parse_energy_level<Real>("6.196", "E"), "");
        return to_decimal(v.value, decimal_digits(check) + 10);
    });
    const int check_only = agreement_digits(at_check, reference.at({"1", "6.196"}).value, 50);
    ASSERT_LT(check_only, cap) << "the row is no longer ill-conditioned in "
                               << precision_name(check) << ": pick another";
    EXPECT_GT(row->digits, check_only) << "the recheck did not raise the row's digits";
    EXPECT_EQ(row->digits, cap);
}

}  // namespace
}  // namespace flipflux
