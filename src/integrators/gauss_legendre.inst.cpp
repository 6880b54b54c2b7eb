// Gauss-Legendre tableaux in the working precision (see integrators/gauss_legendre.hpp).
//
// Roots of P_s: Newton on the three-term recurrence (n+1) P_{n+1} = (2n+1) x P_n - n P_{n-1},
// P_s'(x) = s (x P_s - P_{s-1}) / (x^2 - 1), from the double guess cos(pi (k - 1/4) / (s + 1/2)),
// iterated in Real until the correction stops decreasing. Weights b = 1 / ((1 - x^2) P_s'^2).
// a_ij = int_0^{c_i} l_j = c_i sum_k b_k l_j(c_i c_k) (the s-point Gauss rule is exact for the
// degree-(s-1) Lagrange basis). d solves A^T d = b (Gaussian elimination with partial pivoting).
// e_ij = lt_j(1 + c_i) - lt_j(1), lt_j the Lagrange basis on {0, c_1, .., c_s} (node c_j).
#include <cmath>
#include <map>
#include <memory>
#include <mutex>
#include <stdexcept>
#include <string>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/integrators/gauss_legendre.hpp"

namespace flipflux {

namespace {

template <class Real>
void legendre(int n, const Real& x, Real& p, Real& dp) {
    Real p0 = 1, p1 = x;
    if (n == 0) {
        p = 1;
        dp = 0;
        return;
    }
    for (int k = 1; k < n; ++k) {
        const Real p2 = ((2 * k + 1) * x * p1 - k * p0) / (k + 1);
        p0 = p1;
        p1 = p2;
    }
    p = p1;
    dp = n * (x * p1 - p0) / (x * x - 1);
}

/// Lagrange basis polynomial j on `nodes`, at t.
template <class Real>
Real lagrange(const std::vector<Real>& nodes, std::size_t j, const Real& t) {
    Real v = 1;
    for (std::size_t m = 0; m < nodes.size(); ++m)
        if (m != j) v *= (t - nodes[m]) / (nodes[j] - nodes[m]);
    return v;
}

}  // namespace

template <class Real>
gauss_legendre_tableau<Real> make_gauss_legendre_tableau(int s) {
    if (s < 1 || s > max_gauss_legendre_stages) {
        throw std::invalid_argument("gauss_legendre: stages = " + std::to_string(s) +
                                    " outside [1, " + std::to_string(max_gauss_legendre_stages) +
                                    "]");
    }
    using std::abs;
    const auto n = static_cast<std::size_t>(s);
    gauss_legendre_tableau<Real> t;
    t.stages = s;
    t.roots.resize(n);
    t.c.resize(n);
    t.b.resize(n);
    t.a.assign(n * n, Real(0));
    t.d.resize(n);
    t.e.assign(n * n, Real(0));
    // roots, decreasing in k; stored increasing
    for (int k = 1; k <= s; ++k) {
        // NOTE: a double first guess is enough: Newton below runs in Real to its precision.
        Real x = Real(std::cos(3.14159265358979323846 * (k - 0.25) / (s + 0.5)));
        Real p, dp, last = std::numeric_limits<Real>::max();
        for (int it = 0; it < 200; ++it) {
            legendre(s, x, p, dp);
            const Real dx = p / dp;
            x -= dx;
            const Real m = abs(dx);
            if (m == 0 || (m >= last && m <= 16 * std::numeric_limits<Real>::epsilon())) break;
            last = m;
            if (it == 199) throw std::logic_error("gauss_legendre: Newton on P_s did not converge");
        }
        if (s % 2 == 1 && k == (s + 1) / 2) x = 0;  // the middle root of odd s is exactly 0
        const auto idx = static_cast<std::size_t>(s - k);
        t.roots[idx] = x;
    }
    // symmetrise: root_{s-1-i} = -root_i exactly
    for (std::size_t i = 0; i < n / 2; ++i) {
        const Real r = (t.roots[n - 1 - i] - t.roots[i]) / 2;
        t.roots[n - 1 - i] = r;
        t.roots[i] = -r;
    }
    for (std::size_t i = 0; i < n; ++i) {
        Real p, dp;
        legendre(s, t.roots[i], p, dp);
        t.c[i] = (1 + t.roots[i]) / 2;
        t.b[i] = 1 / ((1 - t.roots[i] * t.roots[i]) * dp * dp);
    }
    for (std::size_t i = 0; i < n / 2; ++i)
        t.b[i] = t.b[n - 1 - i] = (t.b[i] + t.b[n - 1 - i]) / 2;
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            Real v = 0;
            for (std::size_t k = 0; k < n; ++k)
                v += t.b[k] * lagrange(t.c, j, t.c[i] * t.c[k]);
            t.a[i * n + j] = t.c[i] * v;
        }
    // d: A^T d = b
    {
        std::vector<Real> m(n * n), rhs(t.b);
        for (std::size_t i = 0; i < n; ++i)
            for (std::size_t j = 0; j < n; ++j)
                m[i * n + j] = t.a[j * n + i];
        std::vector<std::size_t> perm(n);
        for (std::size_t col = 0; col < n; ++col) {
            std::size_t piv = col;
            for (std::size_t r = col + 1; r < n; ++r)
                if (abs(m[r * n + col]) > abs(m[piv * n + col])) piv = r;
            if (piv != col) {
                for (std::size_t j = 0; j < n; ++j)
                    std::swap(m[col * n + j], m[piv * n + j]);
                std::swap(rhs[col], rhs[piv]);
            }
            for (std::size_t r = col + 1; r < n; ++r) {
                const Real f = m[r * n + col] / m[col * n + col];
                for (std::size_t j = col; j < n; ++j)
                    m[r * n + j] -= f * m[col * n + j];
                rhs[r] -= f * rhs[col];
            }
        }
        for (std::size_t i = n; i-- > 0;) {
            Real v = rhs[i];
            for (std::size_t j = i + 1; j < n; ++j)
                v -= m[i * n + j] * t.d[j];
            t.d[i] = v / m[i * n + i];
        }
    }
    // extrapolation of the collocation polynomial
    std::vector<Real> nodes(n + 1);
    nodes[0] = 0;
    for (std::size_t i = 0; i < n; ++i)
        nodes[i + 1] = t.c[i];
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j)
            t.e[i * n + j] =
                lagrange(nodes, j + 1, Real(1) + t.c[i]) - lagrange(nodes, j + 1, Real(1));
    return t;
}

template <class Real>
const gauss_legendre_tableau<Real>& gauss_legendre_tableau_of(int s) {
    if (s < 1 || s > max_gauss_legendre_stages)
        (void)make_gauss_legendre_tableau<Real>(s);  // throws
    // NOTE: keyed by the working precision too (mp's changes at run time)
    static std::mutex mutex;
    static std::map<std::pair<int, int>, std::unique_ptr<const gauss_legendre_tableau<Real>>> cache;
    std::lock_guard<std::mutex> lock(mutex);
    auto& slot = cache[{s, binary_digits<Real>()}];
    if (!slot)
        slot = std::make_unique<const gauss_legendre_tableau<Real>>(
            make_gauss_legendre_tableau<Real>(s));
    return *slot;
}

template const gauss_legendre_tableau<inst_real>& gauss_legendre_tableau_of<inst_real>(int);
template gauss_legendre_tableau<inst_real> make_gauss_legendre_tableau<inst_real>(int);

}  // namespace flipflux
