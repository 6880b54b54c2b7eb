// The double-precision stage of the saddle-orbit solver: the paper's periodic shooting solved by
// Ceres (Levenberg-Marquardt, analytic Jacobian from the variational equations), and the
// symmetric formulation by a plain Newton iteration. Ceres appears only in
// src/orbits/double_stage.cpp; this header does not include it.
#pragma once

#include <string>
#include <vector>

#include "flipflux/model/double_pendulum.hpp"

namespace flipflux::detail {

struct double_stage_result {
    double beta = 0;
    double period = 0;  ///< T (for the symmetric formulation: 4 tau)
    bool converged = false;
    int iterations = 0;
    double residual = 0;  ///< scaled residual norm at the end
    std::string report;   ///< Ceres' BriefReport, or the Newton iteration's summary
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

/// One attempted continuation step (kept as a record: the step halvings are part of the result).
struct continuation_step {
    double from_excess = 0, to_excess = 0;  ///< E - E_s before and after the step
    bool accepted = false;
    int iterations = 0;
    std::string note;  ///< why a step was rejected
};

/// A solved orbit of the double continuation.
struct double_orbit {
    double excess = 0, beta = 0, period = 0;
};

struct double_continuation {
    bool success = false;
    std::vector<double_orbit> orbits;  ///< every accepted orbit, increasing excess
    std::vector<continuation_step> steps;
    int halvings = 0;
    std::string stop_reason;
};

/// Continues the family at double from `known` (the last one or two solved orbits; empty = start
/// from the centre mode (beta_lin, T_lin) at a small excess) up to `target_excess`, with a secant
/// predictor in sigma = -log(E_max - E) and step halving on failure. `periodic` selects Ceres
/// periodic shooting, else the symmetric Newton iteration.
double_continuation continue_double(const double_pendulum<double>& model, arm a, bool periodic,
                                    int stages, double tolerance, std::vector<double_orbit> known,
                                    double beta_lin, double period_lin, double target_excess);

}  // namespace flipflux::detail
