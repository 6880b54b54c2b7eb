// The microcanonical sampler (paper Sec. 5.3); derivation in include/flipflux/ensemble/sampler.hpp
// and docs/theory.md#ensembles.
#include "flipflux/ensemble/sampler.hpp"

#include <cmath>
#include <numbers>
#include <string>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"

namespace flipflux {
namespace {

// Half-width of the interval of th with 2 k sin^2(th/2) < E (the whole circle when E >= 2 k).
// NOTE: widened by 1e-12 relative so that rounding never cuts off an accessible sliver; the
// rejection test V < E decides membership exactly.
double half_width(double energy, double k) {
    const double r = energy / (2 * k);
    if (r >= 1) return std::numbers::pi;
    return std::min(std::numbers::pi, 2 * std::asin(std::sqrt(r)) * (1 + 1e-12));
}

}  // namespace

microcanonical_sampler::microcanonical_sampler(const double_pendulum<double>& model, double energy)
    : model_(model), energy_(energy) {
    if (!std::isfinite(energy) || !(energy > 0))
        throw input_error::about(
            "energy", "'" + to_shortest_decimal(energy) +
                          "' is invalid (the microcanonical ensemble needs a finite E > 0)");
    const auto& k = model.coefficients();
    box_ = {half_width(energy, k.alpha), half_width(energy, k.beta)};
}

std::array<double, 2> microcanonical_sampler::sample_configuration(philox_stream& rng) const {
    const auto& k = model_.coefficients();
    const double det_max = k.D0 + k.C * k.C;
    for (;;) {
        const double th1 = box_[0] * (2 * rng.uniform() - 1);
        const double th2 = box_[1] * (2 * rng.uniform() - 1);
        const double u = rng.uniform();
        if (!(model_.potential(th1, th2) < energy_)) continue;
        if (u * u * det_max < model_.mass_determinant(th1, th2)) return {th1, th2};
    }
}

phase_point<double> microcanonical_sampler::with_momenta(double th1, double th2,
                                                         double angle) const {
    const auto& k = model_.coefficients();
    const double K = energy_ - model_.potential(th1, th2);
    const double r = std::sqrt(2 * std::max(K, 0.0));
    const double y1 = r * std::cos(angle), y2 = r * std::sin(angle);
    // R = [[sqrt A, 0], [C c / sqrt A, sqrt(det M / A)]], R R^T = M
    const double sa = std::sqrt(k.A);
    const double c = std::cos(th1 - th2);
    const double r22 = std::sqrt(model_.mass_determinant(th1, th2) / k.A);
    return {th1, th2, sa * y1, k.C * c / sa * y1 + r22 * y2};
}

phase_point<double> microcanonical_sampler::operator()(philox_stream& rng) const {
    const std::array<double, 2> th = sample_configuration(rng);
    const double angle = 2 * std::numbers::pi * rng.uniform();
    return with_momenta(th[0], th[1], angle);
}

phase_point<double> microcanonical_sampler::sample(std::uint64_t seed, std::uint64_t index) const {
    philox_stream rng(seed, energy_, index);
    return (*this)(rng);
}

}  // namespace flipflux
