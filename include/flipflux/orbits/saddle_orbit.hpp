// Saddle orbits: the Lyapunov periodic orbit born at the flip saddle of either arm (paper Sec. 3.2,
// 4, 5.4; docs/theory.md#saddle-orbits), its period T, action F = oint l.dtheta > 0 (the saddle
// flux is f3 = 2 F), turning points and Floquet multipliers.
//
// Domain: any admissible pendulum; arm 2 (saddle (0, pi)) for 2 beta < E < 2 (alpha + beta), arm 1
// (saddle (pi, 0)) for 2 alpha < E < 2 (alpha + beta) (model.saddle_energy(a) <
// E < model.maximum_energy()). Energies outside throw input_error naming --energy.
//
// Method: the shooting problem is solved at double with Ceres (periodic formulation; analytic
// Jacobian from the variational equations) or a Newton iteration (symmetric formulation), after
// a continuation from the linearised centre mode when no guess is given; then polished in Real
// by Gauss-Newton / Newton to the working precision, with equal steps of the chosen integrator
// (orbit_options::integrator: Gauss-Legendre, or Taylor series; above quad with Taylor, Newton in
// quad then the chord iteration in Real) chosen for the requested tolerance. Convergence is
// reported in `status`, never thrown.
//
// Accuracy (verified in verification/orbits*.cpp against a higher-precision solve): T and F to a
// relative error of about 1e-13 (double), 1e-31 (quad), 1e-46 (mp:50), 1e-108 (mp:100, Taylor:
// verification/orbits_taylor.cpp); error_estimate_* state the per-orbit estimate. Near E_max the
// multiplier grows like (E_max - E)^(-lambda/...) and the attainable accuracy degrades
// accordingly (see docs/theory.md).
#pragma once

#include <array>
#include <complex>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "flipflux/core/names.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/energy_level.hpp"

namespace flipflux {

/// Which shooting formulation refines the orbit.
enum class orbit_method {
    periodic,   ///< the paper's: unknowns (beta, T), residual x(T) - x(0); Ceres then Gauss-Newton
    symmetric,  ///< time reversal: unknowns (beta, T/4), residual l(T/4) = 0; Newton
};
template <>
struct enum_table<orbit_method> {
    static constexpr std::string_view noun = "a saddle-orbit method";
    static constexpr std::array<std::pair<orbit_method, std::string_view>, 2> entries{
        {{orbit_method::periodic, "periodic"}, {orbit_method::symmetric, "symmetric"}}};
};

/// Which integrator the shooting, the monodromy and the action integral use (fixed equal steps
/// either way, so the residual is smooth in the unknowns).
enum class orbit_integrator {
    taylor,          ///< Taylor series (integrators/taylor.hpp): the default at quad and mp
    gauss_legendre,  ///< symplectic Gauss-Legendre (integrators/gauss_legendre.hpp): the
                     ///< default at double, and the independent (certifying) route elsewhere
};
template <>
struct enum_table<orbit_integrator> {
    static constexpr std::string_view noun = "a saddle-orbit integrator";
    static constexpr std::array<std::pair<orbit_integrator, std::string_view>, 2> entries{
        {{orbit_integrator::taylor, "taylor"},
         {orbit_integrator::gauss_legendre, "gauss-legendre"}}};
};

/// The default integrator at Real: Gauss-Legendre at double (faster there), Taylor above
/// (measured in bench/bench_orbit_integrators.cpp).
template <class Real>
constexpr orbit_integrator default_orbit_integrator() {
    return std::is_same_v<Real, double> ? orbit_integrator::gauss_legendre
                                        : orbit_integrator::taylor;
}

enum class orbit_status {
    converged,      ///< Newton converged to the working precision
    stalled,        ///< Newton stopped improving above the working precision (see residual)
    not_converged,  ///< no solution found from the guess
};
template <>
struct enum_table<orbit_status> {
    static constexpr std::string_view noun = "an orbit status";
    static constexpr std::array<std::pair<orbit_status, std::string_view>, 3> entries{
        {{orbit_status::converged, "converged"},
         {orbit_status::stalled, "stalled"},
         {orbit_status::not_converged, "not converged"}}};
};

template <class Real>
struct orbit_options {
    orbit_method method = orbit_method::periodic;
    orbit_integrator integrator = default_orbit_integrator<Real>();
    int stages = 0;     ///< Gauss-Legendre stages; 0 = the type's default (default_stages)
    Real tolerance{0};  ///< integration tolerance (relative to the orbit's scale); 0 = 64 eps
    int max_newton_iterations = 30;
};

/// Default number of Gauss-Legendre stages at Real (order 2 s): 6, 10, 14, 20.
template <class Real>
int default_stages();

/// A starting point for the shooting: direction of the circularised momentum and period.
template <class Real>
struct orbit_guess {
    Real beta{0};
    Real period{0};
};

/// Floquet multipliers of a periodic orbit from its monodromy matrix (two unit multipliers and a
/// reciprocal pair mu, 1/mu, real or on the unit circle).
template <class Real>
struct floquet_multipliers {
    std::array<std::complex<Real>, 4> eigenvalues;  ///< Eigen's EigenSolver, by increasing |.|
    Real trace{0};                                  ///< tr M = 2 + mu + 1/mu
    Real stability_index{0};  ///< k = mu + 1/mu = tr M - 2 (|k| > 2: hyperbolic)
    bool hyperbolic = false;
    Real multiplier{0};             ///< hyperbolic: the real mu with |mu| > 1 (from k); else 1
    Real angle{0};                  ///< elliptic: nu in [0, pi] with mu = exp(+-i nu); else 0
    Real unit_deviation{0};         ///< max |lambda - 1| over the two eigenvalues nearest 1
    Real determinant_deviation{0};  ///< |det M - 1|
};

/// Floquet analysis of a 4x4 monodromy matrix (EigenSolver in Real).
template <class Real>
floquet_multipliers<Real> floquet_analysis(const std::array<std::array<Real, 4>, 4>& monodromy);

template <class Real>
struct saddle_orbit {
    arm flip_arm = arm::two;
    Real energy{0};             ///< E
    Real excess{0};             ///< E - E_s, the kinetic energy at the saddle
    Real beta{0};               ///< direction of the circularised momentum at the saddle
    Real period{0};             ///< T
    Real action{0};             ///< F = oint (l1 dth1 + l2 dth2) > 0
    Real period_derivative{0};  ///< dT/dE along the family (from the shooting Jacobian)
    Real flux() const { return 2 * action; }  ///< f3 = 2 F (bidirectional saddle flux)
    std::array<Real, 2> saddle{};             ///< q*
    phase_point<Real> start{};                ///< (q*, l0): the state at t = 0
    /// Turning points (theta1, theta2) at t = T/4 and 3T/4 (both momenta zero); the second is the
    /// reflection of the first through q*.
    std::array<std::array<Real, 2>, 2> turning_points{};
    floquet_multipliers<Real> floquet;
    std::array<std::array<Real, 4>, 4> monodromy{};  ///< absolute = frame coordinates' Jacobian

