// The ensemble runner: one trajectory per index, OpenMP across indices (see ensemble.hpp).
#include "flipflux/ensemble/ensemble.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"

namespace flipflux {

std::string to_string(integration_method m) {
    return m == integration_method::dop853 ? "dop853" : "dopri5";
}

integration_method parse_integration_method(const std::string& text, const std::string& option) {
    if (text == "dop853") return integration_method::dop853;
    if (text == "dopri5") return integration_method::dopri5;
    throw input_error(option + ": '" + text + "' is not a method (dop853, dopri5)");
}

void validate(const ensemble_options& o) {
    if (o.trajectories == 0)
        throw input_error(
            "--trajectories: '0' is invalid (the number of trajectories must be > 0)");
    if (!std::isfinite(o.time) || !(o.time > 0))
        throw input_error("--time: '" + to_decimal(o.time) +
                          "' is invalid (the integration time must be finite and > 0)");
    if (!(o.rtol > 0) || !(o.rtol <= 0.1))
        throw input_error("--rtol: '" + to_decimal(o.rtol) + "' is invalid (must be in (0, 0.1])");
    if (o.atol < 0 || !std::isfinite(o.atol))
        throw input_error("--atol: '" + to_decimal(o.atol) + "' is invalid (must be >= 0)");
    if (!std::isfinite(o.energy) || !(o.energy > 0))
        throw input_error("--energy: '" + to_decimal(o.energy) + "' is invalid (must be > 0)");
    if (o.threads < 0)
        throw input_error("--threads: '" + std::to_string(o.threads) + "' is invalid (>= 0)");
    if (!std::isfinite(o.sample_interval) || o.sample_interval < 0)
        throw input_error("--sample-interval: '" + to_decimal(o.sample_interval) +
                          "' is invalid (must be >= 0)");
    if (!std::isfinite(o.chaos_threshold) || !(o.chaos_threshold > 0))
        throw input_error("--chaos-threshold: '" + to_decimal(o.chaos_threshold) +
                          "' is invalid (must be > 0)");
    if (o.first_index > std::numeric_limits<std::uint64_t>::max() - o.trajectories)
        throw input_error("--first-index: the index range overflows");
}

double chaos_threshold_rate(const double_pendulum<double>& model, double threshold) {
    const auto& k = model.coefficients();
    return threshold * std::sqrt(k.alpha / k.A);
}

bool chaos_classification_reliable(const double_pendulum<double>& model, double threshold,
                                   double time) {
    const auto& k = model.coefficients();
    const double nu = std::sqrt(k.alpha / k.A);
    return std::log1p(time * nu) / time <= 0.25 * chaos_threshold_rate(model, threshold);
}

namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2 * std::numbers::pi;

// Reduces an angle that left [-pi, pi] during one step; returns the shift applied.
// NOTE: a step moves an angle by far less than 2 pi, so |th| < 4 pi and th -/+ 2 pi is exact
// (Sterbenz); the loop handles anything else.
double reduction(double th) {
    double shift = 0;
    while (th + shift > pi)
        shift -= two_pi;
    while (th + shift < -pi)
        shift += two_pi;
    return shift;
}

template <class Integrator>
class dense_adapter final : public step_interpolant {
  public:
    explicit dense_adapter(Integrator& rk) : rk_(rk) {}
    std::array<double, 4> state(double t) const override {
        const auto y = rk_.dense(t);
        return {y[0], y[1], y[2], y[3]};
    }

