#include "flipflux/model/critical_points.hpp"

namespace flipflux {

std::string to_string(critical_kind k) {
    switch (k) {
        case critical_kind::minimum:
            return "minimum";
        case critical_kind::saddle:
            return "index-one saddle";
        case critical_kind::maximum:
            break;
    }
    return "maximum";
}

}  // namespace flipflux
