// Golden reference data (include/flipflux/quantities/golden.hpp).
#include "flipflux/quantities/golden.hpp"

#include <gmp.h>
#include <mpfr.h>

#include <Eigen/Core>
#include <algorithm>
#include <boost/version.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <exception>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/budget.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/version.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {
namespace {

/// k/20 as the shortest decimal ("2.05", "2.1", "3").
std::string twentieths(long k) {
    const long hundredths = 5 * k;
    std::string text = std::to_string(hundredths / 100);
    const long frac = hundredths % 100;
    if (frac != 0) {
        char buf[8];
        std::snprintf(buf, sizeof buf, ".%02ld", frac);
        text += buf;
        if (text.back() == '0') text.pop_back();
    }
    return text;
}

const double high_energies[] = {6.5, 7,  7.5, 8,  9,  10, 12, 15, 20,
                                25,  30, 40,  50, 60, 70, 80, 90, 100};

struct golden_task {
    const quantity* q;
    arm a;
    std::string energy;
    const model_text* model;
    double max_seconds;  ///< of each evaluation (golden_options::max_seconds; 0: no bound)
};

/// One evaluation as decimal text (every digit of its precision), or why there is none.
struct evaluation {
    std::string value;    ///< "" when there is none
    std::string method;   ///< the method that produced it
    std::string skipped;  ///< why there is none
};

/// Why a computation bounded by golden_options::max_seconds has no result.
std::string unfinished(double max_seconds) {
    return "did not finish in its " + to_decimal(max_seconds, 6) + " CPU seconds";
}

template <class Real>
evaluation evaluate_text(const golden_task& t, const std::string& method) {
    try {
        const std::optional<cpu_budget_scope> budget =
            t.max_seconds > 0 ? std::optional<cpu_budget_scope>(std::in_place, t.max_seconds)
                              : std::nullopt;
        const double_pendulum<Real> model = make_model<Real>(*t.model);
        const energy_level<Real> energy = parse_energy_level<Real>(t.energy, "energy");
        const quantity_value<Real> v = t.q->evaluate(model, t.a, energy, method);
        // the method's name, not its description (which may hold commas)
        return {to_decimal(v.value), method.empty() ? t.q->methods.front() : method, ""};
    } catch (const input_error& e) {
        return {"", "", e.what()};  // outside the quantity's (or method's) domain
    } catch (const budget_exceeded&) {
        return {"", "", (method.empty() ? "" : method + ": ") + unfinished(t.max_seconds)};
    } catch (const std::runtime_error& e) {
        // undefined here (e.g. the real multiplier of an elliptic orbit), or no solution
        return {"", "", e.what()};
    }
}

/// The default method in the value precision (pass 1).
evaluation value_of(const golden_task& t, const precision& p) {
    return dispatch(p, [&]<class Real>() { return evaluate_text<Real>(t, ""); });
}

/// The default method and the first other applicable method in the check precision (pass 2).
std::pair<evaluation, evaluation> checks_of(const golden_task& t, const precision& p) {
    return dispatch(p, [&]<class Real>() {
        std::pair<evaluation, evaluation> out{evaluate_text<Real>(t, ""), {}};
        const std::vector<std::string> others =
            t.q->check_methods.empty()
                ? std::vector<std::string>(t.q->methods.begin() + 1, t.q->methods.end())
                : t.q->check_methods;
        for (std::size_t i = 0; i < others.size() && out.second.value.empty(); ++i)
            out.second = evaluate_text<Real>(t, others[i]);
        return out;
    });
}

/// The row of a task, or why it has none.
struct golden_outcome {
    std::optional<golden_row> row;
    std::string skipped;
};

golden_outcome certify(const golden_task& t, const evaluation& high,
                       const std::pair<evaluation, evaluation>& checks, int cap) {
    if (high.value.empty()) return {std::nullopt, high.skipped};
    if (decimal_agreement(high.value, "0") == std::numeric_limits<double>::infinity())
        return {std::nullopt, "zero (no relative digits to certify)"};
    if (checks.first.value.empty()) return {std::nullopt, "check: " + checks.first.skipped};
    int digits = agreement_digits(checks.first.value, high.value, cap);
    if (!checks.second.value.empty())
        digits = std::min(digits, agreement_digits(checks.second.value, high.value, cap));
    golden_row row;
    row.quantity = t.q->name;
    row.arm = t.q->per_arm ? to_string(t.a) : "";
    row.energy = t.energy;
    row.digits = digits;
    row.value = round_decimal(high.value, std::max(digits, 1));
    row.method = high.method + (checks.second.value.empty() ? "" : "|" + checks.second.method);
    return {row, ""};
}

/// golden --certify: the row's enclosure (certified/), aiming at its certified digits; the row's
/// value (rounded to them: half a unit of its last digit of slack) must lie in it. The radius
/// written is that of the ball around the row's value: [value +/- radius] contains the exact
/// value. `aim`: the digits asked of the proof (at least the row's).
void prove_row(golden_row& row, const model_text& model, int aim) {
    if (!has_certified_enclosure(row.quantity)) return;
    // a quantity of both arms (omega) has no arm in its row: any arm evaluates it
    const arm a = row.arm.empty() ? arm::two : parse_name<arm>(row.arm, "arm");
    const certified_enclosure e =
        certified_value(row.quantity, model, a, row.energy, std::max({row.digits, aim, 1}));
    const std::string slack = dispatch(mp_precision(row.digits + 10), [&]<class Real>() {
        using std::abs;
        using std::pow;
        const Real v = parse_real<Real>(row.value, "value");
        return to_decimal(Real(abs(v) * pow(Real(10), 1 - row.digits) / 2), 3);
    });
    if (!enclosure_contains(e, row.value, slack))
        throw certification_error("golden: " + row.quantity + " arm " + row.arm +
                                  " at E = " + row.energy + ": the value " + row.value +
                                  " lies outside its proven enclosure [" + e.mid + " +/- " +
                                  e.radius + "]: a bug in one of the two routes");
    const certified_enclosure around = recentre_enclosure(e, row.value);
    row.radius = around.radius;
    row.proven_digits = around.proven_digits;
}

}  // namespace

