// A study's statistics from its ensembles, for simulate() (src/study/simulation.cpp): one
// energy's summary (statistics against the predictions, paired differences), and over the energies
// the quality indices (paper Sec. 5.6), the agreement with the predictions (Sec. 5.5) and the
// differences between the criteria's predictions.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "flipflux/study/simulation.hpp"

namespace flipflux::detail {

/// One energy's result from its finished ensemble: drift and step counts, and per criterion the
/// statistics against the prediction.
energy_result summarise_energy(
    const ensemble_result& r, const std::string& label, const simulation_request& request,
    const process_group& group,
    const std::vector<std::optional<quantity_value<double>>>& predictions);

/// The quality indices of each criterion over the energies, per regime (IQI over all
/// trajectories, PQI also over the chaotic sub-ensemble), with their replicate errors.
void add_quality(study_result& out, const double_pendulum<double>& model);

/// The agreement of every criterion with its predictions and the differences between the
/// criteria's predictions.
void add_comparisons(study_result& out);

}  // namespace flipflux::detail
