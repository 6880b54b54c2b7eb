// CPU-time budgets (core/budget.hpp).
#include "flipflux/core/budget.hpp"

#include <time.h>

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
    // NOTE: reading the thread's clock is a system call (~0.3 us); checks come from loops whose
    // bodies cost far more at the precisions a budget is used with, and every 16th is enough
    thread_local unsigned calls = 0;
    if (++calls % 16 != 0) return;
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

}  // namespace flipflux
