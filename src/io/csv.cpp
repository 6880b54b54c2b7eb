// CSV lines split into trimmed fields (io/csv.hpp), for the golden data and candidate files.
#include "flipflux/io/csv.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/io/atomic_file.hpp"

namespace flipflux {
namespace {

std::string trim(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    const auto e = s.find_last_not_of(" \t\r");
    return s.substr(b, e - b + 1);
}

}  // namespace

std::vector<std::string> split_csv_line(const std::string& line) {
    std::vector<std::string> out;
    std::string field;
    bool quoted = false, was_quoted = false;
    for (std::size_t i = 0; i < line.size(); ++i) {
        const char c = line[i];
        if (quoted) {
            if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
                field += '"';
                ++i;
            } else if (c == '"') {
                quoted = false;
            } else {
                field += c;
            }
        } else if (c == '"') {
            quoted = was_quoted = true;
        } else if (c == ',') {
            out.push_back(was_quoted ? field : trim(field));
            field.clear();
            was_quoted = false;
        } else {
            field += c;
        }
    }
    if (quoted) throw std::invalid_argument("unterminated quote");
    out.push_back(was_quoted ? field : trim(field));
    return out;
}

csv_table parse_csv(const std::string& text, const std::string& name) {
    std::istringstream in(text);
    csv_table t;
    std::string line;
    int number = 0;
    while (std::getline(in, line)) {
        ++number;
        // a UTF-8 byte-order mark (spreadsheet exports write one) is not part of the first field
        if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);
        const std::string trimmed = trim(line);
        if (trimmed.empty() || trimmed.front() == '#') continue;
        std::vector<std::string> fields;
        try {
            fields = split_csv_line(line);
        } catch (const std::invalid_argument& e) {
            throw input_error(name + ":" + std::to_string(number) + ": " + e.what());
        }
        if (t.header.empty()) {
            // a column named twice would be read from its first occurrence only, silently
            for (std::size_t i = 0; i < fields.size(); ++i)
                for (std::size_t j = 0; j < i; ++j)
                    if (!trim(fields[i]).empty() && trim(fields[i]) == trim(fields[j]))
                        throw input_error(name + ":" + std::to_string(number) +
                                          ": the header names the column '" + trim(fields[i]) +
                                          "' twice");
            t.header = fields;
            t.header_line = number;
        } else {
            t.rows.push_back({number, fields});
        }
    }
    if (in.bad()) throw input_error(name + ": read error after line " + std::to_string(number));
    if (t.header.empty()) throw input_error(name + ": empty file (no header line)");
    return t;
}

csv_table read_csv(const std::filesystem::path& file) {
    return parse_csv(read_input_file(file, ""), file.string());
}

int column_index(const csv_table& t, const std::string& name) {
    const auto it = std::find(t.header.begin(), t.header.end(), name);
    return it == t.header.end() ? -1 : static_cast<int>(it - t.header.begin());
}

double finite_field(const std::string& text, const std::string& name, const std::string& at) {
    double x = std::nan("");
    if (is_decimal_number(text)) {
        try {
            x = parse_real<double>(text, name);
        } catch (const input_error&) {  // beyond double: the file's line, not an option
        }
    }
    if (!std::isfinite(x)) throw input_error(at + name + " '" + text + "' is not a finite number");
    return x;
}

}  // namespace flipflux
