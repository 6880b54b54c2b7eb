// The saddle orbit's configuration curve as piecewise Chebyshev series (orbits/saddle_curve.hpp).
//
// Chebyshev-Lobatto interpolation on a panel: nodes x_k = cos(pi k / n), k = 0..n; coefficients
//     a_j = (2/n) sum''_k f_k cos(pi j k / n)   (first and last terms halved),
//     c_0 = a_0 / 2, c_n = a_n / 2, c_j = a_j otherwise;
// derivative series: d_{n-1} = 2 n c_n, d_{j-1} = d_{j+1} + 2 j c_j, then d_0 halved.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/integrators/gauss_legendre.hpp"
#include "flipflux/integrators/taylor.hpp"
#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/orbits/saddle_frame.hpp"
#include "flipflux/orbits/saddle_taylor.hpp"

namespace flipflux {

namespace {

template <class Real>
int curve_degree() {
    // NOTE: 16 at double (53 bits), 28 at quad (113), 40 at 50 digits (168), 64 at 100 (334),
    // measured; beyond, in proportion to the digits
    return scaled_with_precision(binary_digits<Real>(), {{53, 16}, {113, 28}, {168, 40}, {334, 64}},
                                 1.0);
}

template <class Real>
void require_orbit(const saddle_orbit<Real>& orbit) {
    if (orbit.quarter.size() < 2 || !(orbit.quarter_step > 0))
        throw std::invalid_argument("saddle curve: the orbit has no stored solution (status: " +
                                    to_string(orbit.status) + ")");
}

}  // namespace

/// Finds points of the stored quarter orbit by their s-angle. Consecutive queries in the same
/// stored interval reuse the last Gauss-Legendre step's collocation polynomial (restep), or, for
/// an orbit integrated by Taylor series, the interval's Taylor polynomial (its dense output), which
/// makes the Newton iteration in t cheap at high precision.
template <class Real>
class quarter_locator {
  public:
    quarter_locator(const double_pendulum<Real>& model, const saddle_orbit<Real>& orbit)
        : frame_(model, orbit.flip_arm),
          orbit_(orbit),
          gl_(orbit.stages > 0 ? orbit.stages : default_stages<Real>()),
          taylor_(orbit.integrator == orbit_integrator::taylor && orbit.order > 0),
          ti_(taylor_ ? orbit.order : 1),
          tf_(frame_, taylor_ ? orbit.order : 1),
          si_(frame_.s_index()) {
        require_orbit(orbit);
    }

    /// (t, delta1, delta2, l1, l2) where s(t) = s, 0 <= t <= T/4.
    std::array<Real, 5> at(const Real& s) {
        using std::abs;
        const auto& q = orbit_.quarter;
        const std::size_t n = q.size() - 1;
        const Real h = orbit_.quarter_step;
        if (!(s > q.front()[si_]))
            return {Real(0), q.front()[0], q.front()[1], q.front()[2], q.front()[3]};
        if (!(s < q.back()[si_]))
            return {h * n, q.back()[0], q.back()[1], q.back()[2], q.back()[3]};
        // the last stored state with s_j <= s
        const auto it = std::upper_bound(
            q.begin(), q.end(), s,
            [this](const Real& v, const std::array<Real, 4>& x) { return v < x[si_]; });
        const std::size_t j = static_cast<std::size_t>(it - q.begin()) - 1;
        const auto& xj = q[j];
        const auto& xk = q[j + 1];
        // first guess from the cubic Hermite interpolant of s(t) on the interval
        std::array<Real, 4> f0, f1;
        frame_.rhs(xj, f0);
        frame_.rhs(xk, f1);
        const Real s0 = xj[si_], s1 = xk[si_], d0 = f0[si_] * h, d1 = f1[si_] * h;
        Real u = (s - s0) / (s1 - s0);
        for (int k = 0; k < 8; ++k) {
            const Real u2 = u * u, u3 = u2 * u;
            const Real p = (2 * u3 - 3 * u2 + 1) * s0 + (u3 - 2 * u2 + u) * d0 +
                           (-2 * u3 + 3 * u2) * s1 + (u3 - u2) * d1;
            const Real dp = (6 * u2 - 6 * u) * s0 + (3 * u2 - 4 * u + 1) * d0 +
                            (-6 * u2 + 6 * u) * s1 + (3 * u2 - 2 * u) * d1;
            if (!(dp > 0)) break;
            Real next = u - (p - s) / dp;
            if (!(next > 0 && next < 1)) break;
            u = next;
        }
        Real dt = u * h;
        // safeguarded Newton on g(dt) = s(x_j advanced by dt) - s, bracket [0, h]
        Real lo = 0, hi = h;
        const Real eps = std::numeric_limits<Real>::epsilon();
        const Real scale = h * n;
        Real last_step = std::numeric_limits<Real>::max();
        for (int iter = 0; iter < 200; ++iter) {
            advance(j, dt);
            const Real g = y_[si_] - s;
            if (g == 0) break;
            if (g < 0)
                lo = dt;
            else
                hi = dt;
            std::array<Real, 4> f;
            frame_.rhs({y_[0], y_[1], y_[2], y_[3]}, f);
            Real next = dt - g / f[si_];
            if (!(f[si_] > 0) || !(next > lo && next < hi)) next = (lo + hi) / 2;
            const Real step = abs(next - dt);
            dt = next;
            // NOTE: stop at the rounding floor of t (the root is simple: s' > 0 inside the
            // quarter); the last Newton step is then below eps T
            if (step <= 4 * eps * scale || (step >= last_step && step <= 1024 * eps * scale)) {
                advance(j, dt);
                break;
            }
            last_step = step;
        }
        return {h * j + dt, y_[0], y_[1], y_[2], y_[3]};
    }

