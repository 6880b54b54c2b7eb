// The scene reader's source text (src/scene/table_reader.hpp).
#include "table_reader.hpp"

namespace flipflux::scene_toml {

// The text of the scene being parsed (parse_scene sets it): a float literal's own digits, for the
// literals the TOML reader rounds to 0 (1e-400).
thread_local const std::string* scene_text = nullptr;

/// A node's literal as written (one line; underscores removed), or "" when not found.
std::string source_text(const toml::node& n) {
    const toml::source_region& r = n.source();
    if (scene_text == nullptr || r.begin.line != r.end.line || r.begin.line == 0) return {};
    std::size_t at = 0;
    for (toml::source_index line = 1; line < r.begin.line; ++line) {
        at = scene_text->find('\n', at);
        if (at == std::string::npos) return {};
        ++at;
    }
    const std::size_t from = at + r.begin.column - 1, to = at + r.end.column - 1;
    if (to <= from || to > scene_text->size()) return {};
    std::string out;
    for (const char c : scene_text->substr(from, to - from))
        if (c != '_') out += c;
    return out;
}

}  // namespace flipflux::scene_toml
