// Mathematical constants in the working precision.
//
// NOTE: never write a constant as a double literal (`Real(3.14159...)`): that caps quad and MPFR
// results at double accuracy. These forward to Boost.Math's constants, which are exact to the
// type's precision (tests/core/test_constants.cpp would catch a truncation).
#pragma once

#include <boost/math/constants/constants.hpp>

namespace flipflux {

template <class Real>
inline Real pi() {
    return boost::math::constants::pi<Real>();
}
template <class Real>
inline Real two_pi() {
    return boost::math::constants::two_pi<Real>();
}
template <class Real>
inline Real half_pi() {
    return boost::math::constants::half_pi<Real>();
}
template <class Real>
inline Real root_two() {
    return boost::math::constants::root_two<Real>();
}

}  // namespace flipflux
