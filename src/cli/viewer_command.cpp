// flipflux viewer --out DIR [--arms 1,2] [--energies N] [--samples M] [--grid G] [model options]
// [--precision P] [--integrator I]: the interactive saddle-orbit viewer, DIR/viewer.html, one
// self-contained page (study/saddle_viewer.hpp computes the data, io/viewer_page.hpp the page).
// The output is checked before anything is computed and written atomically after.
#include <algorithm>
#include <cstdio>
#include <string>

#include "common.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/io/viewer_page.hpp"
#include "flipflux/study/saddle_viewer.hpp"

namespace flipflux::cli {
namespace {

struct viewer_options {
    std::string out, arms = "1,2", energies = "30", samples = "161", grid = "121", integrator;
    model_options model;
    precision_option precision;
};

int parse_int(const std::string& text, const std::string& option) {
    std::size_t used = 0;
    long value = 0;
    try {
        value = std::stol(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used == 0 || used != text.size() || value < -1000000000L || value > 1000000000L)
        throw input_error(option + ": '" + text + "' is not an integer");
    return static_cast<int>(value);
}

std::vector<arm> parse_arm_list(const std::string& text) {
    std::vector<arm> out;
    std::size_t pos = 0;
    while (true) {
        const std::size_t comma = std::min(text.find(',', pos), text.size());
        out.push_back(parse_arm(text.substr(pos, comma - pos), "--arms"));
        if (comma == text.size()) break;
        pos = comma + 1;
    }
    return out;
}

template <class Real>
std::string viewer_html(const viewer_options& o, const viewer_request& request) {
    const double_pendulum<Real> model = make_model<Real>(o.model);
    orbit_options<Real> options;
    if (!o.integrator.empty())
        options.integrator = parse_name<orbit_integrator>(o.integrator, "--integrator");
    const viewer_data<Real> data = saddle_viewer_data(model, request, options);
    for (const viewer_family<Real>& f : data.families)
        if (!f.stop_reason.empty())
            std::fprintf(stderr, "flipflux: note: arm %s: %s\n", to_string(f.flip_arm).c_str(),
                         f.stop_reason.c_str());
    return viewer_page(viewer_json(data), "flipflux: saddle orbits of the double pendulum");
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<viewer_options>();
    CLI::App* sub = app.add_subcommand(
        "viewer",
        "Write the interactive saddle-orbit viewer, DIR/viewer.html: one self-contained page (no "
        "network access) with an energy slider over each arm's family, the orbit over the "
        "potential's contours, the pendulum animated along it, T, F and the Floquet multiplier");
    sub->add_option("--out", s->out, "output directory DIR (created; the page is DIR/viewer.html)")
        ->required();
    sub->add_option("--arms", s->arms, "the families shown: 1, 2 or 1,2")->capture_default_str();
    sub->add_option("--energies", s->energies,
                    "orbits per arm N in [1, 1000], at E_s + (E_max - E_s) k / (N + 1)")
        ->capture_default_str();
    sub->add_option("--samples", s->samples, "points per orbit over one period, in [8, 100000]")
        ->capture_default_str();
    sub->add_option("--grid", s->grid,
                    "potential grid points per axis over [-pi, 2 pi], in [7, 2001], 1 mod 6")
        ->capture_default_str();
    sub->add_option("--integrator", s->integrator,
                    "taylor or gauss-legendre (default: gauss-legendre at double, taylor above)");
    add_model_options(*sub, s->model);
    add_precision_option(*sub, s->precision);
    sub->callback([s] {
        const precision p = parse_precision(s->precision.text);
        viewer_request request;
        request.arms = parse_arm_list(s->arms);
        request.energies = parse_int(s->energies, "--energies");
        request.samples = parse_int(s->samples, "--samples");
        request.grid = parse_int(s->grid, "--grid");
        check_viewer_request(request);
        const std::filesystem::path file = std::filesystem::path(s->out) / "viewer.html";
        check_output_file(file, "--out");
        const std::string html =
            dispatch(p, [&]<class Real>() { return viewer_html<Real>(*s, request); });
        write_file_atomically(file, html);  // output_error (exit 1) naming the path
        std::fprintf(stderr, "flipflux: wrote %s\n", file.string().c_str());
    });
});

}  // namespace
}  // namespace flipflux::cli
