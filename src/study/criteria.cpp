// The flip criteria's registry and the paper's three criteria
// (include/flipflux/study/criteria.hpp).
#include "flipflux/study/criteria.hpp"

#include <cctype>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/names.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {
namespace {

/// The upright arm: f = pi.
struct make_upright {
    template <class Real>
    upright_curve<Real> operator()(const double_pendulum<Real>&, arm a, const Real&) const {
        return upright_curve<Real>{a};
    }
};

/// The approximate saddle curve: a sine with the centre mode's slope.
struct make_approx {
    template <class Real>
    auto operator()(const double_pendulum<Real>& model, arm a, const Real&) const {
        return approximate_saddle_curve(model, a);
    }
};

/// The saddle orbit's configuration curve at this energy (orbits/: continuation from the centre
/// mode, refined at Real), a Chebyshev interpolant on the turning-point interval (a restricted
/// domain: crossings beyond the turning points do not count).
struct make_saddle {
    template <class Real>
    saddle_curve<Real> operator()(const double_pendulum<Real>& model, arm a,
                                  const Real& energy) const {
        try {
            check_orbit_energy(model, a, energy);
        } catch (const input_error& e) {
            throw criterion_unavailable(e);
        }
        const saddle_orbit<Real> orbit = find_or_solve_saddle_orbit<Real>(model, a, energy);
        if (orbit.status == orbit_status::not_converged)
            throw_not_converged(model, a, energy, orbit, "saddle criterion: saddle orbit");
        return make_saddle_curve<Real>(model, orbit);
    }
};

std::deque<criterion_definition> builtin_criteria() {
    std::deque<criterion_definition> out;
    out.push_back(
        define_criterion<make_upright>({.name = "upright",
                                        .help = "the flip angle equals pi (the upright arm)",
                                        .rate_quantity = "rate-upright",
                                        .is_level = true}));
    out.push_back(define_criterion<make_approx>(
        {.name = "approx",
         .help = "the approximate saddle curve: a sine with the centre mode's slope",
         .rate_quantity = "rate-approx"}));
    out.push_back(define_criterion<make_saddle>(
        {.name = "saddle",
         .help = "the saddle orbit's configuration curve at the energy",
         .rate_quantity = "rate-saddle",
         .needs_saddle_orbit = true,
         .is_reference = true}));
    return out;
}

std::deque<criterion_definition>& registry() {
    static std::deque<criterion_definition> r = builtin_criteria();
    return r;
}

const criterion_definition* find(const std::string& name) {
    for (const criterion_definition& c : registry())
        if (c.name == name) return &c;
    return nullptr;
}

}  // namespace

const std::deque<criterion_definition>& criteria_registry() {
    return registry();
}

const criterion_definition& register_criterion(criterion_definition definition) {
    if (!is_plain_name(definition.name) || find(definition.name))
        throw std::logic_error("register_criterion: the name '" + definition.name +
                               "' is taken or not a plain name");
    return registry().emplace_back(std::move(definition));
}

const criterion_definition& criterion(const std::string& name, const std::string& field) {
    if (const criterion_definition* c = find(name)) return *c;
    throw input_error::about(field,
                             "'" + name + "' is not a criterion (" + criterion_name_list() + ")");
}

std::vector<std::string> criterion_names() {
    std::vector<std::string> names;
    for (const criterion_definition& c : registry())
        names.push_back(c.name);
    return names;
}

std::string criterion_name_list(const std::string& separator) {
    std::string out;
    for (const criterion_definition& c : registry())
        out += (out.empty() ? "" : separator) + c.name;
    return out;
}

std::string criterion_alternatives() {
    const std::vector<std::string> names = criterion_names();
    std::string out;
    for (std::size_t i = 0; i < names.size(); ++i)
        out += (i == 0 ? "" : i + 1 == names.size() ? " or " : ", ") + names[i];
    return out;
}

const std::string& default_criterion() {
    return registry().front().name;
}

std::optional<std::string> criterion_named(const std::string& text) {
    std::string lower = text;
    for (char& c : lower)
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (const criterion_definition* c = find(lower)) return c->name;
    return std::nullopt;
}

void check_criterion_name(const std::string& name, const std::string& option) {
    (void)criterion(name, option);
}

double criterion_threshold(const double_pendulum<double>& model, arm a, const std::string& name) {
    check_criterion_name(name);
    return model.saddle_energy(a);
}

double criterion_ceiling(const double_pendulum<double>& model, arm a, const std::string& name) {
    check_criterion_name(name);
    (void)a;  // the potential's maximum is both arms' ceiling
    return criterion(name).needs_saddle_orbit ? model.maximum_energy()
                                              : std::numeric_limits<double>::infinity();
}

std::string criterion_ceiling_text(double energy, double ceiling, arm a, const std::string& name) {
    return "'" + to_shortest_decimal(energy) + "' is at or above the maximum energy " +
           to_decimal(ceiling) + ", where criterion '" + name + "' of arm " + to_string(a) +
           " has no saddle orbit (its family ends at E_max): leave '" + name +
           "' out of the criteria at this energy";
}

ensemble_criterion make_criterion(const double_pendulum<double>& model, arm a,
                                  const std::string& name, double energy) {
    const double threshold = criterion_threshold(model, a, name);
    if (!(energy > threshold))
        throw input_error::about(
            "energy", "'" + to_shortest_decimal(energy) + "' is at or below the threshold " +
                          to_decimal(threshold) + " of criterion '" + name + "' for arm " +
                          to_string(a) + " (the saddle energy: no flips are possible)");
    if (const double ceiling = criterion_ceiling(model, a, name); !(energy < ceiling))
        throw input_error::about("energy", criterion_ceiling_text(energy, ceiling, a, name));
    return {name, criterion(name).detector(model, a, energy, pendulum_flow(model))};
}

std::optional<quantity_value<double>> criterion_prediction(const double_pendulum<double>& model,
                                                           arm a, const std::string& name,
                                                           double energy) {
    const criterion_definition& c = criterion(name);
    for (const quantity& q : quantities())
        if (!c.rate_quantity.empty() && q.name == c.rate_quantity)
            return q.evaluate(model, a, energy, "");
    return std::nullopt;
}

}  // namespace flipflux
