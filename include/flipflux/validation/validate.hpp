// Validating another implementation against flipflux's golden data (docs/validating.md).
//
// A candidate CSV has the columns quantity, arm, energy, value (any order; other columns are
// ignored; arm is empty or "-" for quantities that are not per arm, such as omega). Each row is
// matched to the golden row with the same quantity, arm and energy (energies compared as numbers,
// to a relative 1e-12, so "2.05" and "2.050" match), and passes when its relative error is at most
// max(rtol, 10^-digits), digits being the golden row's certified digits. Every candidate line is
// accounted for: ok, FAIL, unmatched, duplicate, malformed; and for every (quantity, arm) the
// candidate reports, golden energies it lacks are reported as missing (unless allow_missing).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "flipflux/core/names.hpp"
#include "flipflux/io/csv.hpp"

namespace flipflux {

struct golden_reference {
    std::string quantity, arm, energy, value, method;
    int digits = 0;
    std::string file;
    int line = 0;
};

/// Reads every *.csv under `dir` with the golden header (quantity, arm, energy, value, digits,
/// method). Throws input_error naming file and line for a malformed golden file.
std::vector<golden_reference> read_golden(const std::filesystem::path& dir);

struct validation_entry {
    enum class status { ok, fail, unmatched, duplicate, malformed, missing };
    status what;
    int line = 0;  ///< candidate line (0 for missing rows)
    std::string quantity, arm, energy, candidate, golden;
    double relative_error = 0;
    double matched_digits = 0;
    int certified_digits = 0;
    std::string note;
};

struct validation_report {
    std::vector<validation_entry> entries;
    bool require_all = false;  ///< unmatched candidate rows fail the validation
    std::size_t count(validation_entry::status s) const;
    /// At least one row ok, none FAIL, duplicate, malformed or missing; unmatched rows (values
    /// the golden set lacks) are counted, and fail only with require_all.
    bool passed() const;
};

/// Missing rows (golden rows without a candidate row of a quantity and arm the candidate has)
/// are reported unless allow_missing.
validation_report validate_candidate(const std::filesystem::path& candidate,
                                     const std::filesystem::path& golden_dir, double rtol,
                                     bool allow_missing, bool require_all = false);

/// The same for a candidate table already read (e.g. parse_csv of rows held in memory); `name`
/// stands for its file in errors.
validation_report validate_candidate_table(const csv_table& table, const std::string& name,
                                           const std::filesystem::path& golden_dir, double rtol,
                                           bool allow_missing, bool require_all = false);

/// The report: the summary line first, then a table of the rows that need attention (FAIL,
/// duplicate, malformed, unmatched); with `verbose` every row, the ok and missing ones too.
/// Without `verbose`, a line counts the missing rows, ended by `missing_hint` (the caller's words
/// for listing or accepting them: the command line's options, Python's keyword).
std::string format_report(const validation_report& r, double rtol, bool verbose = false,
                          const std::string& missing_hint = "");

template <>
struct enum_table<validation_entry::status> {
    static constexpr std::string_view noun = "a validation status";
    static constexpr std::array<std::pair<validation_entry::status, std::string_view>, 6> entries{
        {{validation_entry::status::ok, "ok"},
         {validation_entry::status::fail, "FAIL"},
         {validation_entry::status::unmatched, "unmatched"},
         {validation_entry::status::duplicate, "duplicate"},
         {validation_entry::status::malformed, "malformed"},
         {validation_entry::status::missing, "missing"}}};
};

}  // namespace flipflux
