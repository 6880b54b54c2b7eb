// The named quantities flipflux evaluates ("omega", "flux-upright", "period", ...): one registry
// shared by `flipflux eval`, golden-data generation, validation and scenes, so that a quantity's
// name, domain and methods are defined once.
//
// Each module contributes its quantities through an add_*_quantities() function called by
// quantities() (explicit calls, not static registrars, which a static library would drop).
#pragma once

#include <array>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/energy_level.hpp"

namespace flipflux {

/// A value with its estimated absolute error and the method that produced it.
template <class Real>
struct quantity_value {
    Real value;
    Real error_estimate;
    std::string method;
};

/// The value as the decimal the outputs print (every digit of the precision; mp:N: N + 2 digits
/// of a value computed with N + 10) and that decimal's error: the evaluation's estimate plus the
/// decimal's rounding (by the triangle inequality a bound when the estimate is one). The one
/// rule of `eval` and Python's evaluate().
template <class Real>
std::array<std::string, 2> printed_value(const quantity_value<Real>& v) {
    using std::abs;
    std::string value = to_decimal(v.value);
    const Real rounding = abs(parse_real<Real>(value, "value") - v.value);
    // three digits, rounded up (x 1.005 before rounding to nearest): never below the estimate
    return {std::move(value), to_decimal(Real((abs(v.error_estimate) + rounding) * 1.005), 3)};
}

/// Evaluates a quantity at energy E for arm a (ignored by quantities that are not per arm) with a
/// named method ("" = the default). E is an energy_level: parse_energy_level(text) carries the
/// decimal input's distance to the saddles and to E_max exactly; a Real converts implicitly.
/// Throws input_error for an energy outside the domain or an unknown method.
template <class Real>
using quantity_function = std::function<quantity_value<Real>(const double_pendulum<Real>&, arm,
                                                             const energy_level<Real>& energy,
                                                             const std::string& method)>;

struct quantity {
    std::string name;
    std::string description;
    std::vector<std::string> methods;  ///< the first is the default
    bool per_arm = true;
    /// true when every evaluation needs the saddle orbit at E (scenes plan an orbit family for
    /// it; golden data use a coarser grid, the orbit costing minutes in mp:100)
    bool needs_saddle_orbit = false;
    /// the independent routes that certify the default method (golden data): the first that
    /// applies is used; empty: the other entries of `methods`
    std::vector<std::string> check_methods;
    /// the evaluation in every supported real type
    per_real_type<quantity_function> functions;

    template <class Real>
    quantity_value<Real> evaluate(const double_pendulum<Real>& model, arm a,
                                  const level_arg<Real>& energy, const std::string& method) const {
        return std::get<quantity_function<Real>>(functions)(model, a, energy, method);
    }
};

/// Builds a quantity from a generic callable f.template operator()<Real>(model, arm, E, method).
template <class F>
quantity make_quantity(std::string name, std::string description, std::vector<std::string> methods,
                       bool per_arm, F f) {
    quantity q{std::move(name), std::move(description), std::move(methods), per_arm, false, {}, {}};
    for_each_real_type([&]<class Real>() {
        std::get<quantity_function<Real>>(q.functions) = [f](auto&&... a) {
            return f.template operator()<Real>(a...);
        };
    });
    return q;
}

/// Every registered quantity, in a stable order.
const std::vector<quantity>& quantities();

/// The registered quantities' names, comma-separated ("omega, flux-upright, ...").
std::string quantity_names();

/// The quantity called `name`; throws input_error listing the known names otherwise.
const quantity& find_quantity(std::string_view name);

// Contributions of the modules (src/quantities/*.cpp).
void add_prediction_quantities(std::vector<quantity>& list);  // omega, fluxes, rates
void add_orbit_quantities(std::vector<quantity>& list);       // period, action, saddle flux, ...

}  // namespace flipflux
