// The saddle-orbit viewer's request checks and energies (include/flipflux/study/saddle_viewer.hpp).
#include <algorithm>
#include <cmath>
#include <string>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/study/saddle_viewer.hpp"

namespace flipflux {
namespace {

void check_count(const std::string& field, int value, int lo, int hi) {
    if (value < lo || value > hi)
        throw input_error::about(field, "'" + std::to_string(value) + "' is not an integer in [" +
                                            std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

}  // namespace

void check_viewer_request(const viewer_request& request) {
    if (request.arms.empty()) throw input_error::about("arms", "needs at least one arm");
    for (std::size_t i = 0; i < request.arms.size(); ++i)
        for (std::size_t j = 0; j < i; ++j)
            if (request.arms[i] == request.arms[j])
                throw input_error::about("arms",
                                         "arm " + to_string(request.arms[i]) + " is given twice");
    check_count("energies", request.energies, 1, 1000);
    check_count("samples", request.samples, 8, 100000);
    check_count("grid", request.grid, 7, 2001);
    if (request.grid % 6 != 1)
        throw input_error::about("grid", "'" + std::to_string(request.grid) +
                                             "' is not 1 more than a multiple of 6 (the grid's "
                                             "nodes fall on the multiples of pi/2)");
}

std::vector<std::string> viewer_energy_texts(const double_pendulum<double>& model, arm a, int n) {
    check_count("energies", n, 1, 1000);
    const double es = model.saddle_energy(a), emax = model.maximum_energy();
    const double spacing = (emax - es) / (n + 1);
    // rounding to `digits` significant digits moves E by at most |E| 10^(1 - digits) / 2: below
    // spacing / 100 with the digits below (at least 6, for a readable label)
    const int digits = std::clamp(
        static_cast<int>(std::ceil(std::log10(std::max(std::abs(es), std::abs(emax)) / spacing))) +
            3,
        6, 17);
    std::vector<std::string> out;
    double previous = es;
    for (int k = 0; k < n; ++k) {
        const double e = es + (emax - es) * (k + 1) / (n + 1);
        std::string text = to_decimal(e, digits);
        const double parsed = parse_real<double>(text, "energy");
        // NOTE: never reached with the digits above; kept so that a text is never outside the
        // family's range or equal to its neighbour whatever the pendulum
        if (!(parsed > previous && parsed < emax)) text = to_decimal(e);
        previous = parse_real<double>(text, "energy");
        out.push_back(text);
    }
    return out;
}

}  // namespace flipflux
