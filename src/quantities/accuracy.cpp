// What accuracy costs (include/flipflux/quantities/accuracy.hpp).
#include "flipflux/quantities/accuracy.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <optional>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/version.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {
namespace {

struct probe {
    arm a;
    std::string energy;
};

/// The test energies: omega 1, 3, 5.5, 20; arm 2 at 2.5, 4.5, 20; arm 1 at 5, 20 (egalitarian
/// pendulum: E_s = 2 and 4, E_max = 6).
std::vector<probe> probes(const quantity& q) {
    if (!q.per_arm) return {{arm::two, "1"}, {arm::two, "3"}, {arm::two, "5.5"}, {arm::two, "20"}};
    return {
        {arm::two, "2.5"}, {arm::two, "4.5"}, {arm::two, "20"}, {arm::one, "5"}, {arm::one, "20"}};
}

/// A value as decimal text (every digit of its precision) and the time it took.
struct timed_value {
    std::string value;
    double seconds;
};

/// `fresh`: time a saddle-orbit quantity from scratch (the orbit memo, which shares one orbit
/// between period, action, flux, ..., would otherwise make repeated evaluations free); the memo
/// keeps its orbits for the references of the next quantities. Nothing outside the method's
/// domain.
std::optional<timed_value> evaluate(const precision& p, const quantity& q,
                                    const std::string& method, const probe& pr,
                                    bool fresh = false) {
    return dispatch(p, [&]<class Real>() -> std::optional<timed_value> {
        const double_pendulum<Real> model;
        const Real energy = parse_real<Real>(pr.energy, "energy");
        std::optional<saddle_orbit_memo_bypass> bypass;
        if (fresh && q.needs_saddle_orbit) bypass.emplace();
        try {
            const auto start = std::chrono::steady_clock::now();
            const quantity_value<Real> v = q.evaluate(model, pr.a, energy, method);
            const double s =
                std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
            return timed_value{to_decimal(v.value), s};
        } catch (const input_error&) {
            return std::nullopt;
        }
    });
}

/// Digits of agreement, capped at the digits the column prints.
double digits_between(const std::string& value, const std::string& reference, int cap) {
    const double digits = decimal_agreement(value, reference);
    return digits > cap ? cap : digits;
}

int column_cap(const precision& p) {
    return dispatch(p, []<class Real>() { return output_digits<Real>(); });
}

}  // namespace

precision accuracy_reference_precision(const std::vector<precision>& columns) {
    int highest = 100;
    for (const precision& p : columns)
        highest = std::max(highest, decimal_digits(p));
    return mp_precision(highest + 20);
}

std::vector<accuracy_entry> measure_accuracy(const accuracy_options& options) {
    const precision reference_precision = accuracy_reference_precision(options.precisions);
    std::vector<accuracy_entry> entries;
    for (const quantity& q : quantities()) {
        if (!options.quantities.empty() &&
            std::find(options.quantities.begin(), options.quantities.end(), q.name) ==
                options.quantities.end()) {
            continue;
        }
        const std::vector<probe> ps = probes(q);
        // references: the default method in the reference precision (empty: outside its domain)
        // NOTE: plain strings, not optionals: GCC 12 reports a false -Wfree-nonheap-object on
        // destroying a vector of optional strings at -O3.
        std::vector<std::string> ref(ps.size());
        for (std::size_t i = 0; i < ps.size(); ++i)
            if (auto v = evaluate(reference_precision, q, q.methods[0], ps[i])) ref[i] = v->value;
        for (std::size_t m = 0; m < q.methods.size(); ++m) {
            accuracy_entry e{q.name, q.description, q.methods[m], {}};
            bool too_slow = false;
            for (const precision& p : options.precisions) {
                accuracy_cell& cell = e.cells.emplace_back();
                if (too_slow) {
                    cell.skipped = true;
                    continue;
                }
                const int cap = column_cap(p);
                bool timed = false;
                for (std::size_t i = 0; i < ps.size(); ++i) {
                    if (ref[i].empty()) continue;
                    std::optional<timed_value> v = evaluate(p, q, q.methods[m], ps[i], true);
                    if (!v) continue;
                    const double d = digits_between(v->value, ref[i], cap);
                    cell.digits = cell.applies ? std::min(cell.digits, d) : d;
                    cell.applies = true;
                    ++cell.energies;
                    if (!timed) {
                        // time at the first applicable energy: repeat up to min_seconds
                        double total = v->seconds;
                        int reps = 1;
                        while (total < options.min_seconds && v->seconds < options.slow_seconds) {
                            total += evaluate(p, q, q.methods[m], ps[i], true)->seconds;
                            ++reps;
                        }
                        cell.seconds = total / reps;
                        timed = true;
                    }
                    if (cell.seconds > options.slow_seconds) break;  // one energy is enough
                }
                too_slow = cell.seconds > options.max_seconds;
                if (options.progress) {
                    char line[240];
                    std::snprintf(line, sizeof line, "%s %s %s: %.1f digits, %.3g s (%d energies)",
                                  q.name.c_str(), q.methods[m].c_str(), precision_name(p).c_str(),
                                  cell.digits, cell.seconds, cell.energies);
                    options.progress(line);
                }
            }
            entries.push_back(e);
        }
    }
    return entries;
}

