// Files written whole or not at all (io/atomic_file.hpp): a temporary name in the same directory,
// fsync, then rename, so an interrupted run leaves no half-written output.
#include "flipflux/io/atomic_file.hpp"

#include <unistd.h>
#include <cstdio>
#include <stdexcept>

#include "flipflux/core/error.hpp"

namespace flipflux {

void write_file_atomically(const std::filesystem::path& path, const std::string& content) {
    namespace fs = std::filesystem;
    if (path.has_parent_path()) fs::create_directories(path.parent_path());
    const fs::path tmp = path.string() + ".tmp." + std::to_string(::getpid());
    FILE* f = std::fopen(tmp.c_str(), "wb");
    if (f == nullptr) throw std::runtime_error("cannot write '" + path.string() + "'");
    const bool ok = std::fwrite(content.data(), 1, content.size(), f) == content.size() &&
                    std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
    if (std::fclose(f) != 0 || !ok) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write '" + path.string() + "'");
    }
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) {
        std::remove(tmp.c_str());
        throw std::runtime_error("cannot write '" + path.string() + "': " + ec.message());
    }
}

std::string csv_field(const std::string& text) {
    if (text.find_first_of(",\"\n") == std::string::npos) return text;
    std::string out = "\"";
    for (char c : text) {
        if (c == '"') out += '"';
        out += c;
    }
    return out + "\"";
}

void check_output_file(const std::filesystem::path& path, const std::string& field) {
    namespace fs = std::filesystem;
    const std::string where = "'" + path.string() + "' ";
    std::error_code ec;
    if (path.empty() || fs::is_directory(path, ec))
        throw input_error::about(field, where + "is a directory, not a file");
    const fs::path dir = path.has_parent_path() ? path.parent_path() : fs::path(".");
    fs::create_directories(dir, ec);
    if (ec || !fs::is_directory(dir))
        throw input_error::about(field, where + "cannot be written: its folder '" + dir.string() +
                                            "' cannot be created" +
                                            (ec ? " (" + ec.message() + ")" : std::string()));
    const fs::path probe = path.string() + ".probe." + std::to_string(::getpid());
    FILE* f = std::fopen(probe.c_str(), "wb");
    if (f == nullptr) throw input_error::about(field, where + "cannot be written");
    std::fclose(f);
    std::remove(probe.c_str());
}

}  // namespace flipflux
