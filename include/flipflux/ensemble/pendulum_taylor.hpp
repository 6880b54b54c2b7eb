// The Taylor series (jet) of the double pendulum's flow in double precision, several trajectories
// at once in the lanes of a vector V (v2d, v4d, v8d): the recurrences of the ensemble's Taylor
// integrator (ensemble/taylor_ensemble.hpp; docs/theory.md#the-ensembles-taylor-integrator).
//
// With u_k the coefficient of t^k of a series u(t), given the state's coefficients up to k, the
// right-hand side's coefficient k follows from the automatic-differentiation rules of
// integrators/taylor.hpp (Jorba & Zou 2005, Sec. 2) applied to Hamilton's equations written as
// (pendulum_flow.hpp; d = th1 - th2):
//     s_i, c_i = sin th_i, cos th_i          (s_k = (1/k) sum_{j=1..k} j th_j c_{k-j}, c likewise)
//     sd, cd = sin d, cos d
//     det = D0 + C^2 sd^2,  n1 = B l1 - C cd l2,  n2 = A l2 - C cd l1
//     w_i = n_i / det       (w_k = (n_k - sum_{j=1..k} det_j w_{k-j}) (1 / det_0))
//     u = sd w1,  P = C u w2
//     (th1, th2, l1, l2)' = (w1, w2, -P - alpha s1, P - beta s2),   x_{k+1} = f_k / (k + 1):
// thirteen convolutions per order (sd^2 by symmetry, half of one). The tangent (variational) series
// follow the same way from the pointwise identities d(sin th) = cos th dth, d(cos d) = -sin d dd,
// d(det) = 2 C^2 sd dsd, d(w) det = dn - w d(det), du = dsd w1 + sd dw1, dP = C (du w2 + u dw2).
//
// Every operation is lane-wise, in a fixed order, without fused multiply-adds: each lane's
// coefficients are the same bits for any V and any partner lanes (tested).
#pragma once

#include <array>
#include <limits>

#include "flipflux/ensemble/fast_trig.hpp"
#include "flipflux/model/double_pendulum.hpp"

// The helpers return vectors by value: always inlined into their (target-specific) caller, so no
// vector crosses a function boundary and GCC's note about the vector ABI does not apply.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"

namespace flipflux {

/// The highest order of the ensemble's Taylor integrator, and its automatic order at rtol =
/// epsilon (ensemble_taylor_order). Above it the cost model's optimum (25 at epsilon) gains
/// little (1.32 against 1.34 CPU-s at order 24 and 22 on the heyoka bench's workload with T =
/// 10000) and the double limit is missed on the golden states (median state error at t = 10 of
/// 5.0e-14 at order 24 and 4.7e-14 at 25, against 2.1e-14 at 22 and heyoka's 4.4e-14:
/// tools/accuracy_levels.py, bench/results/accuracy_levels.txt, docs/scale.md).
inline constexpr int ensemble_taylor_max_order = 22;

/// The jet of W = lanes_of<V> trajectories: the state's series x[c][k] (c: th1, th2, l1, l2) and,
/// with Tangent, the tangent vector's v[c][k], up to the order of the last compute().
template <class V, bool Tangent>
struct pendulum_jet {
    static constexpr int K = ensemble_taylor_max_order + 1;
    V x[4][K];
    V v[Tangent ? 4 : 1][K];

    /// The coefficients 1..p of x (and v) from their coefficients 0, for the pendulum `k`.
    /// Angles of order 0 must lie within fast_sincos_lanes' range (|th| <= 2^19; the ensemble's
    /// are reduced to [-pi, pi]).
    [[gnu::always_inline]] void compute(const lagrangian_coefficients<double>& k, int p) {
        const double CC = k.C * k.C;
        fast_sincos_lanes(x[0][0], s1[0], c1[0]);
        fast_sincos_lanes(x[1][0], s2[0], c2[0]);
        const V d0 = x[0][0] - x[1][0];
        fast_sincos_lanes(d0, sd[0], cd[0]);
        V inv_det0 = 0.0 * d0;
        for (int n = 0; n < p; ++n) {
            if (n > 0) {
                const double inv = 1.0 / n;
                const double dn = n;
                const V dn_coefficient = x[0][n] - x[1][n];
                j1[n] = dn * x[0][n];
                j2[n] = dn * x[1][n];
                jd[n] = dn * dn_coefficient;
                sincos_order(j1, s1, c1, n, inv);
                sincos_order(j2, s2, c2, n, inv);
                sincos_order(jd, sd, cd, n, inv);
            }
            det[n] = CC * square(sd, n);
            if (n == 0) {
                det[0] = k.D0 + det[0];
                inv_det0 = 1.0 / det[0];
            }
            const V n1 = k.B * x[2][n] - k.C * conv(cd, x[3], n);
            const V n2 = k.A * x[3][n] - k.C * conv(cd, x[2], n);
            w1[n] = (n1 - conv_from1(det, w1, n)) * inv_det0;
            w2[n] = (n2 - conv_from1(det, w2, n)) * inv_det0;
            u[n] = conv(sd, w1, n);
            const V Pn = k.C * conv(u, w2, n);
            const double next = 1.0 / (n + 1);
            x[0][n + 1] = w1[n] * next;
            x[1][n + 1] = w2[n] * next;
            x[2][n + 1] = (-Pn - k.alpha * s1[n]) * next;
            x[3][n + 1] = (Pn - k.beta * s2[n]) * next;
            if constexpr (Tangent) tangent_order(k, n, next, inv_det0);
        }
    }