std::vector<std::string> golden_energies(double start, double maximum) {
    std::vector<std::string> grid;
    for (long k = static_cast<long>(std::floor(start * 20 + 1e-9)) + 1; k <= maximum * 20 + 1e-9;
         ++k)
        grid.push_back(twentieths(k));
    for (double e : high_energies) {
        if (e > maximum) {
            std::ostringstream out;
            out << e;
            grid.push_back(out.str());
        }
    }
    return grid;
}

std::vector<std::string> golden_orbit_energies(double start, double maximum) {
    // just above the saddle, every unit from there, just below the maximum (k/20 as text)
    const long first = static_cast<long>(std::floor(start * 20 + 1e-9)) + 1;
    const long last = static_cast<long>(std::ceil(maximum * 20 - 1e-9)) - 1;
    std::vector<std::string> grid{twentieths(first)};
    for (long k = first - 1 + 20; k < last; k += 20)
        grid.push_back(twentieths(k));
    if (last > first) grid.push_back(twentieths(last));
    // closer to the maximum, where the orbits graze the upright state: E_max - 1/100, - 1/1000
    for (double d : {0.01, 0.001}) {
        const std::string text = round_decimal(to_decimal(maximum - d, 17), 10);
        if (maximum - d > start + 0.05 && text != grid.back()) grid.push_back(text);
    }
    return grid;
}

int agreement_digits(const std::string& value, const std::string& reference, int cap) {
    if (decimal_agreement(reference, "0") == std::numeric_limits<double>::infinity())
        return value == reference ? cap : 0;
    const double digits = std::floor(decimal_agreement(value, reference));
    if (digits < 0) return 0;
    return digits > cap ? cap : static_cast<int>(digits);
}

