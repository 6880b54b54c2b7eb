// What accuracy costs: for every registered quantity and method, the significant digits achieved
// and the time per evaluation in each requested precision (by default double, quad, mp:50 and
// mp:100), as a Markdown report (`flipflux accuracy --out docs/accuracy.md`). Registry-driven,
// like golden data. A saddle-orbit quantity's methods are measured with each orbit integrator
// ("periodic/taylor", "periodic/gauss-legendre", ...); a quantity with a proven enclosure
// (certified/) gets a row "proof (Arb)": the proven digits (the ball's relative radius) and the
// CPU time of the proof, next to what agreement costs, with a check that the higher-precision
// reference lies in the ball.
//
// Digits of a (method, precision) cell: the minimum over test energies (and both arms) of
// -log10(|x - ref| / |ref|), ref the quantity's default method in the column's reference
// precision (accuracy_reference_precision: mp:(N + 20) for mp:N, mp:120 for the lower columns),
// computed only at the energies the cell is checked at. A default-method cell is thus checked
// against a higher precision, every other method against an independent route. Time: the mean
// over repeated evaluations (at least min_seconds in total, at least one) at the first test energy.
// A method whose evaluation takes longer than max_seconds in one precision, or is estimated to
// from the times of the lower ones (t ~ digits^k), is not measured in the higher ones (its cells
// say so, with the estimate).
#pragma once

#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "flipflux/core/real.hpp"

namespace flipflux {

/// The largest timing budget per cell (seconds): a table has hundreds of cells.
inline constexpr double max_min_seconds = 60;

struct accuracy_options {
    std::vector<std::string> quantities;  ///< empty: every registered quantity
    /// the columns, in increasing precision
    std::vector<precision> precisions{precision{real_kind::double_}, precision{real_kind::quad},
                                      mp_precision(50), mp_precision(100)};
    double min_seconds = 0.2;  ///< timing budget per cell, in [0, max_min_seconds]
    /// a cell whose first evaluation takes longer is measured at its first energy only
    double slow_seconds = 3;
    /// a method slower than this in one precision (measured, or estimated from the lower
    /// precisions' times) is not measured in it and the higher ones
    double max_seconds = 120;
    /// cells of one precision are measured concurrently on this many threads (each cell's time is
    /// its own thread's CPU time, so the figures do not depend on it)
    int threads = 1;
    std::function<void(const std::string&)> progress;  ///< called with a line per cell
};

/// The reference precision of a column: mp:(N + 20) for mp:N with N >= 100, mp:120 below.
precision accuracy_reference_precision(const precision& column);

struct accuracy_cell {
    bool applies = false;  ///< false when the method has no test energy in its domain
    bool skipped = false;  ///< not measured: too slow in a lower precision
    /// not measured: abandoned at its CPU budget (2 max_seconds, core/budget.hpp)
    bool over_budget = false;
    double digits = 0;   ///< significant digits achieved (minimum over energies)
    double seconds = 0;  ///< mean time per evaluation
    /// skipped cells: the time one evaluation was estimated to take (0: slower in a lower one)
    double estimated_seconds = 0;
    int energies = 0;  ///< energies (and arms) checked
    /// proof rows: false when a higher-precision reference lay outside a proven ball (a bug in
    /// one of the two routes; the report says so)
    bool contains_reference = true;
    /// not empty: an evaluation or a proof failed (its one-line error; the report says so)
    std::string failure;
};

/// The method name of the proof rows.
inline constexpr std::string_view proof_method = "proof (Arb)";

struct accuracy_entry {
    std::string quantity, description, method;  ///< method: a registry method or proof_method
    std::vector<accuracy_cell> cells;           ///< one per column (accuracy_options::precisions)
};

/// Measures every (quantity, method, precision).
std::vector<accuracy_entry> measure_accuracy(const accuracy_options& options);

/// The digits a column prints (and at which its agreement is capped): those of its precision.
int accuracy_column_cap(const precision& p);

}  // namespace flipflux
