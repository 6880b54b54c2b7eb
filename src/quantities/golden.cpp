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
};

/// One evaluation as decimal text (every digit of its precision), or why there is none.
struct evaluation {
    std::string value;    ///< "" when there is none
    std::string method;   ///< the method that produced it
    std::string skipped;  ///< why there is none
};

template <class Real>
evaluation evaluate_text(const golden_task& t, const std::string& method) {
    try {
        const double_pendulum<Real> model = make_model<Real>(*t.model);
        const energy_level<Real> energy = parse_energy_level<Real>(t.energy, "energy");
        const quantity_value<Real> v = t.q->evaluate(model, t.a, energy, method);
        // the method's name, not its description (which may hold commas)
        return {to_decimal(v.value), method.empty() ? t.q->methods.front() : method, ""};
    } catch (const input_error& e) {
        return {"", "", e.what()};  // outside the quantity's (or method's) domain
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
                tasks.push_back({&q, arm::two, e, &options.model});
            continue;
        }
        for (arm a : {arm::two, arm::one}) {
            const double es = model.saddle_energy(a), emax = model.maximum_energy();
            for (const std::string& e :
                 q.needs_saddle_orbit ? orbit_grid(es, emax) : grid(es, emax))
                tasks.push_back({&q, a, e, &options.model});
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
    if (options.certify) prove_golden_rows(out, options.model, threads);
    return out;
}

void prove_golden_rows(std::vector<golden_row>& rows, const model_text& model, int jobs) {
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
            prove_row(rows[static_cast<std::size_t>(i)], model, shared ? orbit->second : 0);
        } catch (...) {
            failed[static_cast<std::size_t>(i)] = std::current_exception();
        }
    }
    for (const std::exception_ptr& e : failed)
        if (e) std::rethrow_exception(e);
}

std::string golden_csv(const std::vector<golden_row>& rows) {
    const bool proven = std::any_of(rows.begin(), rows.end(),
                                    [](const golden_row& r) { return !r.radius.empty(); });
    std::string text = "quantity,arm,energy,value,digits,method";
    text += proven ? ",radius,proven_digits\n" : "\n";
    for (const golden_row& r : rows) {
        for (const std::string* field :
             {&r.quantity, &r.arm, &r.energy, &r.value, &r.method, &r.radius})
            if (field->find_first_of(",\n\r") != std::string::npos)
                throw std::logic_error("golden csv: a field holds a separator: '" + *field + "'");
        text += r.quantity + "," + r.arm + "," + r.energy + "," + r.value + "," +
                std::to_string(r.digits) + "," + r.method;
        if (proven)
            text += "," + r.radius + "," +
                    (r.radius.empty() ? std::string() : std::to_string(r.proven_digits));
        text += "\n";
    }
    return text;
}

std::vector<golden_row> parse_golden_csv(const std::string& text) {
    std::vector<golden_row> rows;
    std::istringstream in(text);
    std::string line;
    std::size_t number = 0;
    while (std::getline(in, line)) {
        ++number;
        if (number == 1) {  // the header golden_csv writes, or the file is not a golden set
            if (line != "quantity,arm,energy,value,digits,method" &&
                line != "quantity,arm,energy,value,digits,method,radius,proven_digits")
                throw input_error(
                    "golden csv: line 1 is not the header "
                    "'quantity,arm,energy,value,digits,method[,radius,proven_digits]' (not a "
                    "golden set)");
            continue;
        }
        if (line.empty()) continue;
        std::vector<std::string> fields{""};  // every comma separates, trailing empties kept
        for (char c : line) {
            if (c == ',')
                fields.emplace_back();
            else
                fields.back() += c;
        }
        if (fields.size() != 6 && fields.size() != 8) {
            throw input_error("golden csv: line " + std::to_string(number) +
                              " does not have 6 fields (or 8 with radius and proven_digits)");
        }
        golden_row r{fields[0], fields[1], fields[2], fields[3], 0, fields[5], "", -1};
        const auto integer = [number](const std::string& text, const char* what) {
            try {
                std::size_t used = 0;
                const int v = std::stoi(text, &used);
                if (used == text.size()) return v;
            } catch (const std::exception&) {
            }
            throw input_error("golden csv: line " + std::to_string(number) + ": " + what + " '" +
                              text + "' is not an integer");
        };
        r.digits = integer(fields[4], "digits");
        if (fields.size() == 8 && !fields[6].empty()) {
            r.radius = fields[6];
            r.proven_digits = integer(fields[7], "proven_digits");
        }
        rows.push_back(std::move(r));
    }
    return rows;
}

