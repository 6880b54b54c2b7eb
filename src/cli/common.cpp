// The command-line layer's shared pieces (common.hpp): the model and precision options, the
// subcommand registry, printing, and the mapping of the library's input fields to option names.
#include "common.hpp"

#include <cstdio>

namespace flipflux::cli {

void add_model_options(CLI::App& app, model_options& o) {
    auto* g = "Model (decimal numbers, parsed in the working precision)";
    app.add_option("--m1", o.m1, "mass of link 1 (> 0)")->group(g)->capture_default_str();
    app.add_option("--m2", o.m2, "mass of link 2 (> 0)")->group(g)->capture_default_str();
    app.add_option("--L1", o.L1, "pivot-to-joint length of link 1 (> 0)")
        ->group(g)
        ->capture_default_str();
    app.add_option("--L2", o.L2, "length of link 2 (> 0)")->group(g)->capture_default_str();
    app.add_option("--a1", o.a1, "pivot to link 1's centre of mass (> 0) [default: L1]")->group(g);
    app.add_option("--a2", o.a2, "joint to link 2's centre of mass (> 0) [default: L2]")->group(g);
    app.add_option("--I1", o.I1, "link 1's moment of inertia about its centre of mass (>= 0)")
        ->group(g)
        ->capture_default_str();
    app.add_option("--I2", o.I2, "link 2's moment of inertia about its centre of mass (>= 0)")
        ->group(g)
        ->capture_default_str();
    app.add_option("--g", o.g, "gravitational acceleration (> 0)")->group(g)->capture_default_str();
}

void add_precision_option(CLI::App& app, precision_option& o) {
    app.add_option("--precision", o.text,
                   "working precision: double, quad (float128) or mp:DIGITS (MPFR, any DIGITS "
                   "from 1 to " +
                       std::to_string(max_mp_digits) + "; computed with " +
                       std::to_string(mp_guard_digits) + " guard digits, printed with DIGITS + 2)")
        ->capture_default_str();
}

std::vector<command>& commands() {
    static std::vector<command> list;
    return list;
}

register_command::register_command(std::function<void(CLI::App&)> setup) {
    commands().push_back({std::move(setup)});
}

int& exit_status() {
    static int status = 0;
    return status;
}

std::filesystem::path find_share_path(const std::filesystem::path& relative) {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (ec) return {};
    for (const std::filesystem::path& root : {exe.parent_path(), exe.parent_path().parent_path()})
        if (std::filesystem::exists(root / "share/flipflux" / relative, ec))
            return root / "share/flipflux" / relative;
    return {};
}

void print(const std::string& text) {
    std::fwrite(text.data(), 1, text.size(), stdout);
    std::fflush(stdout);
}

}  // namespace flipflux::cli

namespace flipflux::cli {

arm parse_arm(const std::string& text, std::string_view option) {
    if (text == "1") return arm::one;
    if (text == "2") return arm::two;
    throw input_error(std::string(option) + ": '" + text + "' is not an arm (expected 1 or 2)");
}

std::string error_text(const input_error& e) {
    const std::string field = e.field();
    if (field.empty() || field.front() == '-' || field.find_first_of(".:/ '") != std::string::npos)
        return e.what();
    std::string option = "--" + field;
    for (char& c : option)
        if (c == '_') c = '-';
    return option + ": " + e.detail();
}

}  // namespace flipflux::cli
