// The command-line layer's shared pieces (common.hpp): the model and precision options, the
// subcommand registry, printing, and the mapping of the library's input fields to option names.
#include "common.hpp"

#include "flipflux/core/executable.hpp"
#include "flipflux/study/settings.hpp"

#include <algorithm>
#include <array>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

namespace flipflux::cli {

void add_model_options(CLI::App& app, model_options& o) {
    auto* g = "Model (decimal numbers, parsed in the working precision)";
    for (std::size_t i = 0; i < parameter_count; ++i) {
        const parameter_field& f = parameter_fields[i];
        const std::string help =
            std::string(f.help) +
            (f.defaults_to >= 0
                 ? " [default: " +
                       std::string(parameter_fields[static_cast<std::size_t>(f.defaults_to)].name) +
                       "]"
                 : "");
        auto* option =
            app.add_option("--" + std::string(f.name), o.*text_members[i], help)->group(g);
        if (f.defaults_to < 0) option->capture_default_str();
    }
}

void add_precision_option(CLI::App& app, precision_option& o) {
    app.add_option("--precision", o.text,
                   "working precision: double, quad (float128) or mp:DIGITS (MPFR, any DIGITS "
                   "from 1 to " +
                       std::to_string(max_mp_digits) + "; computed with " +
                       std::to_string(mp_guard_digits) + " guard digits, printed with DIGITS + 2)")
        ->capture_default_str();
}

void add_time_bound_option(CLI::App& app, time_bound_option& o) {
    app.add_option("--max-seconds", o.max_seconds,
                   "CPU seconds the evaluation may take (> 0): an mp:N request of more than " +
                       std::to_string(pilot_min_digits) +
                       " digits is first estimated from two smaller pilot runs and refused "
                       "when the estimate is larger; the run itself is abandoned at the bound")
        ->capture_default_str();
}

namespace detail {

void estimate_cost(const precision& p, const time_bound_option& bound,
                   const std::function<void(const precision&)>& pilot) {
    if (!(bound.max_seconds > 0))
        throw input_error("--max-seconds: '" + to_decimal(bound.max_seconds) +
                          "' is invalid (must be > 0)");
    if (p.kind != real_kind::mp || p.digits <= pilot_min_digits) return;
    // pilots at N / 4^k, from the smallest of at least 30 digits up to N / 4: after each, the
    // cost at N is extrapolated from the last two, and the request refused as soon as that
    // exceeds the bound (a pilot then never costs more than the bound's fraction it predicts)
    std::vector<int> ladder;
    for (int d = p.digits / 4; d >= 30; d /= 4)
        ladder.insert(ladder.begin(), d);
    if (ladder.size() < 2) return;
    std::vector<double> seconds;
    double estimate = 0;
    std::string how;
    for (std::size_t k = 0; k < ladder.size(); ++k) {
        const double start = thread_cpu_seconds();
        try {
            const cpu_budget_scope budget(bound.max_seconds);
            pilot(precision{real_kind::mp, ladder[k]});
        } catch (const budget_exceeded&) {
            throw input_error("--precision: mp:" + std::to_string(p.digits) +
                              " would take far more than --max-seconds " +
                              to_decimal(bound.max_seconds, 6) + " CPU seconds: its pilot at mp:" +
                              std::to_string(ladder[k]) + " alone did not finish in them");
        }
        seconds.push_back(thread_cpu_seconds() - start);
        // the least the request can cost: no computation at N digits grows slower than N^1.5
        // from this pilot (the clamp's floor) — refused at once when even that is too much,
        // before a costlier pilot is run (eval period mp:5000: mp:78 took 3 s, and mp:312 would
        // take 65 s more)
        // (from a pilot of 0.5 s or more, in working digits: a fixed cost of a few milliseconds
        // extrapolated from mp:97 to mp:100000 would refuse what could finish)
        const double least =
            seconds[k] * std::pow(static_cast<double>(mp_working_digits(p.digits)) /
                                      mp_working_digits(ladder[k]),
                                  1.5);
        if (seconds[k] >= 0.5 && least > bound.max_seconds)
            throw input_error("--precision: mp:" + std::to_string(p.digits) +
                              " would take at least " + to_decimal(least, 2) +
                              " CPU seconds (mp:" + std::to_string(ladder[k]) + " took " +
                              to_decimal(seconds[k], 2) + " s; the cost grows at least as N^1.5)" +
                              ", more than --max-seconds " + to_decimal(bound.max_seconds, 6) +
                              ": raise --max-seconds or lower the precision");
        if (k == 0) continue;
        // the CPU time's growth with the digits between the last two pilots (MPFR's products
        // grow as N^1.6, a series' terms or an integrator's steps as N), clamped to [1.5, 4]
        // and taken half a power higher: the growth itself grows with N (mp:2500 of omega took
        // 396 s where the unpadded N^2.4 from mp:156 and mp:625 predicted 200 s); below 0.05 s
        // the pilots' clock is too coarse to tell, and 3 is assumed
        const double t0 = seconds[k - 1], t1 = seconds[k];
        double growth = 3;
        if (t0 > 0.05 && t1 > t0)
            growth = std::clamp(std::log(t1 / t0) / std::log(4.0), 1.5, 4.0) + 0.5;
        estimate = t1 * std::pow(static_cast<double>(p.digits) / ladder[k], growth);
        how = "from pilots at mp:" + std::to_string(ladder[k - 1]) + " (" + to_decimal(t0, 2) +
              " s) and mp:" + std::to_string(ladder[k]) + " (" + to_decimal(t1, 2) +
              " s), growth N^" + to_decimal(growth, 2);
        if (estimate > bound.max_seconds)
            throw input_error("--precision: mp:" + std::to_string(p.digits) + " would take about " +
                              to_decimal(estimate, 2) + " CPU seconds (" + how +
                              "), more than --max-seconds " + to_decimal(bound.max_seconds, 6) +
                              ": raise --max-seconds or lower the precision");
    }
    if (estimate > 5)
        std::fprintf(stderr, "flipflux: note: mp:%d expected to take about %s CPU seconds (%s)\n",
                     p.digits, to_decimal(estimate, 2).c_str(), how.c_str());
}

void budget_spent(const time_bound_option& bound, const precision& p) {
    throw input_error("--max-seconds: the evaluation in " + precision_name(p) +
                      " did not finish in its " + to_decimal(bound.max_seconds, 6) +
                      (p.kind == real_kind::double_
                           ? std::string(" CPU seconds (raise --max-seconds)")
                           : std::string(" CPU seconds (raise --max-seconds, or lower the "
                                         "precision)")));
}

}  // namespace detail

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

std::atomic<int>& stop_signal() {
    static std::atomic<int> signal{0};
    return signal;
}

namespace {
extern "C" void on_stop_signal(int signal) {
    stop_signal().store(signal);
}
}  // namespace

signal_guard::signal_guard() {
    stop_signal().store(0);
    struct sigaction sa {};
    sa.sa_handler = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
}

signal_guard::~signal_guard() {
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
}

std::filesystem::path find_share_path(const std::filesystem::path& relative) {
    const std::filesystem::path exe = executable_path();
    if (exe.empty()) return {};
    std::error_code ec;
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
    return flipflux::parse_arm(text, std::string(option));
}

namespace {

// Decimal digits, an optional sign (no '-' for an unsigned option); leading zeros are dropped
// here, so that CLI11 (which reads "010" as octal) sees the decimal the user meant.
std::string integer_grammar(std::string& text, bool is_unsigned) {
    const bool sign = !text.empty() && (text[0] == '+' || text[0] == '-');
    const std::size_t start = sign ? 1 : 0;
    bool ok = text.size() > start && !(is_unsigned && text[0] == '-');
    for (std::size_t i = start; i < text.size(); ++i)
        ok = ok && text[i] >= '0' && text[i] <= '9';
    if (!ok)
        return "'" + text + "' is not a decimal integer (digits only" +
               (is_unsigned ? ", no sign" : "") + ": no hexadecimal, exponent or fraction)";
    const std::size_t first = std::min(text.find_first_not_of('0', start), text.size() - 1);
    text = (text[0] == '-' ? "-" : "") + text.substr(first);
    return {};
}

std::string number_grammar(std::string& text) {
    // ".5" and "-.5" (which CLI11 read before) are "0.5" and "-0.5"
    const std::size_t at = !text.empty() && (text[0] == '+' || text[0] == '-') ? 1 : 0;
    if (text.size() > at + 1 && text[at] == '.' && text[at + 1] >= '0' && text[at + 1] <= '9')
        text.insert(at, "0");
    if (!is_decimal_number(text)) return "'" + text + "' is not a finite decimal number";
    errno = 0;
    const double v = std::strtod(text.c_str(), nullptr);
    if (!std::isfinite(v)) return "'" + text + "' overflows double (largest 1.79e308)";
    if (decimal_sign(text) != 0 && !(std::fabs(v) >= std::numeric_limits<double>::min()))
        return "'" + text + "' underflows double (its smallest normal number is 2.2e-308)";
    return {};
}

void add_grammar(CLI::App& app) {
    for (CLI::Option* o : app.get_options()) {
        const std::string type = o->get_type_name();
        if (type.rfind("INT", 0) == 0 || type.rfind("UINT", 0) == 0) {
            const bool is_unsigned = type.rfind("UINT", 0) == 0;
            o->transform(
                CLI::Validator(
                    [is_unsigned](std::string& t) { return integer_grammar(t, is_unsigned); }, ""),
                "integer grammar");
        } else if (type.rfind("FLOAT", 0) == 0)
            o->transform(CLI::Validator(number_grammar, ""), "number grammar");
    }
    for (CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; }))
        add_grammar(*sub);
}

}  // namespace

