// The saddle orbit's configuration curve as a dividing curve (model/dividing_curve.hpp): the flip
// angle is pi + h(s), s the other angle (arm 2: theta2 = pi + h(theta1); arm 1: theta1 = pi +
// h(theta2)), on the turning-point interval [-s_b, s_b].
//
// Representation: h is odd (the orbit is invariant under the reflection theta -> -theta through
// the saddle) and analytic on the closed interval (near a turning point both angles are even
// functions of t - t_b, hence analytic functions of s_b - s), so it is approximated on [0, s_b] by
// panels of Chebyshev series of degree n, each accepted when the last two coefficients
// of a panel are below the tolerance, else the panel is halved (adaptive: the curve sharpens near
// the turning points as E -> E_max). Values at the Chebyshev-Lobatto nodes come from the
// orbit: the time at which s(t) = s_k on the stored quarter orbit is found by a safeguarded
// Newton iteration on one Gauss-Legendre step from the nearest stored state, and h = the flip
// angle's offset at that time. Slopes come from the differentiated series.
//
// Evaluation costs one panel lookup and a Clenshaw sum of n + 1 terms (n = 16 at double): cheap
// enough for the Monte Carlo flip detector. Outside the domain the curve is energetically
// inaccessible; offset() and slope() clamp s to the domain there.
//
// Accuracy: |h - h_exact| <= error_estimate() (absolute, radians) plus the orbit's own error;
// verified by the curve-flux integral reproducing 2 F (verification/orbits_flux.cpp).
#pragma once

#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {

template <class Real>
class saddle_curve {
  public:
    saddle_curve() = default;
    /// Panels [breaks_i, breaks_{i+1}] covering [0, s_max] (breaks increasing, breaks_0 = 0);
    /// coefficients panel-major, degree + 1 per panel, of h(x) and of dh/ds (already scaled), x in
    /// [-1, 1] the panel's local variable.
    saddle_curve(arm a, int degree, std::vector<Real> breaks, std::vector<Real> values,
                 std::vector<Real> slopes, const Real& error_estimate)
        : arm_(a), degree_(degree), breaks_(std::move(breaks)), error_(error_estimate) {
        const std::size_t panels = breaks_.size() - 1;
        s_max_ = breaks_.back();
        coefficients_.resize(2 * values.size());
        for (std::size_t i = 0; i < values.size(); ++i) {
            coefficients_[2 * i] = values[i];
            coefficients_[2 * i + 1] = slopes[i];
        }
        mid_.resize(panels);
        inv_half_.resize(panels);
        for (std::size_t i = 0; i < panels; ++i) {
            mid_[i] = (breaks_[i] + breaks_[i + 1]) / 2;
            inv_half_[i] = 2 / (breaks_[i + 1] - breaks_[i]);
        }
        // lookup buckets of equal width: bucket b starts at the panel containing b * width
        const std::size_t nb = 4 * panels;
        bucket_scale_ = Real(static_cast<long>(nb)) / s_max_;
        bucket_.resize(nb + 1);
        std::size_t p = 0;
        for (std::size_t b = 0; b <= nb; ++b) {
            const Real left = Real(static_cast<long>(b)) / bucket_scale_;
            while (p + 1 < panels && breaks_[p + 1] <= left)
                ++p;
            bucket_[b] = static_cast<int>(p);
        }
    }

    arm flip_arm() const { return arm_; }
    std::array<Real, 2> domain() const { return {-s_max_, s_max_}; }
    /// h(s); s is clamped to the domain.
    Real offset(const Real& s) const {
        if (s == 0) return Real(0);  // the saddle itself (h is odd)
        const bool negative = s < 0;
        const Real v = clenshaw<1>({0}, negative ? Real(-s) : s)[0];
        return negative ? Real(-v) : v;
    }
    /// h'(s); s is clamped to the domain.
    Real slope(const Real& s) const { return clenshaw<1>({1}, s < 0 ? Real(-s) : s)[0]; }
    /// {offset(s), slope(s)}, the same bits, in one panel lookup and two interleaved Clenshaw
    /// sums (the flip detector needs both; each sum is a chain of dependent operations).
    std::array<Real, 2> offset_and_slope(const Real& s) const {
        const bool negative = s < 0;
        std::array<Real, 2> r = eval2(negative ? Real(-s) : s);
        if (s == 0)
            r[0] = Real(0);
        else if (negative)
            r[0] = -r[0];
        return r;
    }

    int degree() const { return degree_; }
    int panels() const { return static_cast<int>(mid_.size()); }
    const std::vector<Real>& breaks() const { return breaks_; }
    /// Estimated maximum absolute error of h (the largest Chebyshev tail), radians.
    Real error_estimate() const { return error_; }

    /// The same curve at double (for the Monte Carlo flip detector).
    saddle_curve<double> to_double() const {
        std::vector<double> breaks(breaks_.size()), values(coefficients_.size() / 2),
            slopes(coefficients_.size() / 2);
        for (std::size_t i = 0; i < breaks_.size(); ++i)
            breaks[i] = static_cast<double>(breaks_[i]);
        for (std::size_t i = 0; i < values.size(); ++i) {
            values[i] = static_cast<double>(coefficients_[2 * i]);
            slopes[i] = static_cast<double>(coefficients_[2 * i + 1]);
        }
        return saddle_curve<double>(arm_, degree_, std::move(breaks), std::move(values),
                                    std::move(slopes), static_cast<double>(error_));
    }

