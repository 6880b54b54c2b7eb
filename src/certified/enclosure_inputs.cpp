// The certified routes' inputs and energy kinks (prediction_enclosures.hpp): a pendulum's and an
// energy's decimal text as Arb balls, the comparison of an energy ball with a kink of the energy
// surface, and the enclosure of a monotone function across such a kink.
#include <array>
#include <string>
#include <vector>

#include "flipflux/certified/enclosure.hpp"
#include "flipflux/core/error.hpp"
#include "prediction_enclosures.hpp"

namespace flipflux::certified_detail {

std::string take_arb_string(char* s) {
    std::string out(s);
    flint_free(s);
    return out;
}

/// -1, 0 (both exact and equal), +1, or 2 (undecided) for E against the kink K.
int compare_energy(const arb_t E, const arb_t K) {
    if (arb_lt(E, K)) return -1;
    if (arb_gt(E, K)) return 1;
    if (arb_is_exact(E) && arb_is_exact(K) && arb_equal(E, K)) return 0;
    return 2;
}

/// f(E) for f non-decreasing in E whose formula changes at the kinks: when E is undecided
/// against a kink, the union of f at exact energies strictly below and above both.
void monotone_enclosure(arb_t res, const energy_function& f, const arb_t E,
                        const std::vector<const arb_struct*>& kinks, slong prec, int depth) {
    bool decided = true;
    for (const arb_struct* K : kinks)
        decided = decided && compare_energy(E, K) != 2;
    if (decided) {
        f(res, E);
        return;
    }
    if (depth > 0)
        throw certification_error(
            "the energy cannot be separated from a kink of the energy surface at " +
            std::to_string(prec) + " bits (it coincides with one whose value is not exact)");
    arf_t lo, hi, k, eps;
    arf_init(lo), arf_init(hi), arf_init(k), arf_init(eps);
    arb_get_lbound_arf(lo, E, prec);
    arb_get_ubound_arf(hi, E, prec);
    for (const arb_struct* K : kinks) {
        if (compare_energy(E, K) != 2) continue;
        // step 2^20 (|K| 2^-prec + rad K) beyond the kink's ball: there E - K is known to about
        // six digits, so the formulas that depend on it (th_full, th_edge) are well conditioned;
        // the union widens by that step, about 2^(21 - prec) relatively
        arf_set_mag(eps, arb_radref(K));
        arf_mul_2exp_si(k, arb_midref(K), -prec);
        arf_abs(k, k);
        arf_add(eps, eps, k, 64, ARF_RND_CEIL);
        arf_mul_2exp_si(eps, eps, 20);
        arb_get_lbound_arf(k, K, prec);
        arf_sub(k, k, eps, prec, ARF_RND_FLOOR);
        if (arf_cmp(k, lo) < 0) arf_set(lo, k);
        arb_get_ubound_arf(k, K, prec);
        arf_add(k, k, eps, prec, ARF_RND_CEIL);
        if (arf_cmp(k, hi) > 0) arf_set(hi, k);
    }
    arb_ball e_lo, e_hi, v_lo, v_hi;
    arb_set_arf(e_lo.x, lo);
    arb_set_arf(e_hi.x, hi);
    arf_clear(lo), arf_clear(hi), arf_clear(k), arf_clear(eps);
    monotone_enclosure(v_lo.x, f, e_lo.x, kinks, prec, depth + 1);
    monotone_enclosure(v_hi.x, f, e_hi.x, kinks, prec, depth + 1);
    arb_union(res, v_lo.x, v_hi.x, prec);
}

pendulum_balls pendulum_from_text(const model_text& t, slong prec) {
    auto parse = [prec](arb_ball& out, const std::string& text, const char* name, bool zero_ok) {
        if (arb_set_str(out.x, text.c_str(), prec) != 0 || !arb_is_finite(out.x))
            throw input_error::about(name, "'" + text + "' is not a decimal number");
        if (!(arb_is_positive(out.x) || (zero_ok && arb_is_nonnegative(out.x))))
            throw input_error::about(name, "'" + text + "' is outside its domain (" +
                                               (zero_ok ? "needs >= 0" : "needs > 0") + ")");
    };
    std::array<arb_ball, parameter_count> balls;
    for (std::size_t i = 0; i < parameter_count; ++i)
        parse(balls[i], resolved_text(t, i), std::string(parameter_fields[i].name).c_str(),
              parameter_fields[i].domain == parameter_domain::nonnegative);
    auto& [m1, m2, L1, L2, a1, a2, I1, I2, g] = balls;
    pendulum_balls p;
    arb_ball J1, J2, u;
    arb_sqr(J1.x, a1.x, prec);  // J1 = I1 + m1 a1^2, J2 = I2 + m2 a2^2
    arb_mul(J1.x, J1.x, m1.x, prec);
    arb_add(J1.x, J1.x, I1.x, prec);
    arb_sqr(J2.x, a2.x, prec);
    arb_mul(J2.x, J2.x, m2.x, prec);
    arb_add(J2.x, J2.x, I2.x, prec);
    arb_sqr(u.x, L1.x, prec);
    arb_mul(u.x, u.x, m2.x, prec);  // m2 L1^2
    arb_add(p.A.x, J1.x, u.x, prec);
    arb_set(p.B.x, J2.x);
    arb_mul(p.C.x, m2.x, L1.x, prec);
    arb_mul(p.C.x, p.C.x, a2.x, prec);
    arb_mul(p.D0.x, u.x, I2.x, prec);  // D0 = J1 J2 + m2 L1^2 I2
    arb_addmul(p.D0.x, J1.x, J2.x, prec);
    arb_mul(p.alpha.x, m1.x, a1.x, prec);
    arb_addmul(p.alpha.x, m2.x, L1.x, prec);
    arb_mul(p.alpha.x, p.alpha.x, g.x, prec);
    arb_mul(p.beta.x, m2.x, a2.x, prec);
    arb_mul(p.beta.x, p.beta.x, g.x, prec);
    return p;
}

void energy_from_text(arb_t E, const std::string& text, slong prec) {
    if (arb_set_str(E, text.c_str(), prec) != 0 || !arb_is_finite(E))
        throw input_error::about("energy", "'" + text + "' is not a decimal number");
    if (!arb_is_positive(E))
        throw input_error::about("energy", "'" + text +
                                               "' is outside the domain (needs E > 0: the energy "
                                               "surface is empty at and below the minimum 0)");
}

}  // namespace flipflux::certified_detail
