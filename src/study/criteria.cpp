// Flip criteria by name (include/flipflux/study/criteria.hpp).
#include "flipflux/study/criteria.hpp"

#include <cctype>

#include <cmath>
#include <stdexcept>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {

const std::vector<std::string>& criterion_names() {
    static const std::vector<std::string> names{"upright", "approx", "saddle"};
    return names;
}

std::optional<std::string> criterion_named(const std::string& text) {
    std::string lower = text;
    for (char& c : lower)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    for (const std::string& n : criterion_names())
        if (n == lower) return n;
    return std::nullopt;
}

void check_criterion_name(const std::string& name, const std::string& option) {
    for (const std::string& n : criterion_names())
        if (n == name) return;
    throw input_error::about(option, "'" + name + "' is not a criterion (upright, approx, saddle)");
}

double criterion_threshold(const double_pendulum<double>& model, arm a, const std::string& name) {
    check_criterion_name(name);
    return model.saddle_energy(a);
}

ensemble_criterion make_criterion(const double_pendulum<double>& model, arm a,
                                  const std::string& name, double energy) {
    const double threshold = criterion_threshold(model, a, name);
    if (!(energy > threshold))
        throw input_error::about(
            "energy", "'" + to_decimal(energy) + "' is at or below the threshold " +
                          to_decimal(threshold) + " of criterion '" + name + "' for arm " +
                          to_string(a) + " (the saddle energy: no flips are possible)");
    const pendulum_flow flow(model);
    if (name == "upright") return {name, make_flip_detector(upright_curve<double>{a}, flow)};
    if (name == "approx")
        return {name, make_flip_detector(approximate_saddle_curve(model, a), flow)};
    // the saddle orbit at this energy (orbits/: continuation from the centre mode, refined at
    // double) and its configuration curve, a Chebyshev interpolant on the turning-point interval
    // (a restricted domain: crossings beyond the turning points do not count)
    check_orbit_energy(model, a, energy);
    const saddle_orbit<double> orbit = find_or_solve_saddle_orbit<double>(model, a, energy);
    if (orbit.status == orbit_status::not_converged)
        throw_not_converged(model, a, energy, orbit.double_stage, "saddle criterion: saddle orbit");
    return {name, make_flip_detector(make_saddle_curve<double>(model, orbit), flow)};
}

std::optional<quantity_value<double>> criterion_prediction(const double_pendulum<double>& model,
                                                           arm a, const std::string& name,
                                                           double energy) {
    check_criterion_name(name);
    auto find = [](const std::string& qname) -> const quantity* {
        for (const quantity& q : quantities())
            if (q.name == qname) return &q;
        return nullptr;
    };
    if (const quantity* rate = find("rate-" + name)) return rate->evaluate(model, a, energy, "");
    // a module that registers the flux but not the rate: R = f / Omega
    const quantity* flux = find("flux-" + name);
    const quantity* omega = find("omega");
    if (flux && omega) {
        const quantity_value<double> f = flux->evaluate(model, a, energy, "");
        const quantity_value<double> w = omega->evaluate(model, a, energy, "");
        const double r = f.value / w.value;
        return quantity_value<double>{
            r, f.error_estimate / w.value + std::abs(r) * w.error_estimate / w.value,
            "flux-" + name + " (" + f.method + ") / omega (" + w.method + ")"};
    }
    return std::nullopt;
}

}  // namespace flipflux
