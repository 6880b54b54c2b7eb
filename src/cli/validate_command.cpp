// flipflux validate CANDIDATE.csv [--golden DIR] [--rtol X] [--allow-missing]
#include <iostream>

#include "common.hpp"
#include "flipflux/validation/validate.hpp"

namespace flipflux::cli {
namespace {

struct validate_state {
    std::string candidate, golden, rtol = "1e-12";
    bool allow_missing = false;
};

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<validate_state>();
    CLI::App* sub = app.add_subcommand(
        "validate",
        "Compare another implementation's values (CSV: quantity, arm, energy, value) with the "
        "golden data; exit status 1 when any row fails or cannot be matched (docs/validating.md)");
    sub->add_option("candidate", s->candidate, "the candidate CSV file")->required();
    sub->add_option("--golden", s->golden,
                    "the golden-data directory [default: the installation's, share/flipflux/golden "
                    "beside the executable or in ../share]");
    sub->add_option("--rtol", s->rtol, "relative tolerance per row")->capture_default_str();
    sub->add_flag("--allow-missing", s->allow_missing,
                  "accept a candidate that covers only some energies of a quantity");
    sub->callback([s] {
        const double rtol = parse_real<double>(s->rtol, "--rtol");
        if (!(rtol > 0 && rtol < 1)) {
            throw input_error("--rtol: '" + s->rtol + "' must be in (0, 1)");
        }
        std::string golden = s->golden;
        if (golden.empty()) {
            golden = find_share_path("golden").string();
            if (golden.empty())
                throw input_error(
                    "--golden: no golden data beside the executable (share/flipflux/golden or "
                    "../share/flipflux/golden); give the directory");
        }
        const validation_report r =
            validate_candidate(s->candidate, golden, rtol, s->allow_missing);
        print(format_report(r, rtol));
        if (!r.passed()) exit_status() = 1;
    });
});

}  // namespace
}  // namespace flipflux::cli
