// Included only by src/*.inst.cpp: selects the real type of this compilation of the unit.
// CMake compiles every *.inst.cpp once per type with FLIPFLUX_REAL_ID = 0 (double), 1 (quad),
// 2 (mp50), 3 (mp100).
#pragma once

#include "flipflux/core/real.hpp"

#ifndef FLIPFLUX_REAL_ID
#error "FLIPFLUX_REAL_ID must be defined when compiling an instantiation unit"
#endif

namespace flipflux {
#if FLIPFLUX_REAL_ID == 0
using inst_real = double;
#elif FLIPFLUX_REAL_ID == 1
using inst_real = quad;
#elif FLIPFLUX_REAL_ID == 2
using inst_real = mp50;
#elif FLIPFLUX_REAL_ID == 3
using inst_real = mp100;
#else
#error "unknown FLIPFLUX_REAL_ID"
#endif
}  // namespace flipflux
