// The ensemble runner: one trajectory per index, OpenMP across indices (see ensemble.hpp).
#include "flipflux/ensemble/ensemble.hpp"

#include <immintrin.h>
#include <omp.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <limits>
#include <numbers>
#include <utility>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/limits.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/ensemble/taylor_ensemble.hpp"
#include "lane_common.hpp"

namespace flipflux {

namespace {

// The most trajectories a thread advances in lockstep (lanes_per_thread: 16 with AVX-512).
constexpr std::size_t max_lanes = max_thread_lanes;

using detail::angle_reduction;

// A lane's dense output of its last accepted step, as the detectors see it: the lane loads the
// step's stages into its integrator on first use (lane::load_stages).
template <class Lane>
class dense_adapter final : public step_interpolant {
  public:
    explicit dense_adapter(Lane& lane) : lane_(lane) {}
    std::array<double, 4> state(double t) const override {
        lane_.load_stages();
        const auto y = lane_.rk().dense(t);
        return {y[0], y[1], y[2], y[3]};
    }
    bool angles_and_rates(double t, std::array<double, 2>& q,
                          std::array<double, 2>& dq) const override {
        lane_.load_stages();
        lane_.rk().dense_and_rate(t, 2, q.data(), dq.data());
        return true;
    }
    bool angle_bounds(std::array<std::array<double, 2>, 2>& r) const override {
        lane_.load_stages();
        r[0] = lane_.rk().dense_range(0);
        r[1] = lane_.rk().dense_range(1);
        return true;
    }

  private:
    Lane& lane_;
};

// The right-hand sides as named types (the integrator stores them by value).
struct flow_rhs {
    pendulum_flow flow;
    std::array<double, 4> operator()(double, const std::array<double, 4>& y) const {
        return flow(0.0, y);
    }
};
struct tangent_rhs {
    pendulum_flow flow;
    std::array<double, 8> operator()(double, const std::array<double, 8>& y) const {
        return flow.tangent(y);
    }
};

// One trajectory in progress: the integrator and everything done after each accepted step
// (samples, detectors, energy drift, angle reduction, tangent renormalisation). Stepped through
// explicit_rk's phases (begin, stages, end) so that several trajectories can advance in lockstep
// (run_lanes); a trajectory's arithmetic is the same whichever lane or partner it has.
template <class Method, bool Tangent>
class lane {
  public:
    static constexpr std::size_t N = Tangent ? 8 : 4;
    using state = std::array<double, N>;
    using rhs = std::conditional_t<Tangent, tangent_rhs, flow_rhs>;
    using integrator = explicit_rk<Method, N, rhs>;
    static constexpr int stages = Method::stages;

    lane(const double_pendulum<double>& model, const ensemble_options& o,
         const phase_point<double>& x0, std::uint64_t index,
         const std::vector<flip_detector_base*>& detectors)
        : o_(o),
          flow_(model),
          rk_(rhs{flow_}, rk_opts(o)),
          detectors_(detectors),
          dense_(*this),
          model_(model),
          quiet_bound_(detail::quiet_bounds(detectors)) {
        r_.index = index;
        r_.initial_state = x0;
        r_.crossing_times.resize(detectors.size());
        if (o.keep_crossings) r_.crossings.resize(detectors.size());
        state y{};
        for (int i = 0; i < 4; ++i)
            y[i] = x0[i];
        if constexpr (Tangent) {
            const std::array<double, 4> v = detail::initial_tangent(o, index);
            for (int i = 4; i < 8; ++i)
                y[i] = v[static_cast<std::size_t>(i - 4)];
        }
        rk_.initialize(0, y);
        {
            const std::array<double, 4> xs = first4(rk_.x()), fs = first4(rk_.derivative());
            for (flip_detector_base* d : detectors_)
                d->start(xs, fs);
        }
        if (o.sample_interval > 0) {
            r_.samples.push_back({0.0, x0[0], x0[1], x0[2], x0[3]});
            next_sample_ = 1;
        }
        // NOTE: the energy check. An accepted step may not change H by more than
        // energy_jump_factor * (atol + rtol |E|): embedded error estimates occasionally pass a
        // step whose error is orders of magnitude above the tolerance (seen: DOP853 at rtol 1e-7
        // once in ~1e7 steps, |dH| = 2e4 tol), and such a step is retried with half its size.
        // Normal steps change H by 0.02 tol(1 + E) (median), 6-16 tol(1 + E) at the 1e-4
        // quantile.
        energy_ = flow_.hamiltonian_absolute(x0);
        const rk_options& ro = rk_.options();
        jump_ = energy_jump_factor * (ro.atol + ro.rtol * std::abs(energy_));
        h_start_ = h_end_ = energy_;
        r_.status = rk_status::ok;
        if (!(rk_.t() < o_.time)) finish();
    }
    lane(const lane&) = delete;
    lane& operator=(const lane&) = delete;

