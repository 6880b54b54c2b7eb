// A CPU-time budget for the calling thread's long computations. The accuracy harness measures
// the cost of every (quantity, method, precision); a method whose evaluation would take far longer
// than the harness's max_seconds (its cost grew faster with the digits than the lower precisions
// predicted) is abandoned at the budget, not waited for. Long loops (quadrature refinements,
// integrator steps) call check_cpu_budget(), which throws budget_exceeded once the thread has
// used more CPU time than its cpu_budget_scope allows. Without a scope (everywhere but the
// harness) a check costs one thread-local load.
#pragma once

#include <atomic>
#include <stdexcept>
#include <thread>

namespace flipflux {

/// Thrown by check_cpu_budget when the calling thread's budget is spent.
class budget_exceeded : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

namespace detail {
/// The calling thread's CPU-time deadline (seconds of CLOCK_THREAD_CPUTIME_ID); 0: none.
inline thread_local double cpu_deadline = 0;
/// The calling thread's stop flag (stop_poll_scope); null: none.
inline thread_local const std::atomic<int>* stop_poll = nullptr;
// throws budget_exceeded past the deadline or once the stop flag is set (src/core/budget.cpp)
void check_cpu_deadline();
}  // namespace detail

/// The calling thread's CPU time in seconds (CLOCK_THREAD_CPUTIME_ID).
double thread_cpu_seconds();

/// The process's CPU time in seconds, every thread (CLOCK_PROCESS_CPUTIME_ID): beside wall
/// seconds in every timing field (a shared machine's wall time misleads).
double process_cpu_seconds();

/// Throws budget_exceeded when the calling thread's budget (cpu_budget_scope) is spent, or its
/// stop flag (stop_poll_scope) set.
inline void check_cpu_budget() {
    if (detail::cpu_deadline > 0 || detail::stop_poll != nullptr) detail::check_cpu_deadline();
}

/// While it lives, the calling thread may use `seconds` more CPU time in computations that call
/// check_cpu_budget; nested scopes keep the earlier deadline when it comes first.
class cpu_budget_scope {
  public:
    explicit cpu_budget_scope(double seconds);
    ~cpu_budget_scope();
    cpu_budget_scope(const cpu_budget_scope&) = delete;
    cpu_budget_scope& operator=(const cpu_budget_scope&) = delete;

  private:
    double previous_;
};

/// While it lives, check_cpu_budget on the calling thread also throws budget_exceeded once `flag`
/// (a caller's stop flag: a signal's, or a cpu_watch's) is non-zero, so that a long computation
/// on that thread stops where it checks its budget rather than at its end. Null: no flag.
class stop_poll_scope {
  public:
    explicit stop_poll_scope(const std::atomic<int>* flag) : previous_(detail::stop_poll) {
        detail::stop_poll = flag;
    }
    ~stop_poll_scope() { detail::stop_poll = previous_; }
    stop_poll_scope(const stop_poll_scope&) = delete;
    stop_poll_scope& operator=(const stop_poll_scope&) = delete;

  private:
    const std::atomic<int>* previous_;
};

/// While it lives, watches the process's CPU time (every thread) from its construction: once
/// `seconds` more have been used, stores `value` in `flag` (which the computation polls, as it
/// polls a signal's flag) and watches no more. Until then a non-zero value of `relay` (the
/// caller's own stop flag, e.g. a signal's) is copied into `flag`. A watcher thread reads the
/// clocks every 10 ms, so the bound is overrun by at most that much wall time (times the
/// threads) and the computation's poll. seconds <= 0: no watch, no thread.
class cpu_watch {
  public:
    cpu_watch(double seconds, std::atomic<int>& flag, int value,
              const std::atomic<int>* relay = nullptr);
    ~cpu_watch();  // stops and joins the watcher
    cpu_watch(const cpu_watch&) = delete;
    cpu_watch& operator=(const cpu_watch&) = delete;

  private:
    std::jthread watcher_;
};

}  // namespace flipflux
