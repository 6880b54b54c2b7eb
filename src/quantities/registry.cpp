// The registry of named quantities (quantities/registry.hpp): the prediction quantities and the
// saddle-orbit quantities, found by name, each with its methods and a per-real-type table.
#include "flipflux/quantities/registry.hpp"

#include "flipflux/core/error.hpp"

namespace flipflux {

const std::vector<quantity>& quantities() {
    static const std::vector<quantity> list = [] {
        std::vector<quantity> v;
        add_prediction_quantities(v);
        add_orbit_quantities(v);
        return v;
    }();
    return list;
}

std::string quantity_names() {
    std::string known;
    for (const quantity& q : quantities())
        known += (known.empty() ? "" : ", ") + q.name;
    return known;
}

const quantity& find_quantity(std::string_view name) {
    for (const quantity& q : quantities())
        if (q.name == name) return q;
    throw input_error("quantity: '" + std::string(name) +
                      "' is not a known quantity (known: " + quantity_names() + ")");
}

}  // namespace flipflux
