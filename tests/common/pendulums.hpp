// Pendulums the tests and verifications run on, written once: the prediction set (the paper's
// egalitarian one and non-egalitarian sets: unequal point masses, rigid links with moments of
// inertia, a light first link that makes the mass matrix nearly singular; every parameter exactly
// representable in binary, so all precisions see the same pendulum), the lopsided pendulum of the
// ensemble tests, and random admissible pendulums.
#pragma once

#include <string>
#include <vector>

#include "flipflux/model/double_pendulum.hpp"
#include "support.hpp"

namespace flipflux::test {

/// Random admissible parameters: point masses (inertia 0, a = L) or rigid links. The draws are
/// made in double, in a fixed order, so every Real sees the same pendulum.
template <class Real = double>
physical_parameters<Real> random_parameters(random_reals& rnd, bool rigid) {
    physical_parameters<Real> p;
    p.m1 = Real(rnd(0.2, 3));
    p.m2 = Real(rnd(0.2, 3));
    p.L1 = Real(rnd(0.3, 2));
    p.L2 = Real(rnd(0.3, 2));
    p.a1 = rigid ? Real(rnd(0.1, 1.5)) : p.L1;
    p.a2 = rigid ? Real(rnd(0.1, 1.5)) : p.L2;
    p.I1 = rigid ? Real(rnd(0, 0.5)) : Real(0);
    p.I2 = rigid ? Real(rnd(0, 0.5)) : Real(0);
    p.g = Real(rnd(0.5, 10));
    return p;
}

/// Point masses m1, m2 on massless links L1, L2 under gravity g.
inline physical_parameters<double> point_mass_parameters(double m1, double m2, double L1, double L2,
                                                         double g) {
    physical_parameters<double> p;
    p.m1 = m1;
    p.m2 = m2;
    p.L1 = p.a1 = L1;
    p.L2 = p.a2 = L2;
    p.g = g;
    return p;
}

/// Two uniform rods of lengths 1 and 0.7 (masses 1 and 0.7, centres of mass at the middles,
/// moments of inertia m L^2 / 12) under gravity g: the rigid-link pendulum of the orbit tests.
inline physical_parameters<double> uniform_rods_parameters(double g = 9.81) {
    physical_parameters<double> p;
    p.m1 = 1;
    p.m2 = 0.7;
    p.L1 = 1;
    p.L2 = 0.7;
    p.a1 = 0.5;
    p.a2 = 0.35;
    p.I1 = 1.0 / 12;
    p.I2 = 0.7 * 0.49 / 12;
    p.g = g;
    return p;
}

/// The lopsided pendulum of the ensemble tests and verifications: rigid links, unequal masses
/// and lengths, g != 1.
inline physical_parameters<double> lopsided_parameters() {
    physical_parameters<double> p;
    p.m1 = 0.7;
    p.m2 = 1.3;
    p.L1 = 0.8;
    p.L2 = 1.2;
    p.a1 = 0.5;
    p.a2 = 0.65;
    p.I1 = 0.04;
    p.I2 = 0.09;
    p.g = 1.5;
    return p;
}

struct model_spec {
    std::string name;
    const char *m1, *m2, *L1, *L2, *a1, *a2, *I1, *I2, *g;
};

inline const std::vector<model_spec>& model_specs() {
    static const std::vector<model_spec> specs{
        {"egalitarian", "1", "1", "1", "1", "1", "1", "0", "0", "1"},
        {"unequal-point-masses", "3", "0.5", "0.75", "1.25", "0.75", "1.25", "0", "0", "9.8125"},
        {"rigid-links", "2", "1", "1", "1.5", "0.5", "0.75", "0.125", "0.1875", "1"},
        {"light-first-link", "0.0078125", "1", "1", "0.5", "1", "0.5", "0", "0.015625", "1"},
    };
    return specs;
}

template <class Real>
double_pendulum<Real> make_model(const model_spec& s) {
    physical_parameters<Real> p;
    auto r = [](const char* t) { return parse_real<Real>(t, "model"); };
    p.m1 = r(s.m1);
    p.m2 = r(s.m2);
    p.L1 = r(s.L1);
    p.L2 = r(s.L2);
    p.a1 = r(s.a1);
    p.a2 = r(s.a2);
    p.I1 = r(s.I1);
    p.I2 = r(s.I2);
    p.g = r(s.g);
    return double_pendulum<Real>(p);
}

/// x converted exactly to a type of at least its precision (through 140 significant digits;
/// tests/common/support.hpp's convert keeps only the digits that round-trip, which is not exact and
/// matters where a quantity depends on E - E_s ~ 1e-12).
template <class To, class From>
To exactly(const From& x) {
    return parse_real<To>(to_decimal(x, 140), "exactly");
}

/// eps of Real times c.
template <class Real>
double tolerance(double c) {
    return c * static_cast<double>(eps<Real>());
}

/// The accuracy targets: double 1e-14, quad 1e-31, mp:N 10^-(N - 4).
template <class Real>
double target() {
    if constexpr (std::is_same_v<Real, double>)
        return 1e-14;
    else if constexpr (std::is_same_v<Real, quad>)
        return 1e-31;
    else
        return std::pow(10.0, -(active_mp_digits() - 4));
}

}  // namespace flipflux::test