precision golden_check_precision(const precision& value_precision) {
    if (value_precision.kind == real_kind::mp && value_precision.digits >= 2)
        return mp_precision(value_precision.digits / 2);
    if (value_precision.kind == real_kind::quad) return precision{real_kind::double_};
    throw input_error::about(
        "precision",
        "'" + precision_name(value_precision) +
            "' is too low for golden data (a lower precision certifies it: use quad or "
            "mp:DIGITS with DIGITS >= 2)");
}

std::optional<precision> golden_recheck_precision(const precision& value_precision) {
    if (value_precision.kind == real_kind::mp && value_precision.digits >= 8)
        return mp_precision(value_precision.digits * 3 / 4);
    return std::nullopt;
}

std::vector<std::string> golden_relative_energies(double start, double maximum) {
    std::vector<std::string> grid;
    const auto add = [&grid, start](double e) {
        const std::string text = round_decimal(to_decimal(e, 17), 10);
        if (parse_real<double>(text, "energy") > start &&
            std::find(grid.begin(), grid.end(), text) == grid.end())
            grid.push_back(text);
    };
    add(start + maximum / 1000);
    for (int k = 1; k <= 40; ++k) {
        if (k == 40) add(maximum * (1 - 1.0 / 1000));
        add(maximum * k / 40);
    }
    for (double f : {1.25, 1.5, 2.0, 3.0, 5.0, 10.0})
        add(maximum * f);
    std::sort(grid.begin(), grid.end(), [](const std::string& a, const std::string& b) {
        return parse_real<double>(a, "energy") < parse_real<double>(b, "energy");
    });
    return grid;
}

std::vector<std::string> golden_relative_orbit_energies(double start, double maximum) {
    std::vector<std::string> grid;
    for (double f : {0.01, 0.25, 0.5, 0.75, 0.99, 0.999})
        grid.push_back(round_decimal(to_decimal(start + (maximum - start) * f, 17), 10));
    return grid;
}

std::vector<golden_row> generate_golden(const golden_options& options) {
    const double_pendulum<double> model = make_model<double>(options.model);
    const bool paper = options.model.is_default();
    const auto grid = [paper](double start, double maximum) {
        return paper ? golden_energies(start, maximum) : golden_relative_energies(start, maximum);
    };
    const auto orbit_grid = [paper](double start, double maximum) {
        return paper ? golden_orbit_energies(start, maximum)
                     : golden_relative_orbit_energies(start, maximum);
    };
    std::vector<golden_task> tasks;
    for (const quantity& q : quantities()) {
        if (!options.quantities.empty() &&
            std::find(options.quantities.begin(), options.quantities.end(), q.name) ==
                options.quantities.end()) {
            continue;
        }
        if (!q.per_arm) {
            for (const std::string& e : grid(0, model.maximum_energy()))
                tasks.push_back({&q, arm::two, e, &options.model, options.max_seconds});
            continue;
        }
        for (arm a : {arm::two, arm::one}) {
            const double es = model.saddle_energy(a), emax = model.maximum_energy();
            for (const std::string& e :
                 q.needs_saddle_orbit ? orbit_grid(es, emax) : grid(es, emax))
                tasks.push_back({&q, a, e, &options.model, options.max_seconds});
        }
    }
    if (options.max_rows > 0 && tasks.size() > options.max_rows) {
        // an evenly spread sample
        std::vector<golden_task> sample;
        for (std::size_t i = 0; i < options.max_rows; ++i)
            sample.push_back(tasks[i * tasks.size() / options.max_rows]);
        tasks.swap(sample);
    }
    // NOTE: two passes, each in one precision: threads of one precision run concurrently, while
    // a second precision in the same process waits for the first (core/real.hpp, precision_scope)
    const precision check = golden_check_precision(options.value_precision);
    const int cap = decimal_digits(check);
    const long n = static_cast<long>(tasks.size());
    const int threads = options.jobs > 0 ? options.jobs : 1;
    std::vector<evaluation> high(tasks.size());
#pragma omp parallel for schedule(dynamic) num_threads(threads)
    for (long i = 0; i < n; ++i)
        high[i] = value_of(tasks[i], options.value_precision);
    std::vector<golden_outcome> rows(tasks.size());
    std::size_t done = 0;
    const auto report = [&](long i) {
#pragma omp critical(flipflux_golden_progress)
        {
            ++done;
            if (options.progress && rows[i].row) options.progress(*rows[i].row, done, tasks.size());
            if (options.skipped && !rows[i].row) {
                const golden_task& t = tasks[i];
                options.skipped(t.q->name + " arm " + (t.q->per_arm ? to_string(t.a) : "-") +
                                " E " + t.energy + ": " + rows[i].skipped);
            }
        }
    };
    // pass 3, in mp:(3N/4): the rows pass 2 certifies to fewer digits than the cap are checked
    // again there, and certified by that agreement (both methods again, in the higher precision)
    const std::optional<precision> recheck = golden_recheck_precision(options.value_precision);
    std::vector<char> again(tasks.size(), 0);
#pragma omp parallel for schedule(dynamic) num_threads(threads)
    for (long i = 0; i < n; ++i) {
        std::pair<evaluation, evaluation> checks;
        if (!high[i].value.empty()) checks = checks_of(tasks[i], check);
        rows[i] = certify(tasks[i], high[i], checks, cap);
        if (recheck && rows[i].row && rows[i].row->digits < cap)
            again[i] = 1;
        else
            report(i);
    }
    if (recheck) {
#pragma omp parallel for schedule(dynamic) num_threads(threads)
        for (long i = 0; i < n; ++i) {
            if (!again[i]) continue;
            rows[i] = certify(tasks[i], high[i], checks_of(tasks[i], *recheck), cap);
            report(i);
        }
    }
    std::vector<golden_row> out;
    for (auto& r : rows)
        if (r.row) out.push_back(std::move(*r.row));
    if (options.certify)
        prove_golden_rows(out, options.model, threads, options.max_seconds, options.unproven);
    return out;
}