std::string golden_provenance(const std::string& command, std::size_t rows,
                              const precision& value_precision, const model_text& model,
                              const std::string& pendulum, const std::string& merged_into) {
    const precision check = golden_check_precision(value_precision);
    nlohmann::ordered_json j;
    j["command"] = command;
    j["flipflux_version"] = version_string();
    j["git_commit"] = git_commit();
    const std::time_t now = std::chrono::system_clock::to_time_t(std::chrono::system_clock::now());
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", std::gmtime(&now));
    j["generated_utc"] = date;
    if (!merged_into.empty()) {
        check_golden_merge(merged_into, value_precision, model);
        const nlohmann::json earlier = nlohmann::json::parse(merged_into);
        nlohmann::ordered_json runs = nlohmann::ordered_json::array();
        const auto run_of = [](const nlohmann::json& r) {
            nlohmann::ordered_json o;
            for (const char* key : {"command", "git_commit", "generated_utc"})
                o[key] = r.contains(key) && r[key].is_string() ? r[key].get<std::string>() : "";
            return o;
        };
        if (earlier.contains("runs") && earlier["runs"].is_array()) {
            for (const auto& r : earlier["runs"])
                if (r.is_object()) runs.push_back(run_of(r));
        } else {
            runs.push_back(run_of(earlier));
        }
        runs.push_back(run_of(j));
        j["runs"] = runs;
    }
    j["compiler"] = std::string("g++ ") + __VERSION__;
    j["libraries"] = {
        {"boost", BOOST_LIB_VERSION},
        {"mpfr", mpfr_get_version()},
        {"gmp", gmp_version},
        {"eigen", std::to_string(EIGEN_WORLD_VERSION) + "." + std::to_string(EIGEN_MAJOR_VERSION) +
                      "." + std::to_string(EIGEN_MINOR_VERSION)}};
    const std::string hi = precision_name(value_precision), lo = precision_name(check);
    const std::optional<precision> recheck = golden_recheck_precision(value_precision);
    j["precision"] = {
        {"values", hi + " (the quantity's default method)"},
        {"certification",
         "digits = min(agreement of the default method in " + lo + " with " + hi +
             ", agreement of the first applicable independent method in " + lo + " with " + hi +
             "), capped at " + std::to_string(decimal_digits(check)) +
             (recheck
                  ? "; a row certified so to fewer digits than the cap (an ill-conditioned "
                    "quantity) is checked again in " +
                        precision_name(*recheck) + ", both methods, and certified by that agreement"
                  : std::string()) +
             "; the saddle-orbit quantities: periodic shooting (the paper's) with the "
             "Taylor integrator, certified by the symmetric shooting to the brake "
             "point"}};
    j["boost_math_policy"] =
        "promote_double<false> (BOOST_MATH_PROMOTE_DOUBLE_POLICY=false), default error policies "
        "(domain and evaluation errors throw)";
    j["pendulum"] = pendulum;
    j["parameters"] = decltype(j)::object();
    for (std::size_t i = 0; i < parameter_count; ++i)
        j["parameters"][std::string(parameter_fields[i].name)] = resolved_text(model, i);
    // in mp:50, rounded to 40 digits: products and sums of the decimal parameters, so exact
    // decimals (2.2, not double's 2.2000000000000002)
    j["critical_energies"] = dispatch(mp_precision(50), [&]<class Real>() {
        const double_pendulum<Real> mm = make_model<Real>(model);
        return nlohmann::json{{"saddle_arm2", to_decimal(mm.saddle_energy(arm::two), 40)},
                              {"saddle_arm1", to_decimal(mm.saddle_energy(arm::one), 40)},
                              {"maximum", to_decimal(mm.maximum_energy(), 40)}};
    });
    if (model.is_default()) {
        j["model"] =
            "egalitarian double pendulum: m1 = m2 = L1 = L2 = g = 1 (A = 2, B = C = 1, "
            "alpha = 2, beta = 1)";
        j["grid"] =
            "per quantity and arm: every 0.05 from above the saddle energy (0 for omega) to E_max "
            "= 6, then 6.5, 7, 7.5, 8, 9, 10, 12, 15, 20, 25, 30, 40, 50, 60, 70, 80, 90, 100; "
            "energies are decimal text parsed in each precision";
    } else {
        j["model"] = "double pendulum with the parameters above (flipflux --m1 ... --g)";
        j["grid"] =
            "relative to the critical energies, U = E_max: the fractions k/40 of U above the "
            "saddle energy (0 for omega), E_s + U/1000, U (1 - 1/1000), and 1.25, 1.5, 2, 3, 5, 10 "
            "U, each with 10 significant digits; energies are decimal text parsed in each "
            "precision";
    }
    j["orbit_grid"] =
        model.is_default()
            ? "quantities of the saddle orbit (period, action, flux-saddle, rate-saddle, "
              "multiplier, stability-index), per arm: E_s + 0.05, every whole unit above it, "
              "E_max - 0.05, E_max - 0.01, E_max - 0.001"
            : "quantities of the saddle orbit, per arm: E_s + (E_max - E_s) x 1/100, 1/4, 1/2, "
              "3/4, 99/100, 999/1000, each with 10 significant digits";
    j["columns"] = {{"quantity", "registered name (flipflux eval --help)"},
                    {"arm", "1 or 2; empty for quantities that are not per arm"},
                    {"energy", "E as decimal text"},
                    {"value", hi + " value rounded to `digits` significant digits"},
                    {"digits", "certified significant digits"},
                    {"method", "default method | independent method that certified it"},
                    {"radius",
                     "golden --certify only: radius of a proven enclosure [value +/- radius] of "
                     "the exact value (Arb; the saddle orbits by a Krawczyk proof), empty where "
                     "the quantity has none"},
                    {"proven_digits", "golden --certify only: floor(-log10(radius / |value|))"}};
    j["rows"] = rows;
    return j.dump(2) + "\n";
}

