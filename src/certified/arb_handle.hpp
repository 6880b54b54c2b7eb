// RAII owners of Arb's arb_t and acb_t (private to certified/: Arb's C types never leave the
// module). Each owns one initialised ball; use .x where Arb expects arb_t / acb_t.
#pragma once

#include <acb.h>
#include <arb.h>

#include <string>

#include "flipflux/core/budget.hpp"

namespace flipflux::certified_detail {

/// The CPU-time budget (core/budget.hpp) checked where no exception may leave: inside Arb's C
/// callbacks (acb_calc_integrate's integrands) or before temporaries are cleared. Returns true,
/// and sets `spent`, once the budget is spent (then at once, without the clock); the caller
/// stops its work and throws budget_exceeded (throw_if_spent) once Arb has returned.
inline bool budget_spent(bool& spent) {
    if (spent) return true;
    try {
        check_cpu_budget();
    } catch (const budget_exceeded&) {
        spent = true;
    }
    return spent;
}
inline void throw_if_spent(bool spent) {
    if (spent) throw budget_exceeded("the CPU-time budget of this computation is spent");
}

struct arb_ball {
    arb_t x;
    arb_ball() { arb_init(x); }
    arb_ball(const arb_ball& o) {
        arb_init(x);
        arb_set(x, o.x);
    }
    arb_ball& operator=(const arb_ball& o) {
        arb_set(x, o.x);
        return *this;
    }
    ~arb_ball() { arb_clear(x); }
};

struct acb_ball {
    acb_t x;
    acb_ball() { acb_init(x); }
    acb_ball(const acb_ball&) = delete;
    acb_ball& operator=(const acb_ball&) = delete;
    ~acb_ball() { acb_clear(x); }
};

/// A string Arb allocated (flint_free on destruction).
std::string take_arb_string(char* s);

}  // namespace flipflux::certified_detail
