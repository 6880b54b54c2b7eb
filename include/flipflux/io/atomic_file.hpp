// Output files that are either complete or absent, and input files that are what they claim.
//
// Destinations (docs/limits.md, "Files"):
//  - a regular file or a new path is written to a temporary name in the same directory, flushed,
//    then renamed over the target (rename is atomic on POSIX file systems), so an interrupted run
//    never leaves a half-written file;
//  - a symbolic link is followed: its target is the destination (a dangling link is refused);
//  - a character device (/dev/null, /dev/stdout, a terminal) or a FIFO is written in place, never
//    replaced (a FIFO must have a reader: opening it does not wait);
//  - anything else (a folder, a block device, a socket) is refused.
// Inputs: regular files only (a symbolic link to one is fine), read whole up to a size bound; a
// device or FIFO is refused before it is opened for reading, so a reader never blocks.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>

namespace flipflux {

/// Writes `content` to `path` by the rules above, creating missing parent folders. Throws
/// output_error naming the path when it cannot be written (exit status 1 in the CLI).
void write_file_atomically(const std::filesystem::path& path, const std::string& content);

/// Checks, before a long computation, that `path` can be written as write_file_atomically will:
/// an existing destination of an accepted kind that is writable, or a new path whose nearest
/// existing ancestor is a writable folder. Throws input_error about `field` (an option or a scene
/// key) otherwise. Creates nothing.
void check_output_file(const std::filesystem::path& path, const std::string& field);

/// The same check for a folder the program will create and fill (`--csv-dir`, `golden --out`):
/// an existing folder, or a new path under a writable folder. Creates nothing.
void check_output_folder(const std::filesystem::path& path, const std::string& field);

/// The default bound of read_input_file: 256 MiB (docs/limits.md).
inline constexpr std::uintmax_t max_input_bytes = std::uintmax_t{256} << 20;

/// The whole content of the regular file `path` (a symbolic link to one is followed). Throws
/// input_error about `field` (no field: the message names the file alone) when it is missing, not a
/// regular file (a device, a FIFO, a folder), larger than `max_bytes`, or unreadable; it never
/// blocks on a FIFO.
std::string read_input_file(const std::filesystem::path& path, const std::string& field,
                            std::uintmax_t max_bytes = max_input_bytes);

/// Quotes a CSV field when it contains a comma, quote or newline.
std::string csv_field(const std::string& text);

}  // namespace flipflux
