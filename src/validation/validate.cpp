// Validating another implementation (validation/validate.hpp, docs/validating.md): its values,
// row by row, against the golden data, in decimal digits of agreement.
#include "flipflux/validation/validate.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <tuple>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/io/csv.hpp"
#include "flipflux/io/text_table.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {
namespace {

std::string normal_arm(const std::string& quantity, const std::string& arm) {
    bool per_arm = true;
    for (const auto& q : quantities()) {
        if (q.name == quantity) per_arm = q.per_arm;
    }
    if (!per_arm || arm == "-") return "";
    return arm;
}

/// Energies match to a relative 1e-12 (see the header comment).
bool same_energy(const std::string& a, const std::string& b) {
    return decimal_relative_error(a, b, "energy") <= 1e-12;
}

/// A golden row's digits: an integer in [1, max_mp_digits] (a value certified to fewer than one
/// digit, or to more than any precision computes, is no reference).
int checked_golden_digits(const std::string& text, const std::filesystem::path& file, int line) {
    int d = 0;
    const char* end = text.data() + text.size();
    const auto r = std::from_chars(text.data(), end, d);
    if (text.empty() || r.ec != std::errc() || r.ptr != end || d < 1 || d > max_mp_digits)
        throw input_error(file.string() + ":" + std::to_string(line) + ": digits '" + text +
                          "' is invalid (an integer from 1 to " + std::to_string(max_mp_digits) +
                          ")");
    return d;
}

/// A golden row's quantity is named, its arm 1, 2 or none, its energy and value decimal numbers.
void check_golden_row(const golden_reference& g, const std::filesystem::path& file, int line) {
    const std::string at = file.string() + ":" + std::to_string(line) + ": ";
    if (g.quantity.empty()) throw input_error(at + "empty quantity");
    if (!g.arm.empty() && g.arm != "1" && g.arm != "2")
        throw input_error(at + "arm '" + g.arm + "' is not 1, 2 or empty");
    if (!is_decimal_number(g.energy))
        throw input_error(at + "energy '" + g.energy + "' is not a finite decimal number");
    try {  // golden energies are compared as doubles: one beyond double's range is refused here
        (void)parse_real<double>(g.energy, "energy");
    } catch (const input_error& e) {
        throw input_error(at + "energy " + e.detail());
    }
    if (!is_decimal_number(g.value))
        throw input_error(at + "value '" + g.value + "' is not a finite decimal number");
}

/// The golden rows by (quantity, arm), each list sorted by energy (as double), so that a
/// candidate row is matched by a binary search and one or two exact comparisons instead of a scan
/// of every golden row (a 200,000-row candidate took minutes).
class golden_index {
  public:
    explicit golden_index(const std::vector<golden_reference>& golden) : golden_(golden) {
        for (std::size_t i = 0; i < golden.size(); ++i)
            rows_[{golden[i].quantity, golden[i].arm}].push_back(
                {parse_real<double>(golden[i].energy, "energy"), i});
        for (auto& [key, list] : rows_)
            std::sort(list.begin(), list.end());
    }

    /// The first golden row (in file order) of this quantity and arm whose energy matches, or
    /// golden.size().
    std::size_t find(const std::string& quantity, const std::string& arm,
                     const std::string& energy) const {
        const auto it = rows_.find({quantity, arm});
        if (it == rows_.end()) return golden_.size();
        double e = 0;
        try {
            e = parse_real<double>(energy, "energy");
        } catch (const input_error&) {
            return golden_.size();  // beyond double's range: no golden energy is there
        }
        // every energy within a relative 1e-12 of e (with room for the rounding to double)
        const double slack = 4e-12 * std::abs(e) + 1e-300;
        const auto& list = it->second;
        auto j =
            std::lower_bound(list.begin(), list.end(), std::make_pair(e - slack, std::size_t{0}));
        std::size_t best = golden_.size();
        for (; j != list.end() && j->first <= e + slack; ++j)
            if (j->second < best && same_energy(energy, golden_[j->second].energy))
                best = j->second;
        return best;
    }

  private:
    const std::vector<golden_reference>& golden_;
    std::map<std::pair<std::string, std::string>, std::vector<std::pair<double, std::size_t>>>
        rows_;
};

}  // namespace