void prove_golden_rows(std::vector<golden_row>& rows, const model_text& model, int jobs,
                       double max_seconds,
                       const std::function<void(const std::string&)>& unproven) {
    // NOTE: an exception must not leave an OpenMP region: kept, the first rethrown after it
    // NOTE: one proof of a saddle orbit serves its six quantities (the process's proof memo is
    // keyed by the precision): the rows of one orbit ask for the most digits any of them has, so
    // that rows certified to 13, 14 and 15 digits share one proof instead of three
    std::map<std::pair<std::string, std::string>, int> orbit_digits;
    for (const golden_row& r : rows)
        if (has_certified_enclosure(r.quantity) && find_quantity(r.quantity).needs_saddle_orbit) {
            int& d = orbit_digits[{r.arm, r.energy}];
            d = std::max(d, r.digits);
        }
    const long m = static_cast<long>(rows.size());
    std::vector<std::exception_ptr> failed(rows.size());
#pragma omp parallel for schedule(dynamic) num_threads(jobs > 0 ? jobs : 1)
    for (long i = 0; i < m; ++i) {
        try {
            const golden_row& r = rows[static_cast<std::size_t>(i)];
            const auto orbit = orbit_digits.find({r.arm, r.energy});
            const bool shared =
                orbit != orbit_digits.end() && find_quantity(r.quantity).needs_saddle_orbit;
            const std::optional<cpu_budget_scope> budget =
                max_seconds > 0 ? std::optional<cpu_budget_scope>(std::in_place, max_seconds)
                                : std::nullopt;
            prove_row(rows[static_cast<std::size_t>(i)], model, shared ? orbit->second : 0);
        } catch (const budget_exceeded&) {
            // the row stays without an enclosure (no radius), and is named
            if (unproven) {
                const golden_row& r = rows[static_cast<std::size_t>(i)];
#pragma omp critical(flipflux_golden_progress)
                unproven("the proof of " + r.quantity + " arm " + (r.arm.empty() ? "-" : r.arm) +
                         " E " + r.energy + ": " + unfinished(max_seconds));
            }
        } catch (...) {
            failed[static_cast<std::size_t>(i)] = std::current_exception();
        }
    }
    for (const std::exception_ptr& e : failed)
        if (e) std::rethrow_exception(e);
}

}  // namespace flipflux
