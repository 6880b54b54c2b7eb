// The heavy-tail check of replicated ensembles (docs/theory.md, "Replicate errors"): the one home
// of its range, used by the study's verdicts, their JSON and the command line's warning.
#pragma once

#include <array>
#include <cstddef>

namespace flipflux {

/// The heavy-tail check's false-alarm probability per energy, criterion and subset when the
/// per-trajectory error is right.
inline constexpr double replicate_check_false_alarm = 1e-3;

/// The range of r = (replicate error) / (per-trajectory standard error of the pooled mean) outside
/// which the heavy-tail check flags an energy. For R equal replicates of independent trajectories
/// with a finite variance, r^2 is chi^2 with R - 1 degrees of freedom over R - 1, so the range is
/// the square roots of that distribution's replicate_check_false_alarm / 2 and
/// 1 - replicate_check_false_alarm / 2 quantiles: [6.3e-4, 3.48] for R = 2, [0.33, 1.82] for
/// R = 10, narrowing as R grows. (A fixed [1/2, 2] flagged 43 % of well-behaved energies at R = 2.)
/// Throws std::invalid_argument for R < 2.
std::array<double, 2> replicate_error_ratio_range(std::size_t replicates);

/// Whether the heavy-tail check flags `ratio` for R replicates (a NaN ratio is not flagged).
bool replicate_error_ratio_flagged(double ratio, std::size_t replicates);

}  // namespace flipflux