  private:
    // Coefficient n >= 1 of sin u and cos u from ju_j = j u_j (j = 1..n) and theirs below n.
    [[gnu::always_inline]] static void sincos_order(const V* ju, V* s, V* c, int n, double inv) {
        V ss = ju[1] * c[n - 1];
        V cc = ju[1] * s[n - 1];
        for (int j = 2; j <= n; ++j) {
            ss += ju[j] * c[n - j];
            cc += ju[j] * s[n - j];
        }
        s[n] = ss * inv;
        c[n] = -(cc * inv);
    }
    // coefficient n of a^2: 2 sum_{j < n/2} a_j a_{n-j} (+ a_{n/2}^2)
    [[gnu::always_inline]] static V square(const V* a, int n) {
        V r = 0.0 * a[0];
        for (int j = 0; 2 * j < n; ++j)
            r += a[j] * a[n - j];
        r = r + r;
        if (n % 2 == 0) r += a[n / 2] * a[n / 2];
        return r;
    }
    // sum_{j=0..n} a_j b_{n-j}
    [[gnu::always_inline]] static V conv(const V* a, const V* b, int n) {
        V r = a[0] * b[n];
        for (int j = 1; j <= n; ++j)
            r += a[j] * b[n - j];
        return r;
    }
    // sum_{j=1..n} a_j b_{n-j} (0 for n = 0)
    [[gnu::always_inline]] static V conv_from1(const V* a, const V* b, int n) {
        V r = 0.0 * a[0];
        for (int j = 1; j <= n; ++j)
            r += a[j] * b[n - j];
        return r;
    }

    [[gnu::always_inline]] void tangent_order(const lagrangian_coefficients<double>& k, int n,
                                              double next, V inv_det0) {
        const double CC2 = 2 * k.C * k.C;
        dd[n] = v[0][n] - v[1][n];
        const V ds1 = conv(c1, v[0], n);
        const V ds2 = conv(c2, v[1], n);
        dsd[n] = conv(cd, dd, n);
        dcd[n] = -conv(sd, dd, n);
        ddet[n] = CC2 * conv(sd, dsd, n);
        const V dn1 = k.B * v[2][n] - k.C * (conv(dcd, x[3], n) + conv(cd, v[3], n));
        const V dn2 = k.A * v[3][n] - k.C * (conv(dcd, x[2], n) + conv(cd, v[2], n));
        dw1[n] = (dn1 - conv(w1, ddet, n) - conv_from1(det, dw1, n)) * inv_det0;
        dw2[n] = (dn2 - conv(w2, ddet, n) - conv_from1(det, dw2, n)) * inv_det0;
        du[n] = conv(dsd, w1, n) + conv(sd, dw1, n);
        const V dP = k.C * (conv(du, w2, n) + conv(u, dw2, n));
        v[0][n + 1] = dw1[n] * next;
        v[1][n + 1] = dw2[n] * next;
        v[2][n + 1] = (-dP - k.alpha * ds1) * next;
        v[3][n + 1] = (dP - k.beta * ds2) * next;
    }

    static constexpr int KT = Tangent ? K : 1;
    // (d = th1 - th2 and P enter no convolution: only their current coefficient is kept)
    V s1[K], c1[K], s2[K], c2[K], sd[K], cd[K], det[K], w1[K], w2[K], u[K];
    V j1[K], j2[K], jd[K];  // j u_j of th1, th2, d
    V dd[KT], dsd[KT], dcd[KT], ddet[KT], dw1[KT], dw2[KT], du[KT];
};

namespace detail {
/// |x|, lane by lane for a vector.
template <class T>
[[gnu::always_inline]] inline T lane_abs(const T& x) {
    return x < 0 ? -x : x;
}
}  // namespace detail

/// The range of an angle over a Taylor step, for the detectors' prefilter (step_view::
/// angle_ranges): the polynomial th(tau) = sum_k c[k] tau^k on [0, h] lies within its linear
/// part's range [min, max](c0, c0 + c1 h) widened by R = sum_{k >= 2} |c_k| h^k (Horner on the
/// |c_k|), and by 128 eps (1 + |c0| + |c0 + c1 h| + R) for the rounding of these sums (at most
/// 2p + 4 roundings of relative size eps each, p <= ensemble_taylor_max_order). A bound of the
/// dense output itself, the polynomial the detectors search, so it needs no heuristic margin
/// (the RK lanes' cubic Hermite range, flip_angle_range, is widened by one), computed in the
/// group's vectors with the step's end. T is double or a vector of lanes (lane by lane the same
/// operations as a double).
template <class T>
[[gnu::always_inline]] inline void taylor_angle_range(const T* c, int p, const T& h, T& lo, T& hi) {
    using detail::lane_abs;
    T r = lane_abs(c[p]);  // p >= 2 (min_taylor_order)
    for (int k = p - 1; k >= 2; --k)
        r = r * h + lane_abs(c[k]);
    r = r * h * h;
    const T a = c[0], b = c[0] + c[1] * h;
    constexpr double eps = std::numeric_limits<double>::epsilon();
    const T margin = 128 * eps * (1.0 + lane_abs(a) + lane_abs(b) + r);
    lo = (a < b ? a : b) - r - margin;
    hi = (a < b ? b : a) + r + margin;
}

}  // namespace flipflux

#pragma GCC diagnostic pop
