// The nested Clenshaw-Curtis rules after the substitution x = a + (b - a) sin^2(u/2): see
// include/flipflux/quadrature/quadrature.hpp (sine_squared_clenshaw_curtis).
//
// Clenshaw-Curtis on [-1, 1] with M intervals (M even; Trefethen, SIAM Rev. 50 (2008) 67, eq. 2.7
// ): nodes y_k = cos(k pi / M), k = 0..M, weights
//     w_k = (c_k / M) [1 - sum_{j=1}^{M/2} b_j cos(2 j k pi / M) / (4 j^2 - 1)],
// c_k = 1 at k = 0, M and 2 otherwise, b_j = 1 at j = M/2 and 2 otherwise. The rule of 2 M
// intervals reuses the M rule's nodes as its even ones: 32, 64, 128, ... intervals cost one
// evaluation per node of the last. With u = pi (1 + y) / 2 in [0, pi] and x = a + (b - a)
// sin^2(u/2): dx = (b - a) sin(u/2) cos(u/2) du, so the integral is
//     (b - a) sum_k [pi w_k / 2] sin(u_k/2) cos(u_k/2) f(x_k).
// The ends (u = 0, pi) carry the factor sin u = 0 and are not evaluated.
#include <cmath>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <vector>

#include "convergence.hpp"
#include "flipflux/core/budget.hpp"
#include "flipflux/core/constants.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/quadrature/quadrature.hpp"

