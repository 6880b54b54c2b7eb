// Validating a simulator (docs/validating.md, issue 15): its ensemble flip counts against the
// predicted rates, and its flip events of one trajectory against reference events.
//
// Ensembles. A candidate CSV has the columns criterion, arm, energy, trajectories, time, flips
// (any order; optional flips_sq = sum over trajectories of the squared flip count; other columns
// ignored): M trajectories of length tau, microcanonical at energy E, with N flips in all. The
// estimator R^ = N / (M tau) is unbiased for R = f / Omega at every tau (the ensemble is invariant
// under the flow: docs/theory.md, "the estimator"), with Var R^ = Var(N_tau) / (M tau^2).
// Var(N_tau) is taken from the candidate when it gives flips_sq (the unbiased sample variance of
// its per-trajectory counts, as `simulate` computes its standard error); otherwise from a pilot
// ensemble of flipflux's own simulator at (E, tau) with P trajectories, as the upper bound
// s^2 + 3 sqrt((m4 - s^4) / P) (s^2 the sample variance, m4 the fourth central moment of the
// pilot's counts: s^2 plus three standard errors of s^2). Not the Poisson value R tau: counts in
// short trajectories are over-dispersed by recrossing bursts and under-dispersed where flips are
// regular (a rotating arm), so neither is exact.
// Either variance is at least {mu} (1 - {mu}), mu = R tau ({mu} its fractional part): the least
// variance of any integer count with mean mu.
// z = (R^ - R) / sqrt(Var R^); pass |z| < warn_z (3), warn |z| < fail_z (5), FAIL beyond. Where
// fewer than few_flips_expected bursts of D = max(1, Var N / E N) flips are expected in all
// (M R tau / D), the normal law does not hold; z is then the normal quantile of the count's tail
// probability under the compound Poisson law (bursts of D flips). Below an arm's saddle energy
// (R = 0) any flip fails.
//
// A single trajectory's events and states: validation/trajectory_check.hpp.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "flipflux/core/names.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

/// Bursts of flips expected in a row below which its z comes from the Poisson tail.
inline constexpr double few_flips_expected = 10;

struct ensemble_check_options {
    double warn_z = 3, fail_z = 5;
    std::uint64_t pilot_trajectories = 1000;  ///< P, for rows without flips_sq
    std::uint64_t seed = 1;                   ///< of the pilot ensembles
    double rtol = 1e-9;                       ///< of the pilot's integrator
    /// The pilot's variance bound even where the candidate gives flips_sq: the spread of the null
    /// hypothesis (a correct simulator), which a wrong simulator's own wider scatter cannot
    /// inflate (validate --variance pilot).
    bool pilot_variance_always = false;
};

struct ensemble_check_entry {
    enum class status { pass, warn, fail, malformed, no_prediction };
    status what = status::malformed;
    int line = 0;
    std::string criterion, arm, energy;
    std::uint64_t trajectories = 0, flips = 0;
    double time = 0;
    double simulated = 0, predicted = 0, standard_error = 0, z = 0;
    std::string variance;  ///< "candidate" (flips_sq) or "pilot P"
    std::string note;
};

struct ensemble_check_report {
    std::vector<ensemble_check_entry> entries;
    ensemble_check_options options;
    std::size_t count(ensemble_check_entry::status s) const;
    bool passed() const;  ///< at least one row, and none FAIL, malformed or without prediction
};

ensemble_check_report check_simulated_ensemble(const double_pendulum<double>& model,
                                               const std::filesystem::path& candidate,
                                               const ensemble_check_options& options);

/// The summary line first, then one line per candidate row.
std::string format_ensemble_check(const ensemble_check_report& r);

template <>
struct enum_table<ensemble_check_entry::status> {
    static constexpr std::string_view noun = "an ensemble-check status";
    static constexpr std::array<std::pair<ensemble_check_entry::status, std::string_view>, 5>
        entries{{{ensemble_check_entry::status::pass, "pass"},
                 {ensemble_check_entry::status::warn, "warn"},
                 {ensemble_check_entry::status::fail, "FAIL"},
                 {ensemble_check_entry::status::malformed, "malformed"},
                 {ensemble_check_entry::status::no_prediction, "no-prediction"}}};
};

}  // namespace flipflux
