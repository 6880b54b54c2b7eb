// What accuracy costs: for every registered quantity and method, the significant digits achieved
// and the time per evaluation at double, quad, mp:50 and mp:100, as a Markdown report
// (`flipflux accuracy --out docs/accuracy.md`). Registry-driven, like golden data.
//
// Digits of a (method, precision) cell: the minimum over test energies (and both arms) of
// -log10(|x - ref| / |ref|), ref the quantity's default method in mp:100 (for the default method
// in mp:100 itself: the first other applicable method in mp:100). Time: the mean over repeated
// evaluations (at least min_seconds in total, at least one) at the first test energy.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace flipflux {

struct accuracy_options {
    std::vector<std::string> quantities;            ///< empty: every registered quantity
    bool precisions[4] = {true, true, true, true};  ///< double, quad, mp:50, mp:100
    double min_seconds = 0.2;                       ///< timing budget per cell
    /// a cell whose first evaluation takes longer is measured at its first energy only
    double slow_seconds = 3;
    std::function<void(const std::string&)> progress;  ///< called with a line per cell
};

struct accuracy_cell {
    bool applies = false;  ///< false when the method has no test energy in its domain
    double digits = 0;     ///< significant digits achieved (minimum over energies)
    double seconds = 0;    ///< mean time per evaluation
    int energies = 0;      ///< energies (and arms) checked
};

struct accuracy_entry {
    std::string quantity, description, method;
    accuracy_cell cells[4];  ///< double, quad, mp:50, mp:100
};

/// Measures every (quantity, method, precision).
std::vector<accuracy_entry> measure_accuracy(const accuracy_options& options);

/// The Markdown report.
std::string accuracy_markdown(const std::vector<accuracy_entry>& entries,
                              const std::string& command);

}  // namespace flipflux
