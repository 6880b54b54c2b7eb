// Golden reference data: every registered quantity on an energy grid, with its certified digits
// (`flipflux golden`; data/golden/README.md describes the files).
//
// A row's value is computed by the quantity's default method in mp:N (by default mp:100). Its
// certified digits are
//     min( agreement of the default method in mp:(N/2) with mp:N,
//          agreement of the first independent method that applies (the quantity's
//          check_methods, else its other methods), in mp:(N/2), with mp:N ),
// agreement = floor(-log10(|a - b| / |b|)), at most N/2; the value is written with that many
// significant digits. Rows whose quantity is zero (a flux below its saddle) or whose energy is
// outside the quantity's domain (input_error) are left out. Driven by the registry: quantities
// registered by other modules join without change here.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "flipflux/core/real.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/model_text.hpp"

namespace flipflux {

struct golden_row {
    std::string quantity;
    std::string arm;     ///< "1", "2", or "" for quantities that are not per arm
    std::string energy;  ///< decimal text, exactly as parsed in every precision
    std::string value;   ///< the value with `digits` significant digits
    int digits = 0;      ///< certified significant digits
    std::string method;  ///< "default|checked" methods, e.g. "elliptic|quadrature-2d"
    /// golden --certify: the radius of a proven enclosure [value +/- radius] of the exact value
    /// (certified/: its midpoint rounded to the row's digits, the rounding included), and its
    /// proven digits; "" and -1 for rows without one.
    std::string radius;
    int proven_digits = -1;
};

/// The energy grid of a quantity for the egalitarian pendulum (or any model: E_s and E_max are
/// taken from it): every 0.05 from just above `start` up to E_max, then 6.5, 7, 7.5, 8, 9, 10,
/// 12, 15, 20, 25, 30, 40, 50, 60, 70, 80, 90, 100 (those above E_max). start = 0 for quantities
/// not per arm, else the arm's saddle energy.
std::vector<std::string> golden_energies(double start, double maximum);

/// The coarser grid of quantities that need the saddle orbit (a periodic-shooting orbit costs
/// seconds to a minute in mp:100): start + 0.05, then every whole unit above start, maximum - 0.05,
/// maximum - 0.01 and maximum - 0.001 (egalitarian arm 2: 2.05, 3, 4, 5, 5.95, 5.99, 5.999; arm 1:
/// 4.05, 5, 5.95, 5.99, 5.999).
std::vector<std::string> golden_orbit_energies(double start, double maximum);

/// The grid of any other pendulum, relative to its critical energies (U = E_max): the fractions
/// k/40 of U (k = 1..40) above `start`, start + U/1000 (just above the saddle; start = 0 for
/// quantities not per arm), U (1 - 1/1000) (just below the maximum), and 1.25, 1.5, 2, 3, 5 and 10
/// times U; each written with 10 significant digits.
std::vector<std::string> golden_relative_energies(double start, double maximum);
/// Its orbit grid: start + (U - start) x {1/100, 1/4, 1/2, 3/4, 99/100, 999/1000}, 10 significant
/// digits.
std::vector<std::string> golden_relative_orbit_energies(double start, double maximum);

struct golden_options {
    std::vector<std::string> quantities;            ///< empty: every registered quantity
    model_text model;                               ///< the pendulum (default: the paper's)
    std::string pendulum = "egalitarian";           ///< its name, for the provenance
    precision value_precision = mp_precision(100);  ///< of the values (certified in half of it)
    int jobs = 1;                                   ///< OpenMP threads
    std::size_t max_rows = 0;                       ///< 0: all (for quick runs and tests)
    /// prove an enclosure of every row whose quantity has one (certified/: the prediction
    /// quantities and the saddle orbit's), aiming at the row's certified digits; the row's value
    /// must lie in it (certification_error otherwise)
    bool certify = false;
    /// CPU seconds each evaluation of a row (its value, each check) and each proof may take (0:
    /// no bound): a row whose evaluation does not finish in them gives no row (`skipped` names
    /// it), a proof that does not finish leaves its row without an enclosure (`unproven` names it)
    double max_seconds = 0;
    /// called after each row (from one thread at a time), for progress reports
    std::function<void(const golden_row&, std::size_t done, std::size_t total)> progress;
    /// called for each task that gives no row ("QUANTITY arm A E ENERGY: reason"), one thread at
    /// a time: outside the quantity's domain, or undefined there
    std::function<void(const std::string& what)> skipped;
    /// called for each row whose proof did not finish in max_seconds ("the proof of QUANTITY arm
    /// A E ENERGY: reason"), one thread at a time
    std::function<void(const std::string& what)> unproven;
};

/// Generates the rows for options.model: the egalitarian pendulum (the paper's) on the golden grid,
/// any other on the relative grid.
std::vector<golden_row> generate_golden(const golden_options& options);

/// Proves an enclosure of every row whose quantity has one (certified/), aiming at the row's
/// certified digits, on `jobs` threads, and fills its radius and proven_digits (the ball around
/// the row's value). The value must lie in the proof's ball (half a unit of its last digit of
/// slack): certification_error otherwise, as when a proof fails. `golden --certify` calls it on
/// the rows it generates, `golden --certify-existing` on a committed set's rows (no value is
/// recomputed). A proof that does not finish in `max_seconds` CPU seconds (> 0; 0: no bound) leaves
/// its row without an enclosure and is named to `unproven` (one thread at a time).
void prove_golden_rows(std::vector<golden_row>& rows, const model_text& model, int jobs,
                       double max_seconds = 0,
                       const std::function<void(const std::string&)>& unproven = {});

/// Certified significant digits of `value` given a reference: floor(-log10 |a - b| / |b|),
/// clamped to [0, cap]; cap when they are equal.
int agreement_digits(const std::string& value, const std::string& reference, int cap = 50);

/// The precision that certifies golden values computed in `value_precision`: mp:N -> mp:(N/2),
/// quad -> double. Throws input_error for double (and mp:1).
precision golden_check_precision(const precision& value_precision);

/// The precision of the second check of a row the first certifies to fewer digits than its cap
/// (an ill-conditioned quantity, whose condition number takes more than the check precision's
/// guard digits: the multiplier ~1e30 just below E_max): mp:N -> mp:(3N/4), between the check
/// and the value precision; none (nullopt) for quad and for N < 8.
std::optional<precision> golden_recheck_precision(const precision& value_precision);

}  // namespace flipflux