  private:
    void advance(std::size_t j, const Real& dt) {
        const auto& xj = orbit_.quarter[j];
        y_ = {xj[0], xj[1], xj[2], xj[3], Real(0)};
        if (dt == 0) return;
        if (taylor_) {
            // the interval's Taylor polynomial, expanded once (the integrator's own step)
            const bool ok = j == last_j_ || ti_.expand(tf_, y_);
            last_j_ = ok ? j : static_cast<std::size_t>(-1);
            if (ok) y_ = ti_.evaluate(dt);
            return;
        }
        bool ok = j == last_j_ ? gl_.restep(orbit_flow<Real>{&frame_}, y_, dt)
                               : gl_.step(orbit_flow<Real>{&frame_}, y_, dt);
        if (!ok) {  // very rare: fall back to the robust path (split steps)
            y_ = {xj[0], xj[1], xj[2], xj[3], Real(0)};
            ok = gl_.integrate(orbit_flow<Real>{&frame_}, y_, dt, 1).success;
        }
        last_j_ = ok ? j : static_cast<std::size_t>(-1);
    }

    saddle_frame<Real> frame_;
    const saddle_orbit<Real>& orbit_;
    gauss_legendre<Real, 5> gl_;
    bool taylor_;
    taylor_integrator<Real, 5> ti_;
    saddle_taylor_flow<Real> tf_;
    int si_;
    std::size_t last_j_ = static_cast<std::size_t>(-1);
    std::array<Real, 5> y_{};
};

template <class Real>
std::array<Real, 5> orbit_point_at_s(const double_pendulum<Real>& model,
                                     const saddle_orbit<Real>& orbit, const Real& s) {
    quarter_locator<Real> locator(model, orbit);
    return locator.at(s);
}

template <class Real>
saddle_curve<Real> make_saddle_curve(const double_pendulum<Real>& model,
                                     const saddle_orbit<Real>& orbit, const Real& tolerance) {
    using std::abs;
    using std::cos;
    require_orbit(orbit);
    const saddle_frame<Real> frame(model, orbit.flip_arm);
    const int si = frame.s_index(), hi = frame.h_index();
    const auto& q = orbit.quarter;
    for (std::size_t j = 1; j < q.size(); ++j)
        if (!(q[j][si] > q[j - 1][si]))
            throw std::runtime_error(
                "saddle curve: the orbit's configuration curve is not a graph over the other "
                "angle (it turns back before the turning point)");
    const Real s_max = q.back()[si];
    const Real eps = std::numeric_limits<Real>::epsilon();
    const Real tol = tolerance > 0 ? tolerance : 8 * eps * s_max;
    const int n = curve_degree<Real>();
    const auto n1 = static_cast<std::size_t>(n + 1);
    // cos(pi m / n), m = 0..2n-1
    std::vector<Real> cosines(static_cast<std::size_t>(2 * n));
    for (int m = 0; m < 2 * n; ++m)
        cosines[static_cast<std::size_t>(m)] = cos(pi<Real>() * m / n);

    quarter_locator<Real> locator(model, orbit);
    auto h_at = [&](const Real& s) -> Real {
        if (s == 0) return Real(0);
        if (s == s_max) return q.back()[hi];
        return locator.at(s)[static_cast<std::size_t>(1 + hi)];
    };
    struct panel {
        Real a, b;
        std::vector<Real> c;
        Real tail;
    };
    // Chebyshev coefficients on [a, b]; the values at the ends are passed in (shared nodes)
    auto fit = [&](const Real& a, const Real& b, const Real& fa, const Real& fb) {
        panel pn{a, b, std::vector<Real>(n1), Real(0)};
        std::vector<Real> f(n1);
        f[0] = fb;
        f[n1 - 1] = fa;
        for (int k = 1; k < n; ++k) {
            const Real x = cosines[static_cast<std::size_t>(k)];
            f[static_cast<std::size_t>(k)] = h_at(a + (b - a) * (x + 1) / 2);
        }
        for (int j = 0; j <= n; ++j) {
            Real acc = 0;
            for (int k = 0; k <= n; ++k) {
                const Real w = (k == 0 || k == n) ? Real(1) / 2 : Real(1);
                acc += w * f[static_cast<std::size_t>(k)] *
                       cosines[static_cast<std::size_t>((j * k) % (2 * n))];
            }
            acc = 2 * acc / n;
            pn.c[static_cast<std::size_t>(j)] = (j == 0 || j == n) ? acc / 2 : acc;
        }
        pn.tail = std::max(abs(pn.c[n1 - 1]), abs(pn.c[n1 - 2]));
        return pn;
    };
    // adaptive bisection, depth first from the left so that the accepted panels come out sorted
    std::vector<panel> accepted;
    Real error = 0;
    const Real min_width = s_max * ldexp(Real(1), -40);
    struct pending {
        Real a, b, fa, fb;
    };
    std::vector<pending> stack{{Real(0), s_max, Real(0), q.back()[hi]}};
    while (!stack.empty()) {
        const pending w = stack.back();
        stack.pop_back();
        panel pn = fit(w.a, w.b, w.fa, w.fb);
        if (pn.tail <= tol || w.b - w.a <= min_width) {
            if (pn.tail > error) error = pn.tail;
            accepted.push_back(std::move(pn));
            continue;
        }
        const Real m = (w.a + w.b) / 2;
        const Real fm = h_at(m);
        stack.push_back({m, w.b, fm, w.fb});  // right half after the left half
        stack.push_back({w.a, m, w.fa, fm});
    }
    std::vector<Real> breaks{Real(0)}, values, slopes;
    values.reserve(accepted.size() * n1);
    slopes.reserve(accepted.size() * n1);
    for (const panel& pn : accepted) {
        breaks.push_back(pn.b);
        values.insert(values.end(), pn.c.begin(), pn.c.end());
        // derivative with respect to s: d/ds = (2 / width) d/dx
        std::vector<Real> dd(n1 + 1, Real(0));
        for (int j = n; j >= 1; --j)
            dd[static_cast<std::size_t>(j - 1)] =
                dd[static_cast<std::size_t>(j + 1)] + 2 * j * pn.c[static_cast<std::size_t>(j)];
        dd[0] /= 2;
        for (std::size_t j = 0; j < n1; ++j)
            slopes.push_back(dd[j] * 2 / (pn.b - pn.a));
    }
    return saddle_curve<Real>(orbit.flip_arm, n, std::move(breaks), std::move(values),
                              std::move(slopes), error);
}

template saddle_curve<inst_real> make_saddle_curve<inst_real>(const double_pendulum<inst_real>&,
                                                              const saddle_orbit<inst_real>&,
                                                              const inst_real&);
template std::array<inst_real, 5> orbit_point_at_s<inst_real>(const double_pendulum<inst_real>&,
                                                              const saddle_orbit<inst_real>&,
                                                              const inst_real&);

}  // namespace flipflux
