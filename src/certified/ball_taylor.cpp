// The rigorous Taylor integrator (ball_taylor.hpp; docs/certified.md#the-rigorous-taylor-step).
#include "ball_taylor.hpp"

#include "flipflux/core/budget.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace flipflux::certified_detail {
namespace {

/// log2 of an upper bound of |x| (-inf for 0, +inf for a non-finite ball).
double log2_abs_upper(const arb_t x) {
    if (!arb_is_finite(x)) return std::numeric_limits<double>::infinity();
    mag_t m;
    mag_init(m);
    arb_get_mag(m, x);
    const double out =
        mag_is_zero(m) ? -std::numeric_limits<double>::infinity() : mag_get_d_log2_approx(m);
    mag_clear(m);
    return out;
}

/// The step-size scale of each component: the largest |y_i| and |f_i(y)| over its group (so that a
/// group that starts at 0, like the action, still has a scale), as log2.
std::vector<double> group_scales(const ball_vector_field& f, const ball_jet& jet) {
    const slong n = f.dimension();
    std::vector<double> group(static_cast<std::size_t>(n),
                              -std::numeric_limits<double>::infinity());
    for (slong i = 0; i < n; ++i) {
        const auto g = static_cast<std::size_t>(f.group_of(i));
        if (g >= group.size()) group.resize(g + 1, -std::numeric_limits<double>::infinity());
        group[g] =
            std::max({group[g], log2_abs_upper(jet.series(i)), log2_abs_upper(jet.series(i) + 1)});
    }
    std::vector<double> out(static_cast<std::size_t>(n));
    for (slong i = 0; i < n; ++i) {
        const double s = group[static_cast<std::size_t>(f.group_of(i))];
        out[static_cast<std::size_t>(i)] = std::isfinite(s) ? s : 0;
    }
    return out;
}

/// log2 of the Jorba-Zou step for 2^-prec from the last two coefficients of the jet.
double log2_step(const ball_jet& jet, const std::vector<double>& scale, slong prec) {
    const slong p = jet.order();
    double best = std::numeric_limits<double>::infinity();
    for (slong j = std::max<slong>(1, p - 1); j <= p; ++j) {
        double norm = -std::numeric_limits<double>::infinity();
        for (slong i = 0; i < jet.components(); ++i)
            norm = std::max(norm,
                            log2_abs_upper(jet.series(i) + j) - scale[static_cast<std::size_t>(i)]);
        if (!std::isfinite(norm)) continue;
        best = std::min(best, (-static_cast<double>(prec) - norm) / static_cast<double>(j));
    }
    return best - 0.7 / static_cast<double>(std::max<slong>(1, p - 1)) / std::log(2.0);
}

/// Widens every ball of b: radius * 9/8 + 2^(scale - prec).
void inflate(arb_ptr b, slong n, const std::vector<double>& scale, slong prec) {
    mag_t extra;
    mag_init(extra);
    for (slong i = 0; i < n; ++i) {
        mag_mul_ui(arb_radref(b + i), arb_radref(b + i), 9);
        mag_mul_2exp_si(arb_radref(b + i), arb_radref(b + i), -3);
        mag_one(extra);
        mag_mul_2exp_si(extra, extra,
                        static_cast<slong>(std::floor(scale[static_cast<std::size_t>(i)])) - prec);
        mag_add(arb_radref(b + i), arb_radref(b + i), extra);
    }
    mag_clear(extra);
}

/// An a-priori enclosure B over [0, hi] of the solutions through y: y + [0, hi] f(B) in B.
/// fy = f(y) (the jet's coefficient 1). work: a jet whose coefficient 0 is overwritten.
bool a_priori_enclosure(ball_vector_field& f, arb_srcptr y, const ball_jet& thin, const arf_t hi,
                        ball_jet& work, ball_vector& B, const std::vector<double>& scale,
                        slong prec) {
    const slong n = f.dimension();
    arb_ball T;
    arf_t zero;
    arf_init(zero);
    arb_set_interval_arf(T.x, zero, hi, prec);
    arf_clear(zero);
    ball_vector image(n), fb(n);
    for (slong i = 0; i < n; ++i) {
        arb_mul(image[i], T.x, thin.series(i) + 1, prec);
        arb_add(image[i], image[i], y + i, prec);
    }
    for (int iteration = 0; iteration < 8; ++iteration) {
        B = image;
        inflate(B.data(), n, scale, prec);
        for (slong i = 0; i < n; ++i)
            arb_set(work.series(i), B[i]);
        f.coefficient(work, 0, fb.data(), prec);
        bool inside = true;
        for (slong i = 0; i < n; ++i) {
            arb_mul(image[i], T.x, fb[i], prec);
            arb_add(image[i], image[i], y + i, prec);
            inside = inside && arb_is_finite(image[i]) && arb_contains(B[i], image[i]);
        }
        if (inside) return true;
    }
    return false;
}

}  // namespace

slong rigorous_order_for(slong prec) {
    return static_cast<slong>(std::ceil(static_cast<double>(prec) * std::log(2.0) / 2)) + 1;
}

