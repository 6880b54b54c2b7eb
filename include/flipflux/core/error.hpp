// Errors: contract violations by the caller (bad input) are exceptions; numerical outcomes that
// can fail (convergence) are returned as data, see result.hpp.
#pragma once

#include <stdexcept>
#include <string>

namespace flipflux {

/// Bad input: a value outside its domain, a malformed number, an unknown name. The message is one
/// line and names the offending option or key and its value. The CLI maps it to exit status 2.
class input_error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace flipflux
