// The double pendulum: parameters, potential, mass matrix, Hamiltonian, Hamilton's equations and
// their Jacobian (paper Sec. 2 and App. C, generalised to rigid links; derivation in
// docs/theory.md#model).
//
// Every double pendulum (point masses or rigid links) has, with angles measured from the downward
// vertical,
//     T = 1/2 A th1'^2 + 1/2 B th2'^2 + C cos(th1 - th2) th1' th2'
//     V = alpha (1 - cos th1) + beta (1 - cos th2),
// with, for links of mass m_i, centre-of-mass distances a_i (link 1 from the pivot, link 2 from the
// joint), moments of inertia I_i about the centres of mass and pivot-to-joint length L1,
//     A = I1 + m1 a1^2 + m2 L1^2,  B = I2 + m2 a2^2,  C = m2 L1 a2,
//     alpha = g (m1 a1 + m2 L1),   beta = g m2 a2.
// Point masses at the link ends (a1 = L1, a2 = L2, I = 0) give the paper's
// A = (m1+m2) L1^2, B = m2 L2^2, C = m2 L1 L2, alpha = (m1+m2) g L1, beta = m2 g L2.
//
// The canonical momenta are l = M(th) th' with M = [[A, C c], [C c, B]], c = cos(th1 - th2), and
//     det M = A B - C^2 c^2 = D0 + C^2 sin^2(th1 - th2),
//     D0 := A B - C^2 = (I1 + m1 a1^2)(I2 + m2 a2^2) + m2 L1^2 I2 > 0,
// written so that no cancellation occurs (NOTE: A B - C^2 evaluated directly loses all digits when
// m1 << m2). H = 1/2 l^T M^-1 l + V, and Hamilton's equations read (w = M^-1 l, s = sin(th1 - th2))
//     th1' = w1, th2' = w2,
//     l1' = -C s w1 w2 - alpha sin th1,   l2' = +C s w1 w2 - beta sin th2,
// using dH/dq|_l = -dL/dq|_q'.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/error.hpp"
#include "flipflux/core/names.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/model/energy_level.hpp"

