// Hamilton's equations of the double pendulum in double precision, evaluated with one sin/cos pair
// per angle, and their variational (tangent) equations: the right-hand sides the ensemble
// integrates millions of times. The precision-templated model (model/double_pendulum.hpp) is the
// reference; tests/ensemble/test_pendulum_flow.cpp checks these against it (rhs, rhs_jacobian,
// hamiltonian) at random points and parameters.
//
// With (s_i, c_i) = (sin th_i, cos th_i):
//     sin(th1 - th2) = s1 c2 - c1 s2,   cos(th1 - th2) = c1 c2 + s1 s2,
//     det M = D0 + C^2 sin^2(th1 - th2),
//     w1 = (B l1 - C c l2) / det M,      w2 = (A l2 - C c l1) / det M,      (w = M^-1 l)
//     th1' = w1, th2' = w2, l1' = -P - alpha s1, l2' = P - beta s2,  P = C sin(th1 - th2) w1 w2.
// NOTE: the difference formulas lose relative (not absolute) accuracy of sin(th1 - th2) when the
// angles nearly coincide; it enters only through C^2 sin^2 and P, where the absolute error
// (~1 ulp of 1) is what matters.
// Tangent equations (directional derivative along v = (dth1, dth2, dl1, dl2)), with d = th1 - th2:
//     d(sin d) = cos d (dth1 - dth2),  d(cos d) = -sin d (dth1 - dth2),
//     d(det) = 2 C^2 sin d d(sin d),   d(w) = (d(n) - w d(det)) / det,  n = (B l1 - C c l2, ...),
//     d(P) = C (d(sin d) w1 w2 + sin d (dw1 w2 + w1 dw2)),
//     d(f) = (dw1, dw2, -dP - alpha c1 dth1, dP - beta c2 dth2).
#pragma once

#include <array>
#include <cmath>
#include <type_traits>

#include "flipflux/ensemble/fast_trig.hpp"
#include "flipflux/model/double_pendulum.hpp"

namespace flipflux {

class pendulum_flow {
  public:
    explicit pendulum_flow(const double_pendulum<double>& model) : k_(model.coefficients()) {}

    /// Hamilton's equations (th1', th2', l1', l2'); t is ignored (autonomous).
    std::array<double, 4> operator()(double, const std::array<double, 4>& state) const {
        const double* x = state.data();
        std::array<double, 4> f;
        lanes_from(trig_lanes<double>(x), x, f.data());
        return f;
    }

    /// Hamilton's equations at lanes_of<V> states at once (V = v2d, v4d or v8d), x[i] = (component
    /// i of each state): per lane the same operations in the same order as operator(), hence the
    /// same bits (tested), in a fraction of the instructions. Used by the ensemble's lockstep
    /// lanes; always inlined, so that a caller compiled for AVX2 or AVX-512 gets
    /// their instructions.
    template <class V>
    [[gnu::always_inline]] void lanes(const V x[4], V f[4]) const {
        if (!fast_sincos_in_range(x[0]) || !fast_sincos_in_range(x[1])) {
            per_lane<4>(x, f,
                        [this](const std::array<double, 4>& one) { return (*this)(0.0, one); });
            return;
        }
        lanes_from(trig_lanes<V>(x), x, f);
    }

    /// tangent() at lanes_of<V> states at once, y[i] = (component i of each state): per lane
    /// the same bits as tangent() (tested).
    template <class V>
    [[gnu::always_inline]] void tangent_lanes(const V y[8], V f[8]) const {
        if (!fast_sincos_in_range(y[0]) || !fast_sincos_in_range(y[1])) {
            per_lane<8>(y, f, [this](const std::array<double, 8>& one) { return tangent(one); });
            return;
        }
        tangent_lanes_from(trig_lanes<V>(y), y, f);
    }

