// Computer-assisted proofs of the saddle orbits (private to certified/; docs/certified.md#saddle-
// orbits-proven, docs/theory.md).
//
// The symmetric shooting map (orbits/shooting.hpp): from the saddle with the momentum
//     l0(beta) = sqrt(2 (E - E_s)) S (cos beta, sin beta),   S = M*^(1/2),
// (H = E exactly), G(beta, tau) = l(tau), the momenta after a time tau. A zero is a brake orbit:
// by the time reversal R (delta, l) -> (delta, -l) and the reflection P x -> -x of the frame's
// equations, x(2 tau) = -x(0) and x(4 tau) = x(0): a periodic orbit of period T = 4 tau and
// action F = oint l.dtheta = 4 int_0^tau l.w dt.
//
// Krawczyk: for a box X around the centre z^ (the non-rigorous mp orbit) and Y ~ G'(z^)^-1,
//     K(X) = z^ - Y G(z^) + (I - Y G'(X)) (X - z^);
// K(X) inside the interior of X proves a unique zero of G in X, and it lies in K(X). G(z^) is
// enclosed by a rigorous Taylor integration from the point z^ (ball_taylor.hpp), G'(X) by one
// from the whole box with the variational equations (the tangent along beta and the end's
// velocity l'(tau)).
//
// From the proved box K: T = 4 tau in 4 K_tau; F = 4 a(z*) in 4 (a(z^) + grad a(X) (K - z^)) (mean
// value theorem on the convex X; da/dtau = l.w at the end, da/dbeta from the action's tangent);
// the monodromy M = N^2 with N = R Phi(tau)^-1 R Phi(tau) (the half-period map, from the
// symmetries), Phi^-1 = -J Phi^T J (symplectic), so tr M = tr N^2 is enclosed from Phi over X;
// stability index k = tr M - 2 = mu + 1/mu, multiplier mu = (k + sign(k) sqrt(k^2 - 4)) / 2.
#pragma once

#include <string>

#include "ball_taylor.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/model_text.hpp"
#include "prediction_enclosures.hpp"

namespace flipflux::certified_detail {

/// Hamilton's equations in the saddle frame (orbits/saddle_frame.hpp) as ball series: components
/// (delta1, delta2, l1, l2, action), then `columns` tangent vectors of 5 components each (the
/// state's tangent and the action's, action' = l.w, whose gradient is 2 (P, -P, w1, w2)).
class saddle_ball_field final : public ball_vector_field {
  public:
    saddle_ball_field(const pendulum_balls& p, arm a, int columns, slong prec);
    slong dimension() const override { return 5 + 5 * columns_; }
    slong group_of(slong i) const override { return i < 4 ? 0 : i == 4 ? 1 : 2 + (i - 5) / 5; }
    void reserve(slong order) override;
    void coefficient(const ball_jet& x, slong k, arb_ptr out, slong prec) override;

  private:
    void variational(const ball_jet& x, slong k, arb_ptr out, slong prec);

    int columns_;
    arb_ball A_, B_, C_, minus_C_, C2_, two_C2_, D0_, e1alpha_, e2beta_;
    series::sin_cos sd_, s1_, s2_;
    ball_vector one_, d_, ss_, det_, cc_, n1_, n2_, w1_, w2_, ww_, p_;
    ball_vector inv_, i11_, i12_, i22_, sc_, ddet_, nd1_, nd2_, dw1_, dw2_, dww_, pd_, b_, cq_,
        pl1_, pl2_;
    std::vector<ball_vector> dphi_;
    slong reserved_ = -1;
};

/// The non-rigorous orbit's unknowns as decimal text (orbits/: the mp orbit at `digits`).
struct orbit_centre {
    std::string beta, quarter;
};

/// The saddle orbit of arm a at `energy` in mp:digits (find_or_solve_saddle_orbit, default
/// options): its beta and T / 4 with every digit. input_error for an energy outside the family's
/// range; certification_error when the orbit does not converge.
orbit_centre saddle_orbit_centre(const model_text& model, arm a, const std::string& energy,
                                 int digits);

/// What a proof encloses (valid when `proved`).
struct orbit_proof {
    arb_ball beta, quarter;  ///< the box K(X), which holds the unique zero of G in X
    arb_ball period, action;
    bool with_monodromy = false;
    arb_ball trace, stability_index;  ///< tr M and tr M - 2 (with_monodromy)
    double seconds = 0;
    long steps_thin = 0, steps_box = 0;
};

/// The inputs of one proof: the vector field's pendulum (a test may perturb it), the energy ball,
/// the centre and the box's relative radius 10^-box_digits (then 10^-fallback_box_digits when
/// the first box does not contract; 0: no fallback).
struct orbit_proof_input {
    pendulum_balls pendulum;
    arm flip_arm = arm::two;
    arb_ball energy;
    std::string energy_text;
    orbit_centre centre;
    int box_digits = 30;
    int fallback_box_digits = 0;
};

/// The Krawczyk proof at prec bits; throws certification_error ("Krawczyk test failed at E = ...:
/// the box did not contract", or the integration that failed).
orbit_proof prove_saddle_orbit(const orbit_proof_input& in, slong prec, bool monodromy);

/// The state (delta1, delta2, l1, l2, action = 0) at the saddle with l0(beta) and, for each of
/// the `columns` tangents, its start: columns == 1: d/dbeta; columns == 4: the identity's columns
/// (action tangents 0). The integrator's start for a proof; tests integrate it too.
ball_vector saddle_start(const pendulum_balls& p, arm a, const arb_t energy, const arb_t beta,
                         int columns, slong prec);

}  // namespace flipflux::certified_detail
