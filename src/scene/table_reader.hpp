// Reading a scene's TOML tables (private to src/scene; load.cpp uses it): typed keys, numbers
// kept as decimal text, arms, energy grids, and the leftover keys that are errors. Every failure
// is a scene_error naming the file, the line and the key.
#pragma once

#include <toml++/toml.h>

#include <charconv>
#include <cmath>
#include <limits>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "flipflux/core/decimal.hpp"
#include "flipflux/scene/scene.hpp"
#include "flipflux/study/settings.hpp"

namespace flipflux::scene_toml {

/// The text of the scene being parsed (parse_scene sets it): a float literal's own digits, for the
/// literals the TOML reader rounds to 0 (1e-400).
extern thread_local const std::string* scene_text;

/// A node's literal as written (one line; underscores removed), or "" when not found.
std::string source_text(const toml::node& n);

/// Reads one TOML table, remembering which keys were consumed so that leftovers are errors.
class table_reader {
  public:
    table_reader(const toml::table& table, std::string file, std::string path)
        : table_(table), file_(std::move(file)), path_(std::move(path)) {}

    [[noreturn]] void fail(const toml::node* node, const std::string& key,
                           const std::string& what) const {
        const int line = node != nullptr ? static_cast<int>(node->source().begin.line)
                                         : static_cast<int>(table_.source().begin.line);
        throw scene_error(file_ + ":" + std::to_string(line) + ": " + qualified(key) + ": " + what);
    }
    std::string qualified(const std::string& key) const {
        return path_.empty() ? key : path_ + "." + key;
    }
    int line() const { return static_cast<int>(table_.source().begin.line); }

    const toml::node* get(const std::string& key) {
        used_.insert(key);
        return table_.get(key);
    }

