// Constants must carry the full working precision: a double literal anywhere would cap quad and
// MPFR at ~1e-16, which these comparisons against mp100 catch.
#include "flipflux/core/constants.hpp"
#include "support.hpp"

#include <mpfr.h>

#include <thread>
#include <vector>

namespace flipflux::test {
namespace {

template <class Real>
class Constants : public ::testing::Test {};
TYPED_TEST_SUITE(Constants, real_types, real_name);

TYPED_TEST(Constants, AreExactInTheWorkingPrecision) {
    using Real = TypeParam;
    using std::atan;
    using std::sqrt;
    const double tol = 2 * static_cast<double>(eps<Real>());
    const mp100 ref_pi = 4 * atan(mp100(1));
    EXPECT_LE(relative_error(pi<Real>(), ref_pi), tol);
    EXPECT_LE(relative_error(two_pi<Real>(), 2 * ref_pi), tol);
    EXPECT_LE(relative_error(half_pi<Real>(), ref_pi / 2), tol);
    EXPECT_LE(relative_error(root_two<Real>(), sqrt(mp100(2))), tol);
    if constexpr (!std::is_same_v<Real, double>) {
        // what a truncation to double would look like: must be far above the tolerance
        EXPECT_GT(relative_error(Real(3.141592653589793), ref_pi), 1000 * tol);
    }
}

// Boost 1.74 fills the MPFR limits on first call without a guard; flipflux fills them at start-up
// (core/real.hpp). Threads that read them first must all see the exact values, built here with
// MPFR directly.
template <class Real>
void expect_limits_in_threads() {
    using limits = std::numeric_limits<Real>;
    Real max = 0.5, min = 0.5, eps = 1;
    mpfr_mul_2si(max.backend().data(), max.backend().data(), mpfr_get_emax(), MPFR_RNDN);
    mpfr_div_2si(min.backend().data(), min.backend().data(), -mpfr_get_emin(), MPFR_RNDN);
    mpfr_div_2si(eps.backend().data(), eps.backend().data(), limits::digits - 1, MPFR_RNDN);
    std::vector<int> wrong(8, -1);
    {
        std::vector<std::thread> threads;
        for (std::size_t i = 0; i < wrong.size(); ++i) {
            threads.emplace_back([&, i] {
                wrong[i] = static_cast<int>((limits::max)() != max) +
                           static_cast<int>((limits::min)() != min) +
                           static_cast<int>(limits::epsilon() != eps) +
                           static_cast<int>(!(limits::infinity() > max));
            });
        }
        for (std::thread& t : threads)
            t.join();
    }
    for (int w : wrong)
        EXPECT_EQ(w, 0) << precision_name<Real>();
}

TEST(Real, MpfrLimitsAreExactInEveryThreadFromTheStart) {
    EXPECT_TRUE(detail::mpfr_limits_warm);
    expect_limits_in_threads<mp100>();
    expect_limits_in_threads<mp50>();
}

}  // namespace
}  // namespace flipflux::test
