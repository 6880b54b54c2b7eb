// The pendulum a candidate file was computed for (docs/validating.md, "the pendulum"): declared in
// its comment lines before the CSV header,
//
//     # pendulum: m1=1 m2=3 L1=1 L2=0.7 g=9.81
//
// with the keys of the model options (m1 m2 L1 L2 a1 a2 I1 I2 g), in any order, separated by
// spaces or commas, over one or more such lines; keys not given take the model's defaults (m = L =
// g = 1, a = L, I = 0), as the command-line options do. The golden set to compare with is the one
// whose provenance.json "parameters" are equal, parameter by parameter, as decimal numbers.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "flipflux/model/model_text.hpp"

namespace flipflux {

struct declared_pendulum {
    model_text parameters;
    std::string where;  ///< "FILE:LINE" of the (first) `# pendulum:` line
};

/// The `# pendulum:` lines of `file` before its header line; nullopt when there are none. Throws
/// input_error "FILE:LINE: pendulum: ..." for an unknown or repeated key, a missing '=', or a value
/// that is not a finite decimal number.
std::optional<declared_pendulum> read_declared_pendulum(const std::filesystem::path& file);

/// True when every parameter of a and b is the same number (a1/a2 empty means L1/L2; compared
/// from every digit of the decimal texts, so "0.7" equals "0.70" and "3" equals "3.0").
bool same_parameters(const model_text& a, const model_text& b);

/// "m1=1 m2=3 L1=1 L2=0.7 a1=1 a2=0.7 I1=0 I2=0 g=9.81".
std::string parameters_text(const model_text& p);

struct golden_set {
    std::string name;           ///< "egalitarian" (the top-level set) or the folder's name
    std::filesystem::path dir;  ///< the folder holding its golden.csv
    model_text parameters;      ///< from its provenance.json
};

/// The golden sets under `golden`: the top-level one and every sub-folder with a golden.csv and a
/// provenance.json whose "parameters" name the model (sets without parameters are skipped).
std::vector<golden_set> golden_sets(const std::filesystem::path& golden);

/// The golden set with these parameters; throws input_error "<who>: the pendulum m1=... has no
/// golden set under 'DIR' (sets: NAME (m1=...), ...)" when none has them.
golden_set golden_set_for(const std::filesystem::path& golden, const model_text& parameters,
                          const std::string& who);

}  // namespace flipflux
