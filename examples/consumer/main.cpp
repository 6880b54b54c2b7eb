// A consumer of the installed library: the phase volume Omega(E) and the saddle orbit's period T(E)
// of the paper's egalitarian pendulum in quad (113-bit float128), through the public headers only.
// Prints "name value" lines (all digits of the type), read by tests/install/test_install.py.
#include <flipflux/core/decimal.hpp>
#include <flipflux/model/double_pendulum.hpp>
#include <flipflux/orbits/saddle_orbit.hpp>
#include <flipflux/prediction/phase_volume.hpp>
#include <iostream>

template <class Real>
void print_quantities(const char* type) {
    using namespace flipflux;
    const double_pendulum<Real> model;  // m1 = m2 = L1 = L2 = g = 1, point masses
    // above E_max = 6 the whole torus is allowed: Omega = 16 pi^2 sqrt(D0) E(-C^2/D0)
    for (const char* energy : {"3", "10"}) {
        const Real E = parse_real<Real>(energy, "energy");
        std::cout << "omega_" << type << "_" << energy << " "
                  << to_decimal(phase_volume(model, E).value) << "\n";
    }
    const saddle_orbit<Real> orbit =
        solve_saddle_orbit(model, arm::two, parse_real<Real>("3", "E"));
    std::cout << "period_" << type << "_3 " << to_decimal(orbit.period) << "\n";
}

int main() {
    print_quantities<double>("double");
    print_quantities<flipflux::quad>("quad");
}
