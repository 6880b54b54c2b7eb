// Monte Carlo ensembles (paper Sec. 5): microcanonical initial conditions, trajectories integrated
// by DOP853 or DOPRI5 at double precision, flips counted for every requested criterion, energy
// drift and a chaos indicator per trajectory.
//
// Reproducibility: trajectory i's initial condition is a function of (seed, energy, i) only
// (ensemble/random.hpp), its integration and flip detection depend on nothing else, and results
// are stored by index: the result is bit-identical for any number of threads, any schedule, and
// any split of the index range [first_index, first_index + trajectories) across processes.
//
// Per trajectory (run_trajectory):
//   - the state's angles are reduced to [-pi, pi] after every step (by exactly 2 pi_double, an
//     exact subtraction by Sterbenz's lemma), so that the relative tolerance acts on O(1)
//     numbers however many turns the arms make; detectors carry the shift (flip_detector.hpp);
//   - the energy drift max |H(x(t)) - E| over the step ends, and the energy check: a step that
//     changes H by more than energy_jump_factor (atol + rtol |E|) is refused and retried with half
//     its size, whatever the embedded error estimate said;
//   - with `chaos`: the finite-time maximal Lyapunov exponent
//         lambda_T = (1/T) ln(|v(T)| / |v(0)|),  v' = J(x) v,
//     from the variational equations (pendulum_flow::tangent), v(0) a random unit vector drawn
//     from the trajectory's own stream; v rides along uncontrolled (rk_options::
//     controlled_components = 4), so the trajectory and its flips are bit-identical with or
//     without the indicator. The trajectory counts as chaotic when lambda_T > chaos_threshold.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "flipflux/core/names.hpp"
#include "flipflux/ensemble/flip_detector.hpp"
#include "flipflux/ensemble/sampler.hpp"
#include "flipflux/integrators/explicit_rk.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

/// The ensemble's integrators: Dormand-Prince 8(5,3) and 5(4) (explicit_rk.hpp), Taylor series
/// of adaptive order (taylor_ensemble.hpp; the one that reaches double's limit), and the
/// automatic choice by the requested accuracy (resolved_method).
enum class integration_method { dop853, dopri5, taylor, automatic };
template <>
struct enum_table<integration_method> {
    static constexpr std::string_view noun = "an integration method";
    static constexpr std::array<std::pair<integration_method, std::string_view>, 4> entries{
        {{integration_method::dop853, "dop853"},
         {integration_method::dopri5, "dopri5"},
         {integration_method::taylor, "taylor"},
         {integration_method::automatic, "auto"}}};
};

/// Below this rtol `auto` chooses taylor, at and above it dop853 (docs/scale.md measures both:
/// Taylor's cost grows with the digits like sqrt, DOP853's like a power; DOP853 stays the choice
/// at the default rtol 1e-10, so that default runs keep the bits of the paper's calibrated
/// ensembles).
inline constexpr double automatic_taylor_below = 1e-10;

/// The integrator `method` means at `rtol`: itself, or for automatic the choice above.
integration_method resolved_method(integration_method method, double rtol);

/// The vector instructions of the ensemble's lockstep lanes (within a thread, several
/// trajectories advance stage by stage with their stages computed together in vectors). Every
/// choice gives the same bits, trajectory by trajectory (tested); only the speed differs.
///   - avx512: sixteen lanes per thread, eight per AVX-512 vector, two vectors' stages side by
///     side (AVX2 then SSE2 as lanes finish);
///   - avx2: eight lanes per thread, four per AVX2 vector, two side by side (SSE2 for the last
///     two);
///   - sse2: four lanes per thread, two per SSE2 vector (any x86-64);
///   (fewer lanes per thread when an ensemble has fewer trajectories per thread);
///   - automatic: avx512 where the processor has AVX-512F (on AMD's Zen 4 too, whose 512-bit
///     operations are two 256-bit halves: 0.82-0.88 of AVX2's CPU time for DOP853 lanes there and
///     0.44-0.75 for Taylor lanes, docs/scale.md); else avx2 where it has AVX2; else sse2.
enum class vector_isa { automatic, sse2, avx2, avx512 };
template <>
struct enum_table<vector_isa> {
    static constexpr std::string_view noun = "a vector instruction set";
    static constexpr std::array<std::pair<vector_isa, std::string_view>, 4> entries{
        {{vector_isa::automatic, "auto"},
         {vector_isa::sse2, "sse2"},
         {vector_isa::avx2, "avx2"},
         {vector_isa::avx512, "avx512"}}};
};