namespace flipflux {

/// A phase-space point (th1, th2, l1, l2): angles and their canonical momenta.
template <class Real>
using phase_point = std::array<Real, 4>;

/// The two arms. Arm 2 flips over the down-up saddle (0, pi); arm 1 over the up-down saddle (pi,
/// 0).
enum class arm { one = 1, two = 2 };

/// The arms' names: "1", "2" (options, scene keys, CSV columns, JSON; to_string, parse_name).
template <>
struct enum_table<arm> {
    static constexpr std::string_view noun = "an arm";
    static constexpr std::array<std::pair<arm, std::string_view>, 2> entries{
        {{arm::one, "1"}, {arm::two, "2"}}};
};

/// The arm named `text` ("1" or "2"); nullopt for anything else.
inline std::optional<arm> arm_named(std::string_view text) {
    for (const auto& [a, name] : enum_table<arm>::entries)
        if (name == text) return a;
    return std::nullopt;
}

/// The arm numbered n (1 or 2: a scene's integers, a CSV's number); nullopt for anything else.
inline std::optional<arm> arm_numbered(double n) {
    for (const auto& [a, name] : enum_table<arm>::entries)
        if (n == static_cast<double>(static_cast<int>(a))) return a;
    return std::nullopt;
}

/// The arm's number, 1 or 2.
inline int number_of(arm a) {
    return static_cast<int>(a);
}

/// The domain of a physical parameter.
enum class parameter_domain { positive, nonnegative };

/// One physical parameter, the one place each is described: its name (the command line's
/// --NAME, a scene's key, Python's keyword, every JSON key), its domain and the rule an error
/// states, its help text, its default as decimal text, and the parameter whose value it takes
/// when not given (a1: L1, a2: L2; point masses), -1 for none. Every parser and writer of the
/// parameters (model_text.hpp, model_json.hpp, the CLI, scenes, checkpoints, golden provenance,
/// the viewer, Python, the Arb enclosures) loops over parameter_fields.
struct parameter_field {
    std::string_view name;
    parameter_domain domain;
    std::string_view rule;
    std::string_view help;
    std::string_view default_text;
    int defaults_to = -1;
};

inline constexpr std::size_t parameter_count = 9;

inline constexpr std::array<parameter_field, parameter_count> parameter_fields{{
    {"m1", parameter_domain::positive, "a mass must be > 0", "mass of link 1 (> 0)", "1", -1},
    {"m2", parameter_domain::positive, "a mass must be > 0", "mass of link 2 (> 0)", "1", -1},
    {"L1", parameter_domain::positive, "a length must be > 0",
     "pivot-to-joint length of link 1 (> 0)", "1", -1},
    {"L2", parameter_domain::positive, "a length must be > 0", "length of link 2 (> 0)", "1", -1},
    {"a1", parameter_domain::positive, "a centre-of-mass distance must be > 0",
     "pivot to link 1's centre of mass (> 0)", "", 2},
    {"a2", parameter_domain::positive, "a centre-of-mass distance must be > 0",
     "joint to link 2's centre of mass (> 0)", "", 3},
    {"I1", parameter_domain::nonnegative, "a moment of inertia must be >= 0",
     "link 1's moment of inertia about its centre of mass (>= 0)", "0", -1},
    {"I2", parameter_domain::nonnegative, "a moment of inertia must be >= 0",
     "link 2's moment of inertia about its centre of mass (>= 0)", "0", -1},
    {"g", parameter_domain::positive, "gravity must be > 0", "gravitational acceleration (> 0)",
     "1", -1},
}};

/// "m1, m2, L1, L2, a1, a2, I1, I2, g".
inline std::string parameter_name_list() {
    std::string out;
    for (const parameter_field& f : parameter_fields)
        out += (out.empty() ? "" : ", ") + std::string(f.name);
    return out;
}

/// The index of the parameter named `name` in parameter_fields; -1 for anything else.
inline int parameter_index(std::string_view name) {
    for (std::size_t i = 0; i < parameter_count; ++i)
        if (parameter_fields[i].name == name) return static_cast<int>(i);
    return -1;
}

/// Whether v satisfies the domain (v itself compared with 0 by the caller's type).
template <class Real>
bool in_domain(parameter_domain d, const Real& v) {
    return d == parameter_domain::positive ? v > 0 : v >= 0;
}

/// Physical parameters of a double pendulum made of two rigid links (defaults: the paper's
/// "egalitarian" pendulum, unit point masses on unit massless rods, g = 1; parameter_fields'
/// default texts).
template <class Real>
struct physical_parameters {
    Real m1{1};  ///< mass of link 1 (> 0)
    Real m2{1};  ///< mass of link 2 (> 0)
    Real L1{1};  ///< pivot-to-joint length of link 1 (> 0)
    Real L2{1};  ///< length of link 2 (> 0); the default of a2
    Real a1{1};  ///< pivot to the centre of mass of link 1 (> 0); point mass: a1 = L1
    Real a2{1};  ///< joint to the centre of mass of link 2 (> 0); point mass: a2 = L2
    Real I1{0};  ///< moment of inertia of link 1 about its centre of mass (>= 0)
    Real I2{0};  ///< moment of inertia of link 2 about its centre of mass (>= 0)
    Real g{1};   ///< gravitational acceleration (> 0)
};

/// The members of physical_parameters in parameter_fields' order: p.*parameter_members<Real>[i].
template <class Real>
inline constexpr std::array<Real physical_parameters<Real>::*, parameter_count> parameter_members{
    &physical_parameters<Real>::m1, &physical_parameters<Real>::m2, &physical_parameters<Real>::L1,
    &physical_parameters<Real>::L2, &physical_parameters<Real>::a1, &physical_parameters<Real>::a2,
    &physical_parameters<Real>::I1, &physical_parameters<Real>::I2, &physical_parameters<Real>::g};

/// The parameters in another real type, each converted by To's conversion from From (correctly
/// rounded between binary types; exact when To is at least as precise).
template <class To, class From>
physical_parameters<To> convert_parameters(const physical_parameters<From>& p) {
    physical_parameters<To> out;
    for (std::size_t i = 0; i < parameter_count; ++i)
        out.*parameter_members<To>[i] = static_cast<To>(p.*parameter_members<From>[i]);
    return out;
}

/// The Lagrangian's coefficients: T = A/2 th1'^2 + B/2 th2'^2 + C c th1' th2',
/// V = alpha (1 - cos th1) + beta (1 - cos th2); D0 = A B - C^2 (computed without cancellation).
template <class Real>
struct lagrangian_coefficients {
    Real A, B, C, alpha, beta, D0;
};

/// The largest magnitude of a model parameter or an energy computed with at Real:
/// 2^(max_exponent / 8) (1.8e38 in double, about 1e617 in quad), so that the products of up to
/// eight of them formed on the way (A B - C^2 is a sixth power of a length-mass scale, the rates
/// square energies) stay finite; parameters are also at least its reciprocal. MPFR's exponent
/// range is wide enough for any decimal input: no limit (infinity).
template <class Real>
Real magnitude_limit() {
    if constexpr (std::numeric_limits<Real>::max_exponent > 0 &&
                  std::numeric_limits<Real>::max_exponent < 100000) {
        using std::ldexp;
        return ldexp(Real(1), std::numeric_limits<Real>::max_exponent / 8);
    } else {
        return std::numeric_limits<Real>::infinity();
    }
}

/// Throws input_error about `field` when x != 0 and |x| lies outside [1 / magnitude_limit,
/// magnitude_limit] (see there).
template <class Real>
void check_magnitude(const Real& x, const std::string& field) {
    if constexpr (is_supported_real_v<Real>) {  // a test's own reference type: not checked
        using std::abs;
        const Real hi = magnitude_limit<Real>();
        if (x != 0 && (abs(x) > hi || abs(x) < 1 / hi))
            throw input_error::about(
                field, "'" + to_shortest_decimal(x) + "' is outside the magnitudes " +
                           to_decimal(Real(1 / hi), 3) + " .. " + to_decimal(hi, 3) + " that " +
                           precision_name<Real>() +
                           " computes with (docs/limits.md; mp:N has no such limit)");
    }
}

/// Derives the coefficients, validating the parameters (throws input_error naming the parameter).
template <class Real>
lagrangian_coefficients<Real> coefficients_of(const physical_parameters<Real>& p) {
    using boost::multiprecision::isfinite;
    using std::isfinite;
    auto require = [](const Real& v, bool ok, const std::string& name, const std::string& rule) {
        if (!isfinite(v) || !ok) {
            throw input_error::about(name,
                                     "'" + to_shortest_decimal(v) + "' is invalid (" + rule + ")");
        }
        check_magnitude(v, name);
    };
    for (std::size_t i = 0; i < parameter_count; ++i) {
        const parameter_field& f = parameter_fields[i];
        const Real& v = p.*parameter_members<Real>[i];
        require(v, in_domain(f.domain, v), std::string(f.name), std::string(f.rule));
    }
    lagrangian_coefficients<Real> k;
    const Real J1 = p.I1 + p.m1 * p.a1 * p.a1;  // link 1's moment of inertia about the pivot
    const Real J2 = p.I2 + p.m2 * p.a2 * p.a2;  // link 2's about the joint
    k.A = J1 + p.m2 * p.L1 * p.L1;
    k.B = J2;
    k.C = p.m2 * p.L1 * p.a2;
    k.alpha = p.g * (p.m1 * p.a1 + p.m2 * p.L1);
    k.beta = p.g * p.m2 * p.a2;
    k.D0 = J1 * J2 + p.m2 * p.L1 * p.L1 * p.I2;
    for (const Real* v : {&k.A, &k.B, &k.C, &k.alpha, &k.beta, &k.D0}) {
        if (!isfinite(*v) || !(*v > 0)) {
            throw input_error(
                "model: the parameters give a kinetic energy that is not positive definite or a "
                "coefficient that is not finite (A B - C^2 = " +
                to_decimal(k.D0) + ")");
        }
    }
    return k;
}

/// The extreme eigenvalues of the mass matrix over all configurations (at |cos(th1 - th2)| = 1):
/// {smallest, largest}, the smallest as D0 / largest (no cancellation when it is tiny: a link of
/// nearly zero mass).
template <class Real>
std::array<Real, 2> mass_eigenvalue_range(const lagrangian_coefficients<Real>& k) {
    using std::sqrt;
    const Real half_gap = (k.A - k.B) / 2;
    const Real largest = (k.A + k.B) / 2 + sqrt(half_gap * half_gap + k.C * k.C);
    return {k.D0 / largest, largest};
}

/// Throws input_error when the mass matrix's condition number (largest over smallest eigenvalue,
/// at the worst configuration) exceeds 1e-4 / epsilon, epsilon the working precision's: a mass or
/// inertia nearly 0 beside the others (m1 = 2e-16 beside m2 = 1 in double), whose trajectories
/// and orbits that precision cannot integrate. The one home of this refusal (ensembles,
/// trajectories, saddle orbits).
template <class Real>
void check_conditioning(const lagrangian_coefficients<Real>& k, double epsilon) {
    const std::array<Real, 2> range = mass_eigenvalue_range(k);
    const double condition = static_cast<double>(range[1] / range[0]);
    if (!(condition * epsilon <= 1e-4))
        throw input_error(
            "pendulum: the parameters give a mass matrix of condition number " +
            to_decimal(condition, 3) + " (its smallest eigenvalue " +
            to_decimal(static_cast<double>(range[0]), 3) + " beside " +
            to_decimal(static_cast<double>(range[1]), 3) +
            ": a mass or moment of inertia nearly 0 beside the others), more than 1e-4 / "
            "epsilon = " +
            to_decimal(1e-4 / epsilon, 3) +
            " of the working precision, which cannot integrate its motion (docs/limits.md)");
}

/// A 2x2 symmetric matrix [[xx, xy], [xy, yy]].
template <class Real>
struct sym2 {
    Real xx, xy, yy;
};

/// The critical energies 2 alpha, 2 beta and 2 (alpha + beta) of decimal parameters as exact
/// decimal texts (model/model_text.hpp make_model computes them).
struct critical_decimals {
    std::string saddle1, saddle2, maximum;
};

template <class Real>
class double_pendulum {
  public:
    /// The paper's egalitarian pendulum.
    double_pendulum() : double_pendulum(physical_parameters<Real>{}) {}
    /// A pendulum whose parameters are the given Reals: its critical levels are their Real values
    /// (saddle_energy, maximum_energy), with no residual.
    explicit double_pendulum(const physical_parameters<Real>& p)
        : params_(p), k_(coefficients_of(p)) {
        saddle1_ = saddle_energy(arm::one), saddle2_ = saddle_energy(arm::two);
        maximum_ = maximum_energy();
    }
    /// A pendulum of decimal parameters, p their roundings to Real and `exact` its critical
    /// energies as exact decimals: the critical levels carry them, so that the distance of a
    /// decimal energy to them is exact (model/energy_level.hpp).
    double_pendulum(const physical_parameters<Real>& p, const critical_decimals& exact)
        : double_pendulum(p) {
        const auto carry = [](energy_level<Real>& level, const std::string& text) {
            level.residual = parse_difference<Real>(text, level.value, "model");
            level.decimal = text;
        };
        carry(saddle1_, exact.saddle1), carry(saddle2_, exact.saddle2);
        carry(maximum_, exact.maximum);
    }

