// Quantities of the prediction module (phase volume, fluxes, rates): see issue "Phase volume,
// fluxes and predicted flip rates".
#include "flipflux/quantities/registry.hpp"

namespace flipflux {

void add_prediction_quantities(std::vector<quantity>&) {}

}  // namespace flipflux
