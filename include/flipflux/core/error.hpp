// Errors: contract violations by the caller (bad input) are exceptions; numerical outcomes that
// can fail (convergence) are returned as data, see result.hpp, except where a caller asked for a
// value that cannot be computed (convergence_error).
#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>

namespace flipflux {

/// Bad input: a value outside its domain, a malformed number, an unknown name. The message is one
/// line and names the offending input and its value. The CLI maps it to exit status 2.
///
/// The library names inputs by their field (`energy`, `sample_interval`, `precision`), never by a
/// command-line option: `input_error::about("energy", "'7' is outside ...")` has what() =
/// "energy: '7' is outside ...", and the CLI prints the field as its option (`--energy: ...`,
/// cli::error_text), a scene as its file, line and key.
class input_error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;

    /// An error about one named input; `field` may also be a caller's full name for it (an option
    /// "--energy" or a scene key "predictions.energies"), which is then kept as given.
    static input_error about(const std::string& field, const std::string& detail) {
        input_error e(field + ": " + detail);
        e.field_length_ = field.size() + 1;
        return e;
    }

    /// The input's field ("" when the message is free-form) and the message without it.
    std::string field() const {
        return field_length_ == 0 ? std::string() : std::string(what(), field_length_ - 1);
    }
    std::string detail() const { return field_length_ == 0 ? what() : what() + field_length_ + 1; }

  private:
    std::size_t field_length_ = 0;  ///< 1 + the field's length; 0: no field
};

/// How a caller's surface names an input in the library's advice texts ("compare more with
/// `until`"): the library writes the field, the caller's namer gives its own words for it (the
/// command line "--until", cli::option_name). The default keeps the field as it is.
using input_namer = std::function<std::string(std::string_view field)>;

/// The field as it is: the namer of a caller that gives none.
inline std::string field_as_named(std::string_view field) {
    return std::string(field);
}

/// An output that could not be written (a full disk, a read-only folder, a FIFO without a reader):
/// an I/O failure of the environment, not bad input. The message is one line naming the path.
/// The CLI maps it to exit status 1.
class output_error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// A numerical method that did not converge on valid input, where the caller asked for the value
/// (a saddle orbit the continuation from the saddle does not reach): a limitation of the method
/// (docs/limits.md), not a defect of the program, named with what is known of its cause. The
/// CLI prints it as an error with exit status 1.
class convergence_error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

}  // namespace flipflux
