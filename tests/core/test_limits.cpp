// core/limits.hpp: the memory budget (physical memory, or $FLIPFLUX_MEMORY_LIMIT), the memory
// check's one-line refusal naming the field and value, and the thread limit.
#include <atomic>
#include <cstdlib>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/limits.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

TEST(Limits, MemoryBudgetIsThePhysicalMemoryOrTheEnvironmentsLimit) {
    ::unsetenv("FLIPFLUX_MEMORY_LIMIT");
    const double physical = memory_budget_bytes();
    EXPECT_GT(physical, 1e8);  // any machine that builds flipflux has 100 MB
    ::setenv("FLIPFLUX_MEMORY_LIMIT", "12345", 1);
    EXPECT_EQ(memory_budget_bytes(), 12345.0);
    for (const char* bad : {"0", "-3", "12x", ""}) {  // ignored: the physical memory counts
        ::setenv("FLIPFLUX_MEMORY_LIMIT", bad, 1);
        EXPECT_EQ(memory_budget_bytes(), physical) << bad;
    }
    ::unsetenv("FLIPFLUX_MEMORY_LIMIT");
}

TEST(Limits, MemoryCheckRefusesBeyondTheBudgetInOneLine) {
    ::setenv("FLIPFLUX_MEMORY_LIMIT", "1000000000", 1);  // 1 GB
    EXPECT_NO_THROW(check_memory("bins", "7", 1e9, "histograms"));
    try {
        check_memory("trajectories", "4294967297", 1.3e12, "trajectory records");
        ADD_FAILURE() << "not refused";
    } catch (const input_error& e) {
        EXPECT_EQ(e.field(), "trajectories");
        EXPECT_EQ(std::string(e.what()),
                  "trajectories: '4294967297' would need about 1.3e+03 GB for trajectory "
                  "records, more than the 1 GB of memory available (docs/limits.md)");
    }
    EXPECT_THROW(check_memory("x", "1", std::numeric_limits<double>::infinity(), "y"), input_error);
    EXPECT_THROW(check_memory("x", "1", std::numeric_limits<double>::quiet_NaN(), "y"),
                 input_error);
    ::unsetenv("FLIPFLUX_MEMORY_LIMIT");
}

TEST(Limits, ThreadCountsAreBounded) {
    EXPECT_EQ(checked_threads(0, "threads"), 0);
    EXPECT_EQ(checked_threads(max_threads, "threads"), static_cast<int>(max_threads));
    try {
        (void)checked_threads(100000, "--jobs");
        ADD_FAILURE() << "not refused";
    } catch (const input_error& e) {
        EXPECT_EQ(std::string(e.what()), "--jobs: '100000' is too many threads (at most 4096)");
    }
}

// core/budget.hpp: a spent CPU-time budget stops a loop that checks it; none is set by default;
// a nested scope keeps the outer deadline when that comes first, and the outer one is back after.
TEST(CpuBudget, ASpentBudgetStopsTheLoopThatChecksIt) {
    const auto spin = [](double seconds) {
        const double end = thread_cpu_seconds() + seconds;
        while (thread_cpu_seconds() < end)
            check_cpu_budget();
    };
    EXPECT_NO_THROW(spin(0.02));  // no budget
    {
        const cpu_budget_scope budget(0.01);
        EXPECT_THROW(spin(1), budget_exceeded);
    }
    EXPECT_NO_THROW(spin(0.02));  // gone with its scope
    {
        const cpu_budget_scope outer(0.01);
        {
            const cpu_budget_scope inner(100);  // later than the outer deadline: the outer holds
            EXPECT_THROW(spin(1), budget_exceeded);
        }
        EXPECT_THROW(spin(1), budget_exceeded);
    }
}

// core/budget.hpp's stop_poll_scope: while it lives, a set flag stops a loop that checks its
// budget (no CPU budget needed), at once; an unset flag does not; without the scope the flag is
// not looked at; a null flag is none; with a budget too, the budget still holds.
TEST(CpuBudget, APolledStopFlagStopsTheLoopThatChecksItsBudget) {
    const auto spin = [](double seconds) {
        const double end = thread_cpu_seconds() + seconds;
        while (thread_cpu_seconds() < end)
            check_cpu_budget();
    };
    std::atomic<int> flag{0};
    {
        const stop_poll_scope poll(&flag);
        EXPECT_NO_THROW(spin(0.02));  // not set
        flag.store(2);
        EXPECT_THROW(check_cpu_budget(), budget_exceeded);  // set: the first check throws
    }
    EXPECT_NO_THROW(spin(0.02));  // set, but no longer polled
    {
        const stop_poll_scope none(nullptr);
        EXPECT_NO_THROW(spin(0.02));
    }
    flag.store(0);
    {
        const stop_poll_scope poll(&flag);
        const cpu_budget_scope budget(0.01);
        EXPECT_THROW(spin(1), budget_exceeded);  // the budget, with the flag unset
    }
}

// core/budget.hpp's cpu_watch: a loop polling a flag, as the ensemble's lanes poll their stop
// flag, is stopped once the process has used the watch's seconds (measured here by the process's
// CPU clock from before the watch exists, so that the watcher's own start is inside the count),
// and well before the loop's own 5-second cap (the watch sleeps 10 ms between looks; a loaded
// CI host may keep it from running for longer while the loop spins, hence the wide margin);
// until then a value in the relayed flag (a signal's) reaches the polled one; no bound, no watch.
TEST(CpuBudget, AWatchSetsThePolledFlagAtItsBound) {
    std::atomic<int> flag{0};
    const auto spin_until_flag = [&flag](double start, double at_most) {
        while (flag.load(std::memory_order_relaxed) == 0 && process_cpu_seconds() - start < at_most)
            ;
        return process_cpu_seconds() - start;
    };
    {
        const double start = process_cpu_seconds();
        const cpu_watch watch(0.05, flag, -1);
        const double used = spin_until_flag(start, 5);
        EXPECT_EQ(flag.load(), -1);
        EXPECT_GE(used, 0.05);
        EXPECT_LT(used, 2.5);
    }
    flag = 0;
    {
        const cpu_watch none(0, flag, -1);  // no bound: the flag stays clear
        const double start = process_cpu_seconds();
        EXPECT_GE(spin_until_flag(start, 0.05), 0.05);
        EXPECT_EQ(flag.load(), 0);
    }
    std::atomic<int> caller{0};
    {
        const cpu_watch watch(100, flag, -1, &caller);
        caller = 15;  // SIGTERM's number, set by the caller's handler
        spin_until_flag(process_cpu_seconds(), 5);
        EXPECT_EQ(flag.load(), 15);  // relayed, not the bound's value
    }
}

}  // namespace
}  // namespace flipflux::test