namespace flipflux {
namespace {

/// The first rule's intervals; each further rule doubles them.
constexpr std::size_t first_intervals = 32;

/// The rules of 32, 64, ..., M_max intervals in the working precision. Nodes k = 1..M_max-1 of
/// the finest rule: p = sin^2(u/2) and q = cos^2(u/2), each computed directly (so x - a = (b - a) p
/// and b - x = (b - a) q keep full relative accuracy near their end), and the substitution's factor
/// (pi / 2) sin(u/2) cos(u/2); the rule of M intervals uses every (M_max / M)-th node, with its
/// weights weight[l] (l = log2(M / 32)) at its nodes k = 1..M-1.
template <class Real>
struct sine_squared_rules {
    std::size_t max_intervals = 0;
    std::vector<Real> p, q, factor;
    std::vector<std::vector<Real>> weight;
};

template <class Real>
sine_squared_rules<Real> make_rules(std::size_t max_intervals) {
    using std::cos;
    using std::sin;
    const std::size_t N = max_intervals;
    // T[i] = cos(i pi / (2 N)), i < 4 N, from its first quarter by symmetry
    std::vector<Real> T(4 * N);
    for (std::size_t i = 0; i <= N; ++i)
        T[i] = i == N ? Real(0)
                      : cos(Real(pi<Real>() * Real(static_cast<long>(i)) /
                                 Real(static_cast<long>(2 * N))));
    for (std::size_t i = N + 1; i <= 2 * N; ++i)
        T[i] = -T[2 * N - i];
    for (std::size_t i = 2 * N + 1; i < 4 * N; ++i)
        T[i] = T[4 * N - i];
    sine_squared_rules<Real> r;
    r.max_intervals = N;
    // node k: u = pi (1 + cos(k pi / N)) / 2 = pi cos^2(k pi / (2 N)), pi - u = pi sin^2(...);
    // sin((pi - u_k) / 2) = sin(u_(N-k) / 2)
    std::vector<Real> half_sine(N + 1);  // sin(u_k / 2), k = 0..N
    for (std::size_t k = 0; k <= N; ++k)
        half_sine[k] = sin(half_pi<Real>() * T[k] * T[k]);
    for (std::size_t k = 1; k < N; ++k) {
        const Real &s = half_sine[k], &c = half_sine[N - k];
        r.p.push_back(s * s);
        r.q.push_back(c * c);
        r.factor.push_back(half_pi<Real>() * s * c);
    }
    // Clenshaw-Curtis weights of M intervals at k = 1..M/2 (w_k = w_(M-k)); cos(2 j k pi / M) =
    // T[4 j k N / M mod 4 N]
    for (std::size_t M = first_intervals; M <= N; M *= 2) {
        std::vector<Real> coef(M / 2 + 1);  // b_j / (4 j^2 - 1)
        for (std::size_t j = 1; j <= M / 2; ++j) {
            const auto jj = static_cast<long>(j);
            coef[j] = (j == M / 2 ? Real(1) : Real(2)) / Real(4 * jj * jj - 1);
        }
        std::vector<Real> w(M - 1);
        const std::size_t stride = 4 * N / M;
        for (std::size_t k = 1; k <= M / 2; ++k) {
            Real sum = 0;
            for (std::size_t j = 1; j <= M / 2; ++j)
                sum += coef[j] * T[(j * k * stride) % (4 * N)];
            w[k - 1] = w[M - k - 1] = 2 * (1 - sum) / Real(static_cast<long>(M));
        }
        r.weight.push_back(std::move(w));
    }
    return r;
}

/// One set of rules per thread, working precision and finest rule.
template <class Real>
const sine_squared_rules<Real>& thread_rules(std::size_t max_intervals) {
    thread_local std::map<std::pair<int, std::size_t>, std::unique_ptr<sine_squared_rules<Real>>>
        cache;
    auto& slot = cache[{binary_digits<Real>(), max_intervals}];
    if (!slot) slot = std::make_unique<sine_squared_rules<Real>>(make_rules<Real>(max_intervals));
    return *slot;
}

}  // namespace

template <class Real>
std::optional<quadrature_result<Real>> sine_squared_clenshaw_curtis(
    endpoint_integrand<Real> f, const Real& a, const Real& b, std::size_t max_intervals,
    const quadrature_options<Real>& opt) {
    using boost::multiprecision::isfinite;
    using std::abs;
    using std::isfinite;
    if (!isfinite(a) || !isfinite(b) || a > b)
        throw std::domain_error("sine_squared_clenshaw_curtis: needs finite bounds with a <= b");
    if (max_intervals < first_intervals)
        throw std::domain_error("sine_squared_clenshaw_curtis: needs at least 32 intervals");
    quadrature_result<Real> r;
    if (a == b) return r;
    const Real width = b - a;
    const Real tolerance =
        opt.relative_tolerance > 0 ? opt.relative_tolerance : default_quadrature_tolerance<Real>();
    if (max_intervals & (max_intervals - 1))
        throw std::domain_error("sine_squared_clenshaw_curtis: max_intervals must be a power of 2");
    const sine_squared_rules<Real>& rules = thread_rules<Real>(max_intervals);
    const std::size_t N = max_intervals;
    std::vector<Real> values(N - 1);  // f at the finest rule's nodes k = 1..N-1 (index k - 1)
    auto evaluate = [&](std::size_t k) {
        check_cpu_budget();
        const std::size_t i = k - 1;
        const Real to_a = width * rules.p[i], to_b = width * rules.q[i];
        const Real x = rules.p[i] <= rules.q[i] ? Real(a + to_a) : Real(b - to_b);
        const Real v = f(x, to_a, to_b);
        if (!isfinite(v))
            throw std::domain_error("sine_squared_clenshaw_curtis: the integrand is not finite");
        ++r.evaluations;
        values[i] = rules.factor[i] * v;
    };
    Real previous = 0;
    std::size_t level = 0;
    for (std::size_t M = first_intervals; M <= N; M *= 2, ++level) {
        const std::size_t stride = N / M;
        // the new nodes: odd multiples of the stride (all of them in the first rule)
        for (std::size_t k = stride; k < N; k += (M == first_intervals ? stride : 2 * stride))
            evaluate(k);
        const std::vector<Real>& w = rules.weight[level];
        Real sum = 0, l1 = 0;
        for (std::size_t i = 1; i < M; ++i) {
            const Real& v = values[i * stride - 1];
            sum += w[i - 1] * v;
            l1 += w[i - 1] * abs(v);
        }
        r.value = width * sum;
        r.l1_norm = width * l1;
        if (M > first_intervals) {
            if (!(r.l1_norm > 0)) return r;  // f = 0 at every node: 0 for every rule
            const Real d = abs(r.value - previous);
            if (d <= tolerance * r.l1_norm) {
                // the rounding level: 4 eps L1 (the weights are sums of M / 2 terms; measured
                // 1.7 eps L1 at double, e^x sqrt(1 - x^2) in tests/quadrature)
                r.error_estimate =
                    detail::converged_error(d, r.l1_norm) + 4 * epsilon<Real>() * r.l1_norm;
                return r;
            }
        }
        previous = r.value;
    }
    return std::nullopt;
}

#define FLIPFLUX_CLENSHAW_CURTIS_INSTANTIATE(R)                                   \
    template std::optional<quadrature_result<R>> sine_squared_clenshaw_curtis<R>( \
        endpoint_integrand<R>, const R&, const R&, std::size_t, const quadrature_options<R>&)
FLIPFLUX_CLENSHAW_CURTIS_INSTANTIATE(inst_real);

}  // namespace flipflux