  private:
    // The panel of u (clamped to [0, s_max]) and the local variable x in it.
    std::size_t locate(const Real& u, Real& x) const {
        const Real v = u < s_max_ ? u : s_max_;
        long b = static_cast<long>(v * bucket_scale_);
        if (b > static_cast<long>(bucket_.size()) - 1) b = static_cast<long>(bucket_.size()) - 1;
        std::size_t p = static_cast<std::size_t>(bucket_[static_cast<std::size_t>(b)]);
        while (p + 1 < mid_.size() && v > breaks_[p + 1])
            ++p;
        x = (v - mid_[p]) * inv_half_[p];
        return p;
    }

    // Clenshaw sums of the Chebyshev series `series[j]` (0: h, 1: h'; K of them, side by side:
    // each a chain of dependent operations) at u's panel.
    template <std::size_t K>
    std::array<Real, K> clenshaw(const std::array<std::size_t, K>& series, const Real& u) const {
        std::array<Real, K> r{};
        if (mid_.empty()) return r;
        Real x;
        const std::size_t p = locate(u, x);
        const Real* c = coefficients_.data() + 2 * p * static_cast<std::size_t>(degree_ + 1);
        std::array<Real, K> b1{}, b2{};
        const Real x2 = 2 * x;
        for (int k = degree_; k >= 1; --k)
            for (std::size_t j = 0; j < K; ++j) {
                const Real b0 = c[2 * static_cast<std::size_t>(k) + series[j]] + x2 * b1[j] - b2[j];
                b2[j] = b1[j];
                b1[j] = b0;
            }
        for (std::size_t j = 0; j < K; ++j)
            r[j] = c[series[j]] + x * b1[j] - b2[j];
        return r;
    }
    // clenshaw<2> of h and h': at double the two sums run in the lanes of one SSE2 vector (their
    // coefficients side by side), each lane the same operations in the same order as clenshaw's,
    // so the same bits.
    std::array<Real, 2> eval2(const Real& u) const {
        if constexpr (std::is_same_v<Real, double>) {
            using v2 = double __attribute__((vector_size(16)));
            if (mid_.empty()) return {};
            double x;
            const std::size_t p = locate(u, x);
            const double* c = coefficients_.data() + 2 * p * static_cast<std::size_t>(degree_ + 1);
            auto load = [](const double* a) {
                v2 v;
                __builtin_memcpy(&v, a, sizeof v);
                return v;
            };
            v2 b1{0, 0}, b2{0, 0};
            const v2 x2{2 * x, 2 * x};
            // two of clenshaw's iterations per pass, the roles of b1 and b2 swapped in between
            // (no register copies)
            int k = degree_;
            for (; k >= 2; k -= 2) {
                b2 = load(c + 2 * k) + x2 * b1 - b2;
                b1 = load(c + 2 * (k - 1)) + x2 * b2 - b1;
            }
            if (k == 1) {
                const v2 b0 = load(c + 2) + x2 * b1 - b2;
                b2 = b1;
                b1 = b0;
            }
            const v2 xv{x, x};
            const v2 r = load(c) + xv * b1 - b2;
            return {r[0], r[1]};
        } else {
            return clenshaw<2>({0, 1}, u);
        }
    }

    arm arm_ = arm::two;
    int degree_ = 0;
    std::vector<Real> breaks_;
    /// per panel p and degree k: h's coefficient at [2 (p (degree + 1) + k)], h''s next to it
    std::vector<Real> coefficients_;
    Real error_{0};
    Real s_max_{0};
    std::vector<Real> mid_, inv_half_;
    Real bucket_scale_{0};
    std::vector<int> bucket_;
};

/// The saddle curve of a converged orbit, to `tolerance` (absolute, radians; 0 = 8 eps s_b).
/// Throws std::invalid_argument if the orbit has no stored solution and std::runtime_error if its
/// configuration curve is not a graph over s (s not increasing along the quarter orbit).
template <class Real>
saddle_curve<Real> make_saddle_curve(const double_pendulum<Real>& model,
                                     const saddle_orbit<Real>& orbit, const Real& tolerance = 0);

/// The time t in [0, T/4] at which the orbit's s-angle equals s (0 <= s <= s_b), and the state
/// there (frame coordinates): the root-finder behind make_saddle_curve, exposed for tests.
template <class Real>
std::array<Real, 5> orbit_point_at_s(const double_pendulum<Real>& model,
                                     const saddle_orbit<Real>& orbit, const Real& s);

#define FLIPFLUX_CURVE_EXTERN(R)                                                            \
    extern template saddle_curve<R> make_saddle_curve<R>(const double_pendulum<R>&,         \
                                                         const saddle_orbit<R>&, const R&); \
    extern template std::array<R, 5> orbit_point_at_s<R>(const double_pendulum<R>&,         \
                                                         const saddle_orbit<R>&, const R&);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_CURVE_EXTERN)
#undef FLIPFLUX_CURVE_EXTERN

}  // namespace flipflux
