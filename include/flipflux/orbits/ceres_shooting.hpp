// The double-precision stage of the saddle-orbit solver: the paper's periodic shooting solved by
// Ceres (Levenberg-Marquardt, analytic Jacobian from the variational equations), and the
// symmetric formulation by a plain Newton iteration. Ceres appears only in its plugin
// (src/orbits/ceres.plugin.cpp, through orbits/least_squares.hpp); this header does not include it.
#pragma once

#include <array>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux::detail {

struct double_stage_result {
    double beta = 0;
    double period = 0;  ///< T (for the symmetric formulation: 4 tau)
    bool converged = false;
    int iterations = 0;
    double residual = 0;  ///< scaled residual norm at the end
    /// The action F = 4 x the quarter orbit's (symmetric formulation; NaN for the periodic one)
    double action = std::numeric_limits<double>::quiet_NaN();
    /// For a solution that converged: the largest |delta1|, |delta2| along its quarter orbit
    /// (quarter_extent; zero when not computed); it is not the saddle orbit when either reaches
    /// pi (converged is then false)
    std::array<double, 2> extent{};
    bool left_strip() const {
        return extent[0] >= std::numbers::pi || extent[1] >= std::numbers::pi;
    }
    std::string report;  ///< Ceres' BriefReport, or the Newton iteration's summary
};

/// Periodic shooting with Ceres: minimise |x(T) - x(0)|^2 / (2 (E - E_s)) over (beta, T) with
/// `steps` Gauss-Legendre steps of `stages` stages.
double_stage_result ceres_periodic_shooting(const double_pendulum<double>& model, arm a,
                                            double excess, double beta0, double period0, long steps,
                                            int stages);

/// Symmetric shooting with Newton: l(tau) = 0 over (beta, tau = T/4).
double_stage_result newton_symmetric_shooting(const double_pendulum<double>& model, arm a,
                                              double excess, double beta0, double period0,
                                              long quarter_steps, int stages);

/// A solved orbit of the double continuation.
struct double_orbit {
    double excess = 0, beta = 0, period = 0;
    bool requested = false;  ///< one of the targets (else an intermediate step)
    double action = std::numeric_limits<double>::quiet_NaN();  ///< F; NaN: not known
};

struct double_continuation {
    bool success = false;
    std::vector<double_orbit> orbits;  ///< every accepted orbit, increasing excess
    std::vector<continuation_step> steps;
    int halvings = 0;
    double highest_excess = 0;
    std::string stop_reason;
    /// Where the family leaves its saddle's strip (E - E_s; NaN: not seen): the corrector's
    /// solutions on the family's path left it beyond highest_excess while the last accepted
    /// orbit's swing was within 1e-2 of pi (the family's end as saddle orbits, docs/limits.md)
    double strip_end = std::numeric_limits<double>::quiet_NaN();
    int strip_angle = 0;  ///< which angle's swing reaches pi there (1 or 2)
};

/// Continues the family at double from the centre mode (beta_lin, T_lin) through every excess
/// E - E_s in `targets` (increasing), with a secant predictor in sigma = -log(E_max - E) and
/// step halving on failure. `periodic` selects Ceres periodic shooting as the corrector, else the
/// symmetric Newton iteration. Stops at the first excess it cannot reach (success = false).
double_continuation continue_double(const double_pendulum<double>& model, arm a, bool periodic,
                                    int stages, double tolerance, double beta_lin,
                                    double period_lin, const std::vector<double>& targets);

}  // namespace flipflux::detail
