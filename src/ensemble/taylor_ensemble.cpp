// The ensemble's Taylor integrator: lanes, steps and the per-thread runner
// (include/flipflux/ensemble/taylor_ensemble.hpp explains the method).
#include "flipflux/ensemble/taylor_ensemble.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <numbers>

#include "flipflux/core/budget.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/ensemble/pendulum_taylor.hpp"
#include "flipflux/ensemble/random.hpp"
#include "flipflux/ensemble/sampler.hpp"
#include "lane_common.hpp"

// pendulum_taylor.hpp's vector helpers are inlined into the target-specific jets_* (see there).
#pragma GCC diagnostic ignored "-Wpsabi"

namespace flipflux {

int ensemble_taylor_order(double rtol, bool tangent) {
    const double L = -std::log(std::clamp(rtol, min_taylor_rtol, 0.1));
    const double kappa = tangent ? taylor_step_overhead_tangent : taylor_step_overhead;
    const auto cost = [&](int p) { return (kappa + p * p) * std::exp(L / p); };
    int p = min_taylor_order;  // the cost falls, then rises (one minimum): descend to it
    while (p < ensemble_taylor_max_order && cost(p + 1) < cost(p))
        ++p;
    return p;
}

int ensemble_taylor_order(const ensemble_options& o) {
    return o.taylor_order > 0 ? o.taylor_order : ensemble_taylor_order(o.rtol, o.chaos);
}

namespace detail {
namespace {

constexpr double pi = std::numbers::pi;
constexpr double two_pi = 2 * std::numbers::pi;
constexpr double eps = std::numeric_limits<double>::epsilon();

using detail::angle_reduction;

// 2^y and log2(r) in vectors, to ~1e-6 relative: the step size's powers (tol / ||x_j||)^(1/j),
// a heuristic that needs no more (Jorba & Zou's safety factor is 1 - 0.7 / (p - 1)), in plain
// arithmetic: the same bits in every lane, instruction set and process (libm's pow is neither
// vectorised nor the same function on every processor). log2: r = m 2^e, m in [1, 2), log2 m =
// (2 / ln 2) atanh((m - 1) / (m + 1)) by its series to t^9 (|t| <= 1/3: error < 3e-6); exp2:
// y = n + f, |f| <= 1/2, 2^f = e^(f ln 2) by its series to degree 9 (error < 2e-11), n added to
// the exponent. r is clamped to [2^-1000, 2^1000] and y to [-1000, 1000].
template <class V>
[[gnu::always_inline]] inline V approx_log2(V r) {
    using L = typename lane_mask<V>::type;
    r = r < 0x1p-1000 ? V{} + 0x1p-1000 : r;
    r = r > 0x1p1000 ? V{} + 0x1p1000 : r;
    const L bits = reinterpret_cast<L>(r);
    const L e = ((bits >> 52) & 0x7ff) - 1023;
    const V m = reinterpret_cast<V>((bits & 0x000fffffffffffffLL) | 0x3ff0000000000000LL);
    const V t = (m - 1.0) / (m + 1.0);
    const V t2 = t * t;
    const V series = t * (1.0 + t2 * (1.0 / 3 + t2 * (1.0 / 5 + t2 * (1.0 / 7 + t2 * (1.0 / 9)))));
    return __builtin_convertvector(e, V) + (2 / std::numbers::ln2) * series;
}
template <class V>
[[gnu::always_inline]] inline V approx_exp2(V y) {
    using L = typename lane_mask<V>::type;
    y = y < -1000.0 ? V{} - 1000.0 : y;
    y = y > 1000.0 ? V{} + 1000.0 : y;
    constexpr double shifter = 0x1.8p52;
    const V shifted = y + shifter;
    const V n = shifted - shifter;
    const V f = (y - n) * std::numbers::ln2;
    V q = 1.0 + f * (1.0 / 9);
    for (int k = 8; k >= 1; --k)
        q = 1.0 + (f * (1.0 / k)) * q;
    const L ni = (reinterpret_cast<L>(shifted) & 0xfffffffffffffLL) - (1LL << 51);
    return reinterpret_cast<V>(reinterpret_cast<L>(q) + (ni << 52));
}

/// out[i] = sum_k c[i][k] h^k (Horner, k = 0..p) in every lane, lane by lane the scalar
/// horner's bits; the N sums interleaved, so that their chains of dependent operations overlap.
template <class V, int N, std::size_t K>
[[gnu::always_inline]] inline void horner_lanes(const V (&c)[N][K], int p, V h, V* out) {
    V r[N];
    for (int i = 0; i < N; ++i)
        r[i] = c[i][p];
    for (int k = p - 1; k >= 0; --k)
        for (int i = 0; i < N; ++i)
            r[i] = r[i] * h + c[i][k];
    for (int i = 0; i < N; ++i)
        out[i] = r[i];
}

/// A group's step ends: per lane the step size h (`last`: 1 when it is the remaining time), the
/// state x1 at t + h, the right-hand side f1 and H there, with Tangent the tangent vector, and
/// each angle's range over the step (taylor_angle_range: range[i] = {lo, hi} of th_{i+1}).
template <class V, bool Tangent>
struct group_end {
    V h, last, x1[4], f1[4], e1, v1[Tangent ? 4 : 1], range[2][2];
};

template <class V, bool Tangent>
[[gnu::always_inline]] inline void end_of_step(const pendulum_jet<V, Tangent>& jet, int p,
                                               const V& tol, const V& remaining, double safety,
                                               const pendulum_flow& flow,
                                               group_end<V, Tangent>& out) {
    const V inf = V{} + std::numeric_limits<double>::infinity();
    V h = inf;
    for (int j = p - 1; j <= p; ++j) {
        V nj = V{};
        for (int c = 0; c < 4; ++c) {
            const V a = jet.x[c][j] < 0 ? -jet.x[c][j] : jet.x[c][j];
            nj = a > nj ? a : nj;
        }
        const V candidate = nj > 0 ? approx_exp2(approx_log2(tol / nj) * (1.0 / j)) : inf;
        h = candidate < h ? candidate : h;
    }
    h = h * safety;
    const auto last = !(h < remaining);
    out.h = last ? remaining : h;
    out.last = last ? V{} + 1.0 : V{};
    horner_lanes(jet.x, p, out.h, out.x1);
    if constexpr (Tangent) horner_lanes(jet.v, p, out.h, out.v1);
    flow.lanes(out.x1, out.f1);
    flow.hamiltonian_lanes(out.x1, out.e1);
    const V* const angles[2] = {jet.x[0], jet.x[1]};
    V lo[2], hi[2];
    taylor_angle_ranges(angles, p, out.h, lo, hi);
    for (int i = 0; i < 2; ++i) {
        out.range[i][0] = lo[i];
        out.range[i][1] = hi[i];
    }
}

// The angles' ranges over a step of size h of lane l of a jet<V, Tangent> (scalar
// taylor_angle_ranges, the bits of the vector one): after the energy check halved the step.
template <class V, bool Tangent>
std::array<std::array<double, 2>, 2> jet_lane_ranges(const void* jet, int l, int p, double h) {
    const auto& j = *static_cast<const pendulum_jet<V, Tangent>*>(jet);
    double c[2][ensemble_taylor_max_order + 1] = {};
    for (int i = 0; i < 2; ++i)
        for (int k = 0; k <= p; ++k)
            c[i][k] = j.x[i][k][l];
    const double* const angles[2] = {c[0], c[1]};
    double lo[2], hi[2];
    taylor_angle_ranges(angles, p, h, lo, hi);
    return {{{lo[0], hi[0]}, {lo[1], hi[1]}}};
}

// The dense output of lane l of a jet<V, Tangent>: the state's (or the tangent's) polynomial at
// tau (scalar horner, the bits of horner_lanes).
template <class V, bool Tangent>
std::array<double, 4> jet_lane_value(const void* jet, int l, int p, double tau, bool tangent) {
    const auto& j = *static_cast<const pendulum_jet<V, Tangent>*>(jet);
    const auto& x = Tangent && tangent ? j.v : j.x;
    std::array<double, 4> out{};
    for (int c = 0; c < 4; ++c)
        out[c] = x[c][p][l];
    for (int k = p - 1; k >= 0; --k)  // the four sums interleaved (their chains overlap)
        for (int c = 0; c < 4; ++c)
            out[c] = out[c] * tau + x[c][k][l];
    return out;
}

// One trajectory advanced by Taylor steps: its jet and step end are computed in a vector group
// (run_group), the rest (energy check, detectors, samples, reduction) here, scalar.
template <bool Tangent>
class taylor_lane final : public step_interpolant {
  public:
    taylor_lane(const double_pendulum<double>& model, const ensemble_options& o,
                const phase_point<double>& x0, std::uint64_t index,
                const std::vector<flip_detector_base*>& detectors, int order)
        : o_(o),
          flow_(model),
          model_(model),
          detectors_(detectors),
          p_(order),
          quiet_bound_(quiet_bounds(detectors)) {
        r_.index = index;
        r_.initial_state = x0;
        r_.crossing_times.resize(detectors.size());
        if (o.keep_crossings) r_.crossings.resize(detectors.size());
        for (int i = 0; i < 4; ++i)
            x_[i] = x0[i];
        // the initial angles reduced to [-pi, pi] (by the nearest multiple of 2 pi, then
        // exactly), so that H and the energy check start from the state that is integrated: an
        // angle of 1000 rad reduced by repeated 2 pi steps after the first step moved H by
        // ~1e-12, beyond the check's allowance at rtol = eps (every retry refused)
        for (int i = 0; i < 2; ++i) {
            if (!(std::abs(x_[i]) > pi) || !std::isfinite(x_[i])) continue;
            const double coarse = -two_pi * std::nearbyint(x_[i] / two_pi);
            x_[i] += coarse;
            const double fine = angle_reduction(x_[i]);
            x_[i] += fine;
            if (o.unwrapped_angles) unwrap_[i] += coarse + fine;
        }
        if constexpr (Tangent) {
            v_ = initial_tangent(o, index);  // the RK lanes' (the trajectory's own stream)
        }
        rtol_ = o.rtol;
        atol_ = effective_atol(o);
        safety_ = std::exp(-0.7 / (p_ - 1));
        f_ = flow_(0.0, x_);
        for (flip_detector_base* d : detectors_)
            d->start(x_, f_);
        if (o.sample_interval > 0) {
            r_.samples.push_back({0.0, x0[0], x0[1], x0[2], x0[3]});
            next_sample_ = 1;
        }
        energy_ = h_start_ = flow_.hamiltonian_absolute(x_);
        jump_ = energy_jump_factor * (atol_ + rtol_ * std::abs(energy_)) +
                64 * eps * (1 + std::abs(energy_));
        r_.status = rk_status::ok;
        if (!(t_ < o_.time)) finish();
    }
    taylor_lane(const taylor_lane&) = delete;
    taylor_lane& operator=(const taylor_lane&) = delete;

