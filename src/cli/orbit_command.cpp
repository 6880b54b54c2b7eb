// flipflux orbit --energy E [--arm 1|2] [--precision P] [--samples N] [--method M]
// [--integrator I] [--out FILE]:
// the saddle orbit at energy E as CSV rows t,theta1,theta2,l1,l2 (every digit of the working
// precision), N samples at t_k = k T / (N - 1), k = 0..N-1 (the first and last rows coincide).
// With --out the file is written to a temporary name and renamed: never half-written.
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "common.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux::cli {
namespace {

struct orbit_state_options {
    std::string energy, arm_text = "2", samples = "101", method = "periodic", integrator, out;
    model_options model;
    precision_option precision;
    time_bound_option bound;
};

long parse_samples(const std::string& text) {
    long n = 0;
    std::size_t used = 0;
    try {
        n = std::stol(text, &used);
    } catch (const std::exception&) {
        used = 0;
    }
    if (used != text.size() || text.empty() || n < 2 || n > 10000000)
        throw input_error("--samples: '" + text + "' is not an integer in [2, 10000000]");
    return n;
}

template <class Real>
std::string orbit_csv(const orbit_state_options& o) {
    const arm a = parse_arm(o.arm_text);
    const long samples = parse_samples(o.samples);
    const double_pendulum<Real> model = make_model<Real>(o.model);
    const energy_level<Real> level = parse_energy_level<Real>(o.energy, "--energy");
    orbit_options<Real> options;
    options.method = parse_name<orbit_method>(o.method, "--method");
    if (!o.integrator.empty())
        options.integrator = parse_name<orbit_integrator>(o.integrator, "--integrator");
    check_orbit_energy(model, a, level);
    const saddle_orbit<Real> orbit = solve_saddle_orbit(model, a, level, options);
    if (orbit.status == orbit_status::not_converged)
        throw_not_converged(model, a, level, orbit, "orbit");
    std::string csv = "t,theta1,theta2,l1,l2\n";
    for (long k = 0; k < samples; ++k) {
        const Real t = orbit.period * k / (samples - 1);
        const phase_point<Real> x = k + 1 == samples ? orbit.start : orbit_state(model, orbit, t);
        csv += to_decimal(t) + "," + to_decimal(x[0]) + "," + to_decimal(x[1]) + "," +
               to_decimal(x[2]) + "," + to_decimal(x[3]) + "\n";
    }
    return csv;
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<orbit_state_options>();
    CLI::App* sub = app.add_subcommand(
        "orbit",
        "Compute the saddle orbit at one energy and write it as CSV: t,theta1,theta2,l1,l2 "
        "(every digit of the working precision), samples at t = k T / (N - 1)");
    sub->add_option("--energy", s->energy,
                    "energy E, strictly between the saddle's energy and the maximum's")
        ->required();
    sub->add_option("--arm", s->arm_text, "the arm whose saddle orbit: 1 or 2")
        ->capture_default_str();
    sub->add_option("--samples", s->samples, "number of rows N >= 2 (first and last coincide)")
        ->capture_default_str();
    sub->add_option("--method", s->method, "shooting formulation: periodic or symmetric")
        ->capture_default_str();
    sub->add_option("--integrator", s->integrator,
                    "taylor or gauss-legendre (default: gauss-legendre at double, taylor above)");
    sub->add_option("--out", s->out, "write to FILE (atomically) instead of stdout");
    add_model_options(*sub, s->model);
    add_precision_option(*sub, s->precision);
    add_time_bound_option(*sub, s->bound);
    sub->callback([s] {
        const precision p = parse_precision(s->precision.text);
        // before the orbit is solved (seconds to minutes at mp:N): a directory, /proc or a path
        // through a file is refused first, with one line
        if (!s->out.empty()) check_output_file(s->out, "--out");
        const std::string csv =
            bounded_dispatch(p, s->bound, true, [&]<class Real>() { return orbit_csv<Real>(*s); });
        if (s->out.empty()) return print(csv);
        write_file_atomically(s->out, csv);  // output_error (exit 1) naming the path
    });
});

}  // namespace
}  // namespace flipflux::cli
