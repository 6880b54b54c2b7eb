// The Markdown report of measured accuracies (`flipflux accuracy`, scenes' [accuracy]): formats at
// the edge; the measurement (quantities/accuracy.hpp) returns data.
#pragma once

#include <string>
#include <vector>

#include "flipflux/output/command_words.hpp"
#include "flipflux/quantities/accuracy.hpp"

namespace flipflux {

/// The Markdown report of entries measured with `options` (its precisions are the columns), made
/// by `command`; `words` name the caller's commands in its prose.
std::string accuracy_markdown(const std::vector<accuracy_entry>& entries,
                              const accuracy_options& options, const std::string& command,
                              const command_words& words);

}  // namespace flipflux
