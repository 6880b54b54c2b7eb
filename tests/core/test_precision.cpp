// mp's working precision (core/real.hpp, precision_scope): one precision active in the process at
// a time; threads of one precision run concurrently, a second precision waits for the first,
// nested scopes in one thread switch and come back, and every result carries the digits of its
// own precision.
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "flipflux/core/constants.hpp"
#include "flipflux/special/elliptic.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

using namespace std::chrono_literals;

// 16 pi^2 E(-1) by mpmath 1.3.0 (120 digits).
const char* const sixteen_pi2_e_minus_one =
    "301.6307272929579491278041858189564673289868134930415803493231794541102518930997723177695100"
    "239061635259975231883";

/// 16 pi^2 E(-1) in the working precision, as decimal text with every digit.
std::string omega_max_text() {
    const mp v = 16 * pi<mp>() * pi<mp>() * elliptic_e(mp(-1));
    return to_decimal(v, full_digits(v));
}

TEST(PrecisionScope, TwoThreadsOfOnePrecisionRunConcurrently) {
    std::mutex m;
    std::condition_variable cv;
    int inside = 0;
    bool both_inside[2] = {false, false};
    std::string results[2];
    auto work = [&](int i) {
        const precision_scope scope(mp_precision(60));
        {
            std::unique_lock<std::mutex> lock(m);
            ++inside;
            cv.notify_all();
            // the other thread enters while this one holds the same precision
            both_inside[i] = cv.wait_for(lock, 20s, [&] { return inside == 2; });
        }
        results[i] = omega_max_text();
    };
    std::thread a(work, 0), b(work, 1);
    a.join();
    b.join();
    EXPECT_TRUE(both_inside[0] && both_inside[1]);
    EXPECT_EQ(results[0], results[1]);
    EXPECT_GE(correct_digits(results[0], sixteen_pi2_e_minus_one), mp_working_digits(60) - 2);
}

TEST(PrecisionScope, ASecondPrecisionWaitsForTheFirst) {
    std::atomic<bool> first_inside{false}, first_done{false}, second_saw_first_done{false};
    std::string low, high;
    std::thread first([&] {
        const precision_scope scope(mp_precision(40));
        first_inside = true;
        std::this_thread::sleep_for(300ms);  // the second thread asks for mp:200 meanwhile
        low = omega_max_text();
        // still 50 working digits: not switched under it
        EXPECT_EQ(binary_digits<mp>(),
                  static_cast<int>(boost::multiprecision::detail::digits10_2_2(50)));
        first_done = true;
    });
    while (!first_inside)
        std::this_thread::yield();
    std::thread second([&] {
        const precision_scope scope(mp_precision(200));
        second_saw_first_done = first_done.load();
        high = omega_max_text();
    });
    first.join();
    second.join();
    EXPECT_TRUE(second_saw_first_done);
    EXPECT_GE(correct_digits(low, sixteen_pi2_e_minus_one), mp_working_digits(40) - 2);
    EXPECT_GE(correct_digits(high, sixteen_pi2_e_minus_one), 110);  // the reference has 114
    EXPECT_GE(correct_digits(low, high), mp_working_digits(40) - 2);
    EXPECT_GT(high.size(), 200u);
}

TEST(PrecisionScope, NestedScopesSwitchAndComeBack) {
    const precision_scope outer(mp_precision(50));
    const mp x = mp(1) / 3;
    EXPECT_EQ(active_mp_digits(), 50);
    const std::string inner = in_mp(500, [] {
        EXPECT_EQ(active_mp_digits(), 500);
        const mp y = mp(1) / 3;
        EXPECT_EQ(static_cast<int>(y.precision()), mp_working_digits(500));
        return to_decimal(y);
    });
    EXPECT_EQ(inner.size(), 504u);  // "0." and 502 digits
    EXPECT_EQ(active_mp_digits(), 50);
    const mp z = mp(2) / 3;
    EXPECT_EQ(static_cast<int>(z.precision()), mp_working_digits(50));
    EXPECT_EQ(static_cast<int>(x.precision()), mp_working_digits(50));
    EXPECT_EQ(to_decimal(x), "0." + std::string(52, '3'));
    // the same precision nested: no switch
    {
        const precision_scope again(mp_precision(50));
        EXPECT_EQ(active_mp_digits(), 50);
    }
    EXPECT_EQ(active_mp_digits(), 50);
}

TEST(PrecisionScope, ValuesKeepTheirPrecisionAfterTheirScope) {
    const std::string text = in_mp(30, [] { return to_decimal(pi<mp>()); });
    const mp kept = in_mp(300, [] { return pi<mp>(); });
    // a value outside any scope of its precision prints all of its own digits
    EXPECT_EQ(static_cast<int>(kept.precision()), mp_working_digits(300));
    EXPECT_GE(correct_digits(to_decimal(kept, full_digits(kept)), text), 31);
    EXPECT_EQ(text.size(), 33u);  // "3." and 31 decimals: 32 significant digits
    EXPECT_THROW(precision_scope(mp_precision(0)), std::invalid_argument);
    // the fixed kinds need no scope and ignore one
    const precision_scope fixed(precision{real_kind::quad});
    EXPECT_EQ(precision_of<quad>(), precision{real_kind::quad});
}

}  // namespace
}  // namespace flipflux::test
