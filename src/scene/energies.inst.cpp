#include "flipflux/core/decimal.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/scene/scene.hpp"

namespace flipflux {

template <class Real>
std::vector<Real> energies_of(const energy_grid& grid, const std::string& where) {
    std::vector<Real> out;
    if (!grid.is_grid()) {
        for (const auto& v : grid.values)
            out.push_back(parse_real<Real>(v, where));
        return out;
    }
    using std::abs;
    using std::round;
    const Real from = parse_real<Real>(grid.from, where + ".from");
    const Real to = parse_real<Real>(grid.to, where + ".to");
    const Real step = parse_real<Real>(grid.step, where + ".step");
    if (!(step > 0)) throw scene_error(where + ".step: '" + grid.step + "' must be > 0");
    if (to < from) {
        throw scene_error(where + ".to: '" + grid.to + "' is below from = '" + grid.from + "'");
    }
    const Real count = round((to - from) / step);
    if (count > 1000000) throw scene_error(where + ": more than 1000000 energies");
    // NOTE: the end point must lie on the grid to a relative 1e-9 of the step, so that a grid
    // written in decimal (2.05 .. 5.95 by 0.05) is exactly what the user meant in every precision.
    if (abs(from + count * step - to) > step / 1000000000) {
        throw scene_error(where + ": to - from = " + to_decimal(Real(to - from), 10) +
                          " is not a multiple of step = " + grid.step);
    }
    const long n = static_cast<long>(count);
    for (long i = 0; i <= n; ++i)
        out.push_back(i == n ? to : from + i * step);
    return out;
}

template std::vector<inst_real> energies_of<inst_real>(const energy_grid&, const std::string&);

}  // namespace flipflux
