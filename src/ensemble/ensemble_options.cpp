// The ensemble's options: the integrator `auto` resolves to, the tolerance and work checks, and the
// chaos classification's threshold (see ensemble.hpp).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/ensemble/pendulum_taylor.hpp"  // ensemble_taylor_max_order
#include "flipflux/ensemble/taylor_ensemble.hpp"  // min_taylor_rtol, min_taylor_order

namespace flipflux {

integration_method resolved_method(integration_method method, double rtol) {
    if (method != integration_method::automatic) return method;
    return rtol < automatic_taylor_below ? integration_method::taylor : integration_method::dop853;
}

std::string rtol_problem(double rtol, const std::string& text, integration_method method) {
    method = resolved_method(method, rtol);
    const std::string shown = text.empty() ? to_decimal(rtol) : text;
    if (!(rtol > 0) || !(rtol <= 0.1)) return "'" + shown + "' is invalid (must be in (0, 0.1])";
    if (method == integration_method::taylor) {
        if (rtol < min_taylor_rtol)
            return "'" + shown + "' is below what double precision can meet (at least eps = " +
                   to_decimal(min_taylor_rtol) + " with taylor)";
    } else if (rtol < min_rtol) {
        return "'" + shown + "' is below what double precision can meet (at least 100 eps = " +
               to_decimal(min_rtol) + " with " + to_string(method) + "; taylor reaches eps)";
    }
    return {};
}

std::string taylor_order_problem(int order, integration_method method, double rtol,
                                 const std::string& text) {
    if (order == 0) return {};
    const std::string shown = text.empty() ? std::to_string(order) : text;
    if (order < min_taylor_order || order > ensemble_taylor_max_order)
        return "'" + shown + "' is invalid (0: automatic, or " + std::to_string(min_taylor_order) +
               " to " + std::to_string(ensemble_taylor_max_order) + ")";
    if (resolved_method(method, rtol) != integration_method::taylor)
        return "'" + shown + "' is the taylor integrator's order (the method is " +
               to_string(resolved_method(method, rtol)) + ")";
    return {};
}

void validate(const ensemble_options& o) {
    if (o.trajectories == 0)
        throw input_error::about("trajectories",
                                 "'0' is invalid (the number of trajectories must be > 0)");
    if (!std::isfinite(o.time) || !(o.time > 0))
        throw input_error::about("time",
                                 "'" + to_shortest_decimal(o.time) +
                                     "' is invalid (the integration time must be finite and > 0)");
    if (const std::string p = rtol_problem(o.rtol, "", o.method); !p.empty())
        throw input_error::about("rtol", p);
    if (const std::string p = taylor_order_problem(o.taylor_order, o.method, o.rtol); !p.empty())
        throw input_error::about("taylor_order", p);
    if (o.atol < 0 || !std::isfinite(o.atol))
        throw input_error::about("atol",
                                 "'" + to_shortest_decimal(o.atol) + "' is invalid (must be >= 0)");
    if (!std::isfinite(o.energy) || !(o.energy > 0))
        throw input_error::about(
            "energy", "'" + to_shortest_decimal(o.energy) + "' is invalid (must be > 0)");
    if (o.threads < 0)
        throw input_error::about("threads",
                                 "'" + std::to_string(o.threads) + "' is invalid (>= 0)");
    (void)checked_threads(static_cast<std::uint64_t>(o.threads), "threads");
    if (!std::isfinite(o.sample_interval) || o.sample_interval < 0)
        throw input_error::about("sample_interval", "'" + to_shortest_decimal(o.sample_interval) +
                                                        "' is invalid (must be >= 0)");
    if (!std::isfinite(o.chaos_threshold) || !(o.chaos_threshold > 0))
        throw input_error::about("chaos_threshold", "'" + to_shortest_decimal(o.chaos_threshold) +
                                                        "' is invalid (must be > 0)");
    if (o.first_index > std::numeric_limits<std::uint64_t>::max() - o.trajectories)
        throw input_error::about("first_index", "the index range overflows");
}

double turns_bound(const double_pendulum<double>& model, double energy, double time) {
    const auto& k = model.coefficients();
    const double m = mass_eigenvalue_range(k)[0];
    const double w = std::sqrt(2 * std::max(energy, 0.0) / m) + std::sqrt((k.alpha + k.beta) / m);
    return time * w / (2 * std::numbers::pi);
}

void check_trajectory_work(const double_pendulum<double>& model, double energy, double time,
                           const std::string& field, double epsilon) {
    check_conditioning(model.coefficients(), epsilon);
    const double turns = turns_bound(model, energy, time);
    if (!(turns <= max_turns_per_trajectory))
        throw input_error::about(
            field, "T = " + to_decimal(time) + " at E = " + to_decimal(energy) + " allows up to " +
                       to_decimal(turns, 3) + " turns of the arms per trajectory, more than " +
                       to_decimal(max_turns_per_trajectory) + " (docs/limits.md)");
}

double chaos_threshold_rate(const double_pendulum<double>& model, double threshold) {
    const auto& k = model.coefficients();
    return threshold * std::sqrt(k.alpha / k.A);
}

bool is_chaotic(const double_pendulum<double>& model, bool chaos, double threshold,
                double lyapunov) {
    return chaos && lyapunov > chaos_threshold_rate(model, threshold);
}

bool chaos_classification_reliable(const double_pendulum<double>& model, double threshold,
                                   double time) {
    const auto& k = model.coefficients();
    const double nu = std::sqrt(k.alpha / k.A);
    return std::log1p(time * nu) / time <= 0.25 * chaos_threshold_rate(model, threshold);
}

}  // namespace flipflux
