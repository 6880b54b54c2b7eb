// flipflux model: the model's coefficients, critical points and normal modes as JSON;
// --equations: the Hamiltonian and Hamilton's equations with the pendulum's coefficients, as text
// and as blocks of C and Python (NumPy) to paste into a simulator (docs/validating.md).
#include <cmath>
#include <limits>

#include "common.hpp"
#include "flipflux/model/critical_points.hpp"
#include "flipflux/validation/candidate_pendulum.hpp"

namespace flipflux::cli {
namespace {

template <class Real>
json model_json(const model_options& options) {
    const double_pendulum<Real> model = make_model<Real>(options);
    json points = json::array();
    for (const auto& cp : critical_points(model)) {
        json modes = json::array();
        for (const auto& m : cp.modes) {
            modes.push_back(
                {{"omega_squared", to_decimal(m.omega_squared)},
                 {"kind", m.oscillatory ? "oscillatory" : "hyperbolic"},
                 {m.oscillatory ? "frequency" : "rate", to_decimal(m.rate)},
                 {"direction", {to_decimal(m.direction[0]), to_decimal(m.direction[1])}}});
        }
        points.push_back({{"name", cp.name},
                          {"theta1", to_decimal(cp.theta1)},
                          {"theta2", to_decimal(cp.theta2)},
                          {"energy", to_decimal(cp.energy)},
                          {"type", to_string(cp.kind)},
                          {"normal_modes", modes}});
    }
    return json{{"precision", precision_name<Real>()},
                {"model", parameters_json(model)},
                {"critical_points", points}};
}

/// A number as a floating-point literal of C and Python: every digit of the working precision,
/// with a decimal point or exponent so that neither language reads an integer.
std::string literal(const std::string& decimal) {
    if (decimal.find_first_of(".eE") == std::string::npos) return decimal + ".0";
    return decimal;
}

struct coefficient_texts {
    std::string A, B, C, alpha, beta, D0;
};

template <class Real>
coefficient_texts coefficient_texts_of(const model_options& options) {
    const double_pendulum<Real> model = make_model<Real>(options);
    const lagrangian_coefficients<Real>& k = model.coefficients();
    // the pasted blocks compute in double: each coefficient must be a normal double
    for (const auto& [name, v] :
         {std::pair{"A", &k.A}, std::pair{"B", &k.B}, std::pair{"C", &k.C},
          std::pair{"alpha", &k.alpha}, std::pair{"beta", &k.beta}, std::pair{"D0", &k.D0}}) {
        const double d = static_cast<double>(*v);
        if (!std::isfinite(d) || std::abs(d) < std::numeric_limits<double>::min())
            throw input_error("--equations: the coefficient " + std::string(name) + " = " +
                              to_decimal(*v, 6) +
                              " is outside double's range, which the printed C and Python "
                              "compute in: rescale the pendulum's units");
    }
    return {literal(to_decimal(k.A)),     literal(to_decimal(k.B)),    literal(to_decimal(k.C)),
            literal(to_decimal(k.alpha)), literal(to_decimal(k.beta)), literal(to_decimal(k.D0))};
}

std::string equations_text(const coefficient_texts& k, const std::string& pendulum,
                           const std::string& precision) {
    return "The double pendulum " + pendulum + " (coefficients in " + precision +
           ")\n"
           "Canonical variables: theta1, theta2 the angles of the links from the downward "
           "vertical (radians,\n"
           "  unwrapped); l1, l2 their conjugate momenta dL/d(theta1-dot), dL/d(theta2-dot).\n"
           "\n"
           "Coefficients (docs/theory.md, \"Any double pendulum\"):\n"
           "  A = I1 + m1 a1^2 + m2 L1^2 = " +
           k.A +
           "\n"
           "  B = I2 + m2 a2^2 = " +
           k.B +
           "\n"
           "  C = m2 L1 a2 = " +
           k.C +
           "\n"
           "  alpha = g (m1 a1 + m2 L1) = " +
           k.alpha +
           "\n"
           "  beta = g m2 a2 = " +
           k.beta +
           "\n"
           "  D0 = A B - C^2 = (I1 + m1 a1^2)(I2 + m2 a2^2) + m2 L1^2 I2 = " +
           k.D0 +
           "\n"
           "\n"
           "Hamiltonian, with c = cos(theta1 - theta2), s = sin(theta1 - theta2),\n"
           "det = A B - C^2 c^2 = D0 + C^2 s^2:\n"
           "  H = (B l1^2 - 2 C c l1 l2 + A l2^2) / (2 det) + alpha (1 - cos theta1) + beta (1 - "
           "cos theta2)\n"
           "\n"
           "Hamilton's equations:\n"
           "  d theta1/dt = w1 = (B l1 - C c l2) / det\n"
           "  d theta2/dt = w2 = (A l2 - C c l1) / det\n"
           "  d l1/dt = -C s w1 w2 - alpha sin theta1\n"
           "  d l2/dt = +C s w1 w2 - beta sin theta2\n"
           "\n"
           "Flips (the upright criterion): arm i flips when theta_i crosses an odd multiple of "
           "pi;\n"
           "  its direction is the sign of d theta_i/dt = w_i at the crossing (+1 when theta_i "
           "increases).\n"
           "  Not the slope of a crossing function such as cos(theta_i / 2): that slope changes "
           "sign\n"
           "  between theta_i = pi and 3 pi.\n";
}

std::string equations_c(const coefficient_texts& k, const std::string& pendulum) {
    return "/* The double pendulum " + pendulum +
           " (generated by\n"
           "   `flipflux model --equations --language c`; angles from the downward vertical, l1, "
           "l2 the\n"
           "   conjugate momenta dL/d(theta-dot); docs/theory.md, \"Mass matrix and "
           "Hamiltonian\") */\n"
           "#include <math.h>\n"
           "\n"
           "static const double A = " +
           k.A +
           ";\n"
           "static const double B = " +
           k.B +
           ";\n"
           "static const double C = " +
           k.C +
           ";\n"
           "static const double alpha = " +
           k.alpha +
           ";\n"
           "static const double beta = " +
           k.beta +
           ";\n"
           "static const double D0 = " +
           k.D0 +
           "; /* A B - C^2, without cancellation */\n"
           "\n"
           "static double hamiltonian(const double y[4]) {\n"
           "    const double c = cos(y[0] - y[1]), s = sin(y[0] - y[1]);\n"
           "    const double det = D0 + (C * s) * (C * s); /* A B - C^2 c^2 */\n"
           "    const double kinetic =\n"
           "        (B * y[2] * y[2] - 2 * C * c * y[2] * y[3] + A * y[3] * y[3]) / (2 * det);\n"
           "    return kinetic + alpha * (1 - cos(y[0])) + beta * (1 - cos(y[1]));\n"
           "}\n"
           "\n"
           "/* Hamilton's equations: y = (theta1, theta2, l1, l2) -> dy = dy/dt */\n"
           "static void rhs(const double y[4], double dy[4]) {\n"
           "    const double c = cos(y[0] - y[1]), s = sin(y[0] - y[1]);\n"
           "    const double det = D0 + (C * s) * (C * s);\n"
           "    const double w1 = (B * y[2] - C * c * y[3]) / det; /* theta1-dot */\n"
           "    const double w2 = (A * y[3] - C * c * y[2]) / det; /* theta2-dot */\n"
           "    const double k = C * s * w1 * w2;\n"
           "    dy[0] = w1;\n"
           "    dy[1] = w2;\n"
           "    dy[2] = -k - alpha * sin(y[0]);\n"
           "    dy[3] = k - beta * sin(y[1]);\n"
           "}\n";
}

std::string equations_python(const coefficient_texts& k, const std::string& pendulum) {
    return "# The double pendulum " + pendulum +
           " (generated by\n"
           "# `flipflux model --equations --language python`; angles from the downward vertical, "
           "l1, l2 the\n"
           "# conjugate momenta dL/d(theta-dot); docs/theory.md, \"Mass matrix and "
           "Hamiltonian\")\n"
           "import numpy as np\n"
           "\n"
           "A = " +
           k.A +
           "\n"
           "B = " +
           k.B +
           "\n"
           "C = " +
           k.C +
           "\n"
           "alpha = " +
           k.alpha +
           "\n"
           "beta = " +
           k.beta +
           "\n"
           "D0 = " +
           k.D0 +
           "  # A B - C^2, without cancellation\n"
           "\n"
           "\n"
           "def hamiltonian(theta1, theta2, l1, l2):\n"
           "    c = np.cos(theta1 - theta2)\n"
           "    det = D0 + (C * np.sin(theta1 - theta2)) ** 2  # A B - C^2 c^2\n"
           "    kinetic = (B * l1 * l1 - 2 * C * c * l1 * l2 + A * l2 * l2) / (2 * det)\n"
           "    return kinetic + alpha * (1 - np.cos(theta1)) + beta * (1 - np.cos(theta2))\n"
           "\n"
           "\n"
           "def rhs(t, y):\n"
           "    \"\"\"Hamilton's equations: y = (theta1, theta2, l1, l2) -> dy/dt.\"\"\"\n"
           "    theta1, theta2, l1, l2 = y\n"
           "    c, s = np.cos(theta1 - theta2), np.sin(theta1 - theta2)\n"
           "    det = D0 + (C * s) ** 2\n"
           "    w1 = (B * l1 - C * c * l2) / det  # theta1-dot\n"
           "    w2 = (A * l2 - C * c * l1) / det  # theta2-dot\n"
           "    k = C * s * w1 * w2\n"
           "    return np.array([w1, w2, -k - alpha * np.sin(theta1), k - beta * "
           "np.sin(theta2)])\n";
}

struct model_command_state {
    model_options model;
    precision_option precision;
    bool equations = false;
    std::string language;  ///< --language: text, c or python (empty: all three)
};

const register_command registration([](CLI::App& app) {
    auto state = std::make_shared<model_command_state>();
    CLI::App* sub = app.add_subcommand(
        "model",
        "Print the model's coefficients, critical points and normal modes as JSON; with "
        "--equations its Hamiltonian and Hamilton's equations, to copy into a simulator");
    add_model_options(*sub, state->model);
    add_precision_option(*sub, state->precision);
    sub->add_flag("--equations", state->equations,
                  "print the Hamiltonian and Hamilton's equations with this pendulum's "
                  "coefficients (every digit of --precision): as text, then as a C block and a "
                  "Python (NumPy) block ready to paste");
    sub->add_option("--language", state->language,
                    "with --equations, print only this form: text, c or python (a file to save "
                    "as it is, e.g. equations.py)");
    sub->callback([state, sub] {
        const precision p = parse_precision(state->precision.text);
        if (sub->get_option("--language")->count() > 0 && !state->equations)
            throw input_error("--language: needs --equations");
        if (state->equations) {
            const std::string& lang = state->language;
            if ((sub->get_option("--language")->count() > 0 || !lang.empty()) && lang != "text" &&
                lang != "c" && lang != "python")
                throw input_error("--language: '" + lang + "' is not text, c or python");
            const coefficient_texts k =
                dispatch(p, [&]<class Real>() { return coefficient_texts_of<Real>(state->model); });
            const std::string pendulum = parameters_text(state->model);
            if (lang == "text") return print(equations_text(k, pendulum, state->precision.text));
            if (lang == "c") return print(equations_c(k, pendulum));
            if (lang == "python") return print(equations_python(k, pendulum));
            return print(equations_text(k, pendulum, state->precision.text) + "\nC:\n\n" +
                         equations_c(k, pendulum) + "\nPython (NumPy):\n\n" +
                         equations_python(k, pendulum));
        }
        const json out = dispatch(p, [&]<class Real>() { return model_json<Real>(state->model); });
        print(out.dump(2) + "\n");
    });
});

}  // namespace
}  // namespace flipflux::cli