    /// Starts a trial step; false when the trajectory is finished (or failed or abandoned).
    bool begin() {
        if (done_) return false;
        if (o_.stop != nullptr && o_.stop->load(std::memory_order_relaxed) != 0) {
            r_.abandoned = true;
            finish();
            return false;
        }
        rk_status st = rk_status::ok;
        if (!rk_.begin_step(o_.time, st)) {
            r_.status = st;
            finish();
            return false;
        }
        return true;
    }
    integrator& rk() { return rk_; }
    const pendulum_flow& flow() const { return flow_; }
    /// H (hamiltonian_absolute) at the trial step's end, from the vector evaluation of its last
    /// stage (vector_stages).
    void set_end_energy(double h) { end_energy_ = h; }
    /// Whether the trial step is quiet (step_is_quiet with quiet_bound(), from the vector
    /// evaluation of its stages).
    void set_quiet(bool quiet) { quiet_ = quiet; }
    const std::array<double, 2>& quiet_bound() const { return quiet_bound_; }
    /// The trial step's error norm and step-size factor (explicit_rk::step_factor), from the
    /// vector evaluation of the stages (vector_stages).
    void set_error_norm(double err, double factor) {
        error_norm_ = err;
        step_factor_ = factor;
    }
    /// Where the trial step's stages are (round_stages: vectors of `width` lanes, group after
    /// group; this lane's at `index`), until end() returns.
    void set_stage_source(const std::byte* storage, int width, int index) {
        stages_ = storage;
        width_ = static_cast<std::size_t>(width);
        slot_ = static_cast<std::size_t>(index);
    }
    /// Hands the trial step's stages 1 ... stages - 2 to the integrator (once per step, for its
    /// dense output; the first and last it has).
    void load_stages() {
        if (stages_ == nullptr) return;
        for (int s = 1; s < stages - 1; ++s) {
            double f[N];
            for (std::size_t c = 0; c < N; ++c) {
                const std::size_t at = ((static_cast<std::size_t>(s) * N + c) * width_ + slot_);
                std::memcpy(&f[c], stages_ + at * sizeof(double), sizeof(double));
            }
            rk_.set_stage(s, f);
        }
        stages_ = nullptr;
    }
    void end() {
        rk_status st = rk_status::ok;
        // the energy check: H at the trial step's end comes with its last stage (set_end_energy)
        const int outcome = rk_.end_step(st, error_norm_, step_factor_, [this] {
            const double e = end_energy_;
            if (!(std::abs(e - h_start_) <= jump_)) return false;
            h_end_ = e;
            return true;
        });
        if (outcome < 0) {
            r_.status = st;
            finish();
        } else if (outcome > 0) {
            after_step();
            if (!(rk_.t() < o_.time)) finish();
        }  // else rejected: retried at the next begin()
        stages_ = nullptr;
    }
    bool finished() const { return done_; }
    trajectory_result& result() { return r_; }

  private:
    static rk_options rk_opts(const ensemble_options& o) {
        rk_options ro;
        ro.rtol = o.rtol;
        ro.atol = effective_atol(o);
        ro.controlled_components = 4;
        return ro;
    }
    static std::array<double, 4> first4(const state& s) { return {s[0], s[1], s[2], s[3]}; }

    void record_samples(double t_end) {
        while (o_.sample_interval > 0) {
            const double ts = static_cast<double>(next_sample_) * o_.sample_interval;
            if (ts > t_end || ts > o_.time) break;
            const std::array<double, 4> x = ts == rk_.t() ? first4(rk_.x()) : dense_.state(ts);
            r_.samples.push_back({ts, x[0] - unwrap_[0], x[1] - unwrap_[1], x[2], x[3]});
            ++next_sample_;
        }
    }

