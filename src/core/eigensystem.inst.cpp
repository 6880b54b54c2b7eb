// Eigen's nonsymmetric eigensolver on a 4x4 real matrix (core/eigensystem.hpp): its only
// instantiation, one translation unit per real type.
#include "flipflux/core/eigensystem.hpp"

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "flipflux/core/eigen.hpp"
#include "flipflux/core/instantiate.hpp"

namespace flipflux {

template <class Real>
eigensystem4<Real> eigensystem(const matrix4<Real>& m, bool with_vectors) {
    using matrix = Eigen::Matrix<Real, 4, 4>;
    matrix a;
    for (int i = 0; i < 4; ++i)
        for (int j = 0; j < 4; ++j)
            a(i, j) = m[i][j];
    const Eigen::EigenSolver<matrix> solver(a, with_vectors);
    eigensystem4<Real> out;
    const auto values = solver.eigenvalues();
    for (int k = 0; k < 4; ++k)
        out.values[k] = values(k);
    out.determinant = a.determinant();
    if (with_vectors) {
        const auto vectors = solver.eigenvectors();
        for (int k = 0; k < 4; ++k)
            for (int i = 0; i < 4; ++i)
                out.vectors[k][i] = vectors(i, k);
    }
    return out;
}

template eigensystem4<inst_real> eigensystem<inst_real>(const matrix4<inst_real>&, bool);

}  // namespace flipflux
