// Eigenvalues and eigenvectors of a real 4x4 matrix, by Eigen's EigenSolver in Real.
//
// The one place the nonsymmetric eigensolver is instantiated: it is the most expensive template
// of the build to compile (tens of seconds per real type in CI's instrumented build), and two
// routes need it, the normal modes at a critical point (model/critical_points.hpp,
// linearized_eigenvalues) and the Floquet multipliers of a saddle orbit
// (orbits/saddle_orbit.hpp, floquet_analysis). This header does not include Eigen.
#pragma once

#include <array>
#include <complex>

#include "flipflux/core/real.hpp"

namespace flipflux {

/// A 4x4 real matrix, row by row.
template <class Real>
using matrix4 = std::array<std::array<Real, 4>, 4>;

/// Eigen's EigenSolver's result, in its own order (no sorting), and the matrix's determinant
/// (Eigen's closed form for 4x4, independent of the decomposition).
template <class Real>
struct eigensystem4 {
    std::array<std::complex<Real>, 4> values;
    Real determinant{0};
    /// vectors[k] is the eigenvector of values[k] (Eigen's normalisation: unit 2-norm); filled only
    /// when asked for.
    std::array<std::array<std::complex<Real>, 4>, 4> vectors{};
};

/// The eigenvalues of `m`, and its eigenvectors when `with_vectors`.
template <class Real>
eigensystem4<Real> eigensystem(const matrix4<Real>& m, bool with_vectors);

#define FLIPFLUX_EIGENSYSTEM_EXTERN(R) \
    extern template eigensystem4<R> eigensystem<R>(const matrix4<R>&, bool);
FLIPFLUX_FOR_EACH_REAL(FLIPFLUX_EIGENSYSTEM_EXTERN)
#undef FLIPFLUX_EIGENSYSTEM_EXTERN

}  // namespace flipflux
