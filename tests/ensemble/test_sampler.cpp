// The counter-based generator and the microcanonical sampler (paper Sec. 5.3):
//   - Philox4x64-10 known-answer vectors (Random123's kat_vectors) and the keying by
//     (seed, energy, index, purpose);
//   - every sample lies on H = E; the proposal box contains the accessible region;
//   - the configuration distribution against the density sqrt(det M) Theta(E - V) integrated by
//     quadrature over a 2-D grid of bins (chi^2), for the egalitarian and a lopsided pendulum,
//     and the test's power: a sampler without the sqrt(det M) weight fails it;
//   - the momenta: <l l^T> = K M at a fixed configuration, the angle of M^-1/2 l (symmetric
//     square root, not the sampler's Cholesky factor) uniform (Kolmogorov-Smirnov), and
//     equipartition <th'_i l_j> = <K> delta_ij over the ensemble.
#include <Random123/philox.h>

#include <algorithm>
#include <boost/math/distributions/chi_squared.hpp>
#include <cmath>
#include <numbers>
#include <vector>

#include "ensemble_support.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/ensemble/random.hpp"
#include "flipflux/ensemble/sampler.hpp"
#include "flipflux/prediction/phase_volume.hpp"

namespace flipflux::test {
namespace {

constexpr double pi = std::numbers::pi;

TEST(Philox, KnownAnswerVectors) {
    r123::Philox4x64 g;
    r123::Philox4x64::ctr_type c{{0x243f6a8885a308d3ULL, 0x13198a2e03707344ULL,
                                  0xa4093822299f31d0ULL, 0x082efa98ec4e6c89ULL}};
    r123::Philox4x64::key_type k{{0x452821e638d01377ULL, 0xbe5466cf34e90c6cULL}};
    const auto r = g(c, k);
    EXPECT_EQ(r.v[0], 0xa528f45403e61d95ULL);
    EXPECT_EQ(r.v[1], 0x38c72dbd566e9788ULL);
    EXPECT_EQ(r.v[2], 0xa5a1610e72fd18b5ULL);
    EXPECT_EQ(r.v[3], 0x57bd43b5e52b7fe6ULL);
    // the stream with key (0, bits of 0.0) and counter (0, 0, 0, 0) starts with the zero vector
    philox_stream s(0, 0.0, 0);
    EXPECT_EQ(s.bits(), 0x16554d9eca36314cULL);
    EXPECT_EQ(s.bits(), 0xdb20fe9d672d0fdcULL);
    EXPECT_EQ(s.bits(), 0xd7e772cee186176bULL);
    EXPECT_EQ(s.bits(), 0x7e68b68aec7ba23bULL);
    EXPECT_EQ(s.blocks(), 1u);
}

TEST(Philox, StreamsDependOnSeedEnergyIndexAndPurposeOnly) {
    auto first = [](philox_stream s) { return s.bits(); };
    const std::uint64_t base = first(philox_stream(5, 2.5, 17));
    EXPECT_EQ(first(philox_stream(5, 2.5, 17)), base);
    EXPECT_NE(first(philox_stream(6, 2.5, 17)), base);
    EXPECT_NE(first(philox_stream(5, std::nextafter(2.5, 3.0), 17)), base);
    EXPECT_NE(first(philox_stream(5, 2.5, 18)), base);
    EXPECT_NE(first(philox_stream(5, 2.5, 17, random_purpose::tangent_vector)), base);
    // uniform() in [0, 1) with 53 random bits
    philox_stream s(1, 1.0, 0);
    std::array<int, 10> bins{};
    const int n = 100000;
    for (int i = 0; i < n; ++i) {
        const double u = s.uniform();
        ASSERT_GE(u, 0.0);
        ASSERT_LT(u, 1.0);
        ++bins[static_cast<std::size_t>(u * 10)];
    }
    double chi2 = 0;
    for (int b : bins)
        chi2 += (b - n / 10.0) * (b - n / 10.0) / (n / 10.0);
    EXPECT_LT(chi2, 27.9);  // chi^2_9 at p = 0.001
}

TEST(Sampler, RejectsNonPositiveEnergy) {
    const double_pendulum<double> m;
    EXPECT_THROW(microcanonical_sampler(m, 0.0), input_error);
    EXPECT_THROW(microcanonical_sampler(m, -1.0), input_error);
    EXPECT_THROW(microcanonical_sampler(m, std::nan("")), input_error);
}

TEST(Sampler, SamplesLieOnTheEnergySurfaceInsideTheBox) {
    random_reals rnd(3);
    for (int trial = 0; trial < 12; ++trial) {
        const double_pendulum<double> m(trial == 0 ? physical_parameters<double>{}
                                                   : random_parameters(rnd, trial % 2 == 1));
        const double E = m.maximum_energy() * rnd(0.01, 1.5);
        const microcanonical_sampler sampler(m, E);
        EXPECT_EQ(sampler.energy(), E);
        const auto box = sampler.box();
        for (std::uint64_t i = 0; i < 200; ++i) {
            const phase_point<double> x = sampler.sample(9, i);
            EXPECT_NEAR(m.hamiltonian(x), E, 16 * eps<double>() * E);
            EXPECT_LT(m.potential(x[0], x[1]), E);
            EXPECT_LE(std::abs(x[0]), box[0]);
            EXPECT_LE(std::abs(x[1]), box[1]);
            // deterministic in (seed, energy, index)
            const phase_point<double> y = sampler.sample(9, i);
            EXPECT_EQ(x, y);
        }
        // the box contains every accessible configuration: random configurations with V < E
        for (int j = 0; j < 2000; ++j) {
            const double a = rnd(-pi, pi), b = rnd(-pi, pi);
            if (m.potential(a, b) < E) {
                EXPECT_LE(std::abs(a), box[0]);
                EXPECT_LE(std::abs(b), box[1]);
            }
        }
    }
}

// Probabilities of a bins x bins grid over the proposal box under the density
// sqrt(det M) Theta(E - V), by quadrature (normalised; the total is checked against Omega).
std::vector<double> bin_probabilities(const double_pendulum<double>& m, double E, int bins) {
    const microcanonical_sampler sampler(m, E);
    const auto box = sampler.box();
    std::vector<double> prob(static_cast<std::size_t>(bins * bins));
    double total = 0;
    for (int a = 0; a < bins; ++a) {
        const double lo1 = -box[0] + 2 * box[0] * a / bins, hi1 = lo1 + 2 * box[0] / bins;
        for (int b = 0; b < bins; ++b) {
            const double lo2 = -box[1] + 2 * box[1] * b / bins, hi2 = lo2 + 2 * box[1] / bins;
            // kinks of the line integral: where the accessible th2-width is 0, pi or a bin edge
            std::vector<double> breaks;
            for (double w : {0.0, pi, std::abs(lo2), std::abs(hi2)})
                for (double t : width_breaks_th1(m, E, w))
                    breaks.push_back(t);
            const double p = integrate_with_breaks(
                [&](double t1) { return density_line_th2(m, E, t1, lo2, hi2); }, lo1, hi1, breaks);
            prob[static_cast<std::size_t>(a * bins + b)] = p;
            total += p;
        }
    }
    // the total is Omega / (2 pi): check it against the independent phase-volume quadrature
    EXPECT_NEAR(2 * pi * total, verification::phase_volume(m, E), 1e-7 * 2 * pi * total);
    for (double& p : prob)
        p /= total;
    return prob;
}

// chi^2 p-value of n configuration samples in the grid of bin_probabilities.
double configuration_p_value(const double_pendulum<double>& m, double E,
                             const std::vector<double>& prob, int bins, int n, bool weighted,
                             std::uint64_t seed) {
    const microcanonical_sampler sampler(m, E);
    const auto box = sampler.box();
    std::vector<std::uint64_t> counts(prob.size(), 0);
    for (int i = 0; i < n; ++i) {
        philox_stream rng(seed, E, static_cast<std::uint64_t>(i));
        std::array<double, 2> th;
        if (weighted) {
            th = sampler.sample_configuration(rng);
        } else {  // the wrong sampler: uniform on V < E
            do {
                th = {box[0] * (2 * rng.uniform() - 1), box[1] * (2 * rng.uniform() - 1)};
            } while (!(m.potential(th[0], th[1]) < E));
        }
        const int a = std::min(bins - 1, static_cast<int>((th[0] + box[0]) / (2 * box[0]) * bins));
        const int b = std::min(bins - 1, static_cast<int>((th[1] + box[1]) / (2 * box[1]) * bins));
        ++counts[static_cast<std::size_t>(a * bins + b)];
    }
    double chi2 = 0;
    int dof = -1;
    for (std::size_t i = 0; i < counts.size(); ++i) {
        const double expected = n * prob[i];
        if (expected < 5) {  // sparse corner bins: not in the statistic, but must stay sparse
            EXPECT_LT(counts[i], 40u);
            continue;
        }
        chi2 += (counts[i] - expected) * (counts[i] - expected) / expected;
        ++dof;
    }
    const double p = boost::math::cdf(boost::math::complement(boost::math::chi_squared(dof), chi2));
    std::printf("E = %g: chi2 = %.1f with %d dof, p = %.3g (%s)\n", E, chi2, dof, p,
                weighted ? "sampler" : "unweighted");
    return p;
}

TEST(Sampler, ConfigurationDistributionMatchesQuadrature) {
    const int bins = 8, n = 40000;
    const double_pendulum<double> egal;
    const std::vector<double> p5 = bin_probabilities(egal, 5.0, bins);
    EXPECT_GT(configuration_p_value(egal, 5.0, p5, bins, n, true, 1), 1e-3);
    // power: dropping the sqrt(det M) weight is detected at this sample size
    EXPECT_LT(configuration_p_value(egal, 5.0, p5, bins, n, false, 1), 1e-6);
    EXPECT_GT(
        configuration_p_value(egal, 2.5, bin_probabilities(egal, 2.5, bins), bins, n, true, 2),
        1e-3);
    const double_pendulum<double> lop(lopsided_parameters());
    const double E = 0.8 * lop.maximum_energy();
    EXPECT_GT(configuration_p_value(lop, E, bin_probabilities(lop, E, bins), bins, n, true, 3),
              1e-3);
}

// Kolmogorov-Smirnov tests of the sampled th1 and th2 marginals against the cumulative
// distributions of the phase-volume code (prediction/phase_volume.hpp, marginal_cdf: elliptic
// closed-form densities integrated by tanh-sinh), tabulated on 257 points and interpolated
// linearly (interpolation error < 1e-4, against a KS statistic ~1/sqrt(n) = 0.02).
TEST(Sampler, MarginalsMatchThePhaseVolumeCode) {
    struct setting {
        physical_parameters<double> p;
        double fraction;
    };
    for (const setting& c :
         {setting{physical_parameters<double>{}, 5.0 / 6},
          setting{physical_parameters<double>{}, 2.5 / 6}, setting{lopsided_parameters(), 0.8}}) {
        const double_pendulum<double> m(c.p);
        const double E = c.fraction * m.maximum_energy();
        const microcanonical_sampler sampler(m, E);
        const int n = 3000;
        std::array<std::vector<double>, 2> angles;
        for (int i = 0; i < n; ++i) {
            const phase_point<double> x = sampler.sample(21, static_cast<std::uint64_t>(i));
            angles[0].push_back(x[0]);
            angles[1].push_back(x[1]);
        }
        for (int which = 0; which < 2; ++which) {
            const double b = sampler.box()[static_cast<std::size_t>(which)];
            const int grid = 256;
            std::vector<double> cdf(grid + 1);
            for (int k = 0; k <= grid; ++k)
                cdf[static_cast<std::size_t>(k)] =
                    marginal_cdf<double>(
                        m, E,
                        which == 0 ? configuration_angle::theta1 : configuration_angle::theta2,
                        std::min(pi, -b + 2 * b * k / grid))
                        .value;
            EXPECT_NEAR(cdf.front(), 0, 1e-6);
            EXPECT_NEAR(cdf.back(), 1, 1e-6);
            auto F = [&](double x) {
                const double u = (x + b) / (2 * b) * grid;
                const int k = std::clamp(static_cast<int>(u), 0, grid - 1);
                const double f = u - k;
                return (1 - f) * cdf[static_cast<std::size_t>(k)] +
                       f * cdf[static_cast<std::size_t>(k + 1)];
            };
            auto& v = angles[static_cast<std::size_t>(which)];
            std::sort(v.begin(), v.end());
            double D = 0;
            for (int i = 0; i < n; ++i) {
                const double Fi = F(v[static_cast<std::size_t>(i)]);
                D = std::max({D, Fi - double(i) / n, double(i + 1) / n - Fi});
            }
            std::printf("E = %.4g th%d: KS sqrt(n) D = %.3f\n", E, which + 1, D * std::sqrt(n));
            EXPECT_LT(D * std::sqrt(double(n)), 1.95) << "p = 0.001";
        }
    }
}

TEST(Sampler, MomentaHaveCovarianceKMAndUniformSymmetricAngle) {
    const double_pendulum<double> m(lopsided_parameters());
    const double E = 0.7 * m.maximum_energy();
    const microcanonical_sampler sampler(m, E);
    const double th1 = 0.4, th2 = -1.1;
    const double K = E - m.potential(th1, th2);
    ASSERT_GT(K, 0);
    const sym2<double> M = m.mass_matrix(th1, th2);
    // symmetric square root of M^-1 by the 2x2 eigen-decomposition
    const sym2<double> W = m.inverse_mass_matrix(th1, th2);
    const double tr = W.xx + W.yy, dt = W.xx * W.yy - W.xy * W.xy;
    const double s = std::sqrt(dt), t = std::sqrt(tr + 2 * s);
    const sym2<double> R{(W.xx + s) / t, W.xy / t, (W.yy + s) / t};  // R^2 = M^-1
    const int n = 20000;
    double s11 = 0, s12 = 0, s22 = 0, q11 = 0, q12 = 0, q22 = 0;
    std::vector<double> angles;
    for (int i = 0; i < n; ++i) {
        philox_stream rng(4, E, static_cast<std::uint64_t>(i));
        const phase_point<double> x = sampler.with_momenta(th1, th2, 2 * pi * rng.uniform());
        const double l1 = x[2], l2 = x[3];
        EXPECT_NEAR(m.hamiltonian(x), E, 16 * eps<double>() * E);
        s11 += l1 * l1;
        s12 += l1 * l2;
        s22 += l2 * l2;
        q11 += l1 * l1 * l1 * l1;
        q12 += l1 * l1 * l2 * l2;
        q22 += l2 * l2 * l2 * l2;
        const double y1 = R.xx * l1 + R.xy * l2, y2 = R.xy * l1 + R.yy * l2;
        EXPECT_NEAR(y1 * y1 + y2 * y2, 2 * K, 1e-12 * K);
        angles.push_back((std::atan2(y2, y1) + pi) / (2 * pi));
    }
    auto check = [&](double sum, double sum_sq, double expected, const char* what) {
        const double mean = sum / n;
        const double se = std::sqrt((sum_sq / n - mean * mean) / n);
        EXPECT_LT(std::abs(mean - expected), 4 * se) << what << " " << mean << " vs " << expected;
    };
    check(s11, q11, K * M.xx, "<l1 l1>");
    check(s12, q12, K * M.xy, "<l1 l2>");
    check(s22, q22, K * M.yy, "<l2 l2>");
    // Kolmogorov-Smirnov against the uniform distribution
    std::sort(angles.begin(), angles.end());
    double D = 0;
    for (int i = 0; i < n; ++i)
        D = std::max({D, angles[i] - double(i) / n, double(i + 1) / n - angles[i]});
    EXPECT_LT(D * std::sqrt(double(n)), 1.95) << "KS statistic";  // p = 0.001
}

TEST(Sampler, EquipartitionOverTheEnsemble) {
    for (const auto& p : {physical_parameters<double>{}, lopsided_parameters()}) {
        const double_pendulum<double> m(p);
        const double E = 0.75 * m.maximum_energy();
        const microcanonical_sampler sampler(m, E);
        const int n = 20000;
        std::vector<double> k, a11, a12, a21, a22;
        for (int i = 0; i < n; ++i) {
            const phase_point<double> x = sampler.sample(11, static_cast<std::uint64_t>(i));
            const auto w = m.velocities(x);
            k.push_back(m.kinetic_energy(x));
            a11.push_back(w[0] * x[2] - k.back());
            a22.push_back(w[1] * x[3] - k.back());
            a12.push_back(w[0] * x[3]);
            a21.push_back(w[1] * x[2]);
        }
        for (const auto* v : {&a11, &a22, &a12, &a21}) {
            double s = 0, q = 0;
            for (double x : *v) {
                s += x;
                q += x * x;
            }
            const double mean = s / n, se = std::sqrt((q / n - mean * mean) / n);
            EXPECT_LT(std::abs(mean), 4 * se);
        }
    }
}

}  // namespace
}  // namespace flipflux::test
