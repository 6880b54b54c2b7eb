// The convergence model shared by the nested rules (tanh-sinh levels, Clenshaw-Curtis pairs).
#pragma once

#include <cmath>

namespace flipflux::detail {

/// The error of a converged rule's finer result from d, the difference between it and the coarser
/// one, and the L1 norm l1: once converged, each refinement squares the relative error, so d ~
/// r_coarse l1 makes the finer error ~ d^2 / l1; where the convergence has not reached that regime
/// (a near singularity: the doubling starts late) the error falls more slowly, and the estimate
/// uses the power 3/2, d (d / l1)^(1/2). Measured against 40-digit references
/// (tests/prediction/test_error_estimates.cpp).
template <class Real>
Real converged_error(const Real& d, const Real& l1) {
    using std::sqrt;
    return d * sqrt(d / l1);
}

}  // namespace flipflux::detail