void check_golden_merge(const std::string& provenance_text, const precision& value_precision,
                        const model_text& model) {
    nlohmann::json earlier;
    try {
        earlier = nlohmann::json::parse(provenance_text);
    } catch (const nlohmann::json::exception& e) {
        throw input_error(std::string("golden provenance: not JSON (") + e.what() + ")");
    }
    const auto text_at = [&earlier](const char* object, const char* key) -> std::string {
        if (!earlier.is_object() || !earlier.contains(object) || !earlier[object].is_object() ||
            !earlier[object].contains(key) || !earlier[object][key].is_string())
            throw input_error(std::string("golden provenance: no text \"") + object + "." + key +
                              "\"");
        return earlier[object][key].get<std::string>();
    };
    const std::string hi = precision_name(value_precision);
    const std::string values = text_at("precision", "values");
    if (values.substr(0, values.find(' ')) != hi)
        throw input_error("golden --merge: the set's values are in '" +
                          values.substr(0, values.find(' ')) + "', this run's in '" + hi + "'");
    if (!earlier.contains("parameters")) {  // a set written before parameters were recorded
        const bool paper = earlier.contains("model") && earlier["model"].is_string() &&
                           earlier["model"].get<std::string>().rfind("egalitarian", 0) == 0;
        if (paper && model.is_default()) return;
        throw input_error(paper
                              ? "golden --merge: the set is the paper's pendulum, this run's is not"
                              : "golden provenance: no \"parameters\"");
    }
    for (std::size_t i = 0; i < parameter_count; ++i) {
        const std::string name(parameter_fields[i].name);
        const std::string& value = resolved_text(model, i);
        const std::string theirs = text_at("parameters", name.c_str());
        if (theirs != value)
            throw input_error(std::string("golden --merge: the set's ") + name + " is '" + theirs +
                              "', this run's '" + value + "'");
    }
}

std::vector<golden_row> merge_golden(const std::vector<golden_row>& existing,
                                     const std::vector<golden_row>& fresh,
                                     const std::vector<std::string>& regenerated) {
    std::vector<golden_row> out;
    for (const golden_row& r : existing) {
        if (!regenerated.empty() &&
            std::find(regenerated.begin(), regenerated.end(), r.quantity) == regenerated.end())
            out.push_back(r);
    }
    out.insert(out.end(), fresh.begin(), fresh.end());
    std::vector<std::string> order;
    for (const quantity& q : quantities())
        order.push_back(q.name);
    const auto rank = [&order](const golden_row& r) {
        return std::find(order.begin(), order.end(), r.quantity) - order.begin();
    };
    std::stable_sort(out.begin(), out.end(), [&rank](const golden_row& a, const golden_row& b) {
        return rank(a) < rank(b);
    });
    return out;
}

}  // namespace flipflux
