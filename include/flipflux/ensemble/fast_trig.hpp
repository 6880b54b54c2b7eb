// sin and cos of one double together, inline: the ensemble's right-hand side spends most of its
// time in them (bench/ensemble_odeint.cpp: libm's sincos was 36 % of a run).
//
// Method (fdlibm's, as in glibc's and musl's sin/cos for moderate arguments): x = q pi/2 + r with
// q = round(x 2/pi) (to nearest) and r by Cody-Waite reduction with pi/2 split into three parts of
// 33, 33 and 53 bits (each q * part exact for |q| < 2^20), |r| <= pi/4 (plus rounding); then
// fdlibm's minimax kernels __kernel_sin / __kernel_cos (errors below 1 ulp of the result on [-pi/4,
// pi/4]) and the quadrant's signs and swap. Arguments with |x| > 2^19 fall back to std::sin and
// std::cos. Accuracy: tests/ensemble/test_pendulum_flow.cpp checks |error| <= 2 ulp of 1 against
// std::sin/std::cos on random arguments in [-1e5, 1e5] (the ensemble's angles are reduced to
// [-pi, pi] after every step). Deterministic: the same bits on every run, thread and process.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>

namespace flipflux {

inline void fast_sincos(double x, double& s, double& c) {
    if (!(std::abs(x) <= 524288.0)) {  // also NaN
        s = std::sin(x);
        c = std::cos(x);
        return;
    }
    constexpr double two_over_pi = 6.36619772367581382433e-01;
    constexpr double pio2_1 = 1.57079632673412561417e+00;   // first 33 bits of pi/2
    constexpr double pio2_2 = 6.07710050630396597660e-11;   // next 33 bits
    constexpr double pio2_2t = 2.02226624879595063154e-21;  // pi/2 - pio2_1 - pio2_2
    // round to nearest by the 1.5 * 2^52 trick (|x 2/pi| < 2^51; no libm call, no -ffast-math
    // needed: the compiler may not reassociate the two additions)
    constexpr double shifter = 0x1.8p52;
    const double shifted = x * two_over_pi + shifter;  // 2^52 + 2^51 + q exactly
    const double q = shifted - shifter;
    const double r = ((x - q * pio2_1) - q * pio2_2) - q * pio2_2t;
    const double z = r * r;
    // fdlibm __kernel_sin (y = 0): r + r^3 (S1 + z (S2 + ... ))
    constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                     S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                     S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
    const double ps = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    const double sr = r + r * z * (S1 + z * ps);
    // fdlibm __kernel_cos (y = 0): 1 - z/2 + z^2 C(z), with the hz/w splitting for accuracy
    constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                     C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                     C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
    const double pc = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    const double hz = 0.5 * z;
    const double w = 1.0 - hz;
    const double cr = w + (((1.0 - w) - hz) + z * pc);
    // the quadrant's swap and signs without branches (quadrants change often along a trajectory)
    // q mod 4 from the low mantissa bits of `shifted` (2^51 is 0 mod 4)
    const std::uint64_t quadrant = std::bit_cast<std::uint64_t>(shifted) & 3;
    const bool swap = (quadrant & 1) != 0;
    const double a = swap ? cr : sr, b = swap ? sr : cr;
    s = (quadrant & 2) ? -a : a;
    c = ((quadrant + 1) & 2) ? -b : b;
}

using v2d = double __attribute__((vector_size(16)));  ///< two doubles (SSE2 on x86-64)
using v2l = long long __attribute__((vector_size(16)));
/// Four doubles: AVX registers in functions compiled for AVX2 (ensemble.cpp dispatches at run
/// time), two SSE2 registers elsewhere.
using v4d = double __attribute__((vector_size(32)));
using v4l = long long __attribute__((vector_size(32)));
/// Eight doubles: AVX-512 registers in functions compiled for AVX-512 (ensemble.cpp dispatches at
/// run time), narrower registers elsewhere.
using v8d = double __attribute__((vector_size(64)));
using v8l = long long __attribute__((vector_size(64)));

/// The number of lanes of a vector type.
template <class V>
inline constexpr int lanes_of = sizeof(V) / sizeof(double);
/// The integer vector of the same shape.
template <class V>
struct lane_mask;
template <>
struct lane_mask<v2d> {
    using type = v2l;
};
template <>
struct lane_mask<v4d> {
    using type = v4l;
};
template <>
struct lane_mask<v8d> {
    using type = v8l;
};

/// fast_sincos in every lane of a vector V (v2d, v4d or v8d),
/// |x| <= 2^19 in each (the caller checks, fast_sincos_in_range): the same operations in the same
/// order per lane as fast_sincos, hence the same bits (tested). Always inlined, so that a caller
/// compiled for AVX2 or AVX-512 gets it in their instructions.
template <class V>
[[gnu::always_inline]] inline void fast_sincos_lanes(V x, V& s, V& c) {
    using L = typename lane_mask<V>::type;
    constexpr double two_over_pi = 6.36619772367581382433e-01;
    constexpr double pio2_1 = 1.57079632673412561417e+00;
    constexpr double pio2_2 = 6.07710050630396597660e-11;
    constexpr double pio2_2t = 2.02226624879595063154e-21;
    constexpr double shifter = 0x1.8p52;
    const V shifted = x * two_over_pi + shifter;
    const V q = shifted - shifter;
    const V r = ((x - q * pio2_1) - q * pio2_2) - q * pio2_2t;
    const V z = r * r;
    constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                     S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                     S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
    const V ps = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    const V sr = r + r * z * (S1 + z * ps);
    constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                     C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                     C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
    const V pc = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
    const V hz = 0.5 * z;
    const V w = 1.0 - hz;
    const V cr = w + (((1.0 - w) - hz) + z * pc);
    const L quadrant = reinterpret_cast<L>(shifted) & 3;
    const L swap = (quadrant & 1) != 0;
    const V a = swap ? cr : sr, b = swap ? sr : cr;
    s = (quadrant & 2) != 0 ? -a : a;
    c = ((quadrant + 1) & 2) != 0 ? -b : b;
}

/// Whether every lane is in fast_sincos_lanes' range.
template <class V>
[[gnu::always_inline]] inline bool fast_sincos_in_range(V x) {
    bool ok = true;
    for (int i = 0; i < lanes_of<V>; ++i)
        ok = ok && std::abs(x[i]) <= 524288.0;
    return ok;
}

/// fast_sincos in both lanes of a vector (fast_sincos_lanes for v2d).
inline void fast_sincos_v2(v2d x, v2d& s, v2d& c) {
    fast_sincos_lanes(x, s, c);
}

/// Whether both lanes are in fast_sincos_v2's range.
inline bool fast_sincos_v2_range(v2d x) {
    return fast_sincos_in_range(x);
}

/// fast_sincos of two arguments at once, bit for bit fast_sincos(x0) and fast_sincos(x1).
inline void fast_sincos2(double x0, double x1, double& s0, double& c0, double& s1, double& c1) {
    const v2d x = {x0, x1};
    if (!fast_sincos_v2_range(x)) {
        fast_sincos(x0, s0, c0);
        fast_sincos(x1, s1, c1);
        return;
    }
    v2d s, c;
    fast_sincos_v2(x, s, c);
    s0 = s[0];
    s1 = s[1];
    c0 = c[0];
    c1 = c[1];
}

}  // namespace flipflux
