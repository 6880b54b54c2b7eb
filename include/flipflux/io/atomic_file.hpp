// Output files that are either complete or absent: written to a temporary name in the same
// directory, flushed, then renamed over the target (rename is atomic on POSIX file systems), so an
// interrupted run never leaves a half-written file.
#pragma once

#include <filesystem>
#include <string>

namespace flipflux {

/// Writes `content` to `path` atomically, creating parent directories. Throws std::runtime_error
/// naming the path when the file cannot be written.
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Checks, before a long computation, that `path` can be written as write_file_atomically will
/// (its folder created, a file creatable there, `path` not a directory); throws input_error about
/// `field` (an option or a scene key) otherwise. Leaves the folders created, no file.
void check_output_file(const std::filesystem::path& path, const std::string& field);

/// Quotes a CSV field when it contains a comma, quote or newline.
std::string csv_field(const std::string& text);

}  // namespace flipflux
