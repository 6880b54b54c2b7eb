// A scene's energy grid in Real (scene/scene.hpp): the grid's decimal texts, each parsed in the
// working precision.
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/scene/scene.hpp"

namespace flipflux {

template <class Real>
std::vector<energy_level<Real>> energies_of(const energy_grid& grid, const std::string& where) {
    std::vector<energy_level<Real>> out;
    for (const std::string& text : energy_texts(grid, where))
        out.push_back(parse_energy_level<Real>(text, where));
    return out;
}

template std::vector<energy_level<inst_real>> energies_of<inst_real>(const energy_grid&,
                                                                     const std::string&);

}  // namespace flipflux
