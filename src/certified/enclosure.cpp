// The certified route: quantity names, the precision loop, decimal output and containment.
#include "flipflux/certified/enclosure.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <mutex>
#include <optional>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/key_claims.hpp"
#include "flipflux/model/model_text.hpp"
#include "prediction_enclosures.hpp"
#include "saddle_orbit_proof.hpp"

namespace flipflux {
namespace {

using certified_detail::arb_ball;
using certified_detail::take_arb_string;

constexpr double bits_per_digit = 3.3219280948873623;  // log2(10)

enum class certified_quantity {
    omega,
    flux_upright,
    rate_upright,
    flux_approx,
    rate_approx,
    // the saddle-orbit quantities (saddle_orbit_proof.hpp)
    period,
    action,
    flux_saddle,
    rate_saddle,
    multiplier,
    stability_index,
};

bool is_orbit_quantity(certified_quantity q) {
    return q >= certified_quantity::period;
}

bool quantity_named(std::string_view name, certified_quantity& q) {
    if (name == "omega")
        q = certified_quantity::omega;
    else if (name == "flux-upright")
        q = certified_quantity::flux_upright;
    else if (name == "rate-upright")
        q = certified_quantity::rate_upright;
    else if (name == "flux-approx")
        q = certified_quantity::flux_approx;
    else if (name == "rate-approx")
        q = certified_quantity::rate_approx;
    else if (name == "period")
        q = certified_quantity::period;
    else if (name == "action")
        q = certified_quantity::action;
    else if (name == "flux-saddle")
        q = certified_quantity::flux_saddle;
    else if (name == "rate-saddle")
        q = certified_quantity::rate_saddle;
    else if (name == "multiplier")
        q = certified_quantity::multiplier;
    else if (name == "stability-index")
        q = certified_quantity::stability_index;
    else
        return false;
    return true;
}

/// The proofs done in this process, by pendulum, arm, energy and precision (golden --certify asks
/// for six quantities of each orbit; a proof with the monodromy serves every quantity). A thread
/// that needs a proof another thread is doing waits for it rather than doing it a second time
/// (golden --jobs proves the rows of one orbit on several threads): key_claims.
class proof_memo {
  public:
    /// The proof of `key` if there is one (with the monodromy if asked for); else the key is
    /// claimed for the caller, who proves it, calls keep(), and gives the claim back (claim()).
    std::optional<certified_detail::orbit_proof> find_or_claim(const std::string& key,
                                                               bool monodromy) {
        std::unique_lock<std::mutex> lock(mutex_);
        std::optional<certified_detail::orbit_proof> found;
        claims_.ready_or_claim(lock, key, [&] {
            const auto it = proofs_.find(key);
            if (it != proofs_.end() && (!monodromy || it->second.with_monodromy))
                found = it->second;
            return found.has_value();
        });
        return found;
    }
    /// Gives the caller's claim of `key` back at the end of the scope of the returned object.
    key_claims::claim claim(const std::string& key) { return {claims_, mutex_, key}; }
    void keep(const std::string& key, const certified_detail::orbit_proof& p) {
        const std::lock_guard<std::mutex> lock(mutex_);
        auto it = proofs_.find(key);
        if (it == proofs_.end())
            proofs_.emplace(key, p);
        else if (p.with_monodromy || !it->second.with_monodromy)
            it->second = p;
    }

