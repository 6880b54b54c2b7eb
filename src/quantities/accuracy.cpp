// What accuracy costs (include/flipflux/quantities/accuracy.hpp).
#include "flipflux/quantities/accuracy.hpp"

#include <algorithm>
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

/// The CPU time of the calling thread: evaluations are single-threaded, and unlike wall time it
/// does not grow when other jobs share the cores.
double thread_cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

/// `fresh`: time a saddle-orbit quantity from scratch (the orbit memo, which shares one orbit
/// between period, action, flux, ..., would otherwise make repeated evaluations free); the memo
/// keeps its orbits for the references of the next quantities. Nothing outside the method's
/// domain.
std::optional<timed_value> evaluate(const precision& p, const quantity& q,
                                    const std::string& method, const probe& pr,
                                    bool fresh = false) {
    return dispatch(p, [&]<class Real>() -> std::optional<timed_value> {
        const double_pendulum<Real> model;
        const energy_level<Real> energy = parse_energy_level<Real>(pr.energy, "energy");
        std::optional<saddle_orbit_memo_bypass> bypass;
        if (fresh && q.needs_saddle_orbit) bypass.emplace();
        try {
            const double start = thread_cpu_seconds();
            const quantity_value<Real> v = q.evaluate(model, pr.a, energy, method);
            const double s = thread_cpu_seconds() - start;
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

/// The decimal digits a precision computes with (double 16, quad 34, mp:N N + 10, at least 30):
/// the size of the numbers, which is what the cost of an evaluation grows with.
double working_digits(const precision& p) {
    if (p.kind == real_kind::mp) return mp_working_digits(p.digits);
    return decimal_digits(p) + 1;
}

/// The time one evaluation is expected to take in precision `next`, from the times measured in
/// the lower columns (`times`, at `digits`, in increasing precision): t ~ digits^k, k the
/// exponent between the last two columns (clamped to [1, 6]; 3 with one column: a quadrature
/// whose node count grows with the digits times an O(digits^2) arithmetic).
double extrapolated_seconds(const std::vector<double>& digits, const std::vector<double>& times,
                            double next) {
    const std::size_t n = times.size();
    double k = 3;
    if (n >= 2 && times[n - 2] > 0 && digits[n - 1] > digits[n - 2])
        k = std::clamp(
            std::log(times[n - 1] / times[n - 2]) / std::log(digits[n - 1] / digits[n - 2]), 1.0,
            6.0);
    return times[n - 1] * std::pow(next / digits[n - 1], k);
}

}  // namespace

precision accuracy_reference_precision(const precision& column) {
    return mp_precision(std::max(100, decimal_digits(column)) + 20);
}

std::vector<accuracy_entry> measure_accuracy(const accuracy_options& options) {
    std::vector<accuracy_entry> entries;
    for (const quantity& q : quantities()) {
        if (!options.quantities.empty() &&
            std::find(options.quantities.begin(), options.quantities.end(), q.name) ==
                options.quantities.end()) {
            continue;
        }
        const std::vector<probe> ps = probes(q);
        // references: the default method in a column's reference precision, computed when a cell
        // first needs them (a slow method in mp:1000 is checked at one energy only, and so needs
        // one mp:1020 reference). Empty: outside the default method's domain.
        // NOTE: plain strings, not optionals: GCC 12 reports a false -Wfree-nonheap-object on
        // destroying a vector of optional strings at -O3.
        std::map<std::pair<int, std::size_t>, std::string> references;
        const auto reference = [&](const precision& column, std::size_t i) -> const std::string& {
            const precision rp = accuracy_reference_precision(column);
            const auto key = std::make_pair(rp.digits, i);
            auto it = references.find(key);
            if (it == references.end()) {
                std::optional<timed_value> v = evaluate(rp, q, q.methods[0], ps[i]);
                it = references.emplace(key, v ? v->value : std::string()).first;
            }
            return it->second;
        };
        for (std::size_t m = 0; m < q.methods.size(); ++m) {
            accuracy_entry e{q.name, q.description, q.methods[m], {}};
            bool too_slow = false;
            std::vector<double> measured_digits, measured_seconds;  // the columns timed so far
            for (const precision& p : options.precisions) {
                accuracy_cell& cell = e.cells.emplace_back();
                if (!too_slow && !measured_seconds.empty()) {
                    cell.estimated_seconds =
                        extrapolated_seconds(measured_digits, measured_seconds, working_digits(p));
                    too_slow = cell.estimated_seconds > options.max_seconds;
                }
                if (too_slow) {
                    cell.skipped = true;
                    continue;
                }
                const int cap = column_cap(p);
                bool timed = false;
                for (std::size_t i = 0; i < ps.size(); ++i) {
                    std::optional<timed_value> v = evaluate(p, q, q.methods[m], ps[i], true);
                    if (!v) continue;
                    const std::string& ref = reference(p, i);
                    if (ref.empty()) continue;
                    const double d = digits_between(v->value, ref, cap);
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
                if (cell.applies) {
                    measured_digits.push_back(working_digits(p));
                    measured_seconds.push_back(cell.seconds);
                }
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
                              const accuracy_options& options, const std::string& command) {
    const std::vector<precision>& columns = options.precisions;
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
        "quantity's default (first) method in a higher precision, computed only at the energies "
        "a cell is checked at" +
        "; column mp:N is referenced to mp:(N + 20), the lower ones to mp:120 (so the default "
        "method is checked against a higher precision, every other method against an independent "
        "route). Capped at the digits each precision prints (" +
        caps + " for " + names +
        "; mp:N computes with N + 10 digits, at least 30). **Time** is the mean CPU time of one "
        "evaluation at the first test energy (repeated for at least 0.2 s), on one core, measured "
        "by the evaluating thread's clock (so other jobs sharing the machine do not inflate it); "
        "methods "
        "slower than 3 s per evaluation are checked at their first energy only (the number of "
        "energies checked is given). A method is not measured in a precision (\"not measured\") "
        "when "
        "one evaluation would take longer than " +
        format_time(options.max_seconds) +
        ": measured so in a lower precision, or estimated so from the lower precisions' times "
        "(t ~ digits^k, k the exponent between the last two measured columns; the estimate is "
        "given). A closed form that holds only above "
        "the potential maximum is checked at E = 20 only.\n\n"
        "Targets: double <= 1e-14 (14 digits), quad <= 1e-31 (31), mp:N <= 1e-(N-10) relative. "
        "Google Benchmark timings of the same evaluations: `bench_prediction`. The saddle-orbit "
        "quantities at high precision (the period and action at mp:150 against mp:200, with "
        "seconds) and every prediction quantity at mp:300 and mp:1000 against mp:N+30 and "
        "independent routes are checked by the verification suite: "
        "[verification.md](verification.md).\n";
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
                md += c.estimated_seconds > 0
                          ? " | not measured (estimated " + format_time(c.estimated_seconds) + ")"
                          : std::string(" | not measured");
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