    /// Whether the trajectory takes another step (false: finished, failed or abandoned).
    bool begin() {
        if (done_) return false;
        if (o_.stop != nullptr && o_.stop->load(std::memory_order_relaxed) != 0) {
            r_.abandoned = true;
            finish();
            return false;
        }
        if (!std::isfinite(x_[0]) || !std::isfinite(x_[1]) || !(std::abs(x_[0]) <= 524288.0) ||
            !(std::abs(x_[1]) <= 524288.0)) {
            r_.status = rk_status::non_finite;
            finish();
            return false;
        }
        return true;
    }
    /// The order-0 coefficients of lane l of a jet: this trajectory's state.
    template <class V>
    void load(pendulum_jet<V, Tangent>& jet, int l) const {
        for (int c = 0; c < 4; ++c) {
            jet.x[c][0][l] = x_[c];
            if constexpr (Tangent) jet.v[c][0][l] = v_[c];
        }
    }
    /// Lane l of a group's computed jet and step ends: the step.
    template <class V>
    void take(const pendulum_jet<V, Tangent>& jet, const group_end<V, Tangent>& g, int l) {
        jet_ = &jet;
        lane_ = l;
        value_ = jet_lane_value<V, Tangent>;
        ranges_of_ = jet_lane_ranges<V, Tangent>;
        std::array<double, 4> x1{}, f1{}, v1{};
        for (int c = 0; c < 4; ++c) {
            x1[c] = g.x1[c][l];
            f1[c] = g.f1[c][l];
            if constexpr (Tangent) v1[c] = g.v1[c][l];
        }
        std::array<std::array<double, 2>, 2> ranges{};
        for (int i = 0; i < 2; ++i)
            ranges[i] = {g.range[i][0][l], g.range[i][1][l]};
        step(g.h[l], g.last[l] != 0, x1, f1, g.e1[l], v1, ranges);
    }
    /// The tolerance of the step-size rule (see taylor_ensemble.hpp) and the time left.
    double tolerance() const {
        double n0 = 0;
        for (int c = 0; c < 4; ++c)
            n0 = std::max(n0, std::abs(x_[c]));
        return std::max(atol_, rtol_ * n0);
    }
    double remaining() const { return o_.time - t_; }
    double safety() const { return safety_; }
    bool finished() const { return done_; }
    trajectory_result& result() { return r_; }

