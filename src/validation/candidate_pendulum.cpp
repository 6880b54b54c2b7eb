// The pendulum a candidate file declares, and the golden set with its parameters
// (validation/candidate_pendulum.hpp, docs/validating.md).
#include "flipflux/validation/candidate_pendulum.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <utility>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/io/atomic_file.hpp"

namespace flipflux {
namespace {

constexpr std::string_view marker = "pendulum:";

std::string trimmed(const std::string& s) {
    const auto b = s.find_first_not_of(" \t\r");
    if (b == std::string::npos) return "";
    return s.substr(b, s.find_last_not_of(" \t\r") - b + 1);
}

/// The field of model_text named `key`, or nullptr.
std::string* field_of(model_text& p, const std::string& key) {
    const int i = parameter_index(key);
    return i < 0 ? nullptr : &(p.*text_members[static_cast<std::size_t>(i)]);
}

bool same_number(const std::string& a, const std::string& b) {
    return std::isinf(decimal_agreement(a, b, "parameter"));
}

}  // namespace

std::optional<declared_pendulum> read_declared_pendulum(const std::filesystem::path& file) {
    std::istringstream in(read_input_file(file, ""));
    std::optional<declared_pendulum> out;
    std::set<std::string> given;
    std::string line;
    for (int number = 1; std::getline(in, line); ++number) {
        if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 BOM
        const std::string t = trimmed(line);
        if (t.empty()) continue;
        if (t.front() != '#') break;  // the header: the declaration comes before it
        const std::string comment = trimmed(t.substr(1));
        if (comment.rfind(marker, 0) != 0) continue;
        const std::string at = file.string() + ":" + std::to_string(number) + ": pendulum: ";
        if (!out)
            out = declared_pendulum{model_text{}, file.string() + ":" + std::to_string(number)};
        std::string rest = comment.substr(marker.size());
        for (char& c : rest)
            if (c == ',' || c == '\t') c = ' ';
        std::size_t pos = 0;
        while ((pos = rest.find_first_not_of(' ', pos)) != std::string::npos) {
            const std::size_t end = std::min(rest.find(' ', pos), rest.size());
            const std::string item = rest.substr(pos, end - pos);
            pos = end;
            const std::size_t eq = item.find('=');
            if (eq == std::string::npos)
                throw input_error(at + "'" + item + "' is not KEY=VALUE (e.g. m2=3)");
            const std::string key = item.substr(0, eq), value = item.substr(eq + 1);
            std::string* f = field_of(out->parameters, key);
            if (!f)
                throw input_error(at + "'" + key + "' is not a parameter (" +
                                  parameter_name_list() + ")");
            if (!given.insert(key).second) throw input_error(at + key + " is given twice");
            if (!is_decimal_number(value))
                throw input_error(at + key + ": '" + value + "' is not a finite decimal number");
            *f = value;
        }
    }
    if (out && given.empty())
        throw input_error(out->where +
                          ": pendulum: no parameters (e.g. '# pendulum: m2=3 L2=0.7')");
    return out;
}

bool same_parameters(const model_text& a, const model_text& b) {
    for (std::size_t i = 0; i < parameter_count; ++i)
        if (!same_number(resolved_text(a, i), resolved_text(b, i))) return false;
    return true;
}

std::string parameters_text(const model_text& p) {
    std::string out;
    for (std::size_t i = 0; i < parameter_count; ++i)
        out += (out.empty() ? "" : " ") + std::string(parameter_fields[i].name) + "=" +
               resolved_text(p, i);
    return out;
}

std::vector<golden_set> golden_sets(const std::filesystem::path& golden) {
    namespace fs = std::filesystem;
    std::vector<golden_set> sets;
    const auto add = [&sets](const fs::path& dir, std::string name) {
        std::error_code ec;
        if (!fs::is_regular_file(dir / "golden.csv", ec)) return;
        std::string text;
        try {
            text = read_input_file(dir / "provenance.json", "golden");
        } catch (const input_error&) {
            return;  // no readable provenance: not a set that can be picked by its parameters
        }
        const nlohmann::json j = nlohmann::json::parse(text, nullptr, false);
        if (j.is_discarded() || !j.is_object() || !j.contains("parameters") ||
            !j["parameters"].is_object())
            return;  // no parameters: not a set that can be picked by them
        if (j.contains("pendulum") && j["pendulum"].is_string() && name == "egalitarian")
            name = j["pendulum"].get<std::string>();  // --golden DIR naming one set's folder
        golden_set s{name, dir, model_text{}};
        for (const auto& [key, value] : j["parameters"].items()) {
            std::string* f = field_of(s.parameters, key);
            if (!f || !value.is_string() || !is_decimal_number(value.get<std::string>())) return;
            *f = value.get<std::string>();
        }
        sets.push_back(std::move(s));
    };
    add(golden, "egalitarian");
    std::error_code ec;
    std::vector<fs::path> dirs;
    for (const auto& e : fs::directory_iterator(golden, ec))
        if (e.is_directory(ec)) dirs.push_back(e.path());
    std::sort(dirs.begin(), dirs.end());
    for (const auto& d : dirs)
        add(d, d.filename().string());
    return sets;
}

golden_set golden_set_for(const std::filesystem::path& golden, const model_text& parameters,
                          const std::string& who) {
    const std::vector<golden_set> sets = golden_sets(golden);
    for (const golden_set& s : sets)
        if (same_parameters(s.parameters, parameters)) return s;
    std::string known;
    for (const golden_set& s : sets)
        known += (known.empty() ? "" : "; ") + s.name + " (" + parameters_text(s.parameters) + ")";
    throw input_error(who + ": the pendulum " + parameters_text(parameters) +
                      " has no golden set under '" + golden.string() +
                      "' (sets: " + (known.empty() ? "none" : known) + ")");
}

}  // namespace flipflux