namespace {

std::string format_time(double s) {
    char buf[32];
    if (s < 1e-3)
        std::snprintf(buf, sizeof buf, "%.3g µs", s * 1e6);
    else if (s < 1)
        std::snprintf(buf, sizeof buf, "%.3g ms", s * 1e3);
    else
        std::snprintf(buf, sizeof buf, "%.3g s", s);
    return buf;
}

}  // namespace

std::string accuracy_markdown(const std::vector<accuracy_entry>& entries,
                              const std::vector<precision>& columns, const std::string& command) {
    std::string names, caps, header = "| method |", rule = "|---|";
    for (std::size_t c = 0; c < columns.size(); ++c) {
        const std::string sep = c == 0 ? "" : c + 1 == columns.size() ? " and " : ", ";
        names += sep + precision_name(columns[c]);
        caps += sep + std::to_string(column_cap(columns[c]));
        header += " " + precision_name(columns[c]) + " |";
        rule += "---|";
    }
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
#ifdef NDEBUG
    const char* build = "optimised build (NDEBUG)";
#else
    const char* build = "debug build (assertions on): times are not representative";
#endif
    std::string md =
        "# Accuracy and cost\n\n"
        "<!-- generated by `" +
        command +
        "`; do not edit by hand -->\n\n"
        "Generated by `" +
        command + "` (flipflux " + version_string() + ", git " + git_commit() + ", " + date +
        ", g++ " + __VERSION__ + ", " + build +
        ").\n\n"
        "For every registered quantity and method: the significant digits achieved and the time "
        "per evaluation in each precision, for the egalitarian pendulum. **Digits** are the "
        "minimum over the test energies (omega: E = 1, 3, 5.5, 20; per-arm quantities: arm 2 at "
        "E = 2.5, 4.5, 20 and arm 1 at E = 5, 20) of -log10 |x - ref| / |ref|, where ref is the "
        "quantity's default (first) method in " +
        precision_name(accuracy_reference_precision(columns)) +
        " (so the default method is checked against a higher precision, every other method "
        "against an independent route). Capped at the digits each precision prints (" +
        caps + " for " + names +
        "; mp:N computes with N + 10 digits, at least 30). **Time** is the mean wall time of one "
        "evaluation at the first test energy (repeated for at least 0.2 s), on one core; methods "
        "slower than 3 s per evaluation are checked at their first energy only (the number of "
        "energies checked is given), and a method slower than 120 s in one precision is not "
        "measured in the higher ones (\"not measured\"). A closed form that holds only above "
        "the potential maximum is checked at E = 20 only.\n\n"
        "Targets: double <= 1e-14 (14 digits), quad <= 1e-31 (31), mp:N <= 1e-(N-10) relative. "
        "Google Benchmark timings of the same evaluations: `bench_prediction`.\n";
    std::string current;
    for (const accuracy_entry& e : entries) {
        if (e.quantity != current) {
            current = e.quantity;
            md += "\n## " + e.quantity + "\n\n" + e.description + "\n\n" + header + "\n" + rule +
                  "\n";
        }
        md += "| " + e.method;
        for (const accuracy_cell& c : e.cells) {
            if (c.skipped) {
                md += " | not measured";
                continue;
            }
            if (!c.applies) {
                md += " | n/a";
                continue;
            }
            char buf[96];
            std::snprintf(
                buf, sizeof buf, " | %.1f digits, %s%s", c.digits, format_time(c.seconds).c_str(),
                c.energies < 2 ? (" (" + std::to_string(c.energies) + " energy)").c_str() : "");
            md += buf;
        }
        md += " |\n";
    }
    return md;
}

}  // namespace flipflux