    /// hamiltonian_absolute() at lanes_of<V> states at once, x[i] = (component i of each state):
    /// per lane the same operations, hence the same bits (tested). For the ensemble's energy
    /// check at the step's end, evaluated with its last (FSAL) stage.
    template <class V>
    [[gnu::always_inline]] void hamiltonian_lanes(const V x[4], V& h) const {
        if (!fast_sincos_in_range(x[0]) || !fast_sincos_in_range(x[1])) {
            for (int lane = 0; lane < lanes_of<V>; ++lane)
                h[lane] = hamiltonian_absolute({x[0][lane], x[1][lane], x[2][lane], x[3][lane]});
            return;
        }
        energy_from(trig_lanes<V>(x), x, h);
    }

    /// lanes() or tangent_lanes() (N = 4 or 8) and hamiltonian_lanes() at the same states, their
    /// sines and cosines computed once: the same bits as the three apart.
    template <std::size_t N, class V>
    [[gnu::always_inline]] void lanes_and_energy(const V x[N], V f[N], V& h) const {
        static_assert(N == 4 || N == 8);
        if (!fast_sincos_in_range(x[0]) || !fast_sincos_in_range(x[1])) {
            if constexpr (N == 4)
                lanes(x, f);
            else
                tangent_lanes(x, f);
            hamiltonian_lanes(x, h);
            return;
        }
        const trig_lanes<V> g(x);
        if constexpr (N == 4)
            lanes_from(g, x, f);
        else
            tangent_lanes_from(g, x, f);
        energy_from(g, x, h);
    }

    /// Angular velocities th' = M^-1 l.
    std::array<double, 2> velocities(const std::array<double, 4>& x) const {
        double sd = 0, cd = 0;
        fast_sincos(x[0] - x[1], sd, cd);
        const double det = k_.D0 + k_.C * k_.C * sd * sd;
        return {(k_.B * x[2] - k_.C * cd * x[3]) / det, (k_.A * x[3] - k_.C * cd * x[2]) / det};
    }

    /// H from one sin/cos pair per angle, V = alpha (1 - cos th1) + beta (1 - cos th2): an
    /// absolute error of a few ulp of max(E, 1), for the per-step energy check and drift (the
    /// relative accuracy of hamiltonian() near the bottom of the well is not needed there).
    double hamiltonian_absolute(const std::array<double, 4>& x) const {
        double h;
        energy_from(trig_lanes<double>(x.data()), x.data(), h);
        return h;
    }

    /// H = 1/2 l^T M^-1 l + 2 alpha sin^2(th1/2) + 2 beta sin^2(th2/2).
    double hamiltonian(const std::array<double, 4>& x) const {
        const double d = x[0] - x[1];
        const double sd = std::sin(d), cd = std::cos(d);
        const double det = k_.D0 + k_.C * k_.C * sd * sd;
        const double kin =
            (k_.B * x[2] * x[2] - 2 * k_.C * cd * x[2] * x[3] + k_.A * x[3] * x[3]) / (2 * det);
        const double h1 = std::sin(x[0] / 2), h2 = std::sin(x[1] / 2);
        return kin + 2 * (k_.alpha * h1 * h1 + k_.beta * h2 * h2);
    }

    /// Hamilton's equations and their tangent equations: state (x, v), v' = J(x) v.
    std::array<double, 8> tangent(const std::array<double, 8>& state) const {
        std::array<double, 8> f;
        tangent_lanes_from(trig_lanes<double>(state.data()), state.data(), f.data());
        return f;
    }

    const lagrangian_coefficients<double>& coefficients() const { return k_; }

  private:
    /// The libm fallback of lanes() and tangent_lanes() (an angle outside the fast sin/cos
    /// range): `one` (operator() or tangent()) on each lane's state in turn.
    template <std::size_t N, class V, class One>
    static void per_lane(const V in[N], V out[N], One one) {
        for (int lane = 0; lane < lanes_of<V>; ++lane) {
            std::array<double, N> x{};
            for (std::size_t i = 0; i < N; ++i)
                x[i] = in[i][lane];
            const std::array<double, N> f = one(x);
            for (std::size_t i = 0; i < N; ++i)
                out[i][lane] = f[i];
        }
    }

