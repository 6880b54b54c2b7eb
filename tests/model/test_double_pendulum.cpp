// The model against independent routes: the mass matrix and potential from the rigid-body
// kinetic energy and centre-of-mass heights (not from the coefficient formulas), Hamilton's
// equations and their Jacobian against finite differences computed in 120 digits.
#include <cmath>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "pendulums.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

template <class Real>
class Model : public test::real_test<Real> {};
TYPED_TEST_SUITE(Model, real_types, real_name);

/// Kinetic energy of the two links from their centre-of-mass velocities and spins.
template <class Real>
Real rigid_body_kinetic(const physical_parameters<Real>& p, const Real& t1, const Real& t2,
                        const Real& w1, const Real& w2) {
    using std::cos;
    using std::sin;
    const Real v1x = p.a1 * w1 * cos(t1), v1y = p.a1 * w1 * sin(t1);
    const Real v2x = p.L1 * w1 * cos(t1) + p.a2 * w2 * cos(t2);
    const Real v2y = p.L1 * w1 * sin(t1) + p.a2 * w2 * sin(t2);
    return (p.m1 * (v1x * v1x + v1y * v1y) + p.I1 * w1 * w1 + p.m2 * (v2x * v2x + v2y * v2y) +
            p.I2 * w2 * w2) /
           2;
}

/// Potential from the centre-of-mass heights, shifted to zero at the hanging equilibrium.
template <class Real>
Real rigid_body_potential(const physical_parameters<Real>& p, const Real& t1, const Real& t2) {
    using std::cos;
    const Real y1 = -p.a1 * cos(t1), y2 = -p.L1 * cos(t1) - p.a2 * cos(t2);
    const Real y1min = -p.a1, y2min = -p.L1 - p.a2;
    return p.g * (p.m1 * (y1 - y1min) + p.m2 * (y2 - y2min));
}

TYPED_TEST(Model, MassMatrixAndPotentialMatchTheRigidBodyLagrangian) {
    using Real = TypeParam;
    random_reals rnd(11);
    for (int trial = 0; trial < 20; ++trial) {
        const auto p = random_parameters<Real>(rnd, trial % 2 == 1);
        const double_pendulum<Real> model(p);
        const Real t1 = Real(rnd(-7, 7)), t2 = Real(rnd(-7, 7));
        // polarisation: T(e_i) = M_ii / 2, T(e1 + e2) - T(e1) - T(e2) = M_12
        const Real T1 = rigid_body_kinetic(p, t1, t2, Real(1), Real(0));
        const Real T2 = rigid_body_kinetic(p, t1, t2, Real(0), Real(1));
        const Real T12 = rigid_body_kinetic(p, t1, t2, Real(1), Real(1));
        const auto M = model.mass_matrix(t1, t2);
        const double tol = 64 * static_cast<double>(eps<Real>());
        EXPECT_LE(relative_error(M.xx, 2 * T1), tol);
        EXPECT_LE(relative_error(M.yy, 2 * T2), tol);
        using std::abs;
        EXPECT_LE(static_cast<double>(abs(M.xy - (T12 - T1 - T2)) / (abs(M.xx) + abs(M.yy))), tol);
        const Real det = M.xx * M.yy - M.xy * M.xy;
        EXPECT_LE(static_cast<double>(abs(model.mass_determinant(t1, t2) - det) / (M.xx * M.yy)),
                  tol);
        const Real V = rigid_body_potential(p, t1, t2);
        EXPECT_LE(static_cast<double>(abs(model.potential(t1, t2) - V) / (model.maximum_energy())),
                  tol);
        // H(th, M w) = T + V
        const Real w1 = Real(rnd(-2, 2)), w2 = Real(rnd(-2, 2));
        const auto l = model.momenta(t1, t2, w1, w2);
        const phase_point<Real> x{t1, t2, l[0], l[1]};
        EXPECT_LE(relative_error(model.hamiltonian(x), rigid_body_kinetic(p, t1, t2, w1, w2) + V),
                  tol);
        const auto w = model.velocities(x);
        EXPECT_LE(static_cast<double>(abs(w[0] - w1) + abs(w[1] - w2)), tol * 16);
    }
}

TYPED_TEST(Model, PointMassCoefficientsAreThePapers) {
    using Real = TypeParam;
    physical_parameters<Real> p;
    p.m1 = Real(3) / 2;
    p.m2 = Real(7) / 10;
    p.L1 = Real(13) / 10;
    p.L2 = p.a2 = Real(9) / 10;
    p.a1 = p.L1;
    p.g = Real(981) / 100;
    const auto k = double_pendulum<Real>(p).coefficients();
    const double tol = 4 * static_cast<double>(eps<Real>());
    EXPECT_LE(relative_error(k.A, (p.m1 + p.m2) * p.L1 * p.L1), tol);
    EXPECT_LE(relative_error(k.B, p.m2 * p.L2 * p.L2), tol);
    EXPECT_LE(relative_error(k.C, p.m2 * p.L1 * p.L2), tol);
    EXPECT_LE(relative_error(k.alpha, (p.m1 + p.m2) * p.g * p.L1), tol);
    EXPECT_LE(relative_error(k.beta, p.m2 * p.g * p.L2), tol);
    // D0 = A B - C^2 = m1 m2 L1^2 L2^2 for point masses
    EXPECT_LE(relative_error(k.D0, p.m1 * p.m2 * p.L1 * p.L1 * p.L2 * p.L2), tol);
}