    std::optional<std::string> string(const std::string& key) {
        const toml::node* n = get(key);
        if (n == nullptr) return std::nullopt;
        if (!n->is_string()) fail(n, key, "expected a string, got " + type_name(*n));
        return n->value<std::string>();
    }
    std::optional<bool> boolean(const std::string& key) {
        const toml::node* n = get(key);
        if (n == nullptr) return std::nullopt;
        if (!n->is_boolean()) fail(n, key, "expected true or false, got " + type_name(*n));
        return n->value<bool>();
    }
    std::optional<long long> integer(const std::string& key, long long lo, long long hi) {
        const toml::node* n = get(key);
        if (n == nullptr) return std::nullopt;
        if (!n->is_integer()) fail(n, key, "expected an integer, got " + type_name(*n));
        const long long v = *n->value<long long>();
        if (v < lo || v > hi) {
            fail(n, key,
                 std::to_string(v) + " is out of range [" + std::to_string(lo) + ", " +
                     std::to_string(hi) + "]");
        }
        return v;
    }
    /// A number given as a TOML integer, float or string; returned as validated decimal text.
    std::optional<std::string> number(const std::string& key) {
        const toml::node* n = get(key);
        if (n == nullptr) return std::nullopt;
        return number_text(n, key);
    }
    std::string number_text(const toml::node* n, const std::string& key) const {
        std::string text;
        if (n->is_integer()) {
            text = std::to_string(*n->value<long long>());
        } else if (n->is_floating_point()) {
            const double v = *n->value<double>();
            // a nonzero literal the TOML reader rounded to 0 or below double's normal range
            // (1e-400), or beyond it: refused as the command line refuses it (one grammar)
            if (!(std::abs(v) >= std::numeric_limits<double>::min()) || !std::isfinite(v)) {
                const std::string raw = source_text(*n);
                if (!std::isfinite(v) || (is_decimal_number(raw) && decimal_sign(raw) != 0))
                    fail(n, key,
                         "'" + (raw.empty() ? std::string("?") : raw) + "' " +
                             (std::isfinite(v) ? "underflows double (below its smallest normal "
                                                 "number)"
                                               : "is not a finite number in double"));
            }
            char buf[64];
            const auto r = std::to_chars(buf, buf + sizeof buf, v);  // shortest round trip
            text.assign(buf, r.ptr);
        } else if (n->is_string()) {
            text = *n->value<std::string>();
        } else {
            fail(n, key, "expected a number, got " + type_name(*n));
        }
        if (!is_decimal_number(text)) fail(n, key, "'" + text + "' is not a finite decimal number");
        return text;
    }
    /// The text of a run setting of `kind` (study/settings.hpp parses and checks its value, once
    /// for every surface): an integer a TOML integer, a number as number() reads it, a boolean
    /// true/false, a text a string; another TOML type is refused naming the key.
    std::optional<std::string> setting_text(const std::string& key, setting_kind kind) {
        const toml::node* n = get(key);
        if (n == nullptr) return std::nullopt;
        switch (kind) {
            case setting_kind::integer:
                if (!n->is_integer()) fail(n, key, "expected an integer, got " + type_name(*n));
                return std::to_string(*n->value<long long>());
            case setting_kind::number:
                return number_text(n, key);
            case setting_kind::boolean:
                if (!n->is_boolean()) fail(n, key, "expected true or false, got " + type_name(*n));
                return std::string(*n->value<bool>() ? "true" : "false");
            case setting_kind::text:
                break;
        }
        if (!n->is_string()) fail(n, key, "expected a string, got " + type_name(*n));
        return *n->value<std::string>();
    }
    /// An array of exactly `count` numbers (each as number_text validates it).
    std::optional<std::vector<std::string>> numbers(const std::string& key, std::size_t count) {
        const toml::node* n = get(key);
        if (n == nullptr) return std::nullopt;
        const toml::array* a = n->as_array();
        if (a == nullptr || a->size() != count)
            fail(n, key, "expected an array of " + std::to_string(count) + " numbers");
        std::vector<std::string> out;
        for (const toml::node& e : *a)
            out.push_back(number_text(&e, key));
        return out;
    }
    std::optional<std::vector<std::string>> strings(const std::string& key) {
        const toml::node* n = get(key);
        if (n == nullptr) return std::nullopt;
        const toml::array* a = n->as_array();
        if (a == nullptr) fail(n, key, "expected an array of strings, got " + type_name(*n));
        std::vector<std::string> out;
        for (const toml::node& e : *a) {
            if (!e.is_string())
                fail(&e, key, "expected an array of strings, found " + type_name(e));
            out.push_back(*e.value<std::string>());
        }
        return out;
    }
    /// strings(key), each at most once.
    std::optional<std::vector<std::string>> unique_strings(const std::string& key) {
        auto out = strings(key);
        if (out)
            for (std::size_t i = 0; i < out->size(); ++i)
                for (std::size_t j = 0; j < i; ++j)
                    if ((*out)[i] == (*out)[j])
                        fail(table_.get(key), key, "'" + (*out)[i] + "' is given twice");
        return out;
    }
    std::optional<std::vector<int>> arms(const std::string& key) {
        const toml::node* n = get(key);
        if (n == nullptr) return std::nullopt;
        std::vector<int> out;
        auto one = [&](const toml::node& e) {
            if (!e.is_integer() || (*e.value<long long>() != 1 && *e.value<long long>() != 2)) {
                fail(&e, key, "an arm is 1 or 2");
            }
            const int a = static_cast<int>(*e.value<long long>());
            if (std::find(out.begin(), out.end(), a) != out.end())
                fail(&e, key, "arm " + std::to_string(a) + " is given twice");
            out.push_back(a);
        };
        if (const toml::array* a = n->as_array()) {
            for (const toml::node& e : *a)
                one(e);
            if (out.empty()) fail(n, key, "needs at least one arm");
        } else {
            one(*n);
        }
        return out;
    }
    energy_grid energies(const std::string& key, bool required) {
        const toml::node* n = get(key);
        energy_grid g;
        if (n == nullptr) {
            if (required) fail(nullptr, key, "is required");
            return g;
        }
        if (const toml::array* a = n->as_array()) {
            for (const toml::node& e : *a)
                g.values.push_back(number_text(&e, key));
            if (g.values.empty()) fail(n, key, "needs at least one energy");
            return g;
        }
        if (const toml::table* t = n->as_table()) {
            table_reader r(*t, file_, qualified(key));
            g.from = r.required_number("from");
            g.to = r.required_number("to");
            g.step = r.required_number("step");
            r.finish();
            // the grid rule checked here, where the key's line is known (expanded again by
            // energies_of)
            try {
                (void)decimal_grid(g.from, g.to, g.step, key);
            } catch (const input_error& e) {
                fail(n, key, e.detail());
            }
            return g;
        }
        if (n->is_integer() || n->is_floating_point() || n->is_string()) {
            g.values.push_back(number_text(n, key));
            return g;
        }
        fail(n, key, "expected an energy, an array of energies or {from, to, step}");
    }
    std::string required_number(const std::string& key) {
        auto v = number(key);
        if (!v) fail(nullptr, key, "is required");
        return *v;
    }
    const toml::table* subtable(const std::string& key) {
        const toml::node* n = get(key);
        if (n == nullptr) return nullptr;
        if (!n->is_table()) fail(n, key, "expected a table, got " + type_name(*n));
        return n->as_table();
    }
    /// Every key not consumed is an error.
    void finish() const {
        for (auto&& [k, v] : table_) {
            const std::string key(k.str());
            if (!used_.count(key)) fail(&v, key, "unknown key");
        }
    }

    static std::string type_name(const toml::node& n) {
        switch (n.type()) {
            case toml::node_type::string:
                return "a string";
            case toml::node_type::integer:
                return "an integer";
            case toml::node_type::floating_point:
                return "a float";
            case toml::node_type::boolean:
                return "a boolean";
            case toml::node_type::array:
                return "an array";
            case toml::node_type::table:
                return "a table";
            default:
                return "a date/time";
        }
    }

  private:
    const toml::table& table_;
    std::string file_, path_;
    std::set<std::string> used_;
};

}  // namespace flipflux::scene_toml
