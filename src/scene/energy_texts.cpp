// Energy grids as decimal text (include/flipflux/scene/scene.hpp).
#include <iomanip>
#include <sstream>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/scene/scene.hpp"

namespace flipflux {
namespace {

// NOTE: grid arithmetic in a fixed 100-digit MPFR type, independent of the working precision
// (and of mp's process-wide default precision): the grid is decimal text, parsed later in the
// working precision.
using grid_decimal = boost::multiprecision::number<boost::multiprecision::mpfr_float_backend<100>,
                                                   boost::multiprecision::et_off>;

grid_decimal parse_grid_decimal(const std::string& text, const std::string& where) {
    if (!is_decimal_number(text))
        throw input_error(where + ": '" + text + "' is not a finite decimal number");
    return grid_decimal(text);
}

std::string grid_text(const grid_decimal& x, int digits) {
    std::ostringstream out;
    out << std::setprecision(digits) << x;
    return out.str();
}

}  // namespace

std::vector<std::string> energy_texts(const energy_grid& grid, const std::string& where) {
    if (!grid.is_grid()) {
        for (const auto& v : grid.values)
            (void)parse_grid_decimal(v, where);  // a number?
        return grid.values;
    }
    using std::abs;
    using std::round;
    const grid_decimal from = parse_grid_decimal(grid.from, where + ".from");
    const grid_decimal to = parse_grid_decimal(grid.to, where + ".to");
    const grid_decimal step = parse_grid_decimal(grid.step, where + ".step");
    if (!(step > 0)) throw scene_error(where + ".step: '" + grid.step + "' must be > 0");
    if (to < from) {
        throw scene_error(where + ".to: '" + grid.to + "' is below from = '" + grid.from + "'");
    }
    const grid_decimal count = round((to - from) / step);
    if (count > 1000000) throw scene_error(where + ": more than 1000000 energies");
    if (abs(from + count * step - to) > step / 1000000000) {
        throw scene_error(where + ": to - from = " + grid_text(to - from, 10) +
                          " is not a multiple of step = " + grid.step);
    }
    // from + i step in 100 digits, written with 40: the decimal the user meant ("2.1", not
    // 2.1000000000000000888 or 2.0999999999999996447), parsed later in the working precision
    const long n = static_cast<long>(count);
    std::vector<std::string> out;
    for (long i = 0; i <= n; ++i)
        out.push_back(i == n ? grid.to : grid_text(from + i * step, 40));
    return out;
}

}  // namespace flipflux