TYPED_TEST(Model, DeterminantHasNoCancellationForALightFirstMass) {
    using Real = TypeParam;
    physical_parameters<Real> p;
    p.m1 = Real(1) / Real(1000000000) / 1000000000;  // 1e-18: A B - C^2 would cancel to 0 in double
    const double_pendulum<Real> model(p);
    EXPECT_LE(relative_error(model.coefficients().D0, p.m1), 4 * static_cast<double>(eps<Real>()));
    EXPECT_GT(model.mass_determinant(Real(0), Real(0)), 0);
}

TYPED_TEST(Model, EgalitarianPotentialAndHamiltonian) {
    using Real = TypeParam;
    using std::cos;
    const double_pendulum<Real> model;
    random_reals rnd(3);
    const double tol = 16 * static_cast<double>(eps<Real>());
    for (int i = 0; i < 20; ++i) {
        const Real t1 = Real(rnd(-4, 4)), t2 = Real(rnd(-4, 4));
        const Real l1 = Real(rnd(-3, 3)), l2 = Real(rnd(-3, 3));
        using std::abs;
        EXPECT_LE(static_cast<double>(abs(model.potential(t1, t2) - (3 - 2 * cos(t1) - cos(t2)))),
                  tol * 8);
        const Real c = cos(t1 - t2);
        const Real H = (l1 * l1 - 2 * c * l1 * l2 + 2 * l2 * l2) / (2 * (2 - c * c)) + 3 -
                       2 * cos(t1) - cos(t2);  // the paper's eq. (egalitarian Hamiltonian)
        EXPECT_LE(relative_error(model.hamiltonian({t1, t2, l1, l2}), H), tol * 8);
    }
}

/// Central finite differences in 120 digits with h = 1e-30: truncation ~1e-60, rounding ~1e-70.
/// Tolerances against them are therefore floored at fd_floor.
constexpr double fd_floor = 1e-55;
template <class F>
std::array<reference_real, 4> fd_gradient(F&& f, const phase_point<reference_real>& x) {
    const reference_real h = reference_real("1e-30");
    std::array<reference_real, 4> g;
    for (int i = 0; i < 4; ++i) {
        auto xp = x, xm = x;
        xp[i] += h;
        xm[i] -= h;
        g[i] = (f(xp) - f(xm)) / (2 * h);
    }
    return g;
}

TYPED_TEST(Model, HamiltonsEquationsMatchFiniteDifferencesOfH) {
    using Real = TypeParam;
    random_reals rnd(5);
    for (int trial = 0; trial < 10; ++trial) {
        const auto p_ref = random_parameters<reference_real>(rnd, trial % 2 == 0);
        physical_parameters<Real> p;
        p.m1 = convert<Real>(p_ref.m1), p.m2 = convert<Real>(p_ref.m2);
        p.L1 = convert<Real>(p_ref.L1), p.L2 = convert<Real>(p_ref.L2);
        p.a1 = convert<Real>(p_ref.a1), p.a2 = convert<Real>(p_ref.a2);
        p.I1 = convert<Real>(p_ref.I1), p.I2 = convert<Real>(p_ref.I2);
        p.g = convert<Real>(p_ref.g);
        const double_pendulum<reference_real> ref(p_ref);
        const double_pendulum<Real> model(p);
        const phase_point<reference_real> x{reference_real(rnd(-7, 7)), reference_real(rnd(-7, 7)),
                                            reference_real(rnd(-4, 4)), reference_real(rnd(-4, 4))};
        const auto g = fd_gradient(
            [&](const phase_point<reference_real>& y) { return ref.hamiltonian(y); }, x);
        const phase_point<Real> xr{convert<Real>(x[0]), convert<Real>(x[1]), convert<Real>(x[2]),
                                   convert<Real>(x[3])};
        const auto f = model.rhs(xr);
        const std::array<reference_real, 4> expected{g[2], g[3], -g[0], -g[1]};
        reference_real scale = 0;
        for (const auto& v : expected)
            scale += abs(v);
        for (int i = 0; i < 4; ++i) {
            EXPECT_LE(static_cast<double>(abs(to_reference(f[i]) - expected[i]) / scale),
                      std::max(fd_floor, 64 * static_cast<double>(eps<Real>())))
                << "component " << i;
        }
        // dH/dt = grad H . f vanishes to rounding: the gradient here is independent of rhs()
        reference_real dHdt = 0, norm = 0;
        for (int i = 0; i < 4; ++i) {
            dHdt += g[i] * to_reference(f[i]);
            norm += abs(g[i] * to_reference(f[i]));
        }
        EXPECT_LE(static_cast<double>(abs(dHdt) / norm),
                  std::max(fd_floor, 64 * static_cast<double>(eps<Real>())));
        // Jacobian of rhs against finite differences of rhs (in reference_real)
        const auto J = model.rhs_jacobian(xr);
        for (int i = 0; i < 4; ++i) {
            const auto gi =
                fd_gradient([&](const phase_point<reference_real>& y) { return ref.rhs(y)[i]; }, x);
            reference_real row_scale = 1;
            for (const auto& v : gi)
                row_scale += abs(v);
            for (int j = 0; j < 4; ++j) {
                EXPECT_LE(static_cast<double>(abs(to_reference(J[i][j]) - gi[j]) / row_scale),
                          std::max(fd_floor, 256 * static_cast<double>(eps<Real>())))
                    << "J[" << i << "][" << j << "]";
            }
        }
    }
}