void expand(ball_vector_field& f, arb_srcptr y, ball_jet& jet, slong prec) {
    const slong n = f.dimension();
    ball_vector fk(n);
    for (slong i = 0; i < n; ++i)
        arb_set(jet.series(i), y + i);
    for (slong k = 0; k < jet.order(); ++k) {
        f.coefficient(jet, k, fk.data(), prec);
        for (slong i = 0; i < n; ++i)
            arb_div_ui(jet.series(i) + k + 1, fk[i], static_cast<ulong>(k + 1), prec);
    }
}

bool integrate_rigorous(ball_vector_field& f, arb_ptr y, const arb_t duration, slong order,
                        slong prec, rigorous_statistics* stats) {
    const slong n = f.dimension();
    const slong p = order;
    f.reserve(p + 1);
    ball_jet thin(n, p), wide(n, p + 1);
    ball_vector B(n);
    arf_t t, end, h, remaining, hi;
    arf_init(t), arf_init(end), arf_init(h), arf_init(remaining), arf_init(hi);
    mag_t spread;
    mag_init(spread);
    arf_set(end, arb_midref(duration));
    mag_set(spread, arb_radref(duration));
    arf_zero(t);
    double safety = 0.5;  // the step relative to Jorba-Zou's, adapted to the remainder on B
    int halvings = 0;
    bool ok = true, expanded = false, done = false;
    arb_ball H, Hp, acc, rem;
    std::vector<double> scale;
    // the CPU-time budget (eval --max-seconds), checked once a step: the temporaries above are
    // cleared before budget_exceeded leaves
    bool over_budget = false;
    while (ok && !done) {
        if (budget_spent(over_budget)) break;
        if (!expanded) {
            expand(f, y, thin, prec);
            scale = group_scales(f, thin);
            expanded = true;
        }
        // the step: Jorba-Zou's times the safety factor, 30 bits, or what remains
        const double l2h = log2_step(thin, scale, prec) + std::log2(safety);
        arf_sub(remaining, end, t, ARF_PREC_EXACT, ARF_RND_DOWN);
        bool last = false;
        if (!std::isfinite(l2h)) {
            last = true;
        } else {
            const double e = std::floor(l2h);
            arf_set_d(h, std::exp2(l2h - e));
            arf_mul_2exp_si(h, h, static_cast<slong>(e));
            arf_set_round(h, h, 30, ARF_RND_DOWN);
            last = arf_cmp(h, remaining) >= 0;
        }
        if (last) {
            arb_set_arf(H.x, remaining);
            mag_add(arb_radref(H.x), arb_radref(H.x), spread);
            if (!arb_is_nonnegative(H.x)) {
                ok = false;
                break;
            }
        } else {
            arb_set_arf(H.x, h);
        }
        arb_get_ubound_arf(hi, H.x, prec);
        bool accepted = a_priori_enclosure(f, y, thin, hi, wide, B, scale, prec);
        if (accepted) {
            expand(f, B.data(), wide, prec);
            // remainder |hi^(p+1) c_i| <= 2^(scale_i - prec)
            const double l2hi = arf_get_d(hi, ARF_RND_UP) > 0
                                    ? std::log2(arf_get_d(hi, ARF_RND_UP))
                                    : -std::numeric_limits<double>::infinity();
            for (slong i = 0; i < n && accepted; ++i) {
                const double r =
                    log2_abs_upper(wide.series(i) + p + 1) + static_cast<double>(p + 1) * l2hi;
                accepted = r <= scale[static_cast<std::size_t>(i)] - static_cast<double>(prec);
            }
        }
        if (!accepted) {
            if (++halvings > 40) ok = false;
            safety /= 2;
            if (stats) ++stats->rejected;
            continue;
        }
        halvings = 0;
        arb_pow_ui(Hp.x, H.x, static_cast<ulong>(p + 1), prec);
        for (slong i = 0; i < n; ++i) {
            arb_srcptr c = thin.series(i);
            arb_set(acc.x, c + p);
            for (slong k = p - 1; k >= 0; --k) {
                arb_mul(acc.x, acc.x, H.x, prec);
                arb_add(acc.x, acc.x, c + k, prec);
            }
            arb_mul(rem.x, Hp.x, wide.series(i) + p + 1, prec);
            arb_add(y + i, acc.x, rem.x, prec);
            ok = ok && arb_is_finite(y + i);
        }
        if (stats) ++stats->steps;
        expanded = false;
        safety = std::min(1.0, safety * 1.25);
        if (last) {
            done = true;
        } else {
            arf_add(t, t, h, ARF_PREC_EXACT, ARF_RND_DOWN);
        }
    }
    if (stats) stats->order = static_cast<int>(p);
    arf_clear(t), arf_clear(end), arf_clear(h), arf_clear(remaining), arf_clear(hi);
    mag_clear(spread);
    throw_if_spent(over_budget);
    return ok && done;
}

}  // namespace flipflux::certified_detail