/// The instruction set the ensemble uses (never automatic): the one set by
/// set_ensemble_vector_isa, else $FLIPFLUX_VECTOR_ISA (auto, sse2, avx2 or avx512) when set and
/// not empty, else the automatic choice. Throws input_error naming FLIPFLUX_VECTOR_ISA when its
/// value is not one of those or the processor lacks the instructions.
vector_isa ensemble_vector_isa();

/// Sets the instruction set of the ensembles started after this call (automatic: back to the
/// default, $FLIPFLUX_VECTOR_ISA or the automatic choice); throws input_error ("vector_isa: ...")
/// when the processor lacks it. For tests and benchmarks.
void set_ensemble_vector_isa(vector_isa isa);

/// Whether this processor can run `isa` (automatic and sse2: always, on x86-64).
bool processor_supports(vector_isa isa);

/// The most trajectories one thread advances in lockstep with any instruction set.
inline constexpr std::size_t max_thread_lanes = 16;

/// The most trajectories one thread advances in lockstep with `isa` (automatic: the instruction
/// set in use, ensemble_vector_isa): 16 with avx512, 8 with avx2, 4 with sse2 (see vector_isa).
std::size_t ensemble_lanes_per_thread(vector_isa isa = vector_isa::automatic);

/// An accepted step may change H by at most this times (atol + rtol |E|); otherwise it is retried
/// with half the size (the error estimate passed a bad step). See docs/theory.md#ensembles.
inline constexpr double energy_jump_factor = 64;

/// Default chaos threshold on the finite-time Lyapunov exponent, in units of the inverse
/// natural time sqrt(alpha / A) (docs/theory.md#ensembles explains the choice).
inline constexpr double default_chaos_threshold = 0.05;

/// The smallest relative tolerance double arithmetic can meet: 100 eps (2.2e-14). Below it the
/// error estimates of DOP853 and DOPRI5 are dominated by rounding and the step size shrinks
/// without end (Hairer's codes refuse rtol <= 10 eps; the margin keeps runs finite in time).
inline constexpr double min_rtol = 100 * std::numeric_limits<double>::epsilon();

/// Why `rtol` cannot drive the ensemble's integrator `method`, or "" when it can: the one rule of
/// simulate, trajectory (at double) and scenes (so a dry run refuses what the run would).
/// "'RTOL' is invalid (must be in (0, 0.1])" or "'RTOL' is below what double precision can meet
/// (at least 100 eps = ... with dop853 and dopri5, eps = ... with taylor)", RTOL the user's text
/// when given. The Taylor integrator's error control has no rounding floor of its own: it accepts
/// rtol down to epsilon.
std::string rtol_problem(double rtol, const std::string& text = "",
                         integration_method method = integration_method::dop853);

/// Why `order` cannot be the Taylor integrator's order (ensemble_options::taylor_order) for
/// `method` at `rtol`, or "" when it can: 0 (automatic) always can; otherwise it must lie in
/// [min_taylor_order, ensemble_taylor_max_order] and the method must resolve to taylor. The
/// message shows `text` (the user's) when given.
std::string taylor_order_problem(int order, integration_method method, double rtol,
                                 const std::string& text = "");

