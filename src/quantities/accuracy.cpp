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

/// The value in mp100 (as decimal text) and the time, or nothing outside the method's domain.
struct timed_value {
    std::string value;
    double seconds;
};

/// `fresh`: time a saddle-orbit quantity from scratch (the orbit memo, which shares one orbit
/// between period, action, flux, ..., would otherwise make repeated evaluations free); the memo
/// keeps its orbits for the references of the next quantities.
template <class Real>
std::optional<timed_value> evaluate(const quantity& q, const std::string& method, const probe& p,
                                    bool fresh = false) {
    const double_pendulum<Real> model;
    const Real energy = parse_real<Real>(p.energy, "--energy");
    std::optional<saddle_orbit_memo_bypass> bypass;
    if (fresh && q.needs_saddle_orbit) bypass.emplace();
    try {
        const auto start = std::chrono::steady_clock::now();
        const quantity_value<Real> v = q.evaluate(model, p.a, energy, method);
        const double s =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        return timed_value{to_decimal(v.value, output_digits<Real>() + 2), s};
    } catch (const input_error&) {
        return std::nullopt;
    }
}

std::optional<timed_value> evaluate_at(int precision_index, const quantity& q,
                                       const std::string& method, const probe& p) {
    switch (precision_index) {
        case 0:
            return evaluate<double>(q, method, p, true);
        case 1:
            return evaluate<quad>(q, method, p, true);
        case 2:
            return evaluate<mp50>(q, method, p, true);
        default:
            return evaluate<mp100>(q, method, p, true);
    }
}

double digits_between(const std::string& value, const std::string& reference, int cap) {
    using std::abs;
    const mp100 a = parse_real<mp100>(value, "value"), b = parse_real<mp100>(reference, "ref");
    const mp100 d = abs(a - b);
    if (d == 0 || b == 0) return cap;
    const double digits = -static_cast<double>(log10(d / abs(b)));
    return digits > cap ? cap : digits;
}

const char* const precision_names[4] = {"double", "quad", "mp:50", "mp:100"};
const int precision_caps[4] = {17, 36, 52, 102};

}  // namespace

std::vector<accuracy_entry> measure_accuracy(const accuracy_options& options) {
    std::vector<accuracy_entry> entries;
    for (const quantity& q : quantities()) {
        if (!options.quantities.empty() &&
            std::find(options.quantities.begin(), options.quantities.end(), q.name) ==
                options.quantities.end()) {
            continue;
        }
        const std::vector<probe> ps = probes(q);
        // references: default method in mp100, and the first other applicable method in mp100
        // (empty: the method does not apply at that energy)
        // NOTE: plain strings, not optionals: GCC 12 reports a false -Wfree-nonheap-object on
        // destroying a vector of optional strings at -O3.
        std::vector<std::string> ref(ps.size()), ref_other(ps.size());
        for (std::size_t i = 0; i < ps.size(); ++i) {
            if (auto v = evaluate<mp100>(q, q.methods[0], ps[i])) ref[i] = v->value;
            for (std::size_t m = 1; m < q.methods.size() && ref_other[i].empty(); ++m)
                if (auto v = evaluate<mp100>(q, q.methods[m], ps[i])) ref_other[i] = v->value;
        }
        for (std::size_t m = 0; m < q.methods.size(); ++m) {
            accuracy_entry e{q.name, q.description, q.methods[m], {}};
            for (int p = 0; p < 4; ++p) {
                if (!options.precisions[p]) continue;
                accuracy_cell& cell = e.cells[p];
                bool timed = false;
                for (std::size_t i = 0; i < ps.size(); ++i) {
                    const std::string& reference = (m == 0 && p == 3) ? ref_other[i] : ref[i];
                    if (reference.empty()) continue;
                    std::optional<timed_value> v = evaluate_at(p, q, q.methods[m], ps[i]);
                    if (!v) continue;
                    const double d = digits_between(v->value, reference, precision_caps[p]);
                    cell.digits = cell.applies ? std::min(cell.digits, d) : d;
                    cell.applies = true;
                    ++cell.energies;
                    if (!timed) {
                        // time at the first applicable energy: repeat up to min_seconds
                        double total = v->seconds;
                        int reps = 1;
                        while (total < options.min_seconds && v->seconds < options.slow_seconds) {
                            total += evaluate_at(p, q, q.methods[m], ps[i])->seconds;
                            ++reps;
                        }
                        cell.seconds = total / reps;
                        timed = true;
                    }
                    if (cell.seconds > options.slow_seconds) break;  // one energy is enough
                }
                if (options.progress) {
                    char line[200];
                    std::snprintf(line, sizeof line, "%s %s %s: %.1f digits, %.3g s (%d energies)",
                                  q.name.c_str(), q.methods[m].c_str(), precision_names[p],
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
                              const std::string& command) {
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
        "quantity's default (first) method in mp:100 (for that method in mp:100 itself: the next "
        "applicable method in mp:100, an independent route). Capped at 17, 36, 52 and 102. "
        "**Time** is the mean wall time of one evaluation at the first test energy (repeated for "
        "at least 0.2 s), on one core; methods slower than 3 s per evaluation are checked at "
        "their first energy only (the number of energies checked is given). A closed form that "
        "holds only above the potential maximum is checked at E = 20 only.\n\n"
        "The issue's targets: double <= 1e-14 (14 digits), quad <= 1e-31 (31), mp:50 <= 1e-46 "
        "(46) relative. Google Benchmark timings of the same evaluations: `bench_prediction`.\n";
    std::string current;
    for (const accuracy_entry& e : entries) {
        if (e.quantity != current) {
            current = e.quantity;
            md += "\n## " + e.quantity + "\n\n" + e.description +
                  "\n\n| method | double | quad | mp:50 | mp:100 |\n|---|---|---|---|---|\n";
        }
        md += "| " + e.method;
        for (const accuracy_cell& c : e.cells) {
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