    const physical_parameters<Real>& parameters() const { return params_; }
    const lagrangian_coefficients<Real>& coefficients() const { return k_; }

    // ---- configuration space ----------------------------------------------------------------
    /// V(th1, th2) = 2 alpha sin^2(th1/2) + 2 beta sin^2(th2/2): zero at the minimum, accurate near
    /// it.
    Real potential(const Real& th1, const Real& th2) const {
        using std::sin;
        const Real s1 = sin(th1 / 2), s2 = sin(th2 / 2);
        return 2 * (k_.alpha * s1 * s1 + k_.beta * s2 * s2);
    }
    /// grad V = (alpha sin th1, beta sin th2).
    std::array<Real, 2> potential_gradient(const Real& th1, const Real& th2) const {
        using std::sin;
        return {k_.alpha * sin(th1), k_.beta * sin(th2)};
    }
    /// M(th) = [[A, C cos(th1-th2)], [C cos(th1-th2), B]].
    sym2<Real> mass_matrix(const Real& th1, const Real& th2) const {
        using std::cos;
        return {k_.A, k_.C * cos(th1 - th2), k_.B};
    }
    /// det M = D0 + C^2 sin^2(th1 - th2).
    Real mass_determinant(const Real& th1, const Real& th2) const {
        using std::sin;
        const Real s = sin(th1 - th2);
        return k_.D0 + k_.C * k_.C * s * s;
    }
    sym2<Real> inverse_mass_matrix(const Real& th1, const Real& th2) const {
        using std::cos;
        using std::sin;
        const Real d = th1 - th2;
        const Real c = cos(d), s = sin(d);
        const Real det = k_.D0 + k_.C * k_.C * s * s;
        return {k_.B / det, -k_.C * c / det, k_.A / det};
    }

