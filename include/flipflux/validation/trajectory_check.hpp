// Validating a simulator's single trajectory (docs/validating.md, "Trajectories"): its flip events,
// and its states when it gives them, against reference events and states.
//
// Events. Candidate and reference are events CSVs (time, arm, direction[, criterion]; a missing
// criterion column means upright; criterion names are case-insensitive; arm and direction may be
// written as numbers, 2.0 and -1.0). The reference may have a `state` column (the golden
// data/golden/trajectories/events.csv), then `state` selects its rows. Events are compared per
// (arm, criterion) stream in time order: the k-th event of a stream must have the same direction
// and a time within time_tolerance. The first difference (earliest in time over every stream and
// state row) is reported.
//
// What is compared is inferred and said:
// - criteria: those the candidate reports (none: the reference's), unless `criteria` insists;
// - the horizon: `until` when given; otherwise the common horizon of candidate and reference (the
//   ends of the trajectories that are known: the last time of a states file, the golden
//   provenance's T) and, for a candidate whose numbers are plainly double precision (at most 17
//   significant digits) compared with a golden trajectory, its double horizon: the time up to
//   which a correct double-precision simulator (rtol 1e-12 or better) agrees at the time tolerance
//   (data/golden/trajectories/double_horizons.csv, tools/double_horizons.py). A difference before
//   the double horizon is a bug; one after it is what chaos does to any double-precision run.
//
// States. When the candidate gives a states CSV (t, theta1, theta2, l1, l2[, state]) and a
// reference states file is known (given, or the golden states.csv beside the golden events), the
// rows at the reference's sample times before the horizon are compared component by component
// within state_tolerance (angles modulo 2 pi: a candidate may wrap them).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "flipflux/core/error.hpp"

namespace flipflux {

struct event_comparison_options {
    double time_tolerance = 1e-6;  ///< absolute, in time units
    double until = 0;              ///< compare up to this time (0: the inferred horizon)
    std::string state;             ///< the reference rows of this state (reference with `state`)
    std::vector<std::string> criteria;       ///< compare these criteria (empty: the candidate's)
    std::filesystem::path candidate_states;  ///< the candidate's states CSV (empty: none)
    std::filesystem::path reference_states;  ///< empty: the golden states.csv beside the reference
    double state_tolerance = 0;              ///< absolute (0: time_tolerance)
    /// The caller's names of these options in the report's advice (the fields until, states,
    /// criteria, time_tol, state_tol, reference_states; the command line gives its options).
    input_namer name = field_as_named;
};

struct event_stream_summary {
    std::string arm, criterion;
    std::size_t candidate = 0, reference = 0;  ///< events before the horizon
    std::size_t agreeing = 0;                  ///< leading events that agree
    double max_time_difference = 0;            ///< over the agreeing events (none: 0)
};

struct state_row_check {
    double t = 0;
    double max_difference = 0;
    std::string component;  ///< where max_difference is
    int candidate_line = 0;
    bool agrees = true;
};

struct event_comparison {
    std::vector<event_stream_summary> streams;
    std::vector<std::string> criteria;     ///< compared
    bool criteria_inferred = false;        ///< from the candidate (not asked for)
    bool criteria_from_reference = false;  ///< the candidate has a criterion column but no event
    double horizon = 0;                    ///< compared before it (infinity: everything)
    std::string horizon_note;              ///< how the horizon was chosen
    bool candidate_double = false;         ///< every number of the candidate has <= 17 digits
    double double_horizon = 0;             ///< the golden double horizon (rtol-1e-12); NaN: none
    double double_horizon_limit = 0;       ///< the same at the double limit; NaN: none
    std::vector<state_row_check> states;
    std::size_t states_not_compared = 0;  ///< candidate rows after the horizon or without reference
    std::string states_not_compared_at;   ///< their times, comma-separated
    bool reference_states_known = false;  ///< a reference states file was given or found
    bool differs = false;
    std::string first_difference;  ///< readable, empty when none
    double first_difference_time = 0;
    std::string verdict;  ///< where the difference falls relative to the double horizon, if known
};

event_comparison compare_flip_events(const std::filesystem::path& candidate,
                                     const std::filesystem::path& reference,
                                     const event_comparison_options& options);

std::string format_event_comparison(const event_comparison& c,
                                    const event_comparison_options& options);

}  // namespace flipflux
