// What accuracy costs (include/flipflux/quantities/accuracy.hpp).
#include "flipflux/quantities/accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <optional>
#include <tuple>

#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/budget.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/version.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
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

int accuracy_column_cap(const precision& p) {
    return dispatch(p, []<class Real>() { return output_digits<Real>(); });
}

precision accuracy_reference_precision(const precision& column) {
    return mp_precision(std::max(100, decimal_digits(column)) + 20);
}

namespace {

/// The methods a quantity is measured with: its registry methods; a saddle-orbit quantity's
/// with each orbit integrator ("periodic/taylor", "periodic/gauss-legendre", ...), the first
/// integrator being the one its default method uses above double.
std::vector<std::string> measured_methods(const quantity& q) {
    if (!q.needs_saddle_orbit) return q.methods;
    std::vector<std::string> out;
    for (const std::string& m : q.methods)
        for (const std::string& i : names_of<orbit_integrator>())
            out.push_back(m + "/" + i);
    return out;
}

/// One row of the report while it is measured: a (quantity, method) pair, or a quantity's proof.
struct row_state {
    row_state(const quantity& quantity_, std::string method_, bool proof_)
        : q(&quantity_),
          method(std::move(method_)),
          proof(proof_),
          probes(flipflux::probes(quantity_)),
          entry{quantity_.name, quantity_.description, method, {}} {}

    const quantity* q;
    std::string method;
    bool proof;
    std::vector<probe> probes;
    accuracy_entry entry;
    bool too_slow = false;
    std::vector<double> measured_digits, measured_seconds;  // the columns timed so far
    /// the current column's values (by probe index; empty: not evaluated or outside the domain)
    std::vector<std::string> values;
    std::vector<certified_enclosure> balls;  // proof rows
};

/// A proof at one probe: the enclosure at the column's digits, and its CPU time.
std::optional<std::pair<certified_enclosure, double>> prove(const precision& p, const quantity& q,
                                                            const probe& pr) {
    // timed from scratch: neither this process's earlier proofs of the same orbit (period and
    // action share one) nor its non-rigorous orbits (the proof's centre)
    const certified_proof_memo_bypass fresh_proof;
    const saddle_orbit_memo_bypass fresh_orbit;
    try {
        const double start = thread_cpu_seconds();
        certified_enclosure e =
            certified_value(q.name, model_text{}, pr.a, pr.energy, decimal_digits(p));
        return std::make_pair(std::move(e), thread_cpu_seconds() - start);
    } catch (const input_error&) {
        return std::nullopt;  // outside the quantity's domain
    }
}

void measure_values(row_state& r, const precision& p, const accuracy_options& options);

/// Measures row r's cell in column p: evaluates (or proves) at its probes in order, stopping
/// after the first when that one is slow; times the first applicable probe (repeated up to
/// min_seconds). Fills r.values / r.balls; the digits follow once the references exist.
void measure_cell(row_state& r, const precision& p, const accuracy_options& options) {
    accuracy_cell& cell = r.entry.cells.back();
    try {
        // NOTE: a cost that grows faster with the digits than the lower columns predicted must
        // not hold the report for hours: the cell is abandoned at twice max_seconds
        const cpu_budget_scope budget(2 * options.max_seconds);
        measure_values(r, p, options);
    } catch (const budget_exceeded&) {
        r.values.assign(r.probes.size(), std::string());
        cell.over_budget = true;
        cell.seconds = 2 * options.max_seconds;
    } catch (const std::exception& e) {
        // a method or a proof that fails (no convergence, a Krawczyk test that does not
        // contract) is a finding of the report, not the end of the run (these cells run on
        // OpenMP threads, where an escaping exception would terminate the process)
        r.values.assign(r.probes.size(), std::string());
        cell.failure = e.what();
    }
}

/// measure_cell's evaluations (or proofs), without the budget.
void measure_values(row_state& r, const precision& p, const accuracy_options& options) {
    accuracy_cell& cell = r.entry.cells.back();
    r.values.assign(r.probes.size(), std::string());
    r.balls.assign(r.probes.size(), certified_enclosure{});
    bool timed = false;
    for (std::size_t i = 0; i < r.probes.size(); ++i) {
        double seconds = 0;
        if (r.proof) {
            auto b = prove(p, *r.q, r.probes[i]);
            if (!b) continue;
            r.balls[i] = b->first;
            r.values[i] = b->first.mid;
            seconds = b->second;
        } else {
            std::optional<timed_value> v = evaluate(p, *r.q, r.method, r.probes[i], true);
            if (!v) continue;
            r.values[i] = v->value;
            seconds = v->seconds;
        }
        if (!timed) {
            double total = seconds;
            int reps = 1;
            while (total < options.min_seconds && seconds < options.slow_seconds) {
                total += r.proof ? prove(p, *r.q, r.probes[i])->second
                                 : evaluate(p, *r.q, r.method, r.probes[i], true)->seconds;
                ++reps;
            }
            cell.seconds = total / reps;
            timed = true;
        }
        if (cell.seconds > options.slow_seconds) break;  // one energy is enough
    }
}

/// The decimal text x times 10^k (k an exponent shift), exactly.
std::string scaled_decimal(const std::string& x, int k) {
    const std::size_t e = x.find_first_of("eE");
    if (e == std::string::npos) return x + "e" + std::to_string(k);
    return x.substr(0, e) + "e" + std::to_string(std::stol(x.substr(e + 1)) + k);
}

/// Runs f(i) for i in [0, n) on `threads` threads, longest first as `order` gives them.
template <class F>
void parallel_for(const std::vector<std::size_t>& order, int threads, F f) {
    const long n = static_cast<long>(order.size());
#pragma omp parallel for schedule(dynamic) num_threads(threads)
    for (long k = 0; k < n; ++k)
        f(order[static_cast<std::size_t>(k)]);
}

}  // namespace

