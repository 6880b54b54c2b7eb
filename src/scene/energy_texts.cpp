// A scene's energy grid as decimal text (include/flipflux/scene/scene.hpp): its values, or the
// grid {from, to, step} by the one grid rule (core/decimal.hpp, decimal_grid).
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/scene/scene.hpp"

namespace flipflux {

std::vector<std::string> energy_texts(const energy_grid& grid, const std::string& where) {
    try {
        if (!grid.is_grid()) {
            if (grid.values.size() > max_energy_count)
                throw input_error::about(where, "more than " + std::to_string(max_energy_count) +
                                                    " energies (docs/limits.md)");
            for (const auto& v : grid.values)
                if (!is_decimal_number(v))
                    throw input_error::about(where, "'" + v + "' is not a finite decimal number");
            return grid.values;
        }
        return decimal_grid(grid.from, grid.to, grid.step, where);
    } catch (const input_error& e) {
        throw scene_error(e.what());
    }
}

}  // namespace flipflux