TYPED_TEST(Model, TimeReversalAndReflectionSymmetries) {
    using Real = TypeParam;
    const double_pendulum<Real> model;
    random_reals rnd(9);
    for (int i = 0; i < 20; ++i) {
        const phase_point<Real> x{Real(rnd(-4, 4)), Real(rnd(-4, 4)), Real(rnd(-3, 3)),
                                  Real(rnd(-3, 3))};
        const phase_point<Real> reversed{x[0], x[1], -x[2], -x[3]};
        const phase_point<Real> reflected{-x[0], -x[1], -x[2], -x[3]};
        EXPECT_EQ(model.hamiltonian(reversed), model.hamiltonian(x));
        EXPECT_EQ(model.hamiltonian(reflected), model.hamiltonian(x));
        const auto f = model.rhs(x), fr = model.rhs(reversed), fp = model.rhs(reflected);
        // T: (th, l)(t) -> (th, -l)(-t): th' flips, l' is unchanged
        EXPECT_EQ(fr[0], -f[0]);
        EXPECT_EQ(fr[1], -f[1]);
        EXPECT_EQ(fr[2], f[2]);
        EXPECT_EQ(fr[3], f[3]);
        // P: x -> -x maps the vector field to its negative
        for (int k = 0; k < 4; ++k)
            EXPECT_EQ(fp[k], -f[k]);
    }
}

TYPED_TEST(Model, RefusesInadmissibleParameters) {
    using Real = TypeParam;
    const auto refused = [](auto mutate, const char* name) {
        physical_parameters<Real> p;
        mutate(p);
        try {
            double_pendulum<Real> m(p);
            ADD_FAILURE() << name << " accepted";
        } catch (const input_error& e) {
            EXPECT_EQ(e.field(), name) << e.what();
        }
    };
    refused([](auto& p) { p.m1 = 0; }, "m1");
    refused([](auto& p) { p.m2 = -1; }, "m2");
    refused([](auto& p) { p.L1 = 0; }, "L1");
    refused([](auto& p) { p.L2 = -2; }, "L2");
    refused([](auto& p) { p.a1 = 0; }, "a1");
    refused([](auto& p) { p.a2 = -1; }, "a2");
    refused([](auto& p) { p.I1 = -1; }, "I1");
    refused([](auto& p) { p.I2 = -1; }, "I2");
    refused([](auto& p) { p.g = 0; }, "g");
    refused([](auto& p) { p.g = std::numeric_limits<Real>::quiet_NaN(); }, "g");
    refused([](auto& p) { p.m1 = std::numeric_limits<Real>::infinity(); }, "m1");
}

// The sign of an energy is the exact decimal's; an input that underflows double or quad is refused
// by parse_real itself (issue 45: one grammar, "'1e-999999' underflows double", LimitsCommand
// tests), MPFR's exponent range holds it; an energy computed in Real has only its value.
TYPED_TEST(Model, AnEnergyIsPositiveWhenItsExactDecimalIs) {
    using Real = TypeParam;
    if constexpr (has_variable_precision_v<Real>) {
        const energy_level<Real> tiny = parse_energy_level<Real>("1e-999999", "E");
        EXPECT_TRUE(tiny.positive());
        EXPECT_GT(tiny.value, 0);
        EXPECT_FALSE(parse_energy_level<Real>("-1e-999999", "E").positive());
    } else {
        EXPECT_THROW((void)parse_energy_level<Real>("1e-999999", "E"), input_error);
        EXPECT_THROW((void)parse_energy_level<Real>("-1e-999999", "E"), input_error);
    }
    EXPECT_FALSE(parse_energy_level<Real>("0.000e5", "E").positive());
    EXPECT_TRUE(parse_energy_level<Real>("2.5", "E").positive());
    EXPECT_TRUE(energy_level<Real>(Real(3)).positive());
    EXPECT_FALSE(energy_level<Real>(Real(-3)).positive());
    EXPECT_FALSE(energy_level<Real>(Real(0)).positive());
}

}  // namespace
}  // namespace flipflux::test
