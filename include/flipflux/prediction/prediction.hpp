// The prediction module: phase volume, configuration-space densities, fluxes through the upright
// surface and through any dividing curve, and predicted flip rates (paper Sec. 4, App. C).
#pragma once

#include "flipflux/prediction/curve_flux.hpp"
#include "flipflux/prediction/phase_volume.hpp"
#include "flipflux/prediction/rates.hpp"
#include "flipflux/prediction/result.hpp"
#include "flipflux/prediction/upright_flux.hpp"
