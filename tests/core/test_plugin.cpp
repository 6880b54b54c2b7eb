// Plugins loaded on first use (core/plugin.hpp): where they are looked for, what a missing or
// corrupt one says, and that the command-line tool links neither Open MPI nor Ceres' stack (the
// start-up cost they would add to every command, docs/scale.md).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

#include "flipflux/core/plugin.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

namespace fs = std::filesystem;

/// $FLIPFLUX_PLUGIN_DIR set for one scope.
class plugin_dir_override {
  public:
    explicit plugin_dir_override(const std::string& dir) {
        if (const char* old = std::getenv("FLIPFLUX_PLUGIN_DIR")) old_ = old, had_ = true;
        setenv("FLIPFLUX_PLUGIN_DIR", dir.c_str(), 1);
    }
    ~plugin_dir_override() {
        if (had_)
            setenv("FLIPFLUX_PLUGIN_DIR", old_.c_str(), 1);
        else
            unsetenv("FLIPFLUX_PLUGIN_DIR");
    }

  private:
    std::string old_;
    bool had_ = false;
};

std::string caught(const std::string& name, const char* symbol) {
    try {
        plugin_symbol(name, symbol);
    } catch (const plugin_error& e) {
        return e.what();
    }
    return "";
}

// An empty folder of its own, removed with everything in it when the test ends.
class empty_dir {
  public:
    explicit empty_dir(const std::string& tag)
        : path_(fs::path(::testing::TempDir()) /
                ("flipflux_plugins_" + tag + "_" + std::to_string(getpid()))) {
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~empty_dir() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    empty_dir(const empty_dir&) = delete;
    empty_dir& operator=(const empty_dir&) = delete;
    const fs::path& path() const { return path_; }

  private:
    fs::path path_;
};

TEST(Plugins, BuildTreeObjectsLookInTheBuildTreesPluginFolder) {
    if (std::getenv("FLIPFLUX_PLUGIN_DIR")) GTEST_SKIP() << "FLIPFLUX_PLUGIN_DIR is set";
    // the test program is in the build tree, beside the command-line tool
    const fs::path expected = fs::path(FLIPFLUX_EXE).parent_path() / "plugins";
    const auto dirs = plugin_directories();
    ASSERT_EQ(dirs.size(), 1u);
    EXPECT_EQ(fs::weakly_canonical(dirs[0]), fs::weakly_canonical(expected));
    for (const char* name : {"ceres", "mpi"})
        EXPECT_TRUE(fs::exists(expected / plugin_file_name(name))) << name;
}

TEST(Plugins, TheEnvironmentVariableIsTheOnlyPlaceWhenSet) {
    const empty_dir scratch("env");
    const fs::path& d = scratch.path();
    const plugin_dir_override o(d.string());
    ASSERT_EQ(plugin_directories(), std::vector<std::string>{d.string()});
    const std::string e = caught("nosuch", "anything");
    EXPECT_NE(e.find("libflipflux_nosuch.so not found in " + d.string()), std::string::npos) << e;
    EXPECT_NE(e.find("FLIPFLUX_PLUGIN_DIR"), std::string::npos) << e;
    EXPECT_EQ(e.find('\n'), std::string::npos) << e;
}

TEST(Plugins, ACorruptPluginIsNamedWithTheLoadersReason) {
    const empty_dir scratch("corrupt");
    const fs::path& d = scratch.path();
    std::ofstream(d / plugin_file_name("broken")) << "not an ELF object\n";
    const plugin_dir_override o(d.string());
    const std::string e = caught("broken", "anything");
    EXPECT_NE(e.find((d / "libflipflux_broken.so").string() + " does not load: "),
              std::string::npos)
        << e;
}

TEST(Plugins, AMissingSymbolIsNamed) {
    if (std::getenv("FLIPFLUX_PLUGIN_DIR")) GTEST_SKIP() << "FLIPFLUX_PLUGIN_DIR is set";
    const std::string e = caught("ceres", "flipflux_no_such_symbol");
    EXPECT_NE(e.find("plugin ceres: no symbol flipflux_no_such_symbol"), std::string::npos) << e;
    // the real one is there
    EXPECT_NE(plugin_symbol("ceres", "flipflux_least_squares_solve"), nullptr);
}

// The tool's dynamic section: Open MPI and Ceres' libraries (glog, SuiteSparse, LAPACK, BLAS) are
// the plugins' business, not every command's.
TEST(Plugins, TheToolLinksNeitherOpenMpiNorCeresStack) {
    if (std::system("command -v readelf >/dev/null 2>&1") != 0) GTEST_SKIP() << "no readelf";
    FILE* pipe = popen(("readelf -d " + std::string(FLIPFLUX_EXE)).c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string text;
    char buf[4096];
    for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;)
        text.append(buf, n);
    ASSERT_EQ(pclose(pipe), 0);
    ASSERT_NE(text.find("(NEEDED)"), std::string::npos) << text;
    for (const char* lib : {"libmpi", "libopen-", "libglog", "libcholmod", "liblapack", "libblas",
                            "libf77blas", "libcxsparse", "libgflags"})
        EXPECT_EQ(text.find(std::string("[") + lib), std::string::npos) << lib << "\n" << text;
}

TEST(Plugins, CommandsThatNeedAMissingPluginSayWhichInOneLine) {
    const empty_dir scratch("cli");
    const fs::path& d = scratch.path();
    const plugin_dir_override o(d.string());
    // the periodic shooting needs Ceres
    const auto r = run_flipflux("orbit --energy 3 --method periodic --precision double");
    EXPECT_EQ(r.status, 1) << r.out << r.err;
    EXPECT_EQ(
        r.err.rfind(
            "flipflux: error: plugin ceres: libflipflux_ceres.so not found in " + d.string(), 0),
        0u)
        << r.err;
    EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << r.err;
    // the symmetric one does not
    const auto s = run_flipflux("orbit --energy 3 --method symmetric --precision double");
    EXPECT_EQ(s.status, 0) << s.err;
    // simulate under mpirun needs Open MPI's plugin (the launcher's variables faked)
    setenv("OMPI_COMM_WORLD_SIZE", "1", 1);
    const auto m = run_flipflux("simulate --energy 4 --trajectories 2 --time 1 --no-chaos");
    unsetenv("OMPI_COMM_WORLD_SIZE");
    EXPECT_EQ(m.status, 1) << m.out << m.err;
    EXPECT_NE(m.err.find("libflipflux_mpi.so not found in " + d.string()), std::string::npos)
        << m.err;
}

}  // namespace
}  // namespace flipflux::test
