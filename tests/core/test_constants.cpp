// Constants must carry the full working precision: a double literal anywhere would cap quad and
// MPFR at ~1e-16, which these comparisons against 120-digit values catch.
#include "flipflux/core/constants.hpp"
#include "support.hpp"

#include <mpfr.h>

#include <thread>
#include <vector>

namespace flipflux::test {
namespace {

template <class Real>
class Constants : public test::real_test<Real> {};
TYPED_TEST_SUITE(Constants, real_types, real_name);

TYPED_TEST(Constants, AreExactInTheWorkingPrecision) {
    using Real = TypeParam;
    using std::atan;
    using std::sqrt;
    const double tol = 2 * static_cast<double>(eps<Real>());
    const reference_real ref_pi = 4 * atan(reference_real(1));
    EXPECT_LE(relative_error(pi<Real>(), ref_pi), tol);
    EXPECT_LE(relative_error(two_pi<Real>(), reference_real(2 * ref_pi)), tol);
    EXPECT_LE(relative_error(half_pi<Real>(), reference_real(ref_pi / 2)), tol);
    EXPECT_LE(relative_error(root_two<Real>(), reference_real(sqrt(reference_real(2)))), tol);
    if constexpr (!std::is_same_v<Real, double>) {
        // what a truncation to double would look like: must be far above the tolerance
        EXPECT_GT(relative_error(Real(3.141592653589793), ref_pi), 1000 * tol);
    }
}

// mp's limits follow the working precision (Boost computes them on every call from the
// process-wide default precision, with no cache to race on): threads that read them inside one
// scope must all see the exact values, built here with MPFR directly.
TEST(Real, MpLimitsAreExactInEveryThreadOfAScope) {
    for (int digits : {20, 50, 333}) {
        const precision_scope scope(mp_precision(digits));
        using limits = std::numeric_limits<mp>;
        const int bits = binary_digits<mp>();
        EXPECT_GE(bits, static_cast<int>(mp_working_digits(digits) * 3.3219));
        mp max = 0.5, min = 0.5, eps = 1;
        mpfr_mul_2si(max.backend().data(), max.backend().data(), mpfr_get_emax(), MPFR_RNDN);
        mpfr_div_2si(min.backend().data(), min.backend().data(), -mpfr_get_emin(), MPFR_RNDN);
        mpfr_div_2si(eps.backend().data(), eps.backend().data(), bits - 1, MPFR_RNDN);
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
            EXPECT_EQ(w, 0) << "mp:" << digits;
    }
}

}  // namespace
}  // namespace flipflux::test