    // ---- numerical record -------------------------------------------------------------------
    orbit_status status = orbit_status::not_converged;
    orbit_method method = orbit_method::periodic;
    orbit_integrator integrator = orbit_integrator::gauss_legendre;
    int stages = 0;  ///< Gauss-Legendre stages (0 with the Taylor integrator)
    int order = 0;   ///< the integrator's order: 2 stages (Gauss-Legendre), the series' (Taylor)
    long steps = 0;  ///< equal integration steps over the shooting interval
    Real tolerance{0};
    int newton_iterations = 0;
    Real residual{0};      ///< scaled residual norm at the solution
    Real last_update{0};   ///< relative size of the last Newton correction
    Real energy_error{0};  ///< max |H - E| / (E - E_s) over the stored quarter orbit
    Real error_estimate_period{0};
    Real error_estimate_action{0};
    std::string double_stage;  ///< report of the double-precision stage (Ceres' brief report)
    /// Not converged because E lies beyond the family's end as saddle orbits: the E - E_s (at
    /// double) where the continuation found the family's orbit to swing angle
    /// family_end_angle (1 or 2) to the vertical opposite its saddle's; NaN otherwise
    double family_end = std::numeric_limits<double>::quiet_NaN();
    int family_end_angle = 0;
    /// The quarter orbit from the saddle to the first turning point in frame coordinates
    /// (theta - q*, l), at t_k = k * quarter_step, k = 0..n.
    std::vector<std::array<Real, 4>> quarter;
    Real quarter_step{0};
};

/// One attempted step of the continuation in energy (the record keeps the rejected steps, i.e.
/// the step halvings).
struct continuation_step {
    double from_excess = 0, to_excess = 0;  ///< E - E_s before and after the step
    bool accepted = false;
    int iterations = 0;  ///< corrector iterations
    std::string note;    ///< why a step was rejected
};

/// A continued family: the orbits at the requested energies and the continuation's record.
template <class Real>
struct saddle_family {
    arm flip_arm = arm::two;
    std::vector<saddle_orbit<Real>> orbits;  ///< at the requested energies reached, in order
    std::vector<continuation_step> steps;    ///< every attempted step (double stage)
    int halvings = 0;                        ///< rejected steps (each halved the step)
    double highest_excess = 0;               ///< largest E - E_s the double continuation reached
    std::string stop_reason;                 ///< why it stopped short ("" if every energy reached)
};

/// The centre mode's guess: beta of the mode's momentum, T_lin = 2 pi / omega.
template <class Real>
orbit_guess<Real> linear_guess(const double_pendulum<Real>& model, arm a);

/// The saddle orbit at energy E, continued from the centre mode (at double) and refined in Real.
/// The orbit depends on E through E - E_s (energy.above), exact for a decimal input (see
/// model/energy_level.hpp); orbit.energy is E rounded to Real.
template <class Real>
saddle_orbit<Real> solve_saddle_orbit(const double_pendulum<Real>& model, arm a,
                                      const level_arg<Real>& energy,
                                      const orbit_options<Real>& options = {});

/// Why a recorded orbit (a cache entry) is not what the solver would have recorded for its own
/// (beta, T), or "" when it is: the solver's last shot and final orbit are replayed at the
/// recorded (beta, T) with the recorded integrator and grid (about one Newton iteration's work),
/// and the action, quarter orbit, monodromy, multiplier, stability index and dT/dE are compared
/// to the rounding of the record's decimals. A checksum catches accidents; this catches a
/// record edited and resealed.
template <class Real>
std::string orbit_replica_problem(const double_pendulum<Real>& model, const saddle_orbit<Real>& o);

/// The saddle orbit at energy E refined from a guess (no continuation).
template <class Real>
saddle_orbit<Real> refine_saddle_orbit(const double_pendulum<Real>& model, arm a,
                                       const level_arg<Real>& energy,
                                       const orbit_guess<Real>& guess,
                                       const orbit_options<Real>& options = {});

/// The family through the given energies (increasing, each inside the family's range): a
/// continuation at double from the centre mode (symmetric Newton corrector; secant predictor in
/// -log(E_max - E); step halving on failure, recorded), then each requested orbit refined in Real
/// by options.method. Throws input_error for an energy outside the range or a decreasing list.
template <class Real>
saddle_family<Real> continue_saddle_family(const double_pendulum<Real>& model, arm a,
                                           const std::vector<energy_level<Real>>& energies,
                                           const orbit_options<Real>& options = {});
template <class Real>
saddle_family<Real> continue_saddle_family(const double_pendulum<Real>& model, arm a,
                                           const std::vector<Real>& energies,
                                           const orbit_options<Real>& options = {}) {
    return continue_saddle_family(
        model, a, std::vector<energy_level<Real>>(energies.begin(), energies.end()), options);
}

/// The absolute state (theta1, theta2, l1, l2) on the orbit at time t (any real t; reduced modulo
/// T and by the orbit's time-reversal and reflection symmetries to the stored quarter orbit).
template <class Real>
phase_point<Real> orbit_state(const double_pendulum<Real>& model, const saddle_orbit<Real>& orbit,
                              const Real& t);

/// Throws input_error unless E_s(a) < E < E_max.
template <class Real>
void check_orbit_energy(const double_pendulum<Real>& model, arm a, const level_arg<Real>& energy);

/// Throws for an orbit that did not converge: input_error naming the energy where it lies within
/// a relative 1e-6 of E_max - E_s below E_max (the orbit's period diverges there and each
/// precision's continuation stops short of E_max, docs/theory.md, "Near E_max"), else
/// std::runtime_error (`what` names the caller).
template <class Real>
[[noreturn]] void throw_not_converged(const double_pendulum<Real>& model, arm a,
                                      const level_arg<Real>& energy,
                                      const saddle_orbit<Real>& orbit, const std::string& what);

#define FLIPFLUX_ORBIT_EXTERN(R)                                                             \
    extern template int default_stages<R>();                                                 \
    extern template floquet_multipliers<R> floquet_analysis<R>(                              \
        const std::array<std::array<R, 4>, 4>&);                                             \
    extern template orbit_guess<R> linear_guess<R>(const double_pendulum<R>&, arm);          \
    extern template saddle_orbit<R> solve_saddle_orbit<R>(                                   \
        const double_pendulum<R>&, arm, const level_arg<R>&, const orbit_options<R>&);       \
    extern template saddle_orbit<R> refine_saddle_orbit<R>(                                  \
        const double_pendulum<R>&, arm, const level_arg<R>&, const orbit_guess<R>&,          \
        const orbit_options<R>&);                                                            \
    extern template saddle_family<R> continue_saddle_family<R>(                              \
        const double_pendulum<R>&, arm, const std::vector<energy_level<R>>&,                 \
        const orbit_options<R>&);                                                            \
    extern template std::string orbit_replica_problem<R>(const double_pendulum<R>&,          \
                                                         const saddle_orbit<R>&);            \
    extern template phase_point<R> orbit_state<R>(const double_pendulum<R>&,                 \
                                                  const saddle_orbit<R>&, const R&);         \
    extern template void check_orbit_energy<R>(const double_pendulum<R>&, arm,               \
                                               const level_arg<R>&);                         \
    extern template void throw_not_converged<R>(const double_pendulum<R>&, arm,              \
                                                const level_arg<R>&, const saddle_orbit<R>&, \
                                                const std::string&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_ORBIT_EXTERN)
#undef FLIPFLUX_ORBIT_EXTERN

}  // namespace flipflux