void apply_number_grammar(CLI::App& app) {
    add_grammar(app);
}

std::string one_line(const std::string& text) {
    std::string out;
    out.reserve(text.size());
    for (std::size_t i = 0; i < text.size(); ++i) {
        const char ch = text[i];
        const auto c = static_cast<unsigned char>(ch);
        const auto next = i + 1 < text.size() ? static_cast<unsigned char>(text[i + 1]) : 0;
        if (c == 0xc2 && next >= 0x80 && next <= 0x9f) {  // a C1 control (U+0080..U+009F)
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\u%04x", next);
            out += hex;
            ++i;
        } else if (c >= 0x20 && c != 0x7f) {
            out += ch;
        } else if (c == '\n') {
            out += "\\n";
        } else if (c == '\t') {
            out += "\\t";
        } else if (c == '\r') {
            out += "\\r";
        } else {
            char hex[8];
            std::snprintf(hex, sizeof hex, "\\x%02x", c);
            out += hex;
        }
    }
    return out;
}

std::string option_name(std::string_view field) {
    std::string option = "--" + std::string(field);
    for (char& c : option)
        if (c == '_') c = '-';
    return option;
}

command_words cli_command_words() {
    return {"flipflux run",     "flipflux eval --help", "flipflux --m1 ... --g",
            "golden --certify", "eval --certify",       {"--threads", "run --threads"}};
}

std::string error_text(const input_error& e) {
    const std::string field = e.field();
    if (field.empty() || field.front() == '-' || field.find_first_of(".:/ '") != std::string::npos)
        return one_line(e.what());
    return one_line(option_name(field) + ": " + e.detail());
}

}  // namespace flipflux::cli