struct ensemble_options {
    double energy = 0;
    std::uint64_t trajectories = 0;  ///< how many (> 0)
    std::uint64_t first_index = 0;   ///< index of the first trajectory
    double time = 0;                 ///< integration time T per trajectory (> 0)
    std::uint64_t seed = 0;
    double rtol = 1e-10;  ///< relative tolerance of the integrator, in (0, 0.1]
    double atol = 0;      ///< absolute tolerance; 0: equal to rtol (states are O(1))
    integration_method method = integration_method::dop853;
    /// The Taylor integrator's order (method taylor); 0: the order of least modelled cost at rtol,
    /// ensemble_taylor_order (taylor_ensemble.hpp). Not a run setting: for calibrating that
    /// model (bench/taylor_order.cpp) and for studies of the integrator itself.
    int taylor_order = 0;
    bool chaos = true;  ///< integrate the variational equations for the Lyapunov exponent
    /// lambda_T above this (in units of sqrt(alpha / A)) classifies a trajectory as chaotic
    double chaos_threshold = default_chaos_threshold;
    int threads = 0;              ///< OpenMP threads; 0: OpenMP's default
    bool keep_crossings = false;  ///< store every crossing (time, direction, s)
    /// > 0: store the state every sample_interval (from the dense output; angles as integrated,
    /// reduced to [-pi, pi] at each step's start). 0: trajectories are not stored.
    double sample_interval = 0;
    /// Samples and final_state with the angles as integrated from the initial state (the
    /// reductions to [-pi, pi] undone), not reduced: one trajectory's record (study/trajectory).
    bool unwrapped_angles = false;
    /// Called (serialised) after each finished trajectory with (finished, total).
    std::function<void(std::uint64_t, std::uint64_t)> progress;
    /// When non-null and nonzero (e.g. set by a signal handler): no further trajectory is
    /// started, and the ones in flight are abandoned at their next step (trajectory_result::
    /// abandoned). Read with relaxed loads once per step.
    const std::atomic<int>* stop = nullptr;
    /// Given initial states (simulate --initial-states, a paired comparison with another
    /// simulator): trajectory `index` starts from (*initial_states)[index - first_index] instead
    /// of the sample of (seed, energy, index). Null: sampled.
    std::shared_ptr<const std::vector<phase_point<double>>> initial_states;
};

class microcanonical_sampler;

/// Trajectory `index`'s initial state: the given one (options.initial_states) or the sample of
/// (seed, energy, index).
phase_point<double> initial_state_of(const microcanonical_sampler& sampler,
                                     const ensemble_options& options, std::uint64_t index);

/// The absolute tolerance the integrators use: atol, or rtol where atol is 0 (the one home of
/// that rule).
inline double effective_atol(const ensemble_options& o) {
    return o.atol > 0 ? o.atol : o.rtol;
}

/// A flip criterion: its name and a detector prototype (cloned per thread).
struct ensemble_criterion {
    std::string name;
    std::shared_ptr<const flip_detector_base> detector;
};

struct trajectory_result {
    std::uint64_t index = 0;
    phase_point<double> initial_state{};
    rk_status status = rk_status::ok;
    double end_time = 0;          ///< T, unless the integration failed
    double max_energy_drift = 0;  ///< max |H - E| over the step ends
    double lyapunov = 0;          ///< finite-time exponent lambda_T (NaN without `chaos`)
    long steps = 0, rejected_steps = 0, evaluations = 0;
    long energy_check_rejections = 0;  ///< steps the energy check refused (see energy_jump_factor)
    bool abandoned = false;            ///< stopped before T by options.stop (not a result)
    std::vector<std::vector<double>> crossing_times;  ///< per criterion, in time order
    std::vector<std::vector<crossing>> crossings;     ///< per criterion, with keep_crossings
    std::vector<std::array<double, 5>> samples;       ///< (t, th1, th2, l1, l2), sample_interval
    phase_point<double> final_state{};  ///< at end_time (angles reduced unless unwrapped_angles)
    std::size_t flips(std::size_t criterion) const { return crossing_times[criterion].size(); }
};

struct ensemble_result {
    double energy = 0, time = 0, rtol = 0, atol = 0, chaos_threshold = 0;
    /// chaos_threshold in the model's time units (chaos_threshold_rate): set with it
    double chaos_threshold_rate = 0;
    std::uint64_t seed = 0, first_index = 0;
    integration_method method = integration_method::dop853;
    bool chaos = false;
    int threads = 0;  ///< threads actually used
    std::vector<std::string> criteria;
    std::vector<trajectory_result> trajectories;  ///< by index
    double seconds = 0;                           ///< wall-clock time
    double cpu_seconds = 0;                       ///< CPU time of the process, every thread
    /// Whether trajectory t is chaotic here: is_chaotic's rule with this ensemble's threshold
    /// (computed, never stored: studies sharing trajectories classify them each with its own).
    bool chaotic(const trajectory_result& t) const {
        return chaos && t.lyapunov > chaos_threshold_rate;
    }
};

