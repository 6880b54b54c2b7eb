// Fixed-width text tables for reports printed to a terminal (validation's reports): each cell
// left-aligned and padded to its column's width, one space between columns, the last cell of a
// row unpadded; a cell wider than its column pushes the rest of the row right. The same text as
// printf's "%-Ns %-Ms ... %s\n", so reports keep their layout byte for byte.
#pragma once

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace flipflux {

class text_table {
  public:
    /// The widths of the columns but the last (which is never padded).
    explicit text_table(std::vector<std::size_t> widths) : widths_(std::move(widths)) {}

    /// Appends a row of cells (at most one more than widths; fewer leave the rest out).
    void row(const std::vector<std::string>& cells) {
        for (std::size_t j = 0; j < cells.size(); ++j) {
            if (j) text_ += ' ';
            text_ += cells[j];
            if (j + 1 < cells.size() && j < widths_.size() && cells[j].size() < widths_[j])
                text_.append(widths_[j] - cells[j].size(), ' ');
        }
        text_ += '\n';
        ++rows_;
    }
    const std::string& text() const { return text_; }
    std::size_t rows() const { return rows_; }

  private:
    std::vector<std::size_t> widths_;
    std::string text_;
    std::size_t rows_ = 0;
};

/// printf's rendering of one number, e.g. cell("%.3e", x): a table cell.
inline std::string cell(const char* format, double x) {
    const int n = std::snprintf(nullptr, 0, format, x);
    std::string s(static_cast<std::size_t>(n > 0 ? n : 0), '\0');
    std::snprintf(s.data(), s.size() + 1, format, x);
    return s;
}

}  // namespace flipflux