std::vector<golden_reference> read_golden(const std::filesystem::path& dir) {
    namespace fs = std::filesystem;
    if (!fs::is_directory(dir)) {
        throw input_error::about("golden", "'" + dir.string() + "' is not a directory");
    }
    std::vector<fs::path> files;
    for (const auto& e : fs::directory_iterator(dir)) {
        if (e.path().extension() == ".csv") files.push_back(e.path());
    }
    std::sort(files.begin(), files.end());
    std::vector<golden_reference> rows;
    std::map<std::tuple<std::string, std::string, double>, std::string> where;  // -> file:line
    for (const auto& f : files) {
        const csv_table t = read_csv(f);
        const int q = column_index(t, "quantity"), a = column_index(t, "arm"),
                  e = column_index(t, "energy"), v = column_index(t, "value"),
                  d = column_index(t, "digits"), m = column_index(t, "method");
        if (q < 0 || a < 0 || e < 0 || v < 0 || d < 0) continue;  // not a golden table
        for (const auto& r : t.rows) {
            if (r.fields.size() != t.header.size()) {
                throw input_error(f.string() + ":" + std::to_string(r.line) + ": expected " +
                                  std::to_string(t.header.size()) + " fields");
            }
            golden_reference g{r.fields[q],
                               normal_arm(r.fields[q], r.fields[a]),
                               r.fields[e],
                               r.fields[v],
                               m >= 0 ? r.fields[m] : "",
                               checked_golden_digits(r.fields[d], f, r.line),
                               f.string(),
                               r.line};
            check_golden_row(g, f, r.line);
            const auto key =
                std::make_tuple(g.quantity, g.arm, parse_real<double>(g.energy, "energy"));
            if (const auto [it, fresh] = where.emplace(key, g.file + ":" + std::to_string(g.line));
                !fresh)
                throw input_error(g.file + ":" + std::to_string(g.line) + ": " + g.quantity +
                                  (g.arm.empty() ? "" : " arm " + g.arm) + " at E = " + g.energy +
                                  " is given twice (first at " + it->second + ")");
            rows.push_back(g);
        }
    }
    if (rows.empty())
        throw input_error::about("golden", "no golden rows under '" + dir.string() + "'");
    return rows;
}

std::size_t validation_report::count(validation_entry::status s) const {
    return static_cast<std::size_t>(std::count_if(
        entries.begin(), entries.end(), [s](const validation_entry& e) { return e.what == s; }));
}

bool validation_report::passed() const {
    using status = validation_entry::status;
    return count(status::ok) > 0 && count(status::fail) == 0 && count(status::duplicate) == 0 &&
           count(status::malformed) == 0 && count(status::missing) == 0 &&
           (!require_all || count(status::unmatched) == 0);
}

validation_report validate_candidate(const std::filesystem::path& candidate,
                                     const std::filesystem::path& golden_dir, double rtol,
                                     bool allow_missing, bool require_all) {
    return validate_candidate_table(read_csv(candidate), candidate.string(), golden_dir, rtol,
                                    allow_missing, require_all);
}

