// The microcanonical sampler of the paper's Sec. 5.3, for any admissible double pendulum.
//
// The microcanonical density on H = E, integrated over the momenta, is (paper eq. for rho)
//     rho(th) = int d^2l delta(1/2 l^T M^-1 l - K) = 2 pi sqrt(det M(th)) Theta(K(th)),
//     K = E - V(th):
// with y = L l, M^-1 = L^T L, d^2l = sqrt(det M) d^2y and the delta function of 1/2 |y|^2 - K is
// uniform on the circle |y| = sqrt(2K) (its integral 2 pi does not depend on K in two degrees of
// freedom). Hence:
//   1. configuration: uniform proposals in the box |th_i| <= b_i that contains {V < E}
//      (b1 = 2 asin sqrt(E / (2 alpha)), b2 = 2 asin sqrt(E / (2 beta)), or pi), accepted when
//      V < E and u sqrt(D0 + C^2) < sqrt(det M), u uniform in [0, 1) -- i.e. with probability
//      proportional to sqrt(det M), the paper's weight w (evaluated as u^2 (D0 + C^2) < det M,
//      the same test without square roots; D0 + C^2 = max det M);
//   2. momenta: l = R y, y = sqrt(2K) (cos a, sin a), a uniform in [0, 2 pi), R R^T = M (R the
//      lower Cholesky factor of M, i.e. the paper's L^-1 for L = R^-1, M^-1 = L^T L).
// Any choice of L gives the same distribution (two choices differ by a rotation of y, which leaves
// the uniform angle uniform); tests check the configuration marginals against quadrature of rho,
// <l l^T> = K M at fixed configuration, equipartition and H = E.
#pragma once

#include <array>
#include <cstdint>

#include "flipflux/ensemble/random.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

class microcanonical_sampler {
  public:
    /// Throws input_error unless energy is finite and > 0 (the accessible region is then open).
    microcanonical_sampler(const double_pendulum<double>& model, double energy);

    /// One phase-space point with H = E (to rounding), drawn from rng.
    phase_point<double> operator()(philox_stream& rng) const;
    /// The initial condition of trajectory `index` for `seed`: uses philox_stream(seed, E, index).
    phase_point<double> sample(std::uint64_t seed, std::uint64_t index) const;

    /// Step 1 alone: a configuration with density proportional to sqrt(det M) on V < E.
    std::array<double, 2> sample_configuration(philox_stream& rng) const;
    /// Step 2 alone: the momenta at (th1, th2) for the circle angle a (requires V(th) < E).
    phase_point<double> with_momenta(double th1, double th2, double angle) const;

    double energy() const { return energy_; }
    /// Half-widths (b1, b2) of the proposal box.
    std::array<double, 2> box() const { return box_; }
    const double_pendulum<double>& model() const { return model_; }

  private:
    double_pendulum<double> model_;
    double energy_;
    std::array<double, 2> box_;
};

}  // namespace flipflux
