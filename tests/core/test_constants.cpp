// Constants must carry the full working precision: a double literal anywhere would cap quad and
// MPFR at ~1e-16, which these comparisons against mp100 catch.
#include "flipflux/core/constants.hpp"
#include "support.hpp"

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

}  // namespace
}  // namespace flipflux::test
