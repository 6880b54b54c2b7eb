// Plugins loaded on first use (core/plugin.hpp).
#include "flipflux/core/plugin.hpp"

#include "flipflux/core/executable.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>

namespace flipflux {
namespace detail {
// cmake: the configured places (generated/plugin_dirs.cpp)
const char* plugin_build_tree();    ///< the build tree (absolute)
const char* plugin_build_dir();     ///< its plugins' folder (absolute)
const char* plugins_from_bindir();  ///< LIBDIR/flipflux relative to BINDIR
const char* plugins_from_libdir();  ///< LIBDIR/flipflux relative to LIBDIR
}  // namespace detail

namespace {

namespace fs = std::filesystem;

/// The file of the object this code is linked into (the executable or libflipflux.so), resolved.
fs::path this_object() {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void*>(&plugin_directories), &info) != 0 && info.dli_fname &&
        info.dli_fname[0] == '/')
        return fs::weakly_canonical(info.dli_fname);
    // the main program: dladdr gives its name as invoked, not its path
    return executable_path();
}

/// Whether `p` lies inside folder `dir`.
bool inside(const fs::path& p, const fs::path& dir) {
    const auto rel = p.lexically_relative(dir);
    return !rel.empty() && *rel.begin() != "..";
}

std::string searched(const std::vector<std::string>& dirs) {
    std::string s;
    for (const auto& d : dirs)
        s += (s.empty() ? "" : ", ") + d;
    return s;
}

}  // namespace

std::vector<std::string> plugin_directories() {
    if (const char* env = std::getenv("FLIPFLUX_PLUGIN_DIR"); env && *env) return {env};
    const fs::path object = this_object();
    const fs::path build = fs::weakly_canonical(detail::plugin_build_tree());
    if (!object.empty() && inside(object, build)) return {detail::plugin_build_dir()};
    const fs::path dir = object.parent_path();
    return {(dir / detail::plugins_from_bindir()).lexically_normal().string(),
            (dir / detail::plugins_from_libdir()).lexically_normal().string()};
}

std::string plugin_file_name(const std::string& name) {
    return "libflipflux_" + name + ".so";
}

void* plugin_symbol(const std::string& name, const char* symbol, bool global) {
    static std::mutex mutex;
    static std::map<std::string, void*> loaded;
    const std::lock_guard<std::mutex> lock(mutex);
    void*& handle = loaded[name];
    if (handle == nullptr) {
        const auto dirs = plugin_directories();
        std::string reason;
        for (const auto& d : dirs) {
            const fs::path file = fs::path(d) / plugin_file_name(name);
            std::error_code ec;
            if (!fs::exists(file, ec)) continue;
            dlerror();
            handle = dlopen(file.c_str(), RTLD_NOW | (global ? RTLD_GLOBAL : RTLD_LOCAL));
            if (handle != nullptr) break;
            const char* why = dlerror();
            reason = file.string() + " does not load: " + (why ? why : "unknown reason");
            break;
        }
        if (handle == nullptr)
            throw plugin_error(!reason.empty() ? "plugin " + name + ": " + reason
                                               : "plugin " + name + ": " + plugin_file_name(name) +
                                                     " not found in " + searched(dirs) +
                                                     " (FLIPFLUX_PLUGIN_DIR names its folder)");
    }
    dlerror();
    void* address = dlsym(handle, symbol);
    if (address == nullptr) {
        const char* why = dlerror();
        throw plugin_error("plugin " + name + ": no symbol " + symbol + " (" +
                           (why ? why : "null") + ")");
    }
    return address;
}

}  // namespace flipflux
