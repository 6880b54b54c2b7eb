// Fuzz target: the command line's option parsing (cli/common.hpp): the one number and integer
// grammar every numeric option gets (apply_number_grammar), on a CLI11 app with options of each
// type the subcommands use, and the one-line escaping of error messages (one_line). The bytes are
// split at NUL into argv. Bad input must end in a CLI11 ParseError or input_error, never a crash,
// a hang or undefined behaviour; an accepted real is finite and normal, an accepted integer came
// from decimal digits; an escaped message has no control character.
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

#include "../src/cli/common.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    std::vector<std::string> args{"flipflux", "x"};
    std::string current;
    for (std::size_t i = 0; i < size && args.size() < 64; ++i) {
        if (data[i] == 0) {
            args.push_back(current);
            current.clear();
        } else {
            current += static_cast<char>(data[i]);
        }
    }
    args.push_back(current);
    for (const std::string& a : args)
        for (const char c : flipflux::cli::one_line(a))
            if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) std::abort();
    CLI::App app{"fuzz"};
    CLI::App* sub = app.add_subcommand("x");
    int threads = 0;
    unsigned long long seed = 0;
    double interval = 0;
    std::vector<double> list;
    std::string text;
    sub->add_option("--threads", threads);
    sub->add_option("--seed", seed);
    sub->add_option("--interval", interval);
    sub->add_option("--list", list);
    sub->add_option("--text", text);
    flipflux::cli::apply_number_grammar(app);
    std::vector<const char*> argv;
    for (const std::string& a : args)
        argv.push_back(a.c_str());
    try {
        app.parse(static_cast<int>(argv.size()), argv.data());
    } catch (const CLI::ParseError&) {
        return 0;
    } catch (const flipflux::input_error&) {
        return 0;
    }
    const auto normal = [](double v) {
        return v == 0 || (std::isfinite(v) && std::fabs(v) >= std::numeric_limits<double>::min());
    };
    if (!normal(interval)) std::abort();
    for (const double v : list)
        if (!normal(v)) std::abort();
    return 0;
}
