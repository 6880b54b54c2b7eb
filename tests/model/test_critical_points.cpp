// Closed-form normal modes (App. B) against Eigen's eigen-decomposition of the linearised
// Hamiltonian vector field, and the paper's egalitarian values.
#include "flipflux/core/constants.hpp"
#include "flipflux/model/critical_points.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

template <class Real>
class CriticalPoints : public test::real_test<Real> {};
TYPED_TEST_SUITE(CriticalPoints, real_types, real_name);

TYPED_TEST(CriticalPoints, EgalitarianValuesOfThePaper) {
    using Real = TypeParam;
    using std::sqrt;
    const double_pendulum<Real> model;
    const auto cps = critical_points(model);
    const double tol = 8 * static_cast<double>(eps<Real>());
    const char* names[] = {"down-down", "down-up", "up-down", "up-up"};
    const int energies[] = {0, 2, 4, 6};
    for (int i = 0; i < 4; ++i) {
        EXPECT_EQ(cps[i].name, names[i]);
        EXPECT_EQ(cps[i].energy, Real(energies[i]));
        EXPECT_EQ(model.potential(cps[i].theta1, cps[i].theta2) < Real(energies[i]) + Real(tol * 8),
                  true);
    }
    EXPECT_EQ(cps[0].kind, critical_kind::minimum);
    EXPECT_EQ(cps[1].kind, critical_kind::saddle);
    EXPECT_EQ(cps[2].kind, critical_kind::saddle);
    EXPECT_EQ(cps[3].kind, critical_kind::maximum);
    const Real r2 = sqrt(Real(2));
    for (int s : {1, 2}) {
        // x = W^2 = +-sqrt(2) at both saddles
        EXPECT_LE(relative_error(cps[s].modes[0].omega_squared, r2), tol) << s;
        EXPECT_LE(relative_error(cps[s].modes[1].omega_squared, -r2), tol) << s;
        EXPECT_TRUE(cps[s].modes[0].oscillatory);
        EXPECT_FALSE(cps[s].modes[1].oscillatory);
        EXPECT_LE(relative_error(cps[s].modes[0].rate, sqrt(r2)), tol);
    }
    // centre mode at (0, pi): (1, 2 - sqrt 2); at (pi, 0): (1, 2 + sqrt 2)
    EXPECT_LE(relative_error(cps[1].modes[0].direction[1], 2 - r2), tol);
    EXPECT_LE(relative_error(cps[2].modes[0].direction[1], 2 + r2), tol);
    // minimum: x = 2 +- sqrt 2
    EXPECT_LE(relative_error(cps[0].modes[0].omega_squared, 2 + r2), tol);
    EXPECT_LE(relative_error(cps[0].modes[1].omega_squared, 2 - r2), tol);
    EXPECT_EQ(flip_saddle(model, arm::two).name, "down-up");
    EXPECT_EQ(flip_saddle(model, arm::one).name, "up-down");
}

TYPED_TEST(CriticalPoints, ClosedFormAgreesWithEigenDecomposition) {
    using Real = TypeParam;
    using std::abs;
    using std::sqrt;
    random_reals rnd(21);
    for (int trial = 0; trial < 6; ++trial) {
        physical_parameters<Real> p;
        p.m1 = Real(rnd(0.1, 4)), p.m2 = Real(rnd(0.1, 4));
        p.L1 = Real(rnd(0.2, 3)), p.L2 = Real(rnd(0.2, 3));
        p.a1 = trial % 2 ? Real(rnd(0.1, 2)) : p.L1;
        p.a2 = trial % 2 ? Real(rnd(0.1, 2)) : p.L2;
        p.I1 = trial % 2 ? Real(rnd(0, 1)) : Real(0);
        p.I2 = trial % 2 ? Real(rnd(0, 1)) : Real(0);
        p.g = Real(rnd(0.5, 10));
        const double_pendulum<Real> model(p);
        for (const auto& cp : critical_points(model)) {
            std::array<std::array<std::complex<Real>, 2>, 4> dirs;
            const auto ev = linearized_eigenvalues(model, cp.theta1, cp.theta2, &dirs);
            Real scale = 0;
            for (const auto& m : cp.modes)
                scale += abs(m.omega_squared);
            // Eigen's nonsymmetric QR: backward stable, error ~ eps * ||J||
            const double tol = 1e3 * static_cast<double>(eps<Real>());
            for (const auto& m : cp.modes) {
                // eigenvalues lambda = +-sqrt(-x): lambda^2 = -x
                int matches = 0;
                for (int i = 0; i < 4; ++i) {
                    const std::complex<Real> l2 = ev[i] * ev[i];
                    const Real d = abs(l2.real() + m.omega_squared) + abs(l2.imag());
                    if (d <= Real(tol) * scale) {
                        ++matches;
                        // eigenvector's theta part parallel to the mode direction:
                        // v2 * a1 - v1 * a2 = 0
                        const std::complex<Real> cross =
                            dirs[i][1] * m.direction[0] - dirs[i][0] * m.direction[1];
                        const Real norm = abs(dirs[i][0]) + abs(dirs[i][1]);
                        const Real dnorm = abs(m.direction[0]) + abs(m.direction[1]);
                        EXPECT_LE(static_cast<double>(abs(cross) / (norm * dnorm)), tol) << cp.name;
                    }
                }
                EXPECT_EQ(matches, 2) << cp.name << " x = " << to_decimal(m.omega_squared);
            }
            EXPECT_EQ(cp.kind == critical_kind::saddle,
                      cp.modes[0].oscillatory && !cp.modes[1].oscillatory);
        }
    }
}

}  // namespace
}  // namespace flipflux::test
