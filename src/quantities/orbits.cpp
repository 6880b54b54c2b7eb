// Quantities of the saddle-orbit module (period, action, saddle flux and rate, multiplier).
#include "flipflux/quantities/registry.hpp"

namespace flipflux {

void add_orbit_quantities(std::vector<quantity>&) {}

}  // namespace flipflux
