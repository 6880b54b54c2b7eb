// Energy grids as decimal text (include/flipflux/scene/scene.hpp).
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/scene/scene.hpp"

namespace flipflux {

std::vector<std::string> energy_texts(const energy_grid& grid, const std::string& where) {
    if (!grid.is_grid()) {
        for (const auto& v : grid.values)
            (void)parse_real<mp100>(v, where);  // a number?
        return grid.values;
    }
    using std::abs;
    using std::round;
    const mp100 from = parse_real<mp100>(grid.from, where + ".from");
    const mp100 to = parse_real<mp100>(grid.to, where + ".to");
    const mp100 step = parse_real<mp100>(grid.step, where + ".step");
    if (!(step > 0)) throw scene_error(where + ".step: '" + grid.step + "' must be > 0");
    if (to < from) {
        throw scene_error(where + ".to: '" + grid.to + "' is below from = '" + grid.from + "'");
    }
    const mp100 count = round((to - from) / step);
    if (count > 1000000) throw scene_error(where + ": more than 1000000 energies");
    if (abs(from + count * step - to) > step / 1000000000) {
        throw scene_error(where + ": to - from = " + to_decimal(mp100(to - from), 10) +
                          " is not a multiple of step = " + grid.step);
    }
    // from + i step in 100 digits, written with 40: the decimal the user meant ("2.1", not
    // 2.1000000000000000888 or 2.0999999999999996447), parsed later in the working precision
    const long n = static_cast<long>(count);
    std::vector<std::string> out;
    for (long i = 0; i <= n; ++i)
        out.push_back(i == n ? grid.to : to_decimal(mp100(from + i * step), 40));
    return out;
}

}  // namespace flipflux
