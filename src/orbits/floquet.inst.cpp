// Floquet multipliers of a periodic orbit from its 4x4 monodromy matrix M.
//
// For a periodic orbit of an autonomous 2-degree-of-freedom Hamiltonian system, M is symplectic
// with eigenvalues {1, 1, mu, 1/mu} (the unit pair from the flow direction and the energy; a
// Jordan block in general, so its computed eigenvalues scatter like sqrt(eps |M|)). Two routes:
//   - Eigen's EigenSolver in Real (core/eigensystem.hpp);
//   - the trace: mu + 1/mu = tr M - 2 =: k, insensitive to the Jordan block. |k| > 2: hyperbolic,
//     mu = (k + sign(k) sqrt(k^2 - 4)) / 2 (the stable root); |k| <= 2: elliptic, nu = acos(k / 2).
// The reported multiplier and angle come from the trace; the eigenvalues are kept as the check.
#include <algorithm>

#include "flipflux/core/eigensystem.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/orbits/saddle_orbit.hpp"

namespace flipflux {

template <class Real>
floquet_multipliers<Real> floquet_analysis(const std::array<std::array<Real, 4>, 4>& monodromy) {
    using std::abs;
    using std::acos;
    using std::sqrt;
    floquet_multipliers<Real> f;
    const eigensystem4<Real> e = eigensystem(monodromy, false);
    f.eigenvalues = e.values;
    std::sort(
        f.eigenvalues.begin(), f.eigenvalues.end(),
        [](const std::complex<Real>& a, const std::complex<Real>& b) { return abs(a) < abs(b); });
    // the two eigenvalues nearest 1
    std::array<Real, 4> dist;
    for (int i = 0; i < 4; ++i)
        dist[i] = abs(f.eigenvalues[i] - std::complex<Real>(1));
    std::array<int, 4> idx{0, 1, 2, 3};
    std::sort(idx.begin(), idx.end(), [&](int a, int b) { return dist[a] < dist[b]; });
    f.unit_deviation = std::max(dist[idx[0]], dist[idx[1]]);
    f.determinant_deviation = abs(e.determinant - 1);
    f.trace =
        (monodromy[0][0] + monodromy[1][1]) + (monodromy[2][2] + monodromy[3][3]);  // as Eigen sums
    f.stability_index = f.trace - 2;
    const Real& k = f.stability_index;
    if (abs(k) > 2) {
        f.hyperbolic = true;
        const Real root = sqrt((k - 2) * (k + 2));
        f.multiplier = (k > 0 ? k + root : k - root) / 2;
        f.angle = 0;
    } else {
        f.hyperbolic = false;
        f.multiplier = 1;
        f.angle = acos(k / 2);
    }
    return f;
}

template floquet_multipliers<inst_real> floquet_analysis<inst_real>(
    const std::array<std::array<inst_real, 4>, 4>&);

}  // namespace flipflux