    void after_step() {
        const std::array<double, 4> x1 = first4(rk_.x()), f1 = first4(rk_.derivative());
        // the prefilter's range of each flip angle, once for all detectors testing it
        std::array<std::array<double, 2>, 2> ranges{};
        const double h = rk_.t() - rk_.t_previous();
        const std::array<double, 4> x0 = first4(rk_.x_previous()),
                                    f0 = first4(rk_.derivative_previous());
        record_samples(rk_.t());
        if (quiet_) {  // step_is_quiet(quiet_bound_, h, x0, f0, x1, f1), from vector_stages
            detail::skip_detectors(detectors_, skipped_);
        } else {
            skipped_ = false;
            // both angles' ranges: a detector tests one and reads the other (its curve's s)
            for (int i = 0; i < 2; ++i)
                ranges[static_cast<std::size_t>(i)] = flip_angle_range(i, h, x0, f0, x1, f1);
            step_samples samples;  // the examinations' shared samples of this step
            step_view view{rk_.t_previous(), rk_.t(), x0, f0, x1, f1, dense_, &ranges};
            view.samples = &samples;
            detail::detect(detectors_, view, o_.keep_crossings, found_, r_);
        }
        // h_end_ = H(x1), evaluated by the energy check
        r_.max_energy_drift = std::max(r_.max_energy_drift, std::abs(h_end_ - energy_));
        h_start_ = h_end_;
        const double d1 = angle_reduction(x1[0]), d2 = angle_reduction(x1[1]);
        if (d1 != 0 || d2 != 0) {
            if (o_.unwrapped_angles) {
                unwrap_[0] += d1;
                unwrap_[1] += d2;
            }
            state delta{};
            delta[0] = d1;
            delta[1] = d2;
            rk_.translate(delta);
            for (flip_detector_base* d : detectors_)
                d->shift(d1, d2);
        }
        if constexpr (Tangent) {
            double norm2 = 0;
            for (int i = 4; i < 8; ++i)
                norm2 += rk_.x()[i] * rk_.x()[i];
            // renormalise by a power of two (exact) when |v| leaves [2^-400, 2^400]
            if (const int e = detail::tangent_rescaling(norm2, log_growth_); e != 0)
                rk_.rescale_tail(4, std::ldexp(1.0, -e));
        }
    }

    void finish() {
        done_ = true;
        r_.end_time = rk_.t();
        r_.final_state = {rk_.x()[0] - unwrap_[0], rk_.x()[1] - unwrap_[1], rk_.x()[2], rk_.x()[3]};
        r_.steps = rk_.accepted_steps();
        r_.rejected_steps = rk_.rejected_steps();
        r_.evaluations = rk_.evaluations();
        r_.energy_check_rejections = rk_.check_rejections();
        if constexpr (Tangent) {
            double norm2 = 0;
            for (int i = 4; i < 8; ++i)
                norm2 += rk_.x()[i] * rk_.x()[i];
            r_.lyapunov = r_.end_time > 0 ? (log_growth_ + 0.5 * std::log(norm2)) / r_.end_time
                                          : std::numeric_limits<double>::quiet_NaN();
        } else {
            r_.lyapunov = std::numeric_limits<double>::quiet_NaN();
        }
    }

