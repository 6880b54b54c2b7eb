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
#include <tuple>

#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/real.hpp"

namespace flipflux::test {

namespace list_detail {
template <class Tuple>
struct gtest_types;
template <class... Ts>
struct gtest_types<std::tuple<Ts...>> {
    using type = ::testing::Types<Ts...>;
};
}  // namespace list_detail

/// Every supported real type (core/real.hpp's list), for typed tests.
using real_types = list_detail::gtest_types<flipflux::real_types>::type;

/// The precision typed tests run mp in (tolerances follow from its epsilon).
inline constexpr int mp_test_digits = 50;

/// The precision a typed test runs Real in: the fixed types' own, mp:mp_test_digits for mp.
template <class Real>
precision test_precision() {
    if constexpr (has_variable_precision_v<Real>)
        return mp_precision(mp_test_digits);
    else
        return precision_of<Real>();
}

/// The fixture of typed tests: Real's test precision is the working precision throughout.
template <class Real>
class real_test : public ::testing::Test {
    precision_scope scope_{test_precision<Real>()};
};

/// Human-readable names for typed tests.
struct real_name {
    template <class T>
    static std::string GetName(int) {
        std::string n = precision_name(test_precision<T>());
        for (char& c : n)
            if (c == ':') c = '_';
        return n;
    }
};

/// A fixed 120-digit MPFR type for references that tests compute with Boost.Math directly. Not a
/// flipflux real type (no library routine is instantiated for it) and independent of mp's
/// working precision.
using reference_real = boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<120>,
                                                     boost::multiprecision::et_off>;

/// x in reference_real, through every digit of x.
template <class Real>
reference_real to_reference(const Real& x) {
    return reference_real(to_decimal(x, full_digits(x) + 2));
}

/// f() evaluated with mp:digits the working precision (a nested scope: values of another mp
/// precision must not be used inside f except through their decimal text).
template <class F>
auto in_mp(int digits, F&& f) {
    const precision_scope scope(mp_precision(digits));
    return f();
}

// conversion between precisions and relative errors (core/convert.hpp), also as test::...
using flipflux::convert;
using flipflux::correct_digits;
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
