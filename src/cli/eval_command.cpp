// flipflux eval QUANTITY --energy E [--arm 1|2] [--precision P] [--method M] [--integrator I]: one
// quantity as JSON. --integrator (saddle-orbit quantities only) qualifies the method: "M/I".
#include <chrono>

#include "common.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux::cli {
namespace {

struct eval_state {
    std::string quantity, energy, arm_text = "2", method, integrator;
    model_options model;
    precision_option precision;
};

template <class Real>
json eval_json(const eval_state& s) {
    const quantity& q = find_quantity(s.quantity);
    const arm a = parse_arm(s.arm_text);
    const double_pendulum<Real> model(parse_parameters<Real>(s.model));
    const Real energy = parse_real<Real>(s.energy, "--energy");
    check_magnitude(energy, "--energy");
    std::string method = s.method;
    if (!s.integrator.empty()) {
        if (!q.needs_saddle_orbit)
            throw input_error("--integrator: '" + s.integrator + "' applies to the saddle-orbit " +
                              "quantities only, not to " + q.name);
        (void)parse_name<orbit_integrator>(s.integrator, "--integrator");
        method = (method.empty() ? q.methods.front() : method) + "/" + s.integrator;
    }
    const auto start = std::chrono::steady_clock::now();
    const quantity_value<Real> v = q.evaluate(model, a, energy, method);
    using std::isfinite;
    if (!isfinite(v.value))  // never print an overflow as a value
        throw input_error("--energy: '" + s.energy + "': " + q.name + " is not finite in " +
                          precision_name<Real>() + " there (" + to_decimal(v.value) +
                          "); try mp:N");
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    json out{{"quantity", q.name}};
    out["arm"] = q.per_arm ? json(to_string(a)) : json(nullptr);
    out["energy"] = to_decimal(energy);
    out["precision"] = precision_name<Real>();
    out["method"] = v.method;
    out["value"] = to_decimal(v.value);
    out["error_estimate"] = to_decimal(v.error_estimate, 3);
    out["seconds"] = seconds;
    if (!s.model.is_default()) {
        out["model"] = parameters_json(model);
    }
    return out;
}

std::string quantity_help() {
    std::string h = "Evaluate one quantity at one energy and print it as JSON.\n\nQuantities:\n";
    for (const quantity& q : quantities()) {
        h += "  " + q.name + std::string(q.name.size() < 16 ? 16 - q.name.size() : 1, ' ') +
             q.description;
        if (q.methods.size() > 1) {
            h += " [methods:";
            for (const auto& m : q.methods)
                h += " " + m;
            h += "]";
        }
        h += "\n";
    }
    return h;
}

const register_command registration([](CLI::App& app) {
    auto s = std::make_shared<eval_state>();
    CLI::App* sub = app.add_subcommand("eval", quantity_help());
    sub->add_option("quantity", s->quantity, "the quantity's name (see above)")->required();
    sub->add_option("--energy", s->energy, "energy E (decimal, parsed in the working precision)")
        ->required();
    sub->add_option("--arm", s->arm_text, "the arm whose flips are counted: 1 or 2")
        ->capture_default_str();
    sub->add_option("--method", s->method, "evaluation method (default: the quantity's first)");
    sub->add_option("--integrator", s->integrator,
                    "saddle-orbit quantities: taylor or gauss-legendre (default: gauss-legendre "
                    "at double, taylor above)");
    add_model_options(*sub, s->model);
    add_precision_option(*sub, s->precision);
    sub->callback([s] {
        const precision p = parse_precision(s->precision.text);
        const json out = dispatch(p, [&]<class Real>() { return eval_json<Real>(*s); });
        print(out.dump(2) + "\n");
    });
});

}  // namespace
}  // namespace flipflux::cli