    const ensemble_options& o_;
    pendulum_flow flow_;
    integrator rk_;
    std::vector<flip_detector_base*> detectors_;
    dense_adapter<lane> dense_;
    const double_pendulum<double>& model_;
    trajectory_result r_;
    std::vector<crossing> found_;
    std::uint64_t next_sample_ = 0;
    std::array<double, 2> unwrap_{};  ///< the reductions applied so far (unwrapped_angles)
    double energy_ = 0, jump_ = 0, h_start_ = 0, h_end_ = 0, log_growth_ = 0, end_energy_ = 0;
    double error_norm_ = 0, step_factor_ = 0;
    const std::byte* stages_ = nullptr;  ///< the trial step's stages (set_stage_source)
    std::size_t width_ = 0, slot_ = 0;
    /// per angle (th1, th2), the widest prefilter bound of its detectors (-1: none tests it)
    const std::array<double, 2> quiet_bound_;
    bool done_ = false;
    /// the detectors have been told of a quiet step since they last saw one
    bool skipped_ = false;
    bool quiet_ = false;  ///< set_quiet
};

// The right-hand sides of a group's stages, out of line: one copy of the flow's code per vector
// type (stage_flow: pendulum_flow::lanes or tangent_lanes; stage_flow_and_energy: with H, the
// last stage's lanes_and_energy) rather than one inlined into each of the step's stages, group
// types and tails. The flattened stage code (vector_stages_*) stays small enough for the
// processor's instruction caches (inlined, DOP853's AVX2 path was 239 kB of code). The same
// operations either way, so the same bits; v2d's copy is compiled for SSE2 and serves every
// instruction set's pairs (no FMA is enabled anywhere, so its rounding is theirs). Each overload
// carries its own instruction set (a target attribute cannot be a template argument), the body
// is flow_of's.
template <std::size_t N, class V>
[[gnu::always_inline]] inline void flow_of(const pendulum_flow& flow, const V* y, V* f) {
    if constexpr (N == 4)
        flow.lanes(y, f);
    else
        flow.tangent_lanes(y, f);
}
template <std::size_t N>
[[gnu::noinline]] void stage_flow(const pendulum_flow& flow, const v2d* y, v2d* f) {
    flow_of<N>(flow, y, f);
}
template <std::size_t N>
[[gnu::noinline]] __attribute__((target("avx2"))) void stage_flow(const pendulum_flow& flow,
                                                                  const v4d* y, v4d* f) {
    flow_of<N>(flow, y, f);
}
template <std::size_t N>
[[gnu::noinline]] __attribute__((target("avx512f"))) void stage_flow(const pendulum_flow& flow,
                                                                     const v8d* y, v8d* f) {
    flow_of<N>(flow, y, f);
}
template <std::size_t N>
[[gnu::noinline]] void stage_flow_and_energy(const pendulum_flow& flow, const v2d* y, v2d* f,
                                             v2d& e) {
    flow.template lanes_and_energy<N>(y, f, e);
}
template <std::size_t N>
[[gnu::noinline]] __attribute__((target("avx2"))) void stage_flow_and_energy(
    const pendulum_flow& flow, const v4d* y, v4d* f, v4d& e) {
    flow.template lanes_and_energy<N>(y, f, e);
}
template <std::size_t N>
[[gnu::noinline]] __attribute__((target("avx512f"))) void stage_flow_and_energy(
    const pendulum_flow& flow, const v8d* y, v8d* f, v8d& e) {
    flow.template lanes_and_energy<N>(y, f, e);
}

// The square root of each lane for the error norms and step-size factors of vector_stages
// (explicit_rk's Root): a vector's in one instruction of its width, SSE2's, AVX's or AVX-512's;
// each correctly rounded, so the same bits as std::sqrt and explicit_rk's default (SSE2 two lanes
// at a time). The wider two only where vector_stages_avx2 and _avx512 inline them: not
// always_inline, which their instruction sets forbid in explicit_rk's callers compiled without.
struct lanes_root {
    [[gnu::always_inline]] static void of(const v2d& x, v2d& r) { r = __builtin_ia32_sqrtpd(x); }
    __attribute__((target("avx"))) static void of(const v4d& x, v4d& r) {
        r = reinterpret_cast<v4d>(_mm256_sqrt_pd(reinterpret_cast<__m256d>(x)));
    }
    // (the masked form with every lane kept: _mm512_sqrt_pd reads an undefined vector, which
    // GCC warns of)
    __attribute__((target("avx512f"))) static void of(const v8d& x, v8d& r) {
        const auto y = reinterpret_cast<__m512d>(x);
        r = reinterpret_cast<v8d>(_mm512_mask_sqrt_pd(y, static_cast<__mmask8>(0xff), y));
    }
};

// Where a round's stages are kept, lane-major: the groups' vectors (V k[S][N] each, group after
// group), alive until every lane of the round has ended its step. A lane reads its own stages
// from them only when its dense output is used (lane::set_stage_source, load_stages).
template <class Lane>
struct round_stages {
    static constexpr std::size_t bytes = max_lanes * Lane::stages * Lane::N * sizeof(double);
    alignas(64) std::array<std::byte, bytes> storage;
};

// One group of the active lanes in lane-major form: W = lanes_of<V> of them, a short group
// padded with copies of its first lane. The step's start, size and stages are vectors across
// the lanes; the stages live in the round's storage (round_stages).
template <class Lane, class V>
struct lane_group {
    static constexpr int W = lanes_of<V>;
    static constexpr std::size_t N = Lane::N;
    static constexpr int S = Lane::stages;
    using integrator = typename Lane::integrator;
    Lane* const* lanes;
    std::size_t g;  ///< lanes in use
    V (*k)[N];      ///< k[s][c]: stage s, component c
    V h, x0[N];
    V span;  ///< where the trial step ends less where it starts (the quiet test's h)

