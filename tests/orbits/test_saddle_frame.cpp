// The saddle frame against the model (an independently written code path): Hamilton's equations,
// their Jacobian and the energy at absolute coordinates; small-displacement accuracy; the
// shooting set-up's circularised momentum.
#include <cmath>

#include "flipflux/core/constants.hpp"
#include "flipflux/orbits/saddle_frame.hpp"
#include "flipflux/orbits/shooting.hpp"
#include "pendulums.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

template <class Real>
class SaddleFrame : public test::real_test<Real> {};
TYPED_TEST_SUITE(SaddleFrame, real_types, real_name);

TYPED_TEST(SaddleFrame, EquationsMatchTheModelAtAbsoluteCoordinates) {
    using Real = TypeParam;
    using std::abs;
    random_reals rnd(7);
    const double tol = 256 * static_cast<double>(eps<Real>());
    for (int trial = 0; trial < 12; ++trial) {
        const double_pendulum<Real> model(random_parameters<Real>(rnd, trial % 2 == 1));
        for (arm a : {arm::one, arm::two}) {
            const saddle_frame<Real> frame(model, a);
            const std::array<Real, 4> x{Real(rnd(-2, 2)), Real(rnd(-2, 2)), Real(rnd(-3, 3)),
                                        Real(rnd(-3, 3))};
            const phase_point<Real> X = frame.absolute(x);
            std::array<Real, 4> dx;
            typename saddle_frame<Real>::matrix J;
            frame.rhs_and_jacobian(x, dx, J);
            const phase_point<Real> dX = model.rhs(X);
            const auto JX = model.rhs_jacobian(X);
            Real scale = 0, jscale = 0;
            for (int i = 0; i < 4; ++i) {
                scale = std::max(scale, Real(abs(dX[i])));
                for (int j = 0; j < 4; ++j)
                    jscale = std::max(jscale, Real(abs(JX[i][j])));
            }
            for (int i = 0; i < 4; ++i) {
                EXPECT_LE(static_cast<double>(abs(dx[i] - dX[i]) / scale), tol) << i;
                for (int j = 0; j < 4; ++j)
                    EXPECT_LE(static_cast<double>(abs(J[i][j] - JX[i][j]) / jscale), tol)
                        << i << "," << j;
            }
            // energy: E_s + excess = H; the frame's rhs returns l.w = 2 T
            const Real H = model.hamiltonian(X);
            EXPECT_LE(static_cast<double>(abs(frame.excess_energy(x) + frame.saddle_energy() - H) /
                                          (abs(H) + model.maximum_energy())),
                      tol);
            std::array<Real, 4> dummy;
            EXPECT_LE(static_cast<double>(abs(frame.rhs(x, dummy) - 2 * model.kinetic_energy(X)) /
                                          (1 + 2 * model.kinetic_energy(X))),
                      tol);
        }
    }
}

TYPED_TEST(SaddleFrame, SmallDisplacementsKeepRelativeAccuracy) {
    using Real = TypeParam;
    using std::abs;
    // at displacements of 1e-6 the excess energy is 1e-12: it must agree with the quadratic form
    // 1/2 (l^T M*^-1 l + delta^T K delta), K = diag(e1 alpha, e2 beta), to a relative O(1e-12)
    // (the quartic terms), not lose the digits that H - E_s would
    const double_pendulum<Real> model;
    const Real d = Real(1) / 1000000;
    for (arm a : {arm::one, arm::two}) {
        const saddle_frame<Real> frame(model, a);
        const auto& k = frame.coefficients();
        const std::array<Real, 4> x{3 * d, -2 * d, 5 * d, 7 * d};
        const Real kin = (k.B * x[2] * x[2] + 2 * k.C * x[2] * x[3] + k.A * x[3] * x[3]) / k.D0 / 2;
        const Real pot =
            (frame.e1() * k.alpha * x[0] * x[0] + frame.e2() * k.beta * x[1] * x[1]) / 2;
        const Real exact = kin + pot;
        EXPECT_LE(static_cast<double>(abs(frame.excess_energy(x) - exact) / abs(exact)), 1e-10);
    }
}

TYPED_TEST(SaddleFrame, CircularisedMomentumHasTheRequestedEnergy) {
    using Real = TypeParam;
    using std::abs;
    random_reals rnd(3);
    for (int trial = 0; trial < 6; ++trial) {
        const double_pendulum<Real> model(random_parameters<Real>(rnd, trial % 2 == 0));
        const arm a = trial % 3 == 0 ? arm::one : arm::two;
        const Real excess = Real(rnd(1e-9, 2));
        const detail::shooting_setup<Real> setup(model, a, excess, 2);
        // S^2 = M*
        const auto& S = setup.root_mass;
        const auto M = setup.frame.saddle_mass_matrix();
        const double tol = 64 * static_cast<double>(eps<Real>());
        EXPECT_LE(static_cast<double>(abs(S.xx * S.xx + S.xy * S.xy - M.xx) / M.xx), tol);
        EXPECT_LE(static_cast<double>(abs(S.xx * S.xy + S.xy * S.yy - M.xy) / M.xx), tol);
        EXPECT_LE(static_cast<double>(abs(S.xy * S.xy + S.yy * S.yy - M.yy) / M.yy), tol);
        for (int k = 0; k < 5; ++k) {
            const Real beta = Real(rnd(-3.1, 3.1));
            const auto x0 = setup.start(beta);
            EXPECT_LE(static_cast<double>(abs(setup.frame.excess_energy(x0) - excess) / excess),
                      tol);
            EXPECT_LE(static_cast<double>(abs(setup.direction_of({x0[2], x0[3]}) - beta)), tol);
            // the derivative by central differences
            const Real h = Real(1) / 100000;
            const auto p = setup.momentum(beta + h), m = setup.momentum(beta - h);
            const auto dl = setup.momentum_derivative(beta);
            for (int i = 0; i < 2; ++i)
                EXPECT_LE(static_cast<double>(abs((p[i] - m[i]) / (2 * h) - dl[i]) /
                                              setup.momentum_scale),
                          1e-9);
        }
    }
}

}  // namespace
}  // namespace flipflux::test
