// Names of the saddle-orbit module's enumerations.
#include "flipflux/core/error.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {

std::string to_string(orbit_method m) {
    return m == orbit_method::periodic ? "periodic" : "symmetric";
}

orbit_method parse_orbit_method(const std::string& text, const std::string& option) {
    if (text == "periodic") return orbit_method::periodic;
    if (text == "symmetric") return orbit_method::symmetric;
    throw input_error(option + ": '" + text +
                      "' is not a saddle-orbit method (expected periodic or symmetric)");
}

std::string to_string(orbit_status s) {
    switch (s) {
        case orbit_status::converged:
            return "converged";
        case orbit_status::stalled:
            return "stalled";
        case orbit_status::not_converged:
            break;
    }
    return "not converged";
}

}  // namespace flipflux
