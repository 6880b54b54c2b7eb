// The paired ensemble check (docs/validating.md, "Paired ensembles"): a simulator's flip counts
// of its own initial states against flipflux's counts of the same states, trajectory by
// trajectory. The strongest ensemble check: the sampling noise cancels in each pair, so what is
// left is the simulators' difference.
//
// A candidate CSV has one row per trajectory and (arm, criterion): columns energy, theta1,
// theta2, l1, l2 (the initial state, canonical variables), time (T), arm, flips, optional
// criterion (upright when absent; any case) and trajectory (a name used in messages); other
// columns are ignored. Each state must have H = E to a relative 1e-8. flipflux integrates each
// distinct (state, T) once (the ensemble's integrator and detectors, DOP853 at rtol 1e-12 by
// default) and counts every requested (arm, criterion).
//
// Per (criterion, arm, energy) group of n rows: d_i = candidate_i - flipflux_i, the mean d and
// its standard error s_d / sqrt(n) (s_d the sample standard deviation: the spread the pairs were
// measured to have), z = d / se. Counts agree trajectory by trajectory until chaos parts the two
// integrations; after that they differ with mean 0. So two tests:
// - the mean: t = d / se, graded by its two-sided tail under Student's law with n - 1 degrees of
//   freedom as a normal z would be: the z of that tail >= warn_z (3) warns, >= fail_z (5) fails;
//   with se = 0 (one pair, or every pair alike) there is no mean test and the pairs decide;
// - the pairs themselves: a trajectory is stable when flipflux's counts from two independent
//   integrations agree (DOP853 at rtol 1e-12 and DOPRI5 at rtol 1e-9: another method at a looser
//   tolerance, as a correct simulator may be); a correct candidate agrees with flipflux on the
//   stable ones. One unexpected difference warns (a grazing crossing a detector resolves
//   otherwise); more than 1 + 5 % of the stable trajectories fails: that is a wrong simulator,
//   whatever its mean.
// The first row whose counts differ is named.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

struct paired_check_options {
    double warn_z = 3, fail_z = 5;
    double rtol = 1e-12;  ///< of flipflux's integrations
};

struct paired_group {
    enum class status { pass, warn, fail };
    status what = status::pass;
    std::string criterion, arm, energy;
    std::size_t trajectories = 0, identical = 0;
    std::size_t stable = 0;                        ///< flipflux's two integrations agree
    std::size_t unexpected = 0;                    ///< stable, yet the candidate's count differs
    double candidate_mean = 0, flipflux_mean = 0;  ///< flips per trajectory
    double mean_difference = 0, standard_error = 0;
    double z = 0;       ///< t = mean_difference / standard_error (0 without a spread)
    double mean_z = 0;  ///< the normal z of t's two-sided tail (Student, n - 1): what is graded
    std::string first_difference;  ///< the group's first row whose counts differ ("" if none)
    int first_line = 0;
};

struct paired_check_report {
    std::vector<paired_group> groups;
    paired_check_options options;
    std::string first_difference;  ///< the file's first row whose counts differ
    bool passed() const;           ///< at least one group, none FAIL
};

paired_check_report check_paired_ensemble(const double_pendulum<double>& model,
                                          const std::filesystem::path& candidate,
                                          const paired_check_options& options);

std::string format_paired_check(const paired_check_report& r);

}  // namespace flipflux