  private:
    Integrator& rk_;
};

template <class Method, bool Tangent>
void integrate(const double_pendulum<double>& model, const ensemble_options& o,
               const phase_point<double>& x0, std::uint64_t index,
               const std::vector<flip_detector_base*>& detectors, trajectory_result& r) {
    const pendulum_flow flow(model);
    rk_options ro;
    ro.rtol = o.rtol;
    ro.atol = o.atol > 0 ? o.atol : o.rtol;
    ro.controlled_components = 4;
    constexpr std::size_t N = Tangent ? 8 : 4;
    using state = std::array<double, N>;
    auto rhs = [flow](double, const state& y) -> state {
        if constexpr (Tangent)
            return flow.tangent(y);
        else
            return flow(0.0, y);
    };
    using integrator = explicit_rk<Method, N, decltype(rhs)>;
    integrator rk(rhs, ro);
    state y{};
    for (int i = 0; i < 4; ++i)
        y[i] = x0[i];
    double log_growth = 0;
    if constexpr (Tangent) {
        // a random unit tangent vector from the trajectory's own stream
        philox_stream rng(o.seed, o.energy, index, random_purpose::tangent_vector);
        double norm2 = 0;
        for (int i = 4; i < 8; ++i) {
            y[i] = 2 * rng.uniform() - 1;
            norm2 += y[i] * y[i];
        }
        const double norm = std::sqrt(norm2);
        for (int i = 4; i < 8; ++i)
            y[i] /= norm;
    }
    rk.initialize(0, y);
    const auto first4 = [](const state& s) {
        return std::array<double, 4>{s[0], s[1], s[2], s[3]};
    };
    {
        const std::array<double, 4> xs = first4(rk.x()), fs = first4(rk.derivative());
        for (flip_detector_base* d : detectors)
            d->start(xs, fs);
    }
    std::vector<crossing> found;
    const dense_adapter<integrator> dense(rk);
    std::uint64_t next_sample = 0;
    auto record_samples = [&](double t_end) {
        while (o.sample_interval > 0) {
            const double ts = static_cast<double>(next_sample) * o.sample_interval;
            if (ts > t_end || ts > o.time) break;
            const std::array<double, 4> x = ts == rk.t() ? first4(rk.x()) : dense.state(ts);
            r.samples.push_back({ts, x[0], x[1], x[2], x[3]});
            ++next_sample;
        }
    };
    if (o.sample_interval > 0) {
        r.samples.push_back({0.0, x0[0], x0[1], x0[2], x0[3]});
        next_sample = 1;
    }
    const std::size_t nc = detectors.size();
    const double energy = flow.hamiltonian_absolute(x0);
    // NOTE: the energy check. An accepted step may not change H by more than
    // energy_jump_factor * (atol + rtol |E|): embedded error estimates occasionally pass a step
    // whose error is orders of magnitude above the tolerance (seen: DOP853 at rtol 1e-7 once in
    // ~1e7 steps, |dH| = 2e4 tol), and such a step is retried with half its size. Normal steps
    // change H by 0.02 tol(1 + E) (median), 6-16 tol(1 + E) at the 1e-4 quantile.
    const double jump = energy_jump_factor * (ro.atol + ro.rtol * std::abs(energy));
    double h_start = energy, h_end = energy;
    rk.set_step_check([&](const state&, const state& x_new) {
        const double e = flow.hamiltonian_absolute(first4(x_new));
        if (!(std::abs(e - h_start) <= jump)) return false;
        h_end = e;
        return true;
    });
    r.status = rk_status::ok;
    while (rk.t() < o.time) {
        if (o.stop != nullptr && o.stop->load(std::memory_order_relaxed) != 0) {
            r.abandoned = true;
            break;
        }
        const rk_status s = rk.step(o.time);
        if (s != rk_status::ok) {
            r.status = s;
            break;
        }
        const std::array<double, 4> x1 = first4(rk.x()), f1 = first4(rk.derivative());
        const step_view view{rk.t_previous(), rk.t(), x1, f1, dense};
        record_samples(rk.t());
        for (std::size_t c = 0; c < nc; ++c) {
            found.clear();
            if (detectors[c]->step(view, found) > 0) {
                for (const crossing& x : found)
                    r.crossing_times[c].push_back(x.time);
                if (o.keep_crossings)
                    r.crossings[c].insert(r.crossings[c].end(), found.begin(), found.end());
            }
        }
        // h_end = H(x1), evaluated by the energy check
        r.max_energy_drift = std::max(r.max_energy_drift, std::abs(h_end - energy));
        h_start = h_end;
        const double d1 = reduction(x1[0]), d2 = reduction(x1[1]);
        if (d1 != 0 || d2 != 0) {
            state delta{};
            delta[0] = d1;
            delta[1] = d2;
            rk.translate(delta);
            for (flip_detector_base* d : detectors)
                d->shift(d1, d2);
        }
        if constexpr (Tangent) {
            double norm2 = 0;
            for (int i = 4; i < 8; ++i)
                norm2 += rk.x()[i] * rk.x()[i];
            // renormalise by a power of two (exact) when |v| leaves [2^-400, 2^400]
            if (norm2 > 0x1.0p800 || (norm2 < 0x1.0p-800 && norm2 > 0)) {
                const int e = std::ilogb(norm2) / 2;
                rk.rescale_tail(4, std::ldexp(1.0, -e));
                log_growth += e * std::numbers::ln2;
            }
        }
    }
    r.end_time = rk.t();
    r.steps = rk.accepted_steps();
    r.rejected_steps = rk.rejected_steps();
    r.evaluations = rk.evaluations();
    r.energy_check_rejections = rk.check_rejections();
    if constexpr (Tangent) {
        double norm2 = 0;
        for (int i = 4; i < 8; ++i)
            norm2 += rk.x()[i] * rk.x()[i];
        r.lyapunov = r.end_time > 0 ? (log_growth + 0.5 * std::log(norm2)) / r.end_time
                                    : std::numeric_limits<double>::quiet_NaN();
    } else {
        r.lyapunov = std::numeric_limits<double>::quiet_NaN();
    }
}

}  // namespace