    /// The dense output: the step's Taylor polynomial at t in [t0, t1].
    std::array<double, 4> state(double t) const override {
        return value_(jet_, lane_, p_, t - t_, false);
    }

  private:
    void step(double h, bool last, std::array<double, 4> x1, std::array<double, 4> f1, double e,
              std::array<double, 4> v1, std::array<std::array<double, 2>, 2> ranges) {
        if (std::isnan(h)) return fail(rk_status::non_finite);
        for (bool first = true;; first = false) {
            if (!first) {  // the energy check refused the step: half of it, scalar
                ++check_rejections_;
                h *= 0.5;
                last = false;
                if (!(h > 16 * eps * std::max(1.0, std::abs(t_))))
                    return fail(rk_status::step_size_underflow);
                x1 = value_(jet_, lane_, p_, h, false);
                if constexpr (Tangent) v1 = value_(jet_, lane_, p_, h, true);
                f1 = flow_(0.0, x1);
                e = flow_.hamiltonian_absolute(x1);
                ranges = ranges_of_(jet_, lane_, p_, h);
            }
            bool finite = std::isfinite(e);
            for (double y : x1)
                finite = finite && std::isfinite(y);
            if (!finite) return fail(rk_status::non_finite);
            if (std::abs(e - h_start_) <= jump_) break;
        }
        h_end_ = e;
        const double t0 = t_, t1 = last ? o_.time : t_ + h;
        record_samples(t1, x1);
        if (ranges_are_quiet(quiet_bound_, ranges)) {
            skip_detectors(detectors_, skipped_);
        } else {
            skipped_ = false;
            step_samples samples;  // the examinations' shared samples of this step
            step_view view{t0, t1, x_, f_, x1, f1, *this, &ranges};
            view.samples = &samples;
            detect(detectors_, view, o_.keep_crossings, found_, r_);
        }
        ++steps_;
        r_.max_energy_drift = std::max(r_.max_energy_drift, std::abs(h_end_ - energy_));
        h_start_ = h_end_;
        if constexpr (Tangent) v_ = v1;
        t_ = t1;
        x_ = x1;
        f_ = f1;
        const double d1 = angle_reduction(x_[0]), d2 = angle_reduction(x_[1]);
        if (d1 != 0 || d2 != 0) {
            if (o_.unwrapped_angles) {
                unwrap_[0] += d1;
                unwrap_[1] += d2;
            }
            x_[0] += d1;
            x_[1] += d2;
            for (flip_detector_base* d : detectors_)
                d->shift(d1, d2);
        }
        if constexpr (Tangent) {
            double norm2 = 0;
            for (double y : v_)
                norm2 += y * y;
            // renormalise by a power of two (exact) when |v| leaves [2^-400, 2^400]
            if (const int e = tangent_rescaling(norm2, log_growth_); e != 0)
                for (double& y : v_)
                    y = std::ldexp(y, -e);
        }
        if (!(t_ < o_.time)) finish();
    }