/// Validates the options (throws input_error naming the option: --trajectories, --time, --rtol,
/// --energy, --threads).
void validate(const ensemble_options& options);

/// An upper bound on the turns the arms make over `time` at `energy` (both arms together):
/// time (w_E + w_0) / (2 pi) with w_E = sqrt(2 E / m) the largest angular speed the kinetic
/// energy allows (K <= E since V >= 0) and w_0 = sqrt((alpha + beta) / m) the fastest
/// small-oscillation frequency, m = D0 / ((A + B) / 2 + sqrt(((A - B) / 2)^2 + C^2)) the smallest
/// eigenvalue of the mass matrix over all configurations (its determinant over the largest: no
/// cancellation when it is tiny).
double turns_bound(const double_pendulum<double>& model, double energy, double time);

/// Throws input_error about `field` when turns_bound exceeds max_turns_per_trajectory
/// (core/limits.hpp): a trajectory that could not finish; and input_error about the pendulum
/// when its mass matrix's condition number (at the worst angle) exceeds 1e-4 / epsilon (the
/// working precision's): a near-zero mass or inertia whose trajectories that precision cannot
/// integrate (m1 = 2e-16 beside m2 = 1 in double).
void check_trajectory_work(const double_pendulum<double>& model, double energy, double time,
                           const std::string& field,
                           double epsilon = std::numeric_limits<double>::epsilon());

/// The chaos threshold in the model's time units: threshold * sqrt(alpha / A).
double chaos_threshold_rate(const double_pendulum<double>& model, double threshold);

/// The one classification rule: with the indicator on (`chaos`), a trajectory is chaotic when
/// its finite-time exponent exceeds chaos_threshold_rate(model, threshold); without it, never.
/// The ensemble and every study that re-classifies shared trajectories call this.
bool is_chaotic(const double_pendulum<double>& model, bool chaos, double threshold,
                double lyapunov);

/// Whether T is long enough for the classification: a regular trajectory's lambda_T is about
/// ln(1 + T nu) / T (tangent vectors grow linearly), nu = sqrt(alpha / A); the classification is
/// called reliable when that is at most a quarter of the threshold rate (egalitarian, default
/// threshold: T >= ~500).
bool chaos_classification_reliable(const double_pendulum<double>& model, double threshold,
                                   double time);

/// Integrates from x0 to options.time with the given detectors (one per criterion; start() is
/// called on each). `index` selects the tangent vector's random stream (with options.chaos).
/// The energy drift is measured against H(x0).
trajectory_result simulate_trajectory(const double_pendulum<double>& model,
                                      const phase_point<double>& x0,
                                      const ensemble_options& options, std::uint64_t index,
                                      const std::vector<flip_detector_base*>& detectors);

/// Trajectory `index` of the ensemble: the sampled initial condition, then simulate_trajectory.
trajectory_result run_trajectory(const double_pendulum<double>& model,
                                 const microcanonical_sampler& sampler,
                                 const ensemble_options& options, std::uint64_t index,
                                 const std::vector<flip_detector_base*>& detectors);

/// What run_trajectories did.
struct batch_outcome {
    int threads = 1;           ///< OpenMP threads used
    bool interrupted = false;  ///< options.stop was set: some trajectories were not finished
};

/// Runs the trajectories with the given indices (OpenMP across them, dynamic schedule) and
/// calls `finished` (serialised, in completion order) with each finished one; abandoned or
/// skipped trajectories (options.stop) are not reported. options.trajectories and first_index
/// are ignored. Exceptions from a trajectory are rethrown after the loop.
batch_outcome run_trajectories(const double_pendulum<double>& model,
                               const ensemble_options& options,
                               const std::vector<ensemble_criterion>& criteria,
                               std::span<const std::uint64_t> indices,
                               const std::function<void(trajectory_result&&)>& finished);

/// Simulates the ensemble (OpenMP across trajectories; within a thread, 8 or 4 trajectories
/// advance in lockstep, stage by stage -- vector_isa, docs/scale.md -- with the same arithmetic
/// per trajectory as alone). With options.stop set during the run
/// it throws std::runtime_error (the ensemble is incomplete).
ensemble_result run_ensemble(const double_pendulum<double>& model, const ensemble_options& options,
                             const std::vector<ensemble_criterion>& criteria);

}  // namespace flipflux
