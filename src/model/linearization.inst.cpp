// Eigen's nonsymmetric eigensolver on the 4x4 Jacobian of Hamilton's equations: the route that
// checks the closed-form normal modes of critical_points.inst.cpp. Its own translation unit
// because EigenSolver on multiprecision scalars is expensive to compile.
#include <Eigen/Eigenvalues>
#include <algorithm>

#include "flipflux/core/eigen.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/model/critical_points.hpp"

namespace flipflux {

template <class Real>
std::array<std::complex<Real>, 4> linearized_eigenvalues(
    const double_pendulum<Real>& model, const Real& th1, const Real& th2,
    std::array<std::array<std::complex<Real>, 2>, 4>* theta_directions) {
    const auto J = model.rhs_jacobian({th1, th2, Real(0), Real(0)});
    Eigen::Matrix<Real, 4, 4> m;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            m(i, j) = J[i][j];
    Eigen::EigenSolver<Eigen::Matrix<Real, 4, 4>> solver(m, theta_directions != nullptr);
    std::array<int, 4> order{0, 1, 2, 3};
    const auto ev = solver.eigenvalues();
    std::sort(order.begin(), order.end(), [&](int a, int b) {
        return ev(a).real() != ev(b).real() ? ev(a).real() < ev(b).real()
                                            : ev(a).imag() < ev(b).imag();
    });
    std::array<std::complex<Real>, 4> out;
    for (int i = 0; i < 4; ++i)
        out[i] = ev(order[i]);
    if (theta_directions != nullptr) {
        const auto vec = solver.eigenvectors();
        for (int i = 0; i < 4; ++i)
            (*theta_directions)[i] = {vec(0, order[i]), vec(1, order[i])};
    }
    return out;
}

template std::array<std::complex<inst_real>, 4> linearized_eigenvalues<inst_real>(
    const double_pendulum<inst_real>&, const inst_real&, const inst_real&,
    std::array<std::array<std::complex<inst_real>, 2>, 4>*);

}  // namespace flipflux
