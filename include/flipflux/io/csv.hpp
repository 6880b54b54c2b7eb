// A small CSV reader that keeps line numbers (RFC 4180 quoting; no multi-line fields).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace flipflux {

struct csv_row {
    int line = 0;                     ///< 1-based line number in the file
    std::vector<std::string> fields;  ///< unquoted, surrounding spaces trimmed
};

struct csv_table {
    std::vector<std::string> header;
    int header_line = 1;        ///< the header's line (after any '#' comment lines)
    std::vector<csv_row> rows;  ///< blank lines and lines starting with '#' are skipped
};

/// Splits one line; throws std::invalid_argument on an unterminated quote.
std::vector<std::string> split_csv_line(const std::string& line);

/// The index of the header's column `name`, or -1 when the header lacks it.
int column_index(const csv_table& t, const std::string& name);

/// A finite double from a field's decimal text (parsed exactly, core/decimal.hpp); throws
/// input_error "<at><name> '<text>' is not a finite number" otherwise, `at` being "FILE:LINE: ".
double finite_field(const std::string& text, const std::string& name, const std::string& at);

/// Reads a CSV file whose first non-comment line is the header. Throws input_error naming the
/// file and line for unreadable files and malformed quoting.
csv_table read_csv(const std::filesystem::path& file);

/// The same for CSV text in memory; `name` stands for the file in errors ("NAME:LINE: ...").
csv_table parse_csv(const std::string& text, const std::string& name);

}  // namespace flipflux