    void record_samples(double t_end, const std::array<double, 4>& x1) {
        while (o_.sample_interval > 0) {
            const double ts = static_cast<double>(next_sample_) * o_.sample_interval;
            if (ts > t_end || ts > o_.time) break;
            const std::array<double, 4> x = ts == t_end ? x1 : state(ts);
            r_.samples.push_back({ts, x[0] - unwrap_[0], x[1] - unwrap_[1], x[2], x[3]});
            ++next_sample_;
        }
    }

    void fail(rk_status s) {
        r_.status = s;
        finish();
    }

    void finish() {
        done_ = true;
        r_.end_time = t_;
        r_.final_state = {x_[0] - unwrap_[0], x_[1] - unwrap_[1], x_[2], x_[3]};
        r_.steps = steps_;
        r_.rejected_steps = check_rejections_;
        r_.evaluations = steps_ + (r_.status == rk_status::ok ? 0 : 1);
        r_.energy_check_rejections = check_rejections_;
        if constexpr (Tangent) {
            double norm2 = 0;
            for (double y : v_)
                norm2 += y * y;
            r_.lyapunov = t_ > 0 ? (log_growth_ + 0.5 * std::log(norm2)) / t_
                                 : std::numeric_limits<double>::quiet_NaN();
        } else {
            r_.lyapunov = std::numeric_limits<double>::quiet_NaN();
        }
    }

