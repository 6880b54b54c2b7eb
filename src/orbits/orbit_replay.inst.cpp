// The replay of a stored saddle orbit (orbits/saddle_orbit.hpp, orbit_replica_problem): the
// solver's last shot and final orbit repeated at the record's (beta, T), and every derived number
// of the record checked against it. A record that fails is no orbit of this program.
#include <algorithm>
#include <limits>
#include <string>

#include "flipflux/core/budget.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"
#include "saddle_polish.hpp"

namespace flipflux {

namespace {

using namespace saddle_polish;

template <class Real>
std::string replica_problem(const double_pendulum<Real>& model, const saddle_orbit<Real>& o) {
    using std::abs;
    using std::max;
    using std::pow;
    const bool periodic = o.method == orbit_method::periodic;
    const bool taylor = o.integrator == orbit_integrator::taylor;
    const long quarter_steps = static_cast<long>(o.quarter.size()) - 1;
    // the record's own numbers decide the work: bounded as a solve would choose them
    if (quarter_steps < 1 || quarter_steps > 100000000L) return "its quarter grid is out of range";
    // (a solve picks about eps's Taylor order, or default_stages: a record asking for far more
    // work per step than that is no record of this program)
    const int most_order =
        std::min(2 * taylor_order_for(std::numeric_limits<Real>::epsilon()) + 10, max_taylor_order);
    if (taylor ? (o.order < 1 || o.order > most_order)
               : (o.stages < 1 ||
                  o.stages > std::min(4 * default_stages<Real>() + 8, max_gauss_legendre_stages)))
        return "its integrator order is out of range";
    if (!(o.period > 0) || !(o.excess > 0)) return "its period or energy is not > 0";
    const int order = taylor ? o.order : 2 * o.stages;
    const detail::shooting_setup<Real> setup(model, o.flip_arm, o.excess, taylor ? 0 : o.stages,
                                             o.integrator, order);
    orbit_options<Real> options;
    options.method = o.method;
    options.integrator = o.integrator;
    saddle_orbit<Real> r;
    r.flip_arm = o.flip_arm;
    r.excess = o.excess;
    polish<Real> p{setup, options, o.tolerance, quarter_steps, r, o.beta, o.period};
    // the solver's last shot and final orbit, replayed at the recorded (beta, T)
    const bool halves = periodic && taylor;
    const auto shot = halves ? p.shoot_periodic_by_halves(4 * quarter_steps)
                             : p.shoot(periodic, periodic ? 4 * quarter_steps : quarter_steps, 4);
    r.beta = o.beta;
    r.period = o.period;
    if (!shot || !final_orbit(setup, quarter_steps, r))
        return "its orbit cannot be integrated again";
    const auto monodromy = periodic ? p.phi : monodromy_from_quarter(p.phi);
    const floquet_multipliers<Real> floquet = floquet_analysis(monodromy);
    const Real period_slope = period_derivative(setup, p, periodic);
    // NOTE: the replay repeats the solver's arithmetic, so it agrees to the rounding of the
    // record's decimals (exact at double and quad; mp:N records N + 2 of its guard digits),
    // amplified by the multiplier in the monodromy and dT/dE; 1000 times that is allowed (and
    // never more than 1e-3: a doubled value is always found)
    const Real eps = std::numeric_limits<Real>::epsilon();
    const Real printed = pow(Real(10), Real(1 - output_digits<Real>()));
    const Real base = 1000 * max(eps, printed);
    const Real mu = max(Real(1), abs(floquet.multiplier));
    const Real cap = Real(1) / 1000;
    const Real tight = base < cap ? base : cap;
    const Real loose = base * mu < cap ? base * mu : cap;
    const auto differs = [](const Real& a, const Real& b, const Real& tol) {
        return !(abs(a - b) <= tol * max(abs(a), abs(b)));
    };
    if (differs(o.action, r.action, tight))
        return "its action F = " + to_decimal(o.action) + " is not its orbit's (" +
               to_decimal(r.action) + " by quadrature along the recorded orbit)";
    Real scale = 0, deviation = 0;
    for (std::size_t i = 0; i < o.quarter.size(); ++i)
        for (int k = 0; k < 4; ++k) {
            scale = max(scale, abs(r.quarter[i][k]));
            deviation = max(deviation, abs(o.quarter[i][k] - r.quarter[i][k]));
        }
    if (!(deviation <= tight * scale)) return "its quarter orbit is not the recorded (beta, T)'s";
    Real m_scale = 0, m_deviation = 0;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j) {
            m_scale = max(m_scale, abs(monodromy[i][j]));
            m_deviation = max(m_deviation, abs(o.monodromy[i][j] - monodromy[i][j]));
        }
    if (!(m_deviation <= loose * m_scale))
        return "its monodromy is not its orbit's (integrated again along it)";
    if (differs(o.floquet.multiplier, floquet.multiplier, loose) ||
        differs(o.floquet.stability_index, floquet.stability_index, loose) ||
        differs(o.floquet.trace, floquet.trace, loose))
        return "its multiplier " + to_decimal(o.floquet.multiplier) + " (stability index " +
               to_decimal(o.floquet.stability_index) + ") is not its monodromy's (" +
               to_decimal(floquet.multiplier) + ", " + to_decimal(floquet.stability_index) + ")";
    if (differs(o.period_derivative, period_slope, loose))
        return "its dT/dE = " + to_decimal(o.period_derivative) + " is not its orbit's (" +
               to_decimal(period_slope) + ")";
    return {};
}

}  // namespace

template <class Real>
std::string orbit_replica_problem(const double_pendulum<Real>& model, const saddle_orbit<Real>& o) {
    try {
        return replica_problem(model, o);
    } catch (const budget_exceeded&) {
        throw;
    } catch (const std::exception& e) {  // a record that makes the replay fail is no record of ours
        return std::string("its replay failed (") + e.what() + ")";
    }
}

template std::string orbit_replica_problem<inst_real>(const double_pendulum<inst_real>&,
                                                      const saddle_orbit<inst_real>&);

}  // namespace flipflux