std::vector<accuracy_entry> measure_accuracy(const accuracy_options& options) {
    std::vector<row_state> rows;
    for (const quantity& q : quantities()) {
        if (!options.quantities.empty() &&
            std::find(options.quantities.begin(), options.quantities.end(), q.name) ==
                options.quantities.end()) {
            continue;
        }
        for (const std::string& m : measured_methods(q))
            rows.emplace_back(q, m, false);
        if (has_certified_enclosure(q.name)) rows.emplace_back(q, std::string(proof_method), true);
    }
    const int threads = std::max(1, options.threads);
    // references: a quantity's default method in a column's reference precision, by (quantity,
    // reference digits, probe), computed when a cell first needs them (a slow method in mp:1000
    // is checked at one energy only, and so needs one mp:1020 reference). Empty: outside the
    // default method's domain.
    // NOTE: plain strings, not optionals: GCC 12 reports a false -Wfree-nonheap-object on
    // destroying a vector of optional strings at -O3.
    std::map<std::tuple<const quantity*, int, std::size_t>, std::string> references;
    for (const precision& p : options.precisions) {
        // which rows are measured in this column: not those too slow in a lower one, nor those
        // estimated to be (t ~ digits^k); the longest first, so that two threads end together
        std::vector<std::pair<double, std::size_t>> active;
        for (std::size_t k = 0; k < rows.size(); ++k) {
            row_state& r = rows[k];
            accuracy_cell& cell = r.entry.cells.emplace_back();
            if (!r.too_slow && !r.measured_seconds.empty()) {
                cell.estimated_seconds =
                    extrapolated_seconds(r.measured_digits, r.measured_seconds, working_digits(p));
                r.too_slow = cell.estimated_seconds > options.max_seconds;
            }
            if (r.too_slow) {
                cell.skipped = true;
                continue;
            }
            active.emplace_back(cell.estimated_seconds, k);
        }
        std::sort(active.begin(), active.end(), std::greater<>());
        std::vector<std::size_t> order;
        for (const auto& a : active)
            order.push_back(a.second);
        parallel_for(order, threads, [&](std::size_t k) { measure_cell(rows[k], p, options); });

        // the references these cells need, in one precision (a second precision waits for the
        // first: core/real.hpp, precision_scope)
        const precision rp = accuracy_reference_precision(p);
        std::vector<std::tuple<const quantity*, int, std::size_t>> missing;
        for (std::size_t k : order)
            for (std::size_t i = 0; i < rows[k].values.size(); ++i) {
                const auto key = std::make_tuple(rows[k].q, rp.digits, i);
                if (!rows[k].values[i].empty() && !references.count(key) &&
                    std::find(missing.begin(), missing.end(), key) == missing.end())
                    missing.push_back(key);
            }
        std::vector<std::string> computed(missing.size());
        std::vector<std::size_t> all(missing.size());
        for (std::size_t j = 0; j < all.size(); ++j)
            all[j] = j;
        parallel_for(all, threads, [&](std::size_t j) {
            const auto& [q, digits, i] = missing[j];
            std::optional<timed_value> v = evaluate(rp, *q, q->methods[0], probes(*q)[i]);
            computed[j] = v ? v->value : std::string();
        });
        for (std::size_t j = 0; j < missing.size(); ++j)
            references.emplace(missing[j], computed[j]);

        const int cap = accuracy_column_cap(p);
        for (std::size_t k : order) {
            row_state& r = rows[k];
            accuracy_cell& cell = r.entry.cells.back();
            for (std::size_t i = 0; i < r.values.size(); ++i) {
                if (r.values[i].empty()) continue;
                const std::string& ref = references.at(std::make_tuple(r.q, rp.digits, i));
                if (ref.empty()) continue;
                double d = 0;
                if (r.proof) {
                    d = r.balls[i].proven_digits;
                    // the reference is good to rp's digits: slack |ref| 10^-rp.digits
                    const std::string slack = scaled_decimal(ref, -rp.digits);
                    if (!enclosure_contains(r.balls[i], ref, slack))
                        cell.contains_reference = false;
                } else {
                    d = digits_between(r.values[i], ref, cap);
                }
                cell.digits = cell.applies ? std::min(cell.digits, d) : d;
                cell.applies = true;
                ++cell.energies;
            }
            r.too_slow = cell.seconds > options.max_seconds;
            if (cell.over_budget || !cell.failure.empty()) {
                cell.skipped = true;
            } else if (cell.applies) {
                r.measured_digits.push_back(working_digits(p));
                r.measured_seconds.push_back(cell.seconds);
            }
            if (options.progress) {
                char line[240];
                std::snprintf(line, sizeof line, "%s %s %s: %.1f digits, %.3g s (%d energies)%s%s",
                              r.q->name.c_str(), r.method.c_str(), precision_name(p).c_str(),
                              cell.digits, cell.seconds, cell.energies,
                              cell.contains_reference ? "" : " REFERENCE OUTSIDE THE BALL",
                              cell.failure.empty() ? "" : (" FAILED: " + cell.failure).c_str());
                options.progress(line);
            }
        }
    }
    std::vector<accuracy_entry> entries;
    for (row_state& r : rows)
        entries.push_back(std::move(r.entry));
    return entries;
}

}  // namespace flipflux
