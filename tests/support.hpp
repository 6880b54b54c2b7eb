// Shared test support: the typed-test list, precision-derived tolerances, running the CLI.
#pragma once

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>
#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/real.hpp"

namespace flipflux::test {

using real_types = ::testing::Types<double, quad, mp50, mp100>;

/// Human-readable names for typed tests.
struct real_name {
    template <class T>
    static std::string GetName(int) {
        std::string n = precision_name<T>();
        for (char& c : n)
            if (c == ':') c = '_';
        return n;
    }
};

// conversion between precisions and relative errors (core/convert.hpp), also as test::...
using flipflux::convert;
using flipflux::relative_error;

template <class Real>
Real eps() {
    return std::numeric_limits<Real>::epsilon();
}

/// Reproducible random reals in [lo, hi], generated in double (exactly representable in all
/// types, so every precision sees the same inputs).
class random_reals {
  public:
    explicit random_reals(unsigned seed) : gen_(seed) {}
    double operator()(double lo, double hi) {
        return std::uniform_real_distribution<>(lo, hi)(gen_);
    }

  private:
    std::mt19937_64 gen_;
};

struct command_result {
    int status = -1;
    std::string out, err;
};

/// A whole file as text ("" when it cannot be read).
inline std::string read_text(const std::filesystem::path& file) {
    std::ifstream in(file, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// Runs `flipflux <args>` (args are passed through the shell) and captures everything.
inline command_result run_flipflux(const std::string& args) {
    static int counter = 0;  // unique per process and call: tests run in parallel under ctest -j
    const std::string err_file = ::testing::TempDir() + "flipflux_stderr_" +
                                 std::to_string(getpid()) + "_" + std::to_string(counter++) +
                                 ".txt";
    const std::string cmd = std::string(FLIPFLUX_EXE) + " " + args + " 2>" + err_file;
    command_result r;
    FILE* pipe = popen(cmd.c_str(), "r");
    if (pipe == nullptr) return r;
    std::array<char, 4096> buf{};
    std::size_t n;
    while ((n = std::fread(buf.data(), 1, buf.size(), pipe)) > 0)
        r.out.append(buf.data(), n);
    const int status = pclose(pipe);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    if (FILE* f = std::fopen(err_file.c_str(), "r")) {
        while ((n = std::fread(buf.data(), 1, buf.size(), f)) > 0)
            r.err.append(buf.data(), n);
        std::fclose(f);
    }
    std::remove(err_file.c_str());
    return r;
}

}  // namespace flipflux::test
