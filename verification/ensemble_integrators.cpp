// The explicit Runge-Kutta integrators on the double pendulum against a high-precision
// reference: Gragg-Bulirsch-Stoer extrapolation (modified midpoint rule, step sequence 2, 4, ...,
// 32, polynomial extrapolation in h^2: order 32) in 50-digit MPFR on the precision-templated
// model (model/double_pendulum.hpp) -- an independent method, arithmetic and right-hand side.
// The reference is checked against itself with half the macro step (agreement < 1e-20,
// observed 1e-31 egalitarian, 2e-25 lopsided).
// Checked: end states of DOP853 and DOPRI5 for tolerances 1e-8 ... 1e-12 on the egalitarian and
// a lopsided pendulum; the dense output at interior times; error decreasing with tolerance.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "flipflux/core/real.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/ensemble/sampler.hpp"
#include "flipflux/integrators/explicit_rk.hpp"
#include "pendulums.hpp"

namespace flipflux::verification {
namespace {

using state50 = phase_point<mp>;

state50 gbs_step(const double_pendulum<mp>& m, const state50& y, const mp& H, int K) {
    std::vector<state50> T(static_cast<std::size_t>(K));
    auto axpy = [](const state50& a, const mp& h, const state50& f) {
        state50 r;
        for (int i = 0; i < 4; ++i)
            r[i] = a[i] + h * f[i];
        return r;
    };
    for (int j = 0; j < K; ++j) {
        const int n = 2 * (j + 1);
        const mp h = H / n;
        state50 z0 = y, z1 = axpy(y, h, m.rhs(y));
        for (int s = 1; s < n; ++s) {
            const state50 z2 = axpy(z0, 2 * h, m.rhs(z1));
            z0 = z1;
            z1 = z2;
        }
        // Gragg's smoothing
        const state50 f = m.rhs(z1);
        state50 t;
        for (int i = 0; i < 4; ++i)
            t[i] = (z1[i] + z0[i] + h * f[i]) / 2;
        T[static_cast<std::size_t>(j)] = t;
        // Neville (Aitken) extrapolation to h = 0 in powers of h^2
        for (int k = j - 1; k >= 0; --k) {
            const mp r = mp(n) / (2 * (k + 1));
            const mp d = r * r - 1;
            for (int i = 0; i < 4; ++i)
                T[static_cast<std::size_t>(k)][i] =
                    T[static_cast<std::size_t>(k + 1)][i] +
                    (T[static_cast<std::size_t>(k + 1)][i] - T[static_cast<std::size_t>(k)][i]) / d;
        }
    }
    return T[0];
}

// The states at the increasing times `at`, macro steps of about H landing on each.
std::vector<state50> reference(const double_pendulum<mp>& m, const state50& y0,
                               const std::vector<double>& at, double H) {
    std::vector<state50> out;
    state50 y = y0;
    double t = 0;
    for (double target : at) {
        const int n = static_cast<int>(std::ceil((target - t) / H - 1e-9));
        const mp h = (mp(target) - mp(t)) / n;
        for (int i = 0; i < n; ++i)
            y = gbs_step(m, y, h, 16);
        out.push_back(y);
        t = target;
    }
    return out;
}

template <class Method>
double max_error(const double_pendulum<double>& m, const phase_point<double>& x0, double T,
                 double tol, const state50& ref, const std::vector<double>& mids,
                 const std::vector<state50>& mid_refs, double* dense_err) {
    rk_options o;
    o.rtol = o.atol = tol;
    explicit_rk<Method, 4, pendulum_flow> rk(pendulum_flow(m), o);
    rk.initialize(0, x0);
    *dense_err = 0;
    std::size_t next = 0;
    rk.integrate(T, [&](auto& r) {
        while (next < mids.size() && mids[next] <= r.t()) {
            const auto y = r.dense(mids[next]);
            for (int i = 0; i < 4; ++i)
                *dense_err =
                    std::max(*dense_err, std::abs(y[i] - static_cast<double>(mid_refs[next][i])));
            ++next;
        }
    });
    double e = 0;
    for (int i = 0; i < 4; ++i)
        e = std::max(e, std::abs(rk.x()[i] - static_cast<double>(ref[i])));
    return e;
}

void check_pendulum(const char* label, const physical_parameters<double>& p, double fraction) {
    const precision_scope scope(mp_precision(50));  // the reference in mp:50
    const double_pendulum<double> m(p);
    const double_pendulum<mp> mq(convert_parameters<mp>(p));
    const double E = fraction * m.maximum_energy();
    const phase_point<double> x0 = microcanonical_sampler(m, E).sample(77, 0);
    const state50 y0{mp(x0[0]), mp(x0[1]), mp(x0[2]), mp(x0[3])};
    const double T = 5;
    const std::vector<double> mids{0.731, 2.2, 3.97};
    const std::vector<state50> refs = reference(mq, y0, {0.731, 2.2, 3.97, T}, 0.05);
    const state50 ref = refs.back();
    const std::vector<state50> mid_refs(refs.begin(), refs.end() - 1);
    // the reference against itself with half the macro step
    const state50 ref2 = reference(mq, y0, {T}, 0.025).back();
    for (int i = 0; i < 4; ++i)
        ASSERT_LT(static_cast<double>(abs(ref[i] - ref2[i])), 1e-20) << "reference " << i;
    for (int method = 0; method < 2; ++method) {
        double previous = 1;
        for (double tol : {1e-8, 1e-10, 1e-12}) {
            double dense = 0;
            const double err =
                method == 0
                    ? max_error<dormand_prince_853>(m, x0, T, tol, ref, mids, mid_refs, &dense)
                    : max_error<dormand_prince_5>(m, x0, T, tol, ref, mids, mid_refs, &dense);
            std::printf("%-11s E = %.4g %-7s tol %.0e: end error %.2e (%.0f tol), dense %.2e\n",
                        label, E, method == 0 ? "dop853" : "dopri5", tol, err, err / tol, dense);
            EXPECT_LT(err, 1000 * tol) << label << " " << method << " " << tol;
            EXPECT_LT(dense, 1000 * tol) << label << " " << method << " " << tol;
            EXPECT_LT(err, previous);
            previous = err;
        }
    }
}

TEST(IntegratorsAgainstReference, Egalitarian) {
    check_pendulum("egalitarian", physical_parameters<double>{}, 5.0 / 6);
}

TEST(IntegratorsAgainstReference, Lopsided) {
    check_pendulum("lopsided", test::lopsided_parameters(), 0.6);
}

}  // namespace
}  // namespace flipflux::verification
