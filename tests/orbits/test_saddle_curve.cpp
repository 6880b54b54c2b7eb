// The saddle curve: the dividing-curve concept, interpolation against the orbit's own points,
// oddness, slopes against the velocity ratio, the domain against the turning points, the double
// copy, the paper's bound pi < theta2 < pi + theta1 (an erratum near E_max) and bad orbits.
#include <array>
#include <cmath>
#include <vector>

#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/orbits/saddle_curve.hpp"
#include "flipflux/orbits/saddle_frame.hpp"
#include "support.hpp"

namespace flipflux::test {
namespace {

static_assert(dividing_curve<saddle_curve<double>, double>);
static_assert(dividing_curve<saddle_curve<quad>, quad>);
static_assert(dividing_curve<saddle_curve<mp>, mp>);

template <class Real>
void check_curve(const double_pendulum<Real>& model, arm a, const Real& E) {
    using std::abs;
    orbit_options<Real> options;
    options.method = orbit_method::symmetric;
    const auto orbit = solve_saddle_orbit(model, a, E, options);
    ASSERT_NE(orbit.status, orbit_status::not_converged);
    const auto curve = make_saddle_curve(model, orbit);
    EXPECT_EQ(curve.flip_arm(), a);
    const saddle_frame<Real> frame(model, a);
    const int si = frame.s_index(), hi = frame.h_index();
    // the domain ends at the turning points
    const Real sb = orbit.quarter.back()[si];
    EXPECT_EQ(curve.domain()[1], sb);
    EXPECT_EQ(curve.domain()[0], -sb);
    EXPECT_LE(static_cast<double>(abs(orbit.turning_points[0][si] - orbit.saddle[si] - sb)),
              8 * static_cast<double>(eps<Real>()));
    const Real hb = orbit.quarter.back()[hi];
    const Real scale = sb;
    const double tol = 64 * static_cast<double>(eps<Real>());
    EXPECT_LE(static_cast<double>(abs(curve.offset(sb) - hb) / scale), tol);
    EXPECT_LE(static_cast<double>(abs(curve.offset(-sb) + hb) / scale), tol);
    EXPECT_LE(static_cast<double>(abs(curve.offset(2 * sb) - hb) / scale), tol);  // clamped
    EXPECT_EQ(curve.offset(Real(0)), 0);
    EXPECT_LE(static_cast<double>(curve.error_estimate()),
              16 * static_cast<double>(eps<Real>()) * static_cast<double>(sb));
    for (int k = 1; k < 12; ++k) {
        const Real s = sb * k / 12 + sb / 1000;
        const auto p = orbit_point_at_s(model, orbit, s);
        EXPECT_LE(static_cast<double>(abs(p[1 + si] - s) / scale), tol);
        EXPECT_LE(static_cast<double>(abs(curve.offset(s) - p[1 + hi]) / scale), tol) << k;
        EXPECT_EQ(curve.offset(-s), -curve.offset(s));
        EXPECT_EQ(curve.slope(-s), curve.slope(s));
        // slope = w_h / w_s at the point
        std::array<Real, 4> f;
        frame.rhs({p[1], p[2], p[3], p[4]}, f);
        const Real slope = f[hi] / f[si];
        EXPECT_LE(static_cast<double>(abs(curve.slope(s) - slope) / (1 + abs(slope))), 1e4 * tol)
            << k;
        // the time found is on the quarter orbit
        EXPECT_GE(p[0], 0);
        EXPECT_LE(p[0], orbit.period / 4);
    }
    const auto cd = curve.to_double();
    for (int k = 0; k <= 10; ++k) {
        const double s = static_cast<double>(sb) * (2.0 * k / 10 - 1);
        EXPECT_NEAR(cd.offset(s), static_cast<double>(curve.offset(Real(s))), 1e-15);
        EXPECT_NEAR(cd.slope(s), static_cast<double>(curve.slope(Real(s))), 1e-13);
    }
    // offset_and_slope (the flip detector's one pass) is offset and slope, bit for bit: at the
    // panels' breaks and between them, both signs, zero, the ends and beyond them (clamped)
    std::vector<Real> points{Real(0), sb, 2 * sb};
    for (const Real& b : curve.breaks())
        points.push_back(b);
    for (int k = 1; k < 40; ++k)
        points.push_back(sb * k / 40 + sb / 997);
    for (const Real& s : std::vector<Real>(points)) {
        points.push_back(-s);
        points.push_back(s * (1 + eps<Real>()));
    }
    for (const Real& s : points) {
        const std::array<Real, 2> both = curve.offset_and_slope(s);
        EXPECT_EQ(both[0], curve.offset(s)) << static_cast<double>(s);
        EXPECT_EQ(both[1], curve.slope(s)) << static_cast<double>(s);
    }
    EXPECT_EQ(cd.panels(), curve.panels());
    EXPECT_EQ(cd.degree(), curve.degree());
}

TEST(SaddleCurve, InterpolatesTheOrbitAtDouble) {
    const double_pendulum<double> model;
    check_curve(model, arm::two, 3.0);
    check_curve(model, arm::two, 5.99);
    check_curve(model, arm::one, 4.5);
    check_curve(model, arm::two, 2.00000001);
    physical_parameters<double> p;
    p.m1 = 2;
    p.L2 = 0.6;
    check_curve(double_pendulum<double>(p), arm::one, 6.0 + 1.2 * 0.5);  // E_s = 6, E_max = 7.2
}

TEST(SaddleCurve, InterpolatesTheOrbitAtQuad) {
    const double_pendulum<quad> model;
    check_curve(model, arm::two, quad(3));
}

TEST(SaddleCurve, PapersBoundFailsNearTheMaximum) {
    // paper Sec. 3.2: for theta1 > 0 the curve lies in pi < theta2 < pi + theta1. It does at
    // moderate energies; near E = 6 the orbit's turning point dips below theta2 = pi (errata).
    const double_pendulum<double> model;
    const auto moderate = make_saddle_curve(model, solve_saddle_orbit(model, arm::two, 4.0));
    for (int k = 1; k <= 100; ++k) {
        const double s = moderate.domain()[1] * k / 100;
        EXPECT_GT(moderate.offset(s), 0);
        EXPECT_LT(moderate.offset(s), s);
    }
    const auto high = solve_saddle_orbit(model, arm::two, 5.9);
    EXPECT_LT(high.turning_points[0][1], pi<double>());  // theta2 < pi at theta1 = 2.83 > 0
    const auto curve = make_saddle_curve(model, high);
    EXPECT_LT(curve.offset(curve.domain()[1]), 0);
    EXPECT_GT(curve.offset(curve.domain()[1] / 2), 0);
}

TEST(SaddleCurve, RejectsOrbitsWithoutASolutionOrNotAGraph) {
    const double_pendulum<double> model;
    saddle_orbit<double> empty;
    EXPECT_THROW(make_saddle_curve(model, empty), std::invalid_argument);
    EXPECT_THROW(orbit_point_at_s(model, empty, 0.1), std::invalid_argument);
    auto orbit = solve_saddle_orbit(model, arm::two, 3.0);
    std::swap(orbit.quarter[2], orbit.quarter[3]);  // s no longer increasing
    EXPECT_THROW(make_saddle_curve(model, orbit), std::runtime_error);
    // the ends of the root finder
    const auto good = solve_saddle_orbit(model, arm::two, 3.0);
    EXPECT_EQ(orbit_point_at_s(model, good, -1.0)[0], 0);
    EXPECT_EQ(orbit_point_at_s(model, good, 10.0)[0],
              good.quarter_step * (good.quarter.size() - 1));
}

}  // namespace
}  // namespace flipflux::test