    /// The sines and cosines of the angles and of their difference, of one state (V = double)
    /// or of lanes_of<V> states at once (x[0], x[1]: the angles of each lane): each lane the bits
    /// of one state.
    template <class V>
    struct trig_lanes {
        V s1, c1, s2, c2, sd, cd;
        [[gnu::always_inline]] explicit trig_lanes(const V* x) {
            if constexpr (std::is_same_v<V, double>) {
                fast_sincos2(x[0], x[1], s1, c1, s2, c2);
            } else {
                fast_sincos_lanes(x[0], s1, c1);
                fast_sincos_lanes(x[1], s2, c2);
            }
            sd = s1 * c2 - c1 * s2;
            cd = c1 * c2 + s1 * s2;
        }
    };
    // Hamilton's equations, their tangent form and H (hamiltonian_absolute) from the states' sines
    // and cosines: one state (V = double: operator(), tangent(), hamiltonian_absolute()) or
    // several (lanes(), tangent_lanes(), hamiltonian_lanes()), the same operations.
    template <class V>
    [[gnu::always_inline]] void lanes_from(const trig_lanes<V>& g, const V x[4], V f[4]) const {
        const double CC = k_.C * k_.C;
        const V det = k_.D0 + CC * g.sd * g.sd;
        const V w1 = (k_.B * x[2] - k_.C * g.cd * x[3]) / det;
        const V w2 = (k_.A * x[3] - k_.C * g.cd * x[2]) / det;
        const V P = k_.C * g.sd * w1 * w2;
        f[0] = w1;
        f[1] = w2;
        f[2] = -P - k_.alpha * g.s1;
        f[3] = P - k_.beta * g.s2;
    }
    template <class V>
    [[gnu::always_inline]] void tangent_lanes_from(const trig_lanes<V>& g, const V y[8],
                                                   V f[8]) const {
        const double C = k_.C;
        const V det = k_.D0 + C * C * g.sd * g.sd;
        const V n1 = k_.B * y[2] - C * g.cd * y[3];
        const V n2 = k_.A * y[3] - C * g.cd * y[2];
        const V w1 = n1 / det, w2 = n2 / det;
        const V P = C * g.sd * w1 * w2;
        const V dd = y[4] - y[5];
        const V dsd = g.cd * dd, dcd = -g.sd * dd;
        const V ddet = 2 * C * C * g.sd * dsd;
        const V dn1 = k_.B * y[6] - C * (dcd * y[3] + g.cd * y[7]);
        const V dn2 = k_.A * y[7] - C * (dcd * y[2] + g.cd * y[6]);
        const V dw1 = (dn1 - w1 * ddet) / det, dw2 = (dn2 - w2 * ddet) / det;
        const V dP = C * (dsd * w1 * w2 + g.sd * (dw1 * w2 + w1 * dw2));
        f[0] = w1;
        f[1] = w2;
        f[2] = -P - k_.alpha * g.s1;
        f[3] = P - k_.beta * g.s2;
        f[4] = dw1;
        f[5] = dw2;
        f[6] = -dP - k_.alpha * g.c1 * y[4];
        f[7] = dP - k_.beta * g.c2 * y[5];
    }
    template <class V>
    [[gnu::always_inline]] void energy_from(const trig_lanes<V>& g, const V x[4], V& h) const {
        const V det = k_.D0 + k_.C * k_.C * g.sd * g.sd;
        const V kin =
            (k_.B * x[2] * x[2] - 2 * k_.C * g.cd * x[2] * x[3] + k_.A * x[3] * x[3]) / (2 * det);
        h = kin + (k_.alpha * (1 - g.c1) + k_.beta * (1 - g.c2));
    }

    lagrangian_coefficients<double> k_;
};

/// Adapter: the flow as an 8-dimensional right-hand side (state and tangent vector).
struct pendulum_tangent_rhs {
    pendulum_flow flow;
    std::array<double, 8> operator()(double, const std::array<double, 8>& y) const {
        return flow.tangent(y);
    }
};

}  // namespace flipflux