    // ---- phase space --------------------------------------------------------------------------
    /// Angular velocities th' = M^-1 l.
    std::array<Real, 2> velocities(const phase_point<Real>& x) const {
        const sym2<Real> w = inverse_mass_matrix(x[0], x[1]);
        return {w.xx * x[2] + w.xy * x[3], w.xy * x[2] + w.yy * x[3]};
    }
    /// Canonical momenta l = M th'.
    std::array<Real, 2> momenta(const Real& th1, const Real& th2, const Real& w1,
                                const Real& w2) const {
        const sym2<Real> m = mass_matrix(th1, th2);
        return {m.xx * w1 + m.xy * w2, m.xy * w1 + m.yy * w2};
    }
    /// Kinetic energy 1/2 l^T M^-1 l.
    Real kinetic_energy(const phase_point<Real>& x) const {
        const std::array<Real, 2> w = velocities(x);
        return (w[0] * x[2] + w[1] * x[3]) / 2;
    }
    Real hamiltonian(const phase_point<Real>& x) const {
        return kinetic_energy(x) + potential(x[0], x[1]);
    }
    /// Hamilton's equations (th1', th2', l1', l2').
    phase_point<Real> rhs(const phase_point<Real>& x) const {
        using std::sin;
        const std::array<Real, 2> w = velocities(x);
        const Real P = k_.C * sin(x[0] - x[1]) * w[0] * w[1];
        return {w[0], w[1], -P - k_.alpha * sin(x[0]), P - k_.beta * sin(x[1])};
    }
    /// Jacobian d rhs / d x (row i = component i of rhs), for the variational equations.
    std::array<std::array<Real, 4>, 4> rhs_jacobian(const phase_point<Real>& x) const {
        using std::cos;
        using std::sin;
        const Real d = x[0] - x[1];
        const Real c = cos(d), s = sin(d);
        const Real det = k_.D0 + k_.C * k_.C * s * s;
        const Real i11 = k_.B / det, i12 = -k_.C * c / det, i22 = k_.A / det;
        const Real w1 = i11 * x[2] + i12 * x[3];
        const Real w2 = i12 * x[2] + i22 * x[3];
        // derivatives along d = th1 - th2 at fixed momenta
        const Real ddet = 2 * k_.C * k_.C * s * c;
        const Real dw1 = (k_.C * s * x[3] - w1 * ddet) / det;
        const Real dw2 = (k_.C * s * x[2] - w2 * ddet) / det;
        // P = C s w1 w2
        const Real dP_dd = k_.C * (c * w1 * w2 + s * (dw1 * w2 + w1 * dw2));
        const Real dP_dl1 = k_.C * s * (i11 * w2 + w1 * i12);
        const Real dP_dl2 = k_.C * s * (i12 * w2 + w1 * i22);
        std::array<std::array<Real, 4>, 4> J;
        J[0] = {dw1, -dw1, i11, i12};
        J[1] = {dw2, -dw2, i12, i22};
        J[2] = {-dP_dd - k_.alpha * cos(x[0]), dP_dd, -dP_dl1, -dP_dl2};
        J[3] = {dP_dd, -dP_dd - k_.beta * cos(x[1]), dP_dl1, dP_dl2};
        return J;
    }

    // ---- energies of the critical points ----------------------------------------------------
    /// Energy of the index-one saddle over which `a` flips: arm 2 -> (0, pi), 2 beta; arm 1 ->
    /// (pi, 0), 2 alpha.
    Real saddle_energy(arm a) const { return a == arm::two ? 2 * k_.beta : 2 * k_.alpha; }
    /// Energy of the maximum (pi, pi): 2 (alpha + beta).
    Real maximum_energy() const { return 2 * (k_.alpha + k_.beta); }
    /// The saddle's energy as a level: saddle_energy(a) and, for decimal parameters, the exact
    /// decimal (the distance of an energy to it: energy_level::above).
    const energy_level<Real>& saddle_level(arm a) const {
        return a == arm::two ? saddle2_ : saddle1_;
    }
    /// The maximum's energy as a level (likewise).
    const energy_level<Real>& maximum_level() const { return maximum_; }

  private:
    physical_parameters<Real> params_;
    lagrangian_coefficients<Real> k_;
    energy_level<Real> saddle1_, saddle2_, maximum_;
};

}  // namespace flipflux
