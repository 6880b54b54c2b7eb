// Names of the prediction routes (stable: used by the CLI, golden data and docs).
#include "flipflux/prediction/curve_flux.hpp"
#include "flipflux/prediction/phase_volume.hpp"
#include "flipflux/prediction/rates.hpp"
#include "flipflux/prediction/upright_flux.hpp"

namespace flipflux {

std::string to_string(phase_volume_method m) {
    switch (m) {
        case phase_volume_method::elliptic:
            return "elliptic";
        case phase_volume_method::quadrature_2d:
            return "quadrature-2d";
        case phase_volume_method::closed_form:
            break;
    }
    return "closed-form";
}

std::string to_string(upright_flux_method m) {
    switch (m) {
        case upright_flux_method::elliptic:
            return "elliptic";
        case upright_flux_method::integral:
            return "integral";
        case upright_flux_method::curve:
            return "curve";
        case upright_flux_method::momentum:
            break;
    }
    return "momentum";
}

std::string to_string(curve_flux_method m) {
    return m == curve_flux_method::kinetic ? "kinetic" : "momentum";
}

std::string to_string(flip_criterion c) {
    return c == flip_criterion::upright ? "upright" : "approximate-saddle";
}

std::string to_string(rate_route r) {
    return r == rate_route::closed_form ? "closed-form" : "quadrature";
}

}  // namespace flipflux
