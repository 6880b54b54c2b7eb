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
// thirteen convolutions per order. Their terms that hold no coefficient of the current order are
// summed first, in three passes over j, each loading once an operand that several of its products
// share (the jets are bound by their loads, not by their arithmetic); the newest terms come last
// in each sum. The tangent (variational) series
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
            V n1, n2, Pn;
            if (n == 0) {
                det[0] = k.D0 + CC * (sd[0] * sd[0]);
                inv_det0 = 1.0 / det[0];
                n1 = k.B * x[2][0] - k.C * (cd[0] * x[3][0]);
                n2 = k.A * x[3][0] - k.C * (cd[0] * x[2][0]);
                w1[0] = n1 * inv_det0;
                w2[0] = n2 * inv_det0;
                u[0] = sd[0] * w1[0];
                Pn = k.C * (u[0] * w2[0]);
            } else {
                const double inv = 1.0 / n;
                const double dn = n;
                j1[n] = dn * x[0][n];
                j2[n] = dn * x[1][n];
                jd[n] = dn * (x[0][n] - x[1][n]);
                // The terms of the thirteen sums that involve no coefficient n (j = 1..n-1, with
                // m = n - j), in three passes; an operand several products of a pass share is
                // loaded once.
                const V z{};
                V a1 = z, b1 = z, a2 = z, b2 = z;
                for (int j = 1; j < n; ++j) {
                    const int m = n - j;
                    V J1 = j1[j], J2 = j2[j];
                    keep_in_registers(J1, J2);
                    a1 += J1 * c1[m];
                    b1 += J1 * s1[m];
                    a2 += J2 * c2[m];
                    b2 += J2 * s2[m];
                }
                V ad = z, bd = z, sq = z, e2 = z, e1 = z, uu = z;
                for (int j = 1; j < n; ++j) {
                    const int m = n - j;
                    V JD = jd[j], CD = cd[m], SD = sd[m];
                    keep_in_registers(JD, CD, SD);
                    ad += JD * CD;
                    bd += JD * SD;
                    e2 += x[3][j] * CD;
                    e1 += x[2][j] * CD;
                    sq += sd[j] * SD;
                    uu += w1[j] * SD;
                }
                V f1 = z, f2 = z, pp = z;
                for (int j = 1; j < n; ++j) {
                    const int m = n - j;
                    V W2 = w2[j];
                    keep_in_registers(W2);
                    f1 += det[m] * w1[j];
                    f2 += det[m] * W2;
                    pp += u[m] * W2;
                }
                // Then the terms with a coefficient n, each sum's latest last (the critical path
                // of an order is these, not the passes above).
                s1[n] = (a1 + j1[n] * c1[0]) * inv;
                c1[n] = -((b1 + j1[n] * s1[0]) * inv);
                s2[n] = (a2 + j2[n] * c2[0]) * inv;
                c2[n] = -((b2 + j2[n] * s2[0]) * inv);
                sd[n] = (ad + jd[n] * cd[0]) * inv;
                cd[n] = -((bd + jd[n] * sd[0]) * inv);
                const V t = sd[0] * sd[n];
                det[n] = CC * (sq + (t + t));
                n1 = k.B * x[2][n] - k.C * ((e2 + cd[0] * x[3][n]) + cd[n] * x[3][0]);
                n2 = k.A * x[3][n] - k.C * ((e1 + cd[0] * x[2][n]) + cd[n] * x[2][0]);
                w1[n] = (n1 - (f1 + det[n] * w1[0])) * inv_det0;
                w2[n] = (n2 - (f2 + det[n] * w2[0])) * inv_det0;
                u[n] = (uu + sd[n] * w1[0]) + sd[0] * w1[n];
                Pn = k.C * ((pp + u[0] * w2[n]) + u[n] * w2[0]);
            }
            const double next = 1.0 / (n + 1);
            x[0][n + 1] = w1[n] * next;
            x[1][n + 1] = w2[n] * next;
            x[2][n + 1] = (-Pn - k.alpha * s1[n]) * next;
            x[3][n + 1] = (Pn - k.beta * s2[n]) * next;
            if constexpr (Tangent) tangent_order(k, n, next, inv_det0);
        }
    }

  private:
    // GCC reloads an operand that several products share from memory for each of them (it
    // rematerialises loads); the jets are bound by their loads (bench/results/
    // taylor_jet_loads_zen5_2026-12-03.txt), so the loaded values are kept in registers. GCC
    // only: clang checks the operand against the function's own instruction set before inlining
    // it into the AVX2/AVX-512 callers, and refuses a 256- or 512-bit register for "v" there
    // (the fuzz build, -O0 with the sanitizers); its builds do without the hint.
    [[gnu::always_inline]] static void keep_in_register([[maybe_unused]] V& x) {
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
        asm("" : "+v"(x));
#endif
    }
    template <class... T>
    [[gnu::always_inline]] static void keep_in_registers(T&... x) {
        (keep_in_register(x), ...);
    }
    // sum_{j=From..n} a_j b_{n-j} and a_j e_{n-j} (0 for From = 1, n = 0) in one pass, each
    // summed in increasing j (as conv)
    template <int From>
    [[gnu::always_inline]] static void conv_shared_a(const V* a, const V* b, const V* e, int n,
                                                     V& ab, V& ae) {
        V r = From == 0 ? a[0] * b[n] : 0.0 * a[0];
        V q = From == 0 ? a[0] * e[n] : r;
        for (int j = 1; j <= n; ++j) {
            V A = a[j];
            keep_in_registers(A);
            r += A * b[n - j];
            q += A * e[n - j];
        }
        ab = r;
        ae = q;
    }
    // sum_{j=0..n} a_j b_{n-j} and c_j b_{n-j} in one pass (each in the order of conv)
    [[gnu::always_inline]] static void conv_shared_b(const V* a, const V* c, const V* b, int n,
                                                     V& ab, V& cb) {
        V r = a[0] * b[n];
        V q = c[0] * b[n];
        for (int j = 1; j <= n; ++j) {
            V B = b[n - j];
            keep_in_registers(B);
            r += a[j] * B;
            q += c[j] * B;
        }
        ab = r;
        cb = q;
    }
    // sum_{j=0..n} a_j b_{n-j}
    [[gnu::always_inline]] static V conv(const V* a, const V* b, int n) {
        V r = a[0] * b[n];
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
        V cd_dd, sd_dd;
        conv_shared_b(cd, sd, dd, n, cd_dd, sd_dd);
        dsd[n] = cd_dd;
        dcd[n] = -sd_dd;
        ddet[n] = CC2 * conv(sd, dsd, n);
        V dcd_l2, dcd_l1, cd_v2, cd_v1, w1_ddet, w2_ddet, det_dw1, det_dw2;
        conv_shared_a<0>(dcd, x[3], x[2], n, dcd_l2, dcd_l1);
        conv_shared_a<0>(cd, v[3], v[2], n, cd_v2, cd_v1);
        const V dn1 = k.B * v[2][n] - k.C * (dcd_l2 + cd_v2);
        const V dn2 = k.A * v[3][n] - k.C * (dcd_l1 + cd_v1);
        conv_shared_b(w1, w2, ddet, n, w1_ddet, w2_ddet);
        conv_shared_a<1>(det, dw1, dw2, n, det_dw1, det_dw2);
        dw1[n] = (dn1 - w1_ddet - det_dw1) * inv_det0;
        dw2[n] = (dn2 - w2_ddet - det_dw2) * inv_det0;
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
/// operations as a double). N angles at once: their Horner sums interleaved (each one's bits
/// those of N = 1), so that their chains of dependent operations overlap.
template <class T, int N>
[[gnu::always_inline]] inline void taylor_angle_ranges(const T* const (&c)[N], int p, const T& h,
                                                       T (&lo)[N], T (&hi)[N]) {
    using detail::lane_abs;
    T r[N];
    for (int i = 0; i < N; ++i)
        r[i] = lane_abs(c[i][p]);  // p >= 2 (min_taylor_order)
    for (int k = p - 1; k >= 2; --k)
        for (int i = 0; i < N; ++i)
            r[i] = r[i] * h + lane_abs(c[i][k]);
    constexpr double eps = std::numeric_limits<double>::epsilon();
    for (int i = 0; i < N; ++i) {
        const T R = r[i] * h * h;
        const T a = c[i][0], b = c[i][0] + c[i][1] * h;
        const T margin = 128 * eps * (1.0 + lane_abs(a) + lane_abs(b) + R);
        lo[i] = (a < b ? a : b) - R - margin;
        hi[i] = (a < b ? b : a) + R + margin;
    }
}
template <class T>
[[gnu::always_inline]] inline void taylor_angle_range(const T* c, int p, const T& h, T& lo, T& hi) {
    const T* const cs[1] = {c};
    T l[1], u[1];
    taylor_angle_ranges(cs, p, h, l, u);
    lo = l[0];
    hi = u[0];
}

}  // namespace flipflux

#pragma GCC diagnostic pop
