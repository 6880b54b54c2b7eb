// One table per enumeration: its values and their stable names (used by the CLI, scenes, golden
// data, JSON reports and docs), from which to_string, parsing and the list of names are
// generated. An enumeration E gets names by specialising enum_table<E> next to its declaration:
//
//     template <> struct enum_table<rate_route> {
//         static constexpr std::string_view noun = "a rate route";
//         static constexpr std::array<std::pair<rate_route, std::string_view>, 2> entries{
//             {{rate_route::closed_form, "closed-form"}, {rate_route::quadrature, "quadrature"}}};
//     };
#pragma once

#include <array>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "flipflux/core/error.hpp"

namespace flipflux {

/// A name that becomes one path component (an ensemble's files, a golden set's folder): 1 to
/// `max_size` letters, digits, '.', '_' or '-', not starting with '.': nothing can lead outside
/// the folder it is put in.
inline bool is_plain_name(std::string_view name, std::size_t max_size = 100) {
    for (char c : name)
        if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
              c == '.' || c == '_' || c == '-'))
            return false;
    return !name.empty() && name.size() <= max_size && name.front() != '.';
}

template <class E>
struct enum_table;

/// An enumeration with a table of names.
template <class E>
concept named_enum = requires {
    enum_table<E>::entries;
    enum_table<E>::noun;
};

/// The name of e.
template <named_enum E>
std::string to_string(E e) {
    for (const auto& [value, name] : enum_table<E>::entries)
        if (value == e) return std::string(name);
    throw std::logic_error("to_string: a value of " + std::string(enum_table<E>::noun) +
                           " without a name");
}

/// Every name, in the table's order (for a registry, the first is the default).
template <named_enum E>
std::vector<std::string> names_of() {
    std::vector<std::string> out;
    for (const auto& entry : enum_table<E>::entries)
        out.emplace_back(entry.second);
    return out;
}

/// "a, b, c": the names for an error message or a help text.
template <named_enum E>
std::string name_list() {
    std::string out;
    for (const auto& entry : enum_table<E>::entries)
        out += (out.empty() ? "" : ", ") + std::string(entry.second);
    return out;
}

/// The value named `text`; input_error about `field` naming the known names otherwise.
template <named_enum E>
E parse_name(std::string_view text, const std::string& field) {
    for (const auto& [value, name] : enum_table<E>::entries)
        if (name == text) return value;
    throw input_error::about(field, "'" + std::string(text) + "' is not " +
                                        std::string(enum_table<E>::noun) + " (" + name_list<E>() +
                                        ")");
}

}  // namespace flipflux
