// CPU-time budgets (core/budget.hpp).
#include "flipflux/core/budget.hpp"

#include <time.h>

#include <chrono>
#include <string>

namespace flipflux {

double thread_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

double process_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

namespace detail {
void check_cpu_deadline() {
    // NOTE: the thread's CPU clock is a system call (1.7 us on a Zen 5 virtual machine), the coarse
    // monotonic clock is read in user space (vDSO, 6 ns; it advances once a kernel tick, 1-4 ms):
    // the CPU clock is read once the coarse clock has moved by a millisecond since its last
    // reading. A thread's CPU time grows no faster than the wall time, so the budget is overrun
    // by at most one loop body and a tick, whatever the loop's cost (a fixed count of 16 calls
    // between readings let mp:300 Taylor steps of ~0.25 s run 4 s past a bound of 0.5 s).
    if (stop_poll != nullptr && stop_poll->load(std::memory_order_relaxed) != 0)
        throw budget_exceeded("the computation was asked to stop");
    if (!(cpu_deadline > 0)) return;
    thread_local double last = -1;
    timespec w{};
    clock_gettime(CLOCK_MONOTONIC_COARSE, &w);
    const double now = static_cast<double>(w.tv_sec) + 1e-9 * static_cast<double>(w.tv_nsec);
    if (last >= 0 && now - last < 1e-3) return;
    last = now;
    if (thread_cpu_seconds() > cpu_deadline)
        throw budget_exceeded("the CPU-time budget of this computation is spent");
}
}  // namespace detail

cpu_budget_scope::cpu_budget_scope(double seconds) : previous_(detail::cpu_deadline) {
    const double deadline = thread_cpu_seconds() + seconds;
    if (previous_ == 0 || deadline < previous_) detail::cpu_deadline = deadline;
}

cpu_budget_scope::~cpu_budget_scope() {
    detail::cpu_deadline = previous_;
}

cpu_watch::cpu_watch(double seconds, std::atomic<int>& flag, int value,
                     const std::atomic<int>* relay) {
    if (!(seconds > 0)) return;
    const double deadline = process_cpu_seconds() + seconds;
    watcher_ = std::jthread([deadline, &flag, value, relay](const std::stop_token& stop) {
        while (!stop.stop_requested()) {
            if (const int v = relay != nullptr ? relay->load() : 0; v != 0) flag.store(v);
            if (process_cpu_seconds() >= deadline) {
                flag.store(value);
                return;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
    });
}

cpu_watch::~cpu_watch() {
    if (watcher_.joinable()) {
        watcher_.request_stop();
        watcher_.join();
    }
}

}  // namespace flipflux
