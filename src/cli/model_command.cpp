// flipflux model: the model's coefficients, critical points and normal modes as JSON.
#include "common.hpp"
#include "flipflux/model/critical_points.hpp"

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

struct model_command_state {
    model_options model;
    precision_option precision;
};

const register_command registration([](CLI::App& app) {
    auto state = std::make_shared<model_command_state>();
    CLI::App* sub = app.add_subcommand(
        "model", "Print the model's coefficients, critical points and normal modes as JSON");
    add_model_options(*sub, state->model);
    add_precision_option(*sub, state->precision);
    sub->callback([state] {
        const precision p = parse_precision(state->precision.text);
        const json out = dispatch(p, [&]<class Real>() { return model_json<Real>(state->model); });
        print(out.dump(2) + "\n");
    });
});

}  // namespace
}  // namespace flipflux::cli
