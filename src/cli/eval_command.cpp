// flipflux eval QUANTITY --energy E [--arm 1|2] [--precision P] [--method M] [--integrator I]
//     [--certify]: one quantity as JSON. --integrator (saddle-orbit quantities only) qualifies the
// method: "M/I"; --certify adds a proven enclosure (certified/) and checks that the value lies in
// it.
#include <chrono>
#include <cmath>
#include <limits>

#include "common.hpp"
#include "flipflux/certified/enclosure.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux::cli {
namespace {

struct eval_state {
    std::string quantity, energy, arm_text = "2", method, integrator;
    model_options model;
    precision_option precision;
    time_bound_option bound;
    bool certify = false;
};

/// The "enclosure" member of --certify: the proven ball at the precision's digits, and the check
/// that the non-rigorous value lies in it, widened by the value's own error estimate (which the
/// ball may be narrower than); certification_error (exit status 1) if not. Both are of the
/// decimal inputs: the non-rigorous route rounds the parameters to Real but carries the energy's
/// distances to the critical levels exactly (model/energy_level.hpp, model_text.hpp), the only
/// place where the parameters' rounding is amplified (f1 ~ E - E_s just above a saddle).
template <class Real>
json enclosure_json(const eval_state& s, const quantity& q, arm a, const quantity_value<Real>& v) {
    const int digits = decimal_digits(precision_of<Real>());
    const auto start = std::chrono::steady_clock::now();
    const certified_enclosure e = certified_value(q.name, s.model, a, s.energy, digits);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // the value with every digit it has (mp: its working digits), the slack its error estimate
    // plus the rounding of that decimal
    int shown = std::numeric_limits<Real>::max_digits10;
    if constexpr (has_variable_precision_v<Real>) shown = mp_working_digits(digits) + 2;
    using std::abs;
    using std::pow;
    const std::string value = to_decimal(v.value, shown);
    const std::string slack =
        to_decimal(Real(abs(v.error_estimate) + abs(v.value) * pow(Real(10), 1 - shown)), 3);
    json out{{"interval", "[" + e.mid + " +/- " + e.radius + "]"},
             {"mid", e.mid},
             {"radius", e.radius},
             {"proven_digits", e.proven_digits},
             {"bits", e.bits},
             {"seconds", seconds}};
    if (!enclosure_contains(e, value, slack))
        throw certification_error(q.name + " at E = " + s.energy + ": the value " + value +
                                  " (error estimate " + slack +
                                  ") lies outside the proven enclosure [" + e.mid + " +/- " +
                                  e.radius + "]: a bug in one of the two routes");
    return out;
}

template <class Real>
json eval_json(const eval_state& s) {
    const quantity& q = find_quantity(s.quantity);
    const arm a = parse_arm(s.arm_text);
    const double_pendulum<Real> model = make_model<Real>(s.model);
    const energy_level<Real> level = parse_energy_level<Real>(s.energy, "--energy");
    const Real& energy = level.value;
    check_magnitude(energy, "--energy");
    std::string method = s.method;
    if (!s.integrator.empty()) {
        if (!q.needs_saddle_orbit)
            throw input_error("--integrator: '" + s.integrator + "' applies to the saddle-orbit " +
                              "quantities only, not to " + q.name);
        (void)parse_name<orbit_integrator>(s.integrator, "--integrator");
        method = (method.empty() ? q.methods.front() : method) + "/" + s.integrator;
    }
    // before the evaluation: a saddle orbit at mp:N is not computed for nothing
    if (s.certify && !has_certified_enclosure(q.name))
        throw input_error::about("--certify", q.name + " has no certified route");
    const auto start = std::chrono::steady_clock::now();
    const quantity_value<Real> v = q.evaluate(model, a, level, method);
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
    const auto [value, error] = printed_value(v);
    out["value"] = value;
    out["error_estimate"] = error;
    out["seconds"] = seconds;
    if (!s.model.is_default()) {
        out["model"] = parameters_json(model);
    }
    if (s.certify) out["enclosure"] = enclosure_json(s, q, a, v);
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
    sub->add_flag("--certify", s->certify,
                  "also prove an enclosure [mid +/- radius] with Arb and check that the value "
                  "lies in it (exit status 1 if not, or if the proof fails); the saddle-orbit "
                  "quantities by a Krawczyk proof of the orbit");
    add_model_options(*sub, s->model);
    add_precision_option(*sub, s->precision);
    add_time_bound_option(*sub, s->bound);
    sub->callback([s] {
        const precision p = parse_precision(s->precision.text);
        // the pilots evaluate without --certify (the proof is not what the estimate is of)
        eval_state pilot = *s;
        pilot.certify = false;
        detail::estimate_cost(p, s->bound, [&pilot](const precision& q) {
            (void)dispatch(q, [&]<class Real>() { return eval_json<Real>(pilot); });
        });
        const json out =
            bounded_dispatch(p, s->bound, false, [&]<class Real>() { return eval_json<Real>(*s); });
        print(out.dump(2) + "\n");
    });
});

}  // namespace
}  // namespace flipflux::cli