validation_report validate_candidate_table(const csv_table& t, const std::string& name,
                                           const std::filesystem::path& golden_dir, double rtol,
                                           bool allow_missing, bool require_all) {
    using status = validation_entry::status;
    const std::vector<golden_reference> golden = read_golden(golden_dir);
    for (const auto& g : golden)
        if (!is_decimal_number(g.energy))
            throw input_error(g.file + ": energy '" + g.energy +
                              "' is not a finite decimal number");

    const int q = column_index(t, "quantity"), a = column_index(t, "arm"),
              e = column_index(t, "energy"), v = column_index(t, "value");
    if (q < 0 || a < 0 || e < 0 || v < 0) {
        throw input_error(name +
                          ":1: the header must name the columns quantity, arm, energy, value");
    }
    const golden_index index(golden);
    validation_report report;
    report.require_all = require_all;
    std::set<std::size_t> used;                          // golden rows matched
    std::map<std::size_t, int> first_line;               // golden row -> candidate line
    std::set<std::pair<std::string, std::string>> seen;  // (quantity, arm) in the candidate
    for (const auto& row : t.rows) {
        validation_entry x{status::malformed, row.line, "", "", "", "", "", 0, 0, 0, ""};
        if (row.fields.size() != t.header.size()) {
            x.note = "expected " + std::to_string(t.header.size()) + " fields, found " +
                     std::to_string(row.fields.size());
            report.entries.push_back(x);
            continue;
        }
        x.quantity = row.fields[q];
        x.arm = normal_arm(row.fields[q], row.fields[a]);
        x.energy = row.fields[e];
        x.candidate = row.fields[v];
        if (x.quantity.empty() || !is_decimal_number(x.energy) || !is_decimal_number(x.candidate)) {
            x.note = x.quantity.empty()             ? "empty quantity"
                     : !is_decimal_number(x.energy) ? "energy '" + x.energy + "' is not a number"
                                                    : "value '" + x.candidate + "' is not a number";
            report.entries.push_back(x);
            continue;
        }
        // a typo must not drop the row as "unmatched": the name and the arm are checked
        const auto known = std::find_if(quantities().begin(), quantities().end(),
                                        [&](const quantity& k) { return k.name == x.quantity; });
        if (known == quantities().end() || (known->per_arm && x.arm != "1" && x.arm != "2")) {
            x.note =
                known == quantities().end()
                    ? "quantity '" + x.quantity +
                          "' is not a registered quantity (known: " + quantity_names() + ")"
                    : "arm '" + row.fields[a] + "' is not 1 or 2 (" + x.quantity + " is per arm)";
            report.entries.push_back(x);
            continue;
        }
        seen.insert({x.quantity, x.arm});
        const std::size_t match = index.find(x.quantity, x.arm, x.energy);
        if (match == golden.size()) {
            x.what = status::unmatched;
            x.note = "no golden value for this quantity, arm and energy";
            report.entries.push_back(x);
            continue;
        }
        const golden_reference& g = golden[match];
        x.golden = g.value;
        x.certified_digits = g.digits;
        if (used.count(match)) {
            x.what = status::duplicate;
            x.note = "duplicates line " + std::to_string(first_line[match]);
            report.entries.push_back(x);
            continue;
        }
        used.insert(match);
        first_line[match] = row.line;
        x.relative_error = decimal_relative_error(x.candidate, g.value, g.file);
        x.matched_digits =
            std::min<double>(g.digits, decimal_agreement(x.candidate, g.value, g.file));
        const double tol = std::max(rtol, std::pow(10.0, -g.digits));
        x.what = x.relative_error <= tol ? status::ok : status::fail;
        report.entries.push_back(x);
    }
    if (!allow_missing) {
        for (std::size_t i = 0; i < golden.size(); ++i) {
            const auto& g = golden[i];
            if (!used.count(i) && seen.count({g.quantity, g.arm})) {
                report.entries.push_back({status::missing, 0, g.quantity, g.arm, g.energy, "",
                                          g.value, 0, 0, g.digits,
                                          "golden row " + g.file + ":" + std::to_string(g.line) +
                                              " has no candidate row"});
            }
        }
    }
    return report;
}

std::string format_report(const validation_report& r, double rtol, bool verbose,
                          const std::string& missing_hint) {
    using status = validation_entry::status;
    std::string out;
    char buf[512];
    std::snprintf(buf, sizeof buf,
                  "summary: %zu rows: %zu ok, %zu FAIL, %zu unmatched%s, %zu duplicate, %zu "
                  "malformed, %zu missing (rtol %.3g) -> %s\n",
                  r.entries.size(), r.count(status::ok), r.count(status::fail),
                  r.count(status::unmatched), r.require_all ? "" : " (not fatal)",
                  r.count(status::duplicate), r.count(status::malformed), r.count(status::missing),
                  rtol, r.passed() ? "PASSED" : "FAILED");
    out += buf;
    text_table table({6, 10, 16, 4, 22, 11, 7});
    table.row({"line", "status", "quantity", "arm", "energy", "rel.error", "digits", "note"});
    for (const auto& e : r.entries) {
        if (!verbose && (e.what == status::ok || e.what == status::missing)) continue;
        table.row({e.line ? std::to_string(e.line) : "-", to_string(e.what), e.quantity,
                   e.arm.empty() ? "-" : e.arm, e.energy, cell("%.3e", e.relative_error),
                   cell("%.1f", e.matched_digits), e.note});
    }
    if (table.rows() > 1) out += table.text();
    if (!verbose && r.count(status::missing) > 0)
        out += std::to_string(r.count(status::missing)) +
               " missing rows (golden rows with no candidate row)" + missing_hint + "\n";
    return out;
}

}  // namespace flipflux
