// The certified route: quantity names, the precision loop, decimal output and containment.
#include "flipflux/certified/enclosure.hpp"

#include <cmath>

#include "prediction_enclosures.hpp"

namespace flipflux {
namespace {

using certified_detail::arb_ball;
using certified_detail::take_arb_string;

constexpr double bits_per_digit = 3.3219280948873623;  // log2(10)

enum class certified_quantity { omega, flux_upright, rate_upright, flux_approx, rate_approx };

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
    else
        return false;
    return true;
}

void enclose(arb_t res, certified_quantity q, const model_text& model, arm a,
             const std::string& energy, slong prec) {
    const certified_detail::pendulum_balls p = certified_detail::pendulum_from_text(model, prec);
    arb_ball E;
    certified_detail::energy_from_text(E.x, energy, prec);
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
    }
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

certified_enclosure certified_value(std::string_view quantity, const model_text& model, arm a,
                                    const std::string& energy, int digits) {
    certified_quantity q;
    if (!quantity_named(quantity, q))
        throw input_error::about("quantity", "'" + std::string(quantity) +
                                                 "' has no certified route (known: omega, "
                                                 "flux-upright, rate-upright, flux-approx, "
                                                 "rate-approx)");
    if (digits < 1) throw input_error::about("digits", std::to_string(digits) + " is not >= 1");
    const double target = -digits, accepted = -digits + 10;
    slong prec = static_cast<slong>(std::ceil(digits * bits_per_digit)) + 32;
    arb_ball x;
    double rel = INFINITY;
    for (int attempt = 0; attempt < 6; ++attempt) {
        enclose(x.x, q, model, a, energy, prec);
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
    if (std::isinf(rel) && rel < 0)
        e.proven_digits = digits + 5;
    else
        e.proven_digits = static_cast<int>(std::floor(-rel));
    return e;
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
