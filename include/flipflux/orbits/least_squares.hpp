// A small nonlinear least-squares solve, min_x |r(x)|^2 / 2 with an analytic Jacobian and lower
// bounds, by Ceres' Levenberg-Marquardt (dense QR). Ceres lives in a plugin, libflipflux_ceres.so
// (src/orbits/ceres.plugin.cpp, core/plugin.hpp), loaded on the first solve: a process that solves
// nothing never maps Ceres' libraries. The plugin's interface is the plain data below.
#pragma once

#include <functional>
#include <string>
#include <vector>

extern "C" {

/// How far the solver goes (Ceres' Solver::Options of the same names).
struct flipflux_least_squares_settings {
    int max_iterations = 50;
    double function_tolerance = 1e-6;
    double gradient_tolerance = 1e-10;
    double parameter_tolerance = 1e-8;
};

/// The problem as the plugin sees it. `evaluate` returns 1 on success, 0 where r is undefined
/// (the solver then shortens its step); `jacobian` is null when only r is wanted, else row-major
/// residuals x parameters.
struct flipflux_least_squares_problem {
    int parameters = 0;
    int residuals = 0;
    double* x = nullptr;            ///< the start; the solution on return
    const double* lower = nullptr;  ///< per parameter; -HUGE_VAL: unbounded
    int (*evaluate)(void* context, const double* x, double* r, double* jacobian) = nullptr;
    void* context = nullptr;
    flipflux_least_squares_settings settings;
};

struct flipflux_least_squares_summary {
    int usable = 0;         ///< Ceres' IsSolutionUsable()
    int iterations = 0;     ///< including the zeroth
    double final_cost = 0;  ///< |r|^2 / 2 at the solution
    char report[512] = {};  ///< Ceres' BriefReport (truncated)
};

/// The plugin's one symbol: solves `problem`, writes `summary`; returns 0, or -1 on an error the
/// summary's report then describes.
int flipflux_least_squares_solve(const flipflux_least_squares_problem* problem,
                                 flipflux_least_squares_summary* summary);
}

namespace flipflux {

/// r(x) and, when `jacobian` is non-null, dr/dx (row-major); false where r is undefined.
using least_squares_function = std::function<bool(const double* x, double* r, double* jacobian)>;

using least_squares_settings = flipflux_least_squares_settings;

struct least_squares_result {
    bool usable = false;
    int iterations = 0;
    double final_cost = 0;
    std::string report;
};

/// Solves min |r(x)|^2 / 2 from `x` (updated in place) with `lower` bounds (empty: none; else one
/// per parameter, -HUGE_VAL unbounded) and `residuals` residuals. An exception thrown by `f` is
/// rethrown after the solver has stopped. Throws plugin_error when Ceres' plugin cannot be loaded.
least_squares_result solve_least_squares(const least_squares_function& f, std::vector<double>& x,
                                         int residuals, const std::vector<double>& lower,
                                         const least_squares_settings& settings);

}  // namespace flipflux
