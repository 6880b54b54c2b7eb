// The least-squares solve through Ceres' plugin (orbits/least_squares.hpp).
#include "flipflux/orbits/least_squares.hpp"

#include <exception>
#include <stdexcept>

#include "flipflux/core/plugin.hpp"

namespace flipflux {
namespace {

struct callback_context {
    const least_squares_function* f;
    std::exception_ptr error;
};

int evaluate(void* context, const double* x, double* r, double* jacobian) {
    auto& c = *static_cast<callback_context*>(context);
    if (c.error) return 0;
    try {
        return (*c.f)(x, r, jacobian) ? 1 : 0;
    } catch (...) {
        c.error = std::current_exception();
        return 0;
    }
}

}  // namespace

least_squares_result solve_least_squares(const least_squares_function& f, std::vector<double>& x,
                                         int residuals, const std::vector<double>& lower,
                                         const least_squares_settings& settings) {
    if (!lower.empty() && lower.size() != x.size())
        throw std::invalid_argument("solve_least_squares: one lower bound per parameter");
    using solve_fn = decltype(&flipflux_least_squares_solve);
    static const auto solve =
        reinterpret_cast<solve_fn>(plugin_symbol("ceres", "flipflux_least_squares_solve"));
    callback_context context{&f, nullptr};
    flipflux_least_squares_problem p;
    p.parameters = static_cast<int>(x.size());
    p.residuals = residuals;
    p.x = x.data();
    p.lower = lower.empty() ? nullptr : lower.data();
    p.evaluate = &evaluate;
    p.context = &context;
    p.settings = settings;
    flipflux_least_squares_summary s;
    const int status = solve(&p, &s);
    if (context.error) std::rethrow_exception(context.error);
    if (status != 0) throw std::runtime_error(s.report);
    return {s.usable != 0, s.iterations, s.final_cost, s.report};
}

}  // namespace flipflux
