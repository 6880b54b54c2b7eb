// flipflux accuracy [--out FILE] [--quantities a,b]: digits achieved against time per evaluation
// for every registered quantity, method and precision, as Markdown (docs/accuracy.md).
#include <cmath>

#include "common.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/output/accuracy_markdown.hpp"
#include "flipflux/quantities/accuracy.hpp"
#include "flipflux/quantities/golden.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux::cli {
namespace {

struct accuracy_state {
    std::string out = "docs/accuracy.md";
    std::string quantities;
    std::string precisions = "double,quad,mp:50,mp:100";
    double min_seconds = 0.2;
    double max_seconds = 120;
    int threads = 1;
};

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<accuracy_state>();
    CLI::App* sub =
        app.add_subcommand("accuracy",
                           "Measure digits achieved and time per evaluation of every registered "
                           "quantity, method and precision; write a Markdown report");
    sub->add_option("--out", s->out, "the report (Markdown), written atomically")
        ->capture_default_str();
    sub->add_option("--quantities", s->quantities,
                    "comma-separated quantity names (default: every registered quantity)");
    sub->add_option("--precisions", s->precisions,
                    "comma-separated precisions (double, quad, mp:DIGITS), the report's columns")
        ->capture_default_str();
    sub->add_option("--min-seconds", s->min_seconds, "timing budget per cell")
        ->capture_default_str();
    sub->add_option("--max-seconds", s->max_seconds,
                    "a method whose evaluation takes longer in one precision (measured, or "
                    "estimated from the lower precisions) is not measured in it or higher ones")
        ->capture_default_str();
    sub->add_option("--threads", s->threads,
                    "cells of one precision measured concurrently (each timed by its own "
                    "thread's CPU clock)")
        ->capture_default_str();
    sub->callback([s] {
        accuracy_options options;
        std::stringstream in(s->quantities);
        std::string item;
        while (std::getline(in, item, ',')) {
            if (item.empty()) continue;
            find_quantity(item);  // input_error naming an unknown quantity
            options.quantities.push_back(item);
        }
        options.precisions = parse_precision_list(s->precisions, "--precisions");
        if (!(s->min_seconds >= 0) || !(s->min_seconds <= max_min_seconds)) {
            throw input_error("--min-seconds: '" + to_decimal(s->min_seconds) +
                              "' is invalid (must be in [0, " + to_decimal(max_min_seconds) +
                              "] seconds per cell)");
        }
        options.min_seconds = s->min_seconds;
        if (!(s->max_seconds > 0)) {
            throw input_error("--max-seconds: '" + to_decimal(s->max_seconds) + "' must be > 0");
        }
        options.max_seconds = s->max_seconds;
        if (s->threads < 1) {
            throw input_error("--threads: '" + std::to_string(s->threads) + "' must be >= 1");
        }
        options.threads = checked_threads(static_cast<std::uint64_t>(s->threads), "--threads");
        options.progress = [](const std::string& line) {
            std::fprintf(stderr, "accuracy: %s\n", line.c_str());
        };
        std::string command = "flipflux accuracy --out " + s->out;
        if (!s->quantities.empty()) command += " --quantities " + s->quantities;
        if (s->precisions != "double,quad,mp:50,mp:100")
            command += " --precisions " + s->precisions;
        if (s->max_seconds != 120) command += " --max-seconds " + to_decimal(s->max_seconds);
        check_output_file(s->out, "--out");  // before minutes of measuring
        const auto entries = measure_accuracy(options);
        write_file_atomically(s->out,
                              accuracy_markdown(entries, options, command, cli_command_words()));
        print(json{{"entries", entries.size()}, {"out", s->out}}.dump(2) + "\n");
    });
});

}  // namespace
}  // namespace flipflux::cli