trajectory_result simulate_trajectory(const double_pendulum<double>& model,
                                      const phase_point<double>& x0, const ensemble_options& o,
                                      std::uint64_t index,
                                      const std::vector<flip_detector_base*>& detectors) {
    trajectory_result r;
    r.index = index;
    r.initial_state = x0;
    r.crossing_times.resize(detectors.size());
    if (o.keep_crossings) r.crossings.resize(detectors.size());
    if (o.method == integration_method::dop853) {
        if (o.chaos)
            integrate<dormand_prince_853, true>(model, o, x0, index, detectors, r);
        else
            integrate<dormand_prince_853, false>(model, o, x0, index, detectors, r);
    } else {
        if (o.chaos)
            integrate<dormand_prince_5, true>(model, o, x0, index, detectors, r);
        else
            integrate<dormand_prince_5, false>(model, o, x0, index, detectors, r);
    }
    r.chaotic = o.chaos && r.lyapunov > chaos_threshold_rate(model, o.chaos_threshold);
    return r;
}

trajectory_result run_trajectory(const double_pendulum<double>& model,
                                 const microcanonical_sampler& sampler, const ensemble_options& o,
                                 std::uint64_t index,
                                 const std::vector<flip_detector_base*>& detectors) {
    return simulate_trajectory(model, sampler.sample(o.seed, index), o, index, detectors);
}

batch_outcome run_trajectories(const double_pendulum<double>& model, const ensemble_options& o,
                               const std::vector<ensemble_criterion>& criteria,
                               std::span<const std::uint64_t> indices,
                               const std::function<void(trajectory_result&&)>& finished) {
    {
        ensemble_options checked = o;  // the count and first index are not used here
        checked.trajectories = 1;
        checked.first_index = 0;
        validate(checked);
    }
    for (const ensemble_criterion& c : criteria)
        if (!c.detector)
            throw std::invalid_argument("run_trajectories: criterion without detector");
    const microcanonical_sampler sampler(model, o.energy);
    const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
    std::exception_ptr failure;
    const auto n = static_cast<std::int64_t>(indices.size());
    int used = 1;
    bool interrupted = false;
    auto stopped = [&o] { return o.stop != nullptr && o.stop->load(std::memory_order_relaxed); };
#pragma omp parallel num_threads(threads)
    {
#pragma omp single
        used = omp_get_num_threads();
        std::vector<std::unique_ptr<flip_detector_base>> own;
        std::vector<flip_detector_base*> detectors;
        for (const ensemble_criterion& c : criteria) {
            own.push_back(c.detector->clone());
            detectors.push_back(own.back().get());
        }
#pragma omp for schedule(dynamic, 1)
        for (std::int64_t i = 0; i < n; ++i) {
            if (stopped()) {
#pragma omp atomic write
                interrupted = true;
                continue;
            }
            try {
                trajectory_result r = run_trajectory(
                    model, sampler, o, indices[static_cast<std::size_t>(i)], detectors);
                if (r.abandoned) {
#pragma omp atomic write
                    interrupted = true;
                } else {
#pragma omp critical(flipflux_ensemble_finished)
                    finished(std::move(r));
                }
            } catch (...) {
#pragma omp critical(flipflux_ensemble_failure)
                if (!failure) failure = std::current_exception();
            }
        }
    }
    if (failure) std::rethrow_exception(failure);
    return {used, interrupted};
}

ensemble_result run_ensemble(const double_pendulum<double>& model, const ensemble_options& o,
                             const std::vector<ensemble_criterion>& criteria) {
    validate(o);
    const auto start = std::chrono::steady_clock::now();
    ensemble_result result;
    result.energy = o.energy;
    result.time = o.time;
    result.rtol = o.rtol;
    result.atol = o.atol > 0 ? o.atol : o.rtol;
    result.chaos_threshold = o.chaos_threshold;
    result.seed = o.seed;
    result.first_index = o.first_index;
    result.method = o.method;
    result.chaos = o.chaos;
    for (const ensemble_criterion& c : criteria)
        result.criteria.push_back(c.name);
    result.trajectories.resize(o.trajectories);
    std::vector<std::uint64_t> indices(o.trajectories);
    for (std::uint64_t i = 0; i < o.trajectories; ++i)
        indices[i] = o.first_index + i;
    std::uint64_t finished = 0;
    const batch_outcome b =
        run_trajectories(model, o, criteria, indices, [&](trajectory_result&& r) {
            const std::uint64_t k = r.index - o.first_index;
            result.trajectories[k] = std::move(r);
            if (o.progress) o.progress(++finished, o.trajectories);
        });
    if (b.interrupted) throw std::runtime_error("run_ensemble: interrupted");
    result.threads = b.threads;
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return result;
}

}  // namespace flipflux
