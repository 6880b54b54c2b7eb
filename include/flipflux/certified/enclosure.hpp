// Proven enclosures of prediction quantities (issue 13): balls [mid +/- radius] that contain the
// exact value by construction, computed with Arb's ball arithmetic (rigorous elementary and
// elliptic functions, rigorous Gauss-Legendre integration of holomorphic integrands). Arb stays
// behind this header: callers see decimal strings only. Derivations, path splits and the argument
// for rigour: docs/certified.md.
//
// The model and the energy come in as decimal text and are turned into Arb balls containing the
// decimals (never through a double), so the enclosure contains the exact quantity of the decimal
// inputs.
#pragma once

#include <cstddef>
#include <string>
#include <string_view>

#include "flipflux/core/error.hpp"
#include "flipflux/core/scoped_flag.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/model/model_text.hpp"

namespace flipflux {

/// A proof that failed (the requested radius was not reached, or a containment check failed): a
/// numerical outcome, not bad input. The CLI maps it to exit status 1.
class certification_error : public std::runtime_error {
  public:
    using std::runtime_error::runtime_error;
};

/// A ball containing the exact value: |exact - mid| <= radius, both decimal strings (the midpoint
/// with all the digits its precision resolves; the radius rounded up, 3 significant digits).
struct certified_enclosure {
    std::string mid;
    std::string radius;
    /// floor(-log10(radius / |mid|)), capped at the digits of mid; -1 when mid = 0 and radius > 0,
    /// the digits of mid when the radius is 0 (an exact value such as a zero flux).
    int proven_digits = 0;
    long bits = 0;  ///< Arb working precision of the last (successful) attempt
};

/// The quantities with a certified route: omega, flux-upright, rate-upright, flux-approx,
/// rate-approx, and the saddle orbit's period, action, flux-saddle, rate-saddle, multiplier,
/// stability-index (a computer-assisted proof of the orbit: a Krawczyk test on the symmetric
/// shooting map with a rigorous Taylor integrator).
bool has_certified_enclosure(std::string_view quantity);

/// An enclosure of `quantity` at `energy` (decimal text) for the pendulum `model` and arm `a`
/// (ignored by omega), aiming at a relative radius <= 10^-digits and accepting
/// <= 10^(-digits + 10). Works at digits * log2(10) + guard bits and raises the precision when the
/// radius is too wide (near a kink of the energy surface). Throws input_error for an unknown
/// quantity, a malformed or non-positive energy or model parameter; certification_error when the
/// radius cannot be reached or a saddle-orbit proof fails ("Krawczyk test failed at E = ...: the
/// box did not contract", after one retry at a higher precision).
certified_enclosure certified_value(std::string_view quantity, const model_text& model, arm a,
                                    const std::string& energy, int digits);

/// While one lives in a thread, that thread's saddle-orbit proofs neither reuse nor keep the
/// proofs this process did before (a proof with its monodromy serves the six orbit quantities):
/// what the accuracy report needs to time one proof from scratch.
class certified_proof_memo_bypass : public scoped_flag {
  public:
    certified_proof_memo_bypass();
};

/// Saddle-orbit proofs this process has carried out (not counting those served from its memo of
/// proofs): what shows that the quantities of one orbit share one proof (golden --certify).
std::size_t saddle_orbit_proofs_done();

/// The ball centred at the decimal `mid` that contains e: radius |mid - e.mid| + e.radius (rounded
/// up, 3 digits), proven_digits of that radius (golden --certify: an enclosure around the row's
/// rounded value). Throws input_error when a decimal does not parse.
certified_enclosure recentre_enclosure(const certified_enclosure& e, const std::string& mid);

/// True when the decimal `value` lies in [mid - radius - slack, mid + radius + slack] (all
/// decimal; slack >= 0, e.g. the error estimate of a non-rigorous value), decided exactly.
bool enclosure_contains(const certified_enclosure& e, const std::string& value,
                        const std::string& slack = "0");

}  // namespace flipflux
