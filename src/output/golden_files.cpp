// The files of a golden set (include/flipflux/output/golden_files.hpp).
#include "flipflux/output/golden_files.hpp"

#include <gmp.h>
#include <mpfr.h>

#include <Eigen/Core>
#include <algorithm>
#include <boost/version.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/version.hpp"
#include "flipflux/io/csv.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {

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

namespace {

/// " (TEXT)", or nothing when the caller gave no words.
std::string parenthesised(const std::string& text) {
    return text.empty() ? std::string() : " (" + text + ")";
}

}  // namespace

std::string golden_provenance(const std::string& command, std::size_t rows,
                              const precision& value_precision, const command_words& words,
                              const model_text& model, const std::string& pendulum,
                              const std::string& merged_into) {
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
        j["model"] =
            "double pendulum with the parameters above" + parenthesised(words.model_options);
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
    const std::string certified_only =
        (words.golden_certify.empty() ? std::string("a certified run") : words.golden_certify) +
        " only: ";
    j["columns"] = {
        {"quantity", "registered name" + parenthesised(words.quantity_list)},
        {"arm", "1 or 2; empty for quantities that are not per arm"},
        {"energy", "E as decimal text"},
        {"value", hi + " value rounded to `digits` significant digits"},
        {"digits", "certified significant digits"},
        {"method", "default method | independent method that certified it"},
        {"radius", certified_only +
                       "radius of a proven enclosure [value +/- radius] of the exact value (Arb; "
                       "the saddle orbits by a Krawczyk proof), empty where the quantity has "
                       "none"},
        {"proven_digits", certified_only + "floor(-log10(radius / |value|))"}};
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
        throw input_error("the set's values are in '" + values.substr(0, values.find(' ')) +
                          "', this run's in '" + hi + "'");
    if (!earlier.contains("parameters")) {  // a set written before parameters were recorded
        const bool paper = earlier.contains("model") && earlier["model"].is_string() &&
                           earlier["model"].get<std::string>().rfind("egalitarian", 0) == 0;
        if (paper && model.is_default()) return;
        throw input_error(paper ? "the set is the paper's pendulum, this run's is not"
                                : "golden provenance: no \"parameters\"");
    }
    for (std::size_t i = 0; i < parameter_count; ++i) {
        const std::string name(parameter_fields[i].name);
        const std::string& value = resolved_text(model, i);
        const std::string theirs = text_at("parameters", name.c_str());
        if (theirs != value)
            throw input_error(std::string("the set's ") + name + " is '" + theirs +
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
