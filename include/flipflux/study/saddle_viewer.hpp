// The saddle-orbit viewer's data (`flipflux viewer`, a scene's [viewer]; docs/scenes.md): each
// arm's saddle-orbit family (paper Sec. 3.2, 4) at N energies spread evenly over (E_s, E_max), each
// orbit's configuration path (theta1, theta2) at equal times over one period with its period T,
// action F and Floquet multiplier, and the potential V(theta1, theta2) on a grid for its contours.
// The page that shows them is io/viewer_page.hpp; this header only computes and serialises.
//
// Energies: E_k = E_s + (E_max - E_s) (k + 1) / (N + 1), k = 0..N-1, written as decimal text with
// enough significant digits that the rounding moves E_k by less than 1/100 of the spacing
// (viewer_energy_texts); each text is parsed in Real (model/energy_level.hpp), so the CLI and the
// scene (whose plan continues the family at those texts, through the on-disk cache) solve the same
// orbits. Orbits come from the in-process memo (orbits/orbit_store.hpp) when there, else from one
// continuation of the family (continue_saddle_family) through the missing energies.
//
// Path: orbit_state(t_k), t_k = k T / (samples - 1), k = 0..samples-1; the last point is computed
// at t = T (not copied from the first), so path.front() == path.back() up to the orbit's accuracy
// (a test checks that the orbit closes).
#pragma once

#include <array>
#include <string>
#include <vector>

#include "flipflux/core/real.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {

/// What to compute; every count is checked (input_error naming the field, the CLI's option).
struct viewer_request {
    std::vector<arm> arms{arm::one, arm::two};
    int energies = 30;  ///< orbits per arm, in [1, 1000]
    int samples = 161;  ///< points of each orbit's path over one period, in [8, 100000]
    int grid = 121;     ///< potential grid points per axis, in [7, 2001], 1 mod 6 (nodes at k pi/2)
};

/// Throws input_error naming the field ("energies", "samples", "grid", "arms") of a bad request.
void check_viewer_request(const viewer_request& request);

/// The N energies of arm a's family as decimal text, increasing, strictly inside (E_s, E_max).
std::vector<std::string> viewer_energy_texts(const double_pendulum<double>& model, arm a, int n);

template <class Real>
struct viewer_orbit {
    std::string energy;  ///< E as decimal text (viewer_energy_texts)
    Real period{0}, action{0}, stability_index{0};
    bool hyperbolic = false;
    Real multiplier{0};  ///< hyperbolic: the real mu, |mu| > 1
    Real angle{0};       ///< elliptic: nu with mu = exp(+-i nu)
    Real error_estimate_period{0}, error_estimate_action{0};
    orbit_status status = orbit_status::not_converged;
    std::vector<std::array<Real, 2>> path;  ///< (theta1, theta2) at t_k = k T / (samples - 1)
};

template <class Real>
struct viewer_family {
    arm flip_arm = arm::two;
    Real saddle_energy{0};
    std::array<Real, 2> saddle{};
    std::vector<viewer_orbit<Real>> orbits;  ///< converged or stalled, by increasing energy
    std::string stop_reason;                 ///< why energies are missing ("" if none is)
};

/// V on the square [from, to]^2: values[i * n + j] = V(theta1_i, theta2_j), theta_k = from + (to -
/// from) k / (n - 1).
template <class Real>
struct potential_grid {
    Real from{0}, to{0};
    int n = 0;
    std::vector<Real> values;
};

template <class Real>
struct viewer_data {
    physical_parameters<Real> parameters;
    Real maximum_energy{0};
    std::vector<viewer_family<Real>> families;  ///< in the order of request.arms
    potential_grid<Real> potential;             ///< over [-pi, 2 pi]^2: both arms' orbits
    std::size_t solved = 0;                     ///< orbits solved (not from the memo)
};

/// The viewer's data (see the file comment). Throws input_error for a bad request.
template <class Real>
viewer_data<Real> saddle_viewer_data(const double_pendulum<Real>& model,
                                     const viewer_request& request,
                                     const orbit_options<Real>& options = {});

/// The data as JSON text, every real a JSON number with all the digits of Real (to_decimal).
template <class Real>
std::string viewer_json(const viewer_data<Real>& data);

#define FLIPFLUX_VIEWER_EXTERN(R)                                                   \
    extern template viewer_data<R> saddle_viewer_data<R>(                           \
        const double_pendulum<R>&, const viewer_request&, const orbit_options<R>&); \
    extern template std::string viewer_json<R>(const viewer_data<R>&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_VIEWER_EXTERN)
#undef FLIPFLUX_VIEWER_EXTERN

}  // namespace flipflux
