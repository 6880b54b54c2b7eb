// Included only by src/**/*.inst.cpp: selects the real type of this compilation of the unit.
// CMake compiles every *.inst.cpp once per entry of FLIPFLUX_REAL_TYPES (core/real.hpp), with
// FLIPFLUX_REAL_INDEX = the entry's position in the list.
#pragma once

#include <tuple>

#include "flipflux/core/real.hpp"

#ifndef FLIPFLUX_REAL_INDEX
#error "FLIPFLUX_REAL_INDEX must be defined when compiling an instantiation unit"
#endif

namespace flipflux {
using inst_real = std::tuple_element_t<FLIPFLUX_REAL_INDEX, real_types>;
}  // namespace flipflux
