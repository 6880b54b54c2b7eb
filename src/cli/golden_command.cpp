// flipflux golden [--out DIR] [--quantities a,b] [--jobs N] [--max-rows N] [--progress] [--merge]
// [--certify] [--certify-existing]:
// reference data for every registered quantity on the golden energy grid, with certified digits,
// written atomically to DIR/golden.csv and DIR/provenance.json (see
// include/flipflux/quantities/golden.hpp).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/core/names.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/output/golden_files.hpp"
#include "flipflux/quantities/golden.hpp"
#include "flipflux/quantities/registry.hpp"
#include "progress.hpp"
#include "simulate_request.hpp"

namespace flipflux::cli {
namespace {

struct golden_state {
    std::string out = "data/golden";
    std::string quantities;
    int jobs = 2;
    std::string max_rows = "0";
    bool progress = false;
    precision_option precision{"mp:100"};
    model_options model;
    std::string pendulum;
    bool merge = false;
    bool certify = false;
    bool certify_existing = false;
    double max_seconds = 0;
};

/// A file's text, or input_error naming it.
std::string read_text(const std::string& path, const std::string& option) {
    return read_input_file(path, option);
}

/// The model options as the command line gives them back (for the provenance's command).
std::string model_flags(const model_options& m) {
    std::string out;
    for (std::size_t i = 0; i < parameter_count; ++i)
        if (m.*text_members[i] != parameter_fields[i].default_text)
            out += " --" + std::string(parameter_fields[i].name) + " " + m.*text_members[i];
    return out;
}

std::vector<std::string> split_list(const std::string& text) {
    std::vector<std::string> items;
    std::stringstream in(text);
    std::string item;
    while (std::getline(in, item, ','))
        if (!item.empty()) items.push_back(item);
    return items;
}

/// The options of the command line, checked (input_error naming the option).
golden_options checked_options(const golden_state& s) {
    golden_options options;
    options.model = s.model;
    (void)make_model<double>(s.model);  // input_error naming a bad parameter
    if (s.pendulum.empty() && !s.model.is_default())
        throw input_error(
            "--pendulum: a name is required for a pendulum other than the "
            "paper's (it names the golden set)");
    options.pendulum = s.pendulum.empty() ? "egalitarian" : s.pendulum;
    if (!is_plain_name(options.pendulum))
        throw input_error("--pendulum: '" + options.pendulum +
                          "' is not a plain name (one path component: letters, digits, '.', '_' or "
                          "'-', not starting with '.')");
    options.value_precision = parse_precision(s.precision.text);
    (void)golden_check_precision(options.value_precision);  // input_error when too low
    options.quantities = split_list(s.quantities);
    for (const std::string& name : options.quantities)
        find_quantity(name);  // input_error naming an unknown quantity
    if (s.jobs < 1) {
        throw input_error("--jobs: '" + std::to_string(s.jobs) + "' must be >= 1");
    }
    options.jobs = checked_threads(static_cast<std::uint64_t>(s.jobs), "--jobs");
    // parsed here, not by CLI11: its unsigned conversion wraps '-1' to 2^64 - 1 (all rows: a
    // run of hours where a refusal belongs)
    options.max_rows = parse_unsigned(s.max_rows, "--max-rows", false);
    options.certify = s.certify;
    if (!(s.max_seconds >= 0) || !std::isfinite(s.max_seconds))
        throw input_error("--max-seconds: '" + to_decimal(s.max_seconds) +
                          "' must be finite and >= 0 (0: no bound)");
    options.max_seconds = s.max_seconds;
    return options;
}

/// The command line as the provenance records it (the options that differ from the defaults).
std::string provenance_command(const golden_state& s, std::size_t max_rows) {
    std::string command = "flipflux golden --out " + s.out + " --jobs " + std::to_string(s.jobs);
    if (!s.quantities.empty()) command += " --quantities " + s.quantities;
    if (max_rows > 0) command += " --max-rows " + std::to_string(max_rows);
    if (s.precision.text != "mp:100") command += " --precision " + s.precision.text;
    if (!s.pendulum.empty()) command += " --pendulum " + s.pendulum;
    command += model_flags(s.model);
    if (s.merge) command += " --merge";
    if (s.certify) command += " --certify";
    if (s.certify_existing) command += " --certify-existing";
    if (s.max_seconds > 0) command += " --max-seconds " + to_decimal(s.max_seconds);
    return command;
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<golden_state>();
    CLI::App* sub = app.add_subcommand(
        "golden",
        "Write golden reference data (values in --precision mp:N certified against mp:(N/2) and "
        "an independent method) for every registered quantity on the golden energy grid");
    sub->add_option("--out", s->out, "output directory (golden.csv, provenance.json)")
        ->capture_default_str();
    sub->add_option("--quantities", s->quantities,
                    "comma-separated quantity names (default: every registered quantity)");
    sub->add_option("--jobs", s->jobs, "threads")->capture_default_str();
    sub->add_option("--max-rows", s->max_rows, "an evenly spread sample of at most N rows (0: all)")
        ->capture_default_str();
    sub->add_flag("--progress", s->progress,
                  "progress bar on stderr (default: only when stderr is a terminal)");
    add_precision_option(*sub, s->precision);
    add_model_options(*sub, s->model);
    sub->add_option("--pendulum", s->pendulum,
                    "the pendulum's name in the provenance (and the folder name under data/golden "
                    "that validate --pendulum reads) [default: egalitarian for the paper's, else "
                    "required]");
    sub->add_flag("--certify", s->certify,
                  "also prove an enclosure of every row whose quantity has one (certified/: the "
                  "prediction quantities, and the saddle orbit's by a Krawczyk proof) at the row's "
                  "certified digits: columns radius and proven_digits (exit status 1 if a proof "
                  "fails or a value lies outside its enclosure)");
    sub->add_flag("--certify-existing", s->certify_existing,
                  "add the proven enclosures (radius, proven_digits) to the rows of the set in "
                  "--out without recomputing any value (same pendulum and precision, checked as "
                  "for --merge; the provenance lists the runs)");
    sub->add_option("--max-seconds", s->max_seconds,
                    "CPU seconds each evaluation of a row (its value, each check) and each proof "
                    "may take (0: no bound): a row that does not finish in them is skipped, a "
                    "proof leaves its row without an enclosure; both are named on stderr")
        ->capture_default_str();
    sub->add_flag("--merge", s->merge,
                  "extend the set in --out: its rows of the other quantities are kept, those of "
                  "--quantities replaced (same pendulum and precision; the provenance lists the "
                  "runs)");
    sub->callback([s] {
        golden_options options = checked_options(*s);
        progress_bar bar(s->progress);
        options.progress = [&bar](const golden_row& r, std::size_t done, std::size_t total) {
            bar.update(done, total, "rows", 0,
                       r.quantity + " arm " + (r.arm.empty() ? "-" : r.arm) + " E " + r.energy +
                           ": " + std::to_string(r.digits) + " digits");
        };
        std::size_t skipped = 0;
        options.skipped = [&skipped](const std::string& what) {
            ++skipped;
            std::fprintf(stderr, "golden: skipped %s\n", what.c_str());
        };
        std::size_t unproven = 0;
        options.unproven = [&unproven](const std::string& what) {
            ++unproven;
            std::fprintf(stderr, "golden: unproven: %s\n", what.c_str());
        };
        if (s->certify_existing &&
            (s->merge || s->certify || !s->quantities.empty() || options.max_rows > 0))
            throw input_error(
                "--certify-existing: proves the set in --out as it is; it takes no --merge, "
                "--certify, --quantities or --max-rows");
        std::vector<golden_row> kept;
        std::string merged_into;
        if (s->merge || s->certify_existing) {  // read and check before hours of computation
            const std::string option = s->merge ? "--merge" : "--certify-existing";
            merged_into = read_text(s->out + "/provenance.json", option);
            try {
                check_golden_merge(merged_into, options.value_precision, options.model);
            } catch (const input_error& e) {
                throw input_error(option + ": " + e.what());
            }
            const std::string csv = s->out + "/golden.csv";
            try {
                kept = parse_golden_csv(read_text(csv, option));
                for (const golden_row& r : kept)
                    find_quantity(r.quantity);  // input_error naming an unknown quantity
            } catch (const input_error& e) {
                throw input_error(option + ": '" + csv + "': " + e.detail());
            }
            if (s->certify_existing && kept.empty())
                throw input_error(option + ": '" + csv + "' holds no golden row to prove");
        }
        // every destination checked before hours of computation; nothing created yet
        check_output_folder(s->out, "--out");
        check_output_file(s->out + "/golden.csv", "--out");
        check_output_file(s->out + "/provenance.json", "--out");
        std::vector<golden_row> rows;
        if (s->certify_existing) {
            rows = std::move(kept);
            prove_golden_rows(rows, options.model, options.jobs, options.max_seconds,
                              options.unproven);
        } else {
            rows = generate_golden(options);
            if (s->merge) rows = merge_golden(kept, rows, options.quantities);
        }
        bar.finish();
        const std::string command = provenance_command(*s, options.max_rows);
        write_file_atomically(s->out + "/golden.csv", golden_csv(rows));
        write_file_atomically(
            s->out + "/provenance.json",
            golden_provenance(command, rows.size(), options.value_precision, cli_command_words(),
                              options.model, options.pendulum, merged_into));
        int least = rows.empty() ? 0 : rows.front().digits;
        for (const golden_row& r : rows)
            least = std::min(least, r.digits);
        const auto proven = std::count_if(rows.begin(), rows.end(),
                                          [](const golden_row& r) { return !r.radius.empty(); });
        const json summary{{"rows", rows.size()},
                           {"proven_rows", proven},
                           {"skipped", skipped},
                           {"unproven", unproven},
                           {"least_digits", least},
                           {"csv", s->out + "/golden.csv"},
                           {"provenance", s->out + "/provenance.json"}};
        print(summary.dump(2) + "\n");
    });
});

}  // namespace
}  // namespace flipflux::cli
