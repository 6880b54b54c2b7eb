// The saddle-orbit viewer's data in Real (include/flipflux/study/saddle_viewer.hpp): each arm's
// family from the memo or one continuation, each orbit's path at equal times, the potential grid.
#include <nlohmann/json.hpp>
#include <string>

#include "flipflux/core/constants.hpp"
#include "flipflux/core/convert.hpp"
#include "flipflux/core/decimal.hpp"
#include "flipflux/core/instantiate.hpp"
#include "flipflux/orbits/orbit_store.hpp"
#include "flipflux/study/saddle_viewer.hpp"

namespace flipflux {
namespace {

template <class Real>
viewer_orbit<Real> make_viewer_orbit(const double_pendulum<Real>& model,
                                     const saddle_orbit<Real>& o, const std::string& energy,
                                     int samples) {
    viewer_orbit<Real> v;
    v.energy = energy;
    v.period = o.period;
    v.action = o.action;
    v.stability_index = o.floquet.stability_index;
    v.hyperbolic = o.floquet.hyperbolic;
    v.multiplier = o.floquet.multiplier;
    v.angle = o.floquet.angle;
    v.error_estimate_period = o.error_estimate_period;
    v.error_estimate_action = o.error_estimate_action;
    v.status = o.status;
    v.path.reserve(static_cast<std::size_t>(samples));
    for (int k = 0; k < samples; ++k) {
        // the last point at t = T itself: the path closes only if the orbit does
        const Real t = o.period * Real(k) / Real(samples - 1);
        const phase_point<Real> x = orbit_state(model, o, t);
        v.path.push_back({x[0], x[1]});
    }
    return v;
}

template <class Real>
viewer_family<Real> family_data(const double_pendulum<Real>& model, arm a,
                                const viewer_request& request, const orbit_options<Real>& options,
                                std::size_t& solved) {
    viewer_family<Real> fam;
    fam.flip_arm = a;
    fam.saddle_energy = model.saddle_energy(a);
    fam.saddle = a == arm::two ? std::array<Real, 2>{Real(0), pi<Real>()}
                               : std::array<Real, 2>{pi<Real>(), Real(0)};
    const double_pendulum<double> model_double(convert_parameters<double>(model.parameters()));
    const std::vector<std::string> texts = viewer_energy_texts(model_double, a, request.energies);
    std::vector<energy_level<Real>> levels, missing;
    for (const std::string& text : texts) {
        levels.push_back(parse_energy_level<Real>(text, "energy"));
        if (!recall_saddle_orbit(model, a, levels.back(), options.method, options.integrator))
            missing.push_back(levels.back());
    }
    if (!missing.empty()) {
        const saddle_family<Real> f = continue_saddle_family(model, a, missing, options);
        solved += f.orbits.size();
        for (const saddle_orbit<Real>& o : f.orbits)
            if (o.status != orbit_status::not_converged) remember_saddle_orbit(model, o);
        fam.stop_reason = f.stop_reason;
    }
    for (std::size_t i = 0; i < levels.size(); ++i) {
        const auto o = recall_saddle_orbit(model, a, levels[i], options.method, options.integrator);
        if (o && o->status != orbit_status::not_converged)
            fam.orbits.push_back(make_viewer_orbit(model, *o, texts[i], request.samples));
        else if (fam.stop_reason.empty())
            fam.stop_reason = "no converged orbit at E = " + texts[i];
    }
    return fam;
}

std::string json_string(const std::string& text) {
    return nlohmann::json(text).dump();
}

template <class Real>
std::string json_numbers(const std::vector<std::array<Real, 2>>& path, std::size_t which) {
    std::string s = "[";
    for (std::size_t k = 0; k < path.size(); ++k)
        s += (k ? "," : "") + to_decimal(path[k][which]);
    return s + "]";
}

template <class Real>
std::string orbit_json(const viewer_orbit<Real>& o) {
    return "{\"energy\":" + o.energy + ",\"period\":" + to_decimal(o.period) +
           ",\"action\":" + to_decimal(o.action) +
           ",\"stability_index\":" + to_decimal(o.stability_index) +
           ",\"hyperbolic\":" + (o.hyperbolic ? "true" : "false") +
           ",\"multiplier\":" + to_decimal(o.multiplier) + ",\"angle\":" + to_decimal(o.angle) +
           ",\"error_estimate_period\":" + to_decimal(o.error_estimate_period, 3) +
           ",\"error_estimate_action\":" + to_decimal(o.error_estimate_action, 3) +
           ",\"status\":" + json_string(std::string(to_string(o.status))) +
           ",\"theta1\":" + json_numbers(o.path, 0) + ",\"theta2\":" + json_numbers(o.path, 1) +
           "}";
}

}  // namespace

template <class Real>
viewer_data<Real> saddle_viewer_data(const double_pendulum<Real>& model,
                                     const viewer_request& request,
                                     const orbit_options<Real>& options) {
    check_viewer_request(request);
    viewer_data<Real> out;
    out.parameters = model.parameters();
    out.maximum_energy = model.maximum_energy();
    for (const arm a : request.arms)
        out.families.push_back(family_data(model, a, request, options, out.solved));
    // [-pi, 2 pi] holds both families: arm 2's orbits around (0, pi) reach theta1 = -+pi only as
    // E -> E_max, arm 1's around (pi, 0) likewise in theta2
    potential_grid<Real>& g = out.potential;
    g.from = -pi<Real>();
    g.to = 2 * pi<Real>();
    g.n = request.grid;
    g.values.reserve(static_cast<std::size_t>(g.n) * static_cast<std::size_t>(g.n));
    auto node = [&](int k) { return g.from + (g.to - g.from) * Real(k) / Real(g.n - 1); };
    for (int i = 0; i < g.n; ++i)
        for (int j = 0; j < g.n; ++j)
            g.values.push_back(model.potential(node(i), node(j)));
    return out;
}

template <class Real>
std::string viewer_json(const viewer_data<Real>& d) {
    const physical_parameters<Real>& p = d.parameters;
    std::string s =
        "{\"format\":\"flipflux-viewer-1\",\"precision\":" + json_string(precision_name<Real>()) +
        ",\"parameters\":{";
    for (std::size_t i = 0; i < parameter_count; ++i)
        s += std::string(i ? "," : "") + "\"" + std::string(parameter_fields[i].name) +
             "\":" + to_decimal(p.*parameter_members<Real>[i]);
    s += "},\"maximum_energy\":" + to_decimal(d.maximum_energy) + ",\"families\":[";
    for (std::size_t f = 0; f < d.families.size(); ++f) {
        const viewer_family<Real>& fam = d.families[f];
        s += std::string(f ? "," : "") + "{\"arm\":" + std::string(to_string(fam.flip_arm)) +
             ",\"saddle_energy\":" + to_decimal(fam.saddle_energy) + ",\"saddle\":[" +
             to_decimal(fam.saddle[0]) + "," + to_decimal(fam.saddle[1]) +
             "],\"stop_reason\":" + json_string(fam.stop_reason) + ",\"orbits\":[";
        for (std::size_t k = 0; k < fam.orbits.size(); ++k)
            s += (k ? "," : "") + orbit_json(fam.orbits[k]);
        s += "]}";
    }
    const potential_grid<Real>& g = d.potential;
    s += "],\"potential\":{\"from\":" + to_decimal(g.from) + ",\"to\":" + to_decimal(g.to) +
         ",\"n\":" + std::to_string(g.n) + ",\"values\":[";
    for (std::size_t k = 0; k < g.values.size(); ++k)
        s += (k ? "," : "") + to_decimal(g.values[k]);
    return s + "]}}";
}

template viewer_data<inst_real> saddle_viewer_data<inst_real>(const double_pendulum<inst_real>&,
                                                              const viewer_request&,
                                                              const orbit_options<inst_real>&);
template std::string viewer_json<inst_real>(const viewer_data<inst_real>&);

}  // namespace flipflux