  private:
    std::mutex mutex_;
    key_claims claims_;
    std::map<std::string, certified_detail::orbit_proof> proofs_;
};

proof_memo& memo() {
    static proof_memo m;
    return m;
}

thread_local bool proof_memo_bypassed = false;

std::atomic<std::size_t> proofs_done{0};

/// The proof of the saddle orbit at prec bits: its centre is the non-rigorous orbit in mp:D, D the
/// decimal digits of prec - 32 bits, and the box's relative radius at most 10^-D.
certified_detail::orbit_proof saddle_orbit_proof(const model_text& model, arm a,
                                                 const std::string& energy, bool monodromy,
                                                 slong prec) {
    std::string key;
    for (std::size_t i = 0; i < parameter_count; ++i)
        key += resolved_text(model, i) + ",";
    key += "|" + to_string(a) + "|" + energy + "|" + std::to_string(prec);
    // the claim is given back however this ends: the proof kept below, or an exception
    std::optional<key_claims::claim> claim;
    if (!proof_memo_bypassed) {
        if (auto p = memo().find_or_claim(key, monodromy)) return *p;
        claim.emplace(memo().claim(key));
    }
    certified_detail::orbit_proof_input in;
    in.pendulum = certified_detail::pendulum_from_text(model, prec);
    in.flip_arm = a;
    in.energy_text = energy;
    certified_detail::energy_from_text(in.energy.x, energy, prec);
    // the family's range E_s < E < E_max, decided on the balls
    arb_ball es, emax;
    const certified_detail::pendulum_balls& p = in.pendulum;
    arb_mul_2exp_si(es.x, a == arm::two ? p.beta.x : p.alpha.x, 1);
    arb_add(emax.x, p.alpha.x, p.beta.x, prec);
    arb_mul_2exp_si(emax.x, emax.x, 1);
    if (arb_le(in.energy.x, es.x) || arb_ge(in.energy.x, emax.x))
        throw input_error::about("energy", "'" + energy + "' is outside the arm-" + to_string(a) +
                                               " saddle-orbit family's range (E_s, E_max), open "
                                               "at both ends");
    if (!arb_gt(in.energy.x, es.x) || !arb_lt(in.energy.x, emax.x))
        throw certification_error("saddle orbit at E = " + energy +
                                  ": the energy cannot be separated from the ends of the family's "
                                  "range (E_s, E_max)");
    const int digits =
        std::max(1, static_cast<int>(std::floor(static_cast<double>(prec - 32) / bits_per_digit)));
    in.centre = certified_detail::saddle_orbit_centre(model, a, energy, digits);
    // the box: 4 |Y G(z^)| (the centre's actual distance from the zero, times 4) between
    // 10^-(D + 10) (the mp:D orbit's working digits) and 10^-D (the digits it claims); the
    // multiplier's radius follows the box's
    in.box_digits = digits + 10;
    in.fallback_box_digits = digits;
    // The rigorous integration loses bits to the orbit's growth (near E_max, where the multiplier
    // reaches 1e8 and more, the centre's G(z^) can come out wider than the box 10^-D): a proof that
    // failed is tried again around the same centre and box with 64, then 192, more bits of ball
    // arithmetic (e.g. unequal-point-masses at E = 118.8972, arm 2, loses 36 bits).
    certified_detail::orbit_proof proof;
    for (const slong extra : {slong(0), slong(64), slong(192)}) {
        if (extra > 0) {
            in.pendulum = certified_detail::pendulum_from_text(model, prec + extra);
            certified_detail::energy_from_text(in.energy.x, energy, prec + extra);
        }
        try {
            proof = certified_detail::prove_saddle_orbit(in, prec + extra, monodromy);
            break;
        } catch (const certification_error&) {
            if (extra == 192) throw;
        }
    }
    ++proofs_done;
    if (!proof_memo_bypassed) memo().keep(key, proof);
    return proof;
}

void enclose_orbit_quantity(arb_t res, certified_quantity q, const model_text& model, arm a,
                            const std::string& energy, slong prec) {
    // NOTE: always with the monodromy (the box integration with Phi's four columns costs about
    // 1.75 times the one with the tangent along beta alone, and one proof then serves all six
    // quantities of the orbit, as golden --certify asks for)
    const certified_detail::orbit_proof proof = saddle_orbit_proof(model, a, energy, true, prec);
    switch (q) {
        case certified_quantity::period:
            arb_set(res, proof.period.x);
            return;
        case certified_quantity::action:
            arb_set(res, proof.action.x);
            return;
        case certified_quantity::flux_saddle:
            arb_mul_2exp_si(res, proof.action.x, 1);
            return;
        case certified_quantity::rate_saddle: {
            const certified_detail::pendulum_balls p =
                certified_detail::pendulum_from_text(model, prec);
            arb_ball E, omega;
            certified_detail::energy_from_text(E.x, energy, prec);
            certified_detail::enclose_phase_volume(omega.x, p, E.x, prec);
            arb_mul_2exp_si(res, proof.action.x, 1);
            arb_div(res, res, omega.x, prec);
            return;
        }
        case certified_quantity::stability_index:
            arb_set(res, proof.stability_index.x);
            return;
        case certified_quantity::multiplier: {
            // mu = (k + sign(k) sqrt(k^2 - 4)) / 2 for |k| > 2 (orbits/floquet: the real |mu| > 1)
            const arb_struct* k = proof.stability_index.x;
            arb_ball two, root;
            arb_set_ui(two.x, 2);
            const bool positive = arb_gt(k, two.x);
            arb_neg(two.x, two.x);
            if (!positive && !arb_lt(k, two.x))
                throw certification_error("saddle orbit at E = " + energy +
                                          ": the orbit is not proven hyperbolic (|tr M - 2| > 2)");
            arb_sqr(root.x, k, prec);
            arb_sub_ui(root.x, root.x, 4, prec);
            arb_sqrt(root.x, root.x, prec);
            if (positive)
                arb_add(res, k, root.x, prec);
            else
                arb_sub(res, k, root.x, prec);
            arb_mul_2exp_si(res, res, -1);
            return;
        }
        default:
            arb_indeterminate(res);
            return;
    }
}

/// True when E <= E_s of arm a, decided exactly from the decimal inputs (model/model_text.hpp
/// critical_decimals_of): where the balls of E and of E_s = 2 g m2 a2 (say) overlap, as they do
/// at E = E_s for decimal parameters, no precision separates them, and the fluxes, which vanish
/// there, would have only the enclosure [0, f(E_s + 2^-prec)] of no relative accuracy.
bool at_or_below_saddle(const model_text& model, arm a, const std::string& energy) {
    const critical_decimals levels = critical_decimals_of(model);
    const std::string& saddle = a == arm::two ? levels.saddle2 : levels.saddle1;
    if (saddle.empty()) return false;  // beyond the decimal range: the balls decide
    const std::string d = decimal_difference(energy, saddle, "energy");
    return d == "0" || d.front() == '-';
}

void enclose(arb_t res, certified_quantity q, const model_text& model, arm a,
             const std::string& energy, slong prec) {
    const certified_detail::pendulum_balls p = certified_detail::pendulum_from_text(model, prec);
    arb_ball E;
    certified_detail::energy_from_text(E.x, energy, prec);
    const bool upright =
        q == certified_quantity::flux_upright || q == certified_quantity::rate_upright;
    const bool approx =
        q == certified_quantity::flux_approx || q == certified_quantity::rate_approx;
    // the exact decimals first: the curve's slope (an eigenproblem in balls) only where they say
    // E <= E_s, not again for every enclosure above the saddle
    if ((upright || approx) && at_or_below_saddle(model, a, energy) &&
        (upright || certified_detail::approximate_curve_above_saddle(p, a, prec))) {
        arb_zero(res);  // no accessible point on the surface: f = 0, and f / Omega = 0
        return;
    }
    switch (q) {
        case certified_quantity::omega:
            certified_detail::enclose_phase_volume(res, p, E.x, prec);
            return;
        case certified_quantity::flux_upright:
            certified_detail::enclose_upright_flux(res, p, a, E.x, prec);
            return;
        case certified_quantity::rate_upright: {
            arb_ball omega;
            certified_detail::enclose_upright_flux(res, p, a, E.x, prec);
            certified_detail::enclose_phase_volume(omega.x, p, E.x, prec);
            arb_div(res, res, omega.x, prec);
            return;
        }
        case certified_quantity::flux_approx:
            certified_detail::enclose_approximate_flux(res, p, a, E.x, prec);
            return;
        case certified_quantity::rate_approx: {
            arb_ball omega;
            certified_detail::enclose_approximate_flux(res, p, a, E.x, prec);
            if (arb_is_zero(res)) return;  // an inaccessible curve: 0 / Omega = 0 (Omega > 0)
            certified_detail::enclose_phase_volume(omega.x, p, E.x, prec);
            arb_div(res, res, omega.x, prec);
            return;
        }
        default:
            break;
    }
    enclose_orbit_quantity(res, q, model, a, energy, prec);
}

/// Relative radius as a power of ten: log10(radius / |mid|) (-inf for a zero radius, +inf for a
/// ball containing 0 with a non-zero radius or a non-finite ball).
double log10_relative_radius(const arb_t x) {
    if (!arb_is_finite(x)) return INFINITY;
    if (mag_is_zero(arb_radref(x))) return -INFINITY;
    if (arb_contains_zero(x)) return INFINITY;
    arb_ball r, m;
    arb_get_rad_arb(r.x, x);
    arb_get_mid_arb(m.x, x);
    arb_abs(m.x, m.x);
    arb_div(r.x, r.x, m.x, 64);
    arb_log_base_ui(r.x, r.x, 10, 64);
    return arf_get_d(arb_midref(r.x), ARF_RND_UP) + 1e-9;
}

/// The decimal text of x's midpoint with `digits` significant digits and a radius (3 digits,
/// rounded up) that covers the rounding of the midpoint: the printed ball contains x.
certified_enclosure to_decimal_ball(const arb_t x, int digits, slong prec) {
    certified_enclosure e;
    arb_ball mid, printed_mid, excess;
    arb_get_mid_arb(mid.x, x);
    e.mid = take_arb_string(arb_get_str(mid.x, digits, ARB_STR_NO_RADIUS));
    if (e.mid.rfind("0e", 0) == 0 || e.mid == "0") e.mid = "0";
    arb_set_str(printed_mid.x, e.mid.c_str(), prec + 64);
    // radius of the printed ball >= |x - printed_mid| + rad(x) over the whole ball
    arb_sub(excess.x, printed_mid.x, mid.x, prec + 64);
    arb_abs(excess.x, excess.x);
    arf_t bound;
    arf_init(bound);
    arb_get_ubound_arf(bound, excess.x, prec + 64);
    arf_t rad;
    arf_init(rad);
    arf_set_mag(rad, arb_radref(x));
    arf_add(bound, bound, rad, 64, ARF_RND_CEIL);
    arf_clear(rad);
    if (arf_is_zero(bound)) {
        e.radius = "0";
    } else {
        // 3 significant digits, rounded up: increase the printed value until it is >= bound
        arb_ball b, printed;
        arb_set_arf(b.x, bound);
        arb_mul_ui(b.x, b.x, 1001, 64);
        arb_div_ui(b.x, b.x, 1000, 64);
        for (;;) {
            e.radius = take_arb_string(arb_get_str(b.x, 3, ARB_STR_NO_RADIUS));
            arb_set_str(printed.x, e.radius.c_str(), 128);
            arf_t lo;
            arf_init(lo);
            arb_get_lbound_arf(lo, printed.x, 128);
            const bool ok = arf_cmp(lo, bound) >= 0;
            arf_clear(lo);
            if (ok) break;
            arb_mul_ui(b.x, b.x, 101, 64);
            arb_div_ui(b.x, b.x, 100, 64);
        }
    }
    arf_clear(bound);
    return e;
}

}  // namespace

bool has_certified_enclosure(std::string_view quantity) {
    certified_quantity q;
    return quantity_named(quantity, q);
}

std::size_t saddle_orbit_proofs_done() {
    return proofs_done.load();
}

certified_proof_memo_bypass::certified_proof_memo_bypass() : scoped_flag(proof_memo_bypassed) {}

certified_enclosure certified_value(std::string_view quantity, const model_text& model, arm a,
                                    const std::string& energy, int digits) {
    certified_quantity q;
    if (!quantity_named(quantity, q))
        throw input_error::about("quantity", "'" + std::string(quantity) +
                                                 "' has no certified route (known: omega, "
                                                 "flux-upright, rate-upright, flux-approx, "
                                                 "rate-approx, period, action, flux-saddle, "
                                                 "rate-saddle, multiplier, stability-index)");
    if (digits < 1) throw input_error::about("digits", std::to_string(digits) + " is not >= 1");
    const double target = -digits, accepted = -digits + 10;
    slong prec = static_cast<slong>(std::ceil(digits * bits_per_digit)) + 32;
    arb_ball x;
    double rel = INFINITY;
    int failures = 0;
    for (int attempt = 0; attempt < 6; ++attempt) {
        try {
            enclose(x.x, q, model, a, energy, prec);
        } catch (const certification_error&) {
            // a saddle-orbit proof that failed (the Krawczyk test, a rigorous integration): once
            // more at half as many bits again (a more accurate centre, narrower balls; near E_max
            // the multiplier amplifies every error), then the failure is reported
            if (!is_orbit_quantity(q) || ++failures > 1) throw;
            prec += prec / 2 + 32;
            continue;
        }
        rel = log10_relative_radius(x.x);
        if (rel <= target) break;
        // raise the precision by the missing digits (at least doubling the guard) and retry
        const double missing = std::isfinite(rel) ? rel - target : prec / bits_per_digit;
        prec += static_cast<slong>(std::ceil(missing * bits_per_digit)) + 32 + prec / 4;
    }
    if (!(rel <= accepted))
        throw certification_error(
            std::string(quantity) + " at E = " + energy + ": the enclosure's relative radius " +
            (std::isfinite(rel) ? "1e" + std::to_string(static_cast<int>(std::ceil(rel)))
                                : std::string("(unbounded)")) +
            " did not reach 1e" + std::to_string(static_cast<int>(accepted)) + " (at " +
            std::to_string(prec) + " bits)");
    certified_enclosure e = to_decimal_ball(x.x, digits + 5, prec);
    e.bits = prec;
    if (std::isinf(rel) && rel < 0) {
        e.proven_digits = digits + 5;
    } else {
        // of the printed ball (its radius covers the midpoint's rounding to digits + 5 digits,
        // which dominates when the loop raised the precision beyond the request)
        arb_ball printed;
        arb_set_str(printed.x, e.mid.c_str(), prec + 64);
        arb_ball r;
        arb_set_str(r.x, e.radius.c_str(), 64);
        arb_add_error(printed.x, r.x);
        e.proven_digits =
            static_cast<int>(std::floor(-std::max(rel, log10_relative_radius(printed.x))));
    }
    return e;
}

certified_enclosure recentre_enclosure(const certified_enclosure& e, const std::string& mid) {
    const slong prec = 64 + static_cast<slong>(4 * (e.mid.size() + mid.size()));
    arb_ball m, r, v, ball;
    if (arb_set_str(m.x, e.mid.c_str(), prec) || arb_set_str(r.x, e.radius.c_str(), prec) ||
        arb_set_str(v.x, mid.c_str(), prec))
        throw input_error("recentre_enclosure: a decimal does not parse ('" + e.mid + "', '" +
                          e.radius + "', '" + mid + "')");
    // the ball v +/- (|v - m| + r), written as e's printing writes a ball: the radius rounded up
    arb_sub(ball.x, v.x, m.x, prec);
    arb_abs(ball.x, ball.x);
    arb_add(ball.x, ball.x, r.x, prec);
    arf_t u;
    arf_init(u);
    arb_get_ubound_arf(u, ball.x, prec);
    arb_set(ball.x, v.x);
    mag_zero(arb_radref(ball.x));
    arb_add_error_arf(ball.x, u);
    arf_clear(u);
    certified_enclosure out = to_decimal_ball(ball.x, static_cast<int>(mid.size()) + 2, prec);
    out.mid = mid;
    out.bits = e.bits;
    const double rel = log10_relative_radius(ball.x);
    out.proven_digits =
        std::isinf(rel) && rel < 0 ? e.proven_digits : static_cast<int>(std::floor(-rel));
    return out;
}

bool enclosure_contains(const certified_enclosure& e, const std::string& value,
                        const std::string& slack) {
    const slong prec = 64 + static_cast<slong>(4 * (e.mid.size() + value.size()));
    arb_ball mid, radius, v, s, ball;
    if (arb_set_str(mid.x, e.mid.c_str(), prec) || arb_set_str(radius.x, e.radius.c_str(), prec) ||
        arb_set_str(v.x, value.c_str(), prec) || arb_set_str(s.x, slack.c_str(), prec))
        throw input_error("enclosure_contains: a decimal does not parse ('" + e.mid + "', '" +
                          e.radius + "', '" + value + "', '" + slack + "')");
    // |v - mid| <= radius + |slack| decided on balls: certain only if it holds for every point
    arb_sub(ball.x, v.x, mid.x, prec);
    arb_abs(ball.x, ball.x);
    arb_abs(s.x, s.x);
    arb_add(radius.x, radius.x, s.x, prec);
    return arb_le(ball.x, radius.x);
}

}  // namespace flipflux