    const ensemble_options& o_;
    pendulum_flow flow_;
    const double_pendulum<double>& model_;
    std::vector<flip_detector_base*> detectors_;
    int p_;
    double rtol_ = 0, atol_ = 0, safety_ = 1;
    double t_ = 0;
    std::array<double, 4> x_{}, v_{};
    std::array<double, 4> f_{};  ///< Hamilton's equations at x_ (the detectors' step start)
    /// per angle (th1, th2), the widest prefilter bound of its detectors (-1: none tests it)
    const std::array<double, 2> quiet_bound_;
    // the current step's jet (in its group's buffer) and its dense output
    const void* jet_ = nullptr;
    int lane_ = 0;
    std::array<double, 4> (*value_)(const void*, int, int, double, bool) = nullptr;
    std::array<std::array<double, 2>, 2> (*ranges_of_)(const void*, int, int, double) = nullptr;
    trajectory_result r_;
    std::vector<crossing> found_;
    std::uint64_t next_sample_ = 0;
    std::array<double, 2> unwrap_{};
    double energy_ = 0, jump_ = 0, h_start_ = 0, h_end_ = 0, log_growth_ = 0;
    long steps_ = 0, check_rejections_ = 0;
    bool done_ = false;
    /// the detectors have been told of a quiet step since they last saw one
    bool skipped_ = false;
};

// The jets of a group of lanes, in the widest vectors of the instruction set (`flatten`
// inlines the recurrences, so that all of them are compiled for it; no FMA is enabled).
// The inputs of a group's step: the lanes' tolerances and remaining times.
template <class V>
struct group_start {
    V tol, remaining;
    double safety;
};
template <bool Tangent>
void jets_sse2(pendulum_jet<v2d, Tangent>& jet, const pendulum_flow& flow, int p,
               const group_start<v2d>& in, group_end<v2d, Tangent>& out) {
    jet.compute(flow.coefficients(), p);
    end_of_step(jet, p, in.tol, in.remaining, in.safety, flow, out);
}
template <bool Tangent>
__attribute__((target("avx2"), flatten)) void jets_avx2(pendulum_jet<v4d, Tangent>& jet,
                                                        const pendulum_flow& flow, int p,
                                                        const group_start<v4d>& in,
                                                        group_end<v4d, Tangent>& out) {
    jet.compute(flow.coefficients(), p);
    end_of_step(jet, p, in.tol, in.remaining, in.safety, flow, out);
}
template <bool Tangent>
__attribute__((target("avx512f"), flatten)) void jets_avx512(pendulum_jet<v8d, Tangent>& jet,
                                                             const pendulum_flow& flow, int p,
                                                             const group_start<v8d>& in,
                                                             group_end<v8d, Tangent>& out) {
    jet.compute(flow.coefficients(), p);
    end_of_step(jet, p, in.tol, in.remaining, in.safety, flow, out);
}

// One thread's jet buffers, one per vector width (groups of one width reuse theirs: each
// lane's steps, and its detectors' reads of the dense output, end before the next group's jets).
template <bool Tangent>
struct jet_buffers {
    std::unique_ptr<pendulum_jet<v2d, Tangent>> j2 = std::make_unique<pendulum_jet<v2d, Tangent>>();
    std::unique_ptr<pendulum_jet<v4d, Tangent>> j4 = std::make_unique<pendulum_jet<v4d, Tangent>>();
    std::unique_ptr<pendulum_jet<v8d, Tangent>> j8;
};

// The lanes active[0, g) (g <= W) in one vector group: load (a short group padded with its
// first lane), compute the jets and step ends, take.
template <bool Tangent, class V, class Compute>
void run_group(taylor_lane<Tangent>* const* active, std::size_t g, pendulum_jet<V, Tangent>& jet,
               const pendulum_flow& flow, int p, Compute compute) {
    constexpr std::size_t W = lanes_of<V>;
    std::array<double, W> tol{}, remaining{};
    for (std::size_t l = 0; l < W; ++l) {
        const taylor_lane<Tangent>* lane = active[l < g ? l : 0];
        lane->load(jet, static_cast<int>(l));
        tol[l] = lane->tolerance();
        remaining[l] = lane->remaining();
    }
    group_start<V> in;
    std::memcpy(&in.tol, tol.data(), sizeof(V));
    std::memcpy(&in.remaining, remaining.data(), sizeof(V));
    in.safety = active[0]->safety();
    group_end<V, Tangent> out;
    compute(jet, flow, p, in, out);
    for (std::size_t l = 0; l < g; ++l)
        active[l]->take(jet, out, static_cast<int>(l));
}

// One step of every unfinished lane.
template <bool Tangent>
void run_round(std::span<taylor_lane<Tangent>* const> lanes, vector_isa isa,
               jet_buffers<Tangent>& buf, const pendulum_flow& k, int p) {
    std::array<taylor_lane<Tangent>*, 8> active{};
    std::size_t m = 0;
    for (taylor_lane<Tangent>* l : lanes)
        if (l != nullptr && l->begin()) active[m++] = l;
    if (m > 4 && isa == vector_isa::avx512) {
        if (!buf.j8) buf.j8 = std::make_unique<pendulum_jet<v8d, Tangent>>();
        run_group(active.data(), m, *buf.j8, k, p, jets_avx512<Tangent>);
        return;
    }
    const bool wide = m > 2 && isa != vector_isa::sse2;
    const std::size_t W = wide ? 4 : 2;
    for (std::size_t i = 0; i < m; i += W) {
        const std::size_t g = std::min(W, m - i);
        if (wide)
            run_group(active.data() + i, g, *buf.j4, k, p, jets_avx2<Tangent>);
        else
            run_group(active.data() + i, g, *buf.j2, k, p, jets_sse2<Tangent>);
    }
}

template <bool Tangent>
void run_lanes(const double_pendulum<double>& model, const ensemble_options& o,
               const microcanonical_sampler& sampler, lane_detectors& detectors, vector_isa isa,
               std::size_t count, const std::function<bool(std::uint64_t&)>& next_index,
               const std::function<void(trajectory_result&)>& deliver) {
    using lane_type = taylor_lane<Tangent>;
    const int p = ensemble_taylor_order(o);  // o.chaos == Tangent
    const pendulum_flow k(model);
    jet_buffers<Tangent> buf;
    refill_lanes<lane_type, 8>(
        std::min<std::size_t>(count, 8),
        [&](std::uint64_t index, std::size_t l) {
            return std::make_unique<lane_type>(model, o, initial_state_of(sampler, o, index), index,
                                               detectors[l], p);
        },
        next_index, deliver,
        [&](std::span<lane_type* const> view) { run_round<Tangent>(view, isa, buf, k, p); });
}

template <bool Tangent>
trajectory_result one_trajectory(const double_pendulum<double>& model,
                                 const phase_point<double>& x0, const ensemble_options& o,
                                 std::uint64_t index,
                                 const std::vector<flip_detector_base*>& detectors) {
    const int p = ensemble_taylor_order(o);  // o.chaos == Tangent
    const pendulum_flow k(model);
    jet_buffers<Tangent> buf;
    taylor_lane<Tangent> l(model, o, x0, index, detectors, p);
    taylor_lane<Tangent>* const one[1] = {&l};
    while (!l.finished()) {
        check_cpu_budget();  // a bounded caller's (e.g. a scene's trajectory step)
        run_round<Tangent>(one, vector_isa::sse2, buf, k, p);
    }
    return std::move(l.result());
}

}  // namespace

void run_taylor_lanes(const double_pendulum<double>& model, const ensemble_options& o,
                      const microcanonical_sampler& sampler, lane_detectors& detectors,
                      vector_isa isa, std::size_t count,
                      const std::function<bool(std::uint64_t&)>& next_index,
                      const std::function<void(trajectory_result&)>& deliver) {
    if (o.chaos)
        run_lanes<true>(model, o, sampler, detectors, isa, count, next_index, deliver);
    else
        run_lanes<false>(model, o, sampler, detectors, isa, count, next_index, deliver);
}

trajectory_result taylor_trajectory(const double_pendulum<double>& model,
                                    const phase_point<double>& x0, const ensemble_options& o,
                                    std::uint64_t index,
                                    const std::vector<flip_detector_base*>& detectors) {
    return o.chaos ? one_trajectory<true>(model, x0, o, index, detectors)
                   : one_trajectory<false>(model, x0, o, index, detectors);
}

}  // namespace detail
}  // namespace flipflux
