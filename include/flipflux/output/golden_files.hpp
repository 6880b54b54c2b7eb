// The files of a golden set (data/golden/README.md): rows.csv text, the provenance record, and the
// checks and merge of a run that extends a set. Formats at the edge: the rows are data
// (quantities/golden.hpp's golden_row, computed there), written and read here.
#pragma once

#include <string>
#include <vector>

#include "flipflux/core/real.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/output/command_words.hpp"
#include "flipflux/quantities/golden.hpp"

namespace flipflux {

/// Writes rows.csv-style text: header "quantity,arm,energy,value,digits,method", and
/// ",radius,proven_digits" when a row has an enclosure (empty in the rows without one).
std::string golden_csv(const std::vector<golden_row>& rows);

/// Parses golden_csv text (6 columns, or 8 with radius and proven_digits); throws input_error
/// naming the line on malformed input.
std::vector<golden_row> parse_golden_csv(const std::string& text);

/// The provenance record (JSON text): command, git commit, flipflux version, compiler, library
/// versions (Boost, MPFR, GMP, Eigen), precisions, Boost.Math policy, grid, row count. With
/// `merged_into` (the provenance text of the set that this run extends, `golden --merge`), its
/// "runs" list the earlier runs' commands, commits and dates, then this one's. `words` name the
/// caller's commands in the descriptions of the model and the columns.
std::string golden_provenance(const std::string& command, std::size_t rows,
                              const precision& value_precision, const command_words& words,
                              const model_text& model = {},
                              const std::string& pendulum = "egalitarian",
                              const std::string& merged_into = "");

/// Checks that a golden set's provenance text (possibly corrupt) describes the same pendulum
/// (parameters, as text) and value precision as a run that would extend it; throws input_error
/// naming what differs (free-form: the caller prefixes the option or key that asked for it).
void check_golden_merge(const std::string& provenance_text, const precision& value_precision,
                        const model_text& model);

/// The rows of a golden set extended by a run (`golden --merge`): the rows of `existing` whose
/// quantity is not among `regenerated` (every quantity when empty), then `fresh`, in the
/// registry's order of quantities (rows of one quantity keep their order).
std::vector<golden_row> merge_golden(const std::vector<golden_row>& existing,
                                     const std::vector<golden_row>& fresh,
                                     const std::vector<std::string>& regenerated);

}  // namespace flipflux