    lane_group() = default;
    [[gnu::always_inline]] lane_group(Lane* const* first, std::size_t count, std::byte* storage)
        : lanes(first), g(count), k(reinterpret_cast<V (*)[N]>(storage)) {
        for (int l = 0; l < W; ++l) {
            const integrator& rk = lanes[static_cast<std::size_t>(l) < g ? l : 0]->rk();
            h[l] = rk.trial_step();
            span[l] = rk.trial_end_time() - rk.t();
            for (std::size_t c = 0; c < N; ++c) {
                x0[c][l] = rk.x()[c];
                k[0][c][l] = rk.derivative()[c];
            }
        }
        for (std::size_t l = 0; l < g; ++l)
            lanes[l]->set_stage_source(storage, W, static_cast<int>(l));
    }

    // Stage s (every function here is always_inline, so all of it is compiled for the caller's
    // target, AVX-512, AVX2 or SSE2, but for the right-hand sides, out of line in stage_flow and
    // stage_flow_and_energy, each compiled for its vector type's instruction set).
    template <int s>
    [[gnu::always_inline]] void stage(const pendulum_flow& flow) {
        V y[N];
        integrator::template stage_sum<s>(h, x0, k, y);
        if constexpr (s < S - 1) {
            stage_flow<N>(flow, y, k[s]);
        } else {
            // the trial step's end: f and H there (for the energy check) from the same sines and
            // cosines, the error norm and step-size factor
            V e;
            stage_flow_and_energy<N>(flow, y, k[s], e);
            const rk_options& o = lanes[0]->rk().options();  // the same for every lane
            V first, second;
            integrator::error_sums(h, x0, y, k, o, first, second);
            V err, factor;
            integrator::template error_norms<V, lanes_root>(h, first, second, o, err);
            integrator::template step_factors<V, lanes_root>(err, factor);
            // the quiet test of the step, should it be accepted (the lane's after_step):
            // step_is_quiet's arithmetic on the group's vectors (detail::quiet_reach), the
            // rounding lane by lane; every lane's detectors are clones of the same criteria, so
            // one lane's bounds are every lane's
            const std::array<double, 2>& bound = lanes[0]->quiet_bound();
            std::array<V, 2> reach_lo{}, reach_hi{};
            for (std::size_t i = 0; i < 2; ++i)
                if (bound[i] >= 0)
                    detail::quiet_reach(bound[i], span, x0[i], y[i], k[0][i], k[s][i], reach_lo[i],
                                        reach_hi[i]);
            for (std::size_t l = 0; l < g; ++l) {
                Lane& lane = *lanes[l];
                double end[N], f[N];
                for (std::size_t c = 0; c < N; ++c) {
                    end[c] = y[c][l];
                    f[c] = k[s][c][l];
                }
                integrator& rk = lane.rk();
                rk.set_trial_end(end, f);
                lane.set_end_energy(e[l]);
                lane.set_error_norm(err[l], factor[l]);
                bool quiet = true;
                for (std::size_t i = 0; i < 2; ++i)
                    if (bound[i] >= 0 && detail::reaches_level(reach_lo[i][l], reach_hi[i][l]))
                        quiet = false;
                lane.set_quiet(quiet);
            }
        }
    }
};

// Stage s of every group: the groups' dependency chains (each stage needs the one before) are
// independent, so the processor overlaps one group's stage with the next one's. `tail` (null:
// none) is a last group of a narrower vector type.
template <int s, class Group, class Tail>
[[gnu::always_inline]] inline void stage_of_every(Group* groups, std::size_t count, Tail* tail,
                                                  const pendulum_flow& flow) {
    for (std::size_t i = 0; i < count; ++i)
        groups[i].template stage<s>(flow);
    if (tail != nullptr) tail->template stage<s>(flow);
}

// Stages 1 to S - 1 of every group, stage by stage (a fold rather than a recursion or a lambda:
// always_inline throughout, and each stage's code once in an unoptimised build, where a
// recursion's out-of-line copies held every later stage again).
template <class Group, class Tail, int... s>
[[gnu::always_inline]] inline void stages_of_step(Group* groups, std::size_t count, Tail* tail,
                                                  const pendulum_flow& flow,
                                                  std::integer_sequence<int, s...>) {
    (stage_of_every<s + 1>(groups, count, tail, flow), ...);
}

// Every stage of a trial step of the active lanes: m / W groups of W = lanes_of<V> lanes and the
// rest, if any, in a group of type Tail (lane_group), its storage after theirs: the stage sums
// (explicit_rk::stage_sum) and the right-hand sides (pendulum_flow::lanes / tangent_lanes) are
// vector operations, each lane's the same operations as one integrator alone (the same bits). The
// stages stay in the round's storage; each integrator gets its trial step's end and f there
// (set_trial_end), H there serves the energy check, and the error norm's sums over components
// are vector operations too (explicit_rk::error_sums).
template <class Lane, class V, class Tail>
[[gnu::always_inline]] inline void vector_stages_with(Lane* const* active, std::size_t m,
                                                      std::byte* storage) {
    constexpr std::size_t W = lanes_of<V>;
    constexpr std::size_t most = max_lanes / W;
    constexpr std::size_t bytes = sizeof(V) * Lane::stages * Lane::N;
    const pendulum_flow& flow = active[0]->flow();
    using group = lane_group<Lane, V>;
    std::array<group, most> groups;
    const std::size_t full = m / W, rest = m % W;
    for (std::size_t i = 0; i < full; ++i)
        groups[i] = group(active + i * W, W, storage + i * bytes);
    constexpr auto later = std::make_integer_sequence<int, Lane::stages - 1>();  // stages 1..S-1
    if (rest == 0) {
        stages_of_step(groups.data(), full, static_cast<group*>(nullptr), flow, later);
    } else {
        lane_group<Lane, Tail> tail(active + full * W, rest, storage + full * bytes);
        stages_of_step(groups.data(), full, &tail, flow, later);
    }
}

// ... the rest in a group of the narrowest of V, V2 and V1 (widths W > W2 > W1, or V2 = V1 = V)
// that holds it: fewer padded lanes than a group of W for all of them.
template <class Lane, class V, class V2, class V1>
[[gnu::always_inline]] inline void vector_stages(Lane* const* active, std::size_t m,
                                                 std::byte* storage) {
    const std::size_t rest = m % lanes_of<V>;
    if (rest == 0 || rest > static_cast<std::size_t>(lanes_of<V2>))
        vector_stages_with<Lane, V, V>(active, m, storage);
    else if (rest > static_cast<std::size_t>(lanes_of<V1>))
        vector_stages_with<Lane, V, V2>(active, m, storage);
    else
        vector_stages_with<Lane, V, V1>(active, m, storage);
}

// Every stage of a trial step of the active lanes, two lanes per SSE2 vector (any x86-64) ...
template <class Lane>
void vector_stages_sse2(Lane* const* active, std::size_t m, std::byte* storage) {
    vector_stages<Lane, v2d, v2d, v2d>(active, m, storage);
}

// ... or four per AVX2 vector, the rest of one or two lanes in an SSE2 pair (the same bits; used
// when the processor has AVX2). `flatten' inlines everything called here but the noinline
// right-hand sides (stage_flow, stage_flow_and_energy: AVX2's copy for the four-lane groups,
// SSE2's for the pairs), so that the stage sums, error norms and step tests are compiled for
// AVX2; no FMA is enabled, so the operations and their rounding are those of the scalar code.
template <class Lane>
__attribute__((target("avx2"), flatten)) void vector_stages_avx2(Lane* const* active, std::size_t m,
                                                                 std::byte* storage) {
    vector_stages<Lane, v4d, v2d, v2d>(active, m, storage);
}

// ... or eight per AVX-512 vector, the rest in a group of eight, four or two (the same bits again;
// used for more than four lanes when the processor has AVX-512F: 1.24x the AVX2 path's
// throughput on a Zen 5 EPYC, docs/scale.md).
template <class Lane>
__attribute__((target("avx512f"), flatten)) void vector_stages_avx512(Lane* const* active,
                                                                      std::size_t m,
                                                                      std::byte* storage) {
    vector_stages<Lane, v8d, v4d, v2d>(active, m, storage);
}

// Trajectories per thread in lockstep with `isa`: two of its widest vectors' worth (SSE2: two
// pairs), whose stages are computed side by side (stage_of_every), for `n` trajectories on
// `threads` threads: fewer when there are not that many per thread, so that a small ensemble's
// trajectories do not gather on one thread.
std::size_t lanes_per_thread(vector_isa isa, std::size_t n, int threads) {
    const std::size_t most = ensemble_lanes_per_thread(isa);
    const std::size_t share = (n + static_cast<std::size_t>(threads) - 1) /
                              static_cast<std::size_t>(std::max(threads, 1));
    return std::clamp<std::size_t>(share, 1, most);
}

// One trial step of every unfinished lane, stage by stage (lanes of one type), the lanes'
// stages computed together in vectors (vector_stages) of `isa`'s widest width that the active
// lanes fill more than half of.
template <class Lane>
void lockstep_round(std::span<Lane* const> lanes, vector_isa isa) {
    std::array<Lane*, max_lanes> active;  // the first m set (not zeroed: every round's cost)
    std::size_t m = 0;
    for (Lane* l : lanes)
        if (l != nullptr && l->begin()) active[m++] = l;
    if (m == 0) return;
    round_stages<Lane> stages;
    std::byte* storage = stages.storage.data();
    if (m > 4 && isa == vector_isa::avx512)
        vector_stages_avx512<Lane>(active.data(), m, storage);
    else if (m > 2 && isa != vector_isa::sse2)
        vector_stages_avx2<Lane>(active.data(), m, storage);
    else
        vector_stages_sse2<Lane>(active.data(), m, storage);
    for (std::size_t i = 0; i < m; ++i)
        active[i]->end();
}

// Runs one thread's share: `count` trajectories (lanes_per_thread) advanced in lockstep, the next
// index taken whenever one finishes. `deliver` gets each finished (or abandoned) lane's result.
template <class Method, bool Tangent, class Next, class Deliver>
void run_lanes(const double_pendulum<double>& model, const ensemble_options& o,
               const microcanonical_sampler& sampler,
               std::array<std::vector<flip_detector_base*>, max_lanes>& detectors, vector_isa isa,
               std::size_t count, Next&& next_index, Deliver&& deliver) {
    using lane_type = lane<Method, Tangent>;
    detail::refill_lanes<lane_type, max_lanes>(
        count,
        [&](std::uint64_t index, std::size_t l) {
            return std::make_unique<lane_type>(model, o, initial_state_of(sampler, o, index), index,
                                               detectors[l]);
        },
        next_index, deliver,
        [isa](std::span<lane_type* const> view) { lockstep_round<lane_type>(view, isa); });
}

template <class Next, class Deliver>
void run_lanes(const double_pendulum<double>& model, const ensemble_options& o,
               const microcanonical_sampler& sampler,
               std::array<std::vector<flip_detector_base*>, max_lanes>& detectors, vector_isa isa,
               std::size_t count, Next&& next_index, Deliver&& deliver) {
    if (resolved_method(o.method, o.rtol) != o.method) {
        ensemble_options resolved = o;
        resolved.method = resolved_method(o.method, o.rtol);
        run_lanes(model, resolved, sampler, detectors, isa, count, next_index, deliver);
        return;
    }
    if (o.method == integration_method::taylor) {
        detail::run_taylor_lanes(model, o, sampler, detectors, isa, count, next_index, deliver);
        return;
    }
    if (o.method == integration_method::dop853) {
        if (o.chaos)
            run_lanes<dormand_prince_853, true>(model, o, sampler, detectors, isa, count,
                                                next_index, deliver);
        else
            run_lanes<dormand_prince_853, false>(model, o, sampler, detectors, isa, count,
                                                 next_index, deliver);
    } else {
        if (o.chaos)
            run_lanes<dormand_prince_5, true>(model, o, sampler, detectors, isa, count, next_index,
                                              deliver);
        else
            run_lanes<dormand_prince_5, false>(model, o, sampler, detectors, isa, count, next_index,
                                               deliver);
    }
}

template <class Method, bool Tangent>
trajectory_result single_trajectory(const double_pendulum<double>& model, const ensemble_options& o,
                                    const phase_point<double>& x0, std::uint64_t index,
                                    const std::vector<flip_detector_base*>& detectors) {
    using lane_type = lane<Method, Tangent>;
    lane_type l(model, o, x0, index, detectors);
    lane_type* const one[1] = {&l};
    while (!l.finished()) {
        check_cpu_budget();  // a bounded caller's (e.g. a scene's trajectory step)
        lockstep_round<lane_type>(one, vector_isa::sse2);
    }
    return std::move(l.result());
}

}  // namespace

trajectory_result simulate_trajectory(const double_pendulum<double>& model,
                                      const phase_point<double>& x0, const ensemble_options& o,
                                      std::uint64_t index,
                                      const std::vector<flip_detector_base*>& detectors) {
    if (resolved_method(o.method, o.rtol) != o.method) {
        ensemble_options resolved = o;
        resolved.method = resolved_method(o.method, o.rtol);
        return simulate_trajectory(model, x0, resolved, index, detectors);
    }
    if (o.method == integration_method::taylor)
        return detail::taylor_trajectory(model, x0, o, index, detectors);
    if (o.method == integration_method::dop853)
        return o.chaos
                   ? single_trajectory<dormand_prince_853, true>(model, o, x0, index, detectors)
                   : single_trajectory<dormand_prince_853, false>(model, o, x0, index, detectors);
    return o.chaos ? single_trajectory<dormand_prince_5, true>(model, o, x0, index, detectors)
                   : single_trajectory<dormand_prince_5, false>(model, o, x0, index, detectors);
}

phase_point<double> initial_state_of(const microcanonical_sampler& sampler,
                                     const ensemble_options& o, std::uint64_t index) {
    if (!o.initial_states) return sampler.sample(o.seed, index);
    if (index < o.first_index || index - o.first_index >= o.initial_states->size())
        throw std::logic_error("initial_state_of: trajectory " + std::to_string(index) +
                               " has no given initial state");
    return (*o.initial_states)[index - o.first_index];
}

trajectory_result run_trajectory(const double_pendulum<double>& model,
                                 const microcanonical_sampler& sampler, const ensemble_options& o,
                                 std::uint64_t index,
                                 const std::vector<flip_detector_base*>& detectors) {
    return simulate_trajectory(model, initial_state_of(sampler, o, index), o, index, detectors);
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
    const vector_isa isa = ensemble_vector_isa();
    std::exception_ptr failure;
    const std::size_t n = indices.size();
    const std::size_t lanes = lanes_per_thread(isa, n, threads);
    std::atomic<std::size_t> next{0};
    std::atomic<bool> failed{false};
    int used = 1;
    bool interrupted = false;
    auto stopped = [&o] { return o.stop != nullptr && o.stop->load(std::memory_order_relaxed); };
#pragma omp parallel num_threads(threads)
    {
#pragma omp single
        used = omp_get_num_threads();
        // each thread advances `lanes` trajectories in lockstep (run_lanes), taking the next index
        // whenever one finishes
        std::array<std::vector<std::unique_ptr<flip_detector_base>>, max_lanes> own;
        std::array<std::vector<flip_detector_base*>, max_lanes> detectors;
        for (std::size_t l = 0; l < lanes; ++l)
            for (const ensemble_criterion& c : criteria) {
                own[l].push_back(c.detector->clone());
                detectors[l].push_back(own[l].back().get());
            }
        try {
            run_lanes(
                model, o, sampler, detectors, isa, lanes,
                [&](std::uint64_t& index) {
                    if (failed.load(std::memory_order_relaxed)) return false;
                    if (stopped()) {
                        if (next.load() < n) {
#pragma omp atomic write
                            interrupted = true;
                        }
                        return false;
                    }
                    const std::size_t i = next.fetch_add(1);
                    if (i >= n) return false;
                    index = indices[i];
                    return true;
                },
                [&](trajectory_result& r) {
                    if (r.abandoned) {
#pragma omp atomic write
                        interrupted = true;
                    } else {
#pragma omp critical(flipflux_ensemble_finished)
                        finished(std::move(r));
                    }
                });
        } catch (...) {
            failed.store(true);
#pragma omp critical(flipflux_ensemble_failure)
            if (!failure) failure = std::current_exception();
        }
    }
    if (failure) std::rethrow_exception(failure);
    return {used, interrupted};
}

ensemble_result run_ensemble(const double_pendulum<double>& model, const ensemble_options& o,
                             const std::vector<ensemble_criterion>& criteria) {
    validate(o);
    const auto start = std::chrono::steady_clock::now();
    const double cpu_start = process_cpu_seconds();
    ensemble_result result;
    result.energy = o.energy;
    result.time = o.time;
    result.rtol = o.rtol;
    result.atol = effective_atol(o);
    result.chaos_threshold = o.chaos_threshold;
    result.chaos_threshold_rate = chaos_threshold_rate(model, o.chaos_threshold);
    result.seed = o.seed;
    result.first_index = o.first_index;
    result.method = resolved_method(o.method, o.rtol);
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
    result.cpu_seconds = process_cpu_seconds() - cpu_start;
    return result;
}

}  // namespace flipflux
