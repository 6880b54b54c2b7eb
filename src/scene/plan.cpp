// Scene plans: what to compute (make_plan), and printing it (--dry-run).
#include "flipflux/scene/plan.hpp"

#include <algorithm>
#include <set>

#include "flipflux/core/decimal.hpp"
#include "flipflux/model/double_pendulum.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {

std::size_t plan::count(plan_step::kind k) const {
    return static_cast<std::size_t>(
        std::count_if(steps.begin(), steps.end(), [k](const plan_step& s) { return s.what == k; }));
}

bool needs_saddle_orbit(const std::string& quantity) {
    return find_quantity(quantity).needs_saddle_orbit;
}

namespace {

std::string join(const std::vector<std::string>& v, const std::string& sep = ", ") {
    std::string out;
    for (const auto& x : v)
        out += (out.empty() ? "" : sep) + x;
    return out;
}

/// Energies as text, with the value in double for ordering and domain filtering.
struct energy_entry {
    double value;
    std::string text;
};

std::vector<energy_entry> expand(const energy_grid& g, const std::string& where) {
    std::vector<energy_entry> out;
    for (const std::string& text : energy_texts(g, where))
        out.push_back({parse_real<double>(text, where), text});
    return out;
}

std::string range_text(const std::vector<std::string>& energies) {
    if (energies.empty()) return "no energies";
    if (energies.size() == 1) return "E = " + energies.front();
    return std::to_string(energies.size()) + " energies, E = " + energies.front() + " .. " +
           energies.back();
}

}  // namespace

plan make_plan(const scene& s) {
    plan p;
    const double_pendulum<double> model = make_model<double>(s.model);
    // energies at which each arm's saddle-orbit family is needed
    std::map<std::pair<int, precision>, std::map<double, std::string>> family;
    auto want_orbits = [&](int arm_number, const std::vector<energy_entry>& energies,
                           precision prec) {
        const arm a = arm_number == 1 ? arm::one : arm::two;
        for (const auto& e : energies) {
            if (e.value > model.saddle_energy(a) && e.value < model.maximum_energy()) {
                family[{arm_number, prec}].emplace(e.value, e.text);
            }
        }
    };

    std::vector<energy_entry> prediction_energies;
    if (s.predictions) {
        for (const auto& q : s.predictions->quantities) {
            try {
                (void)find_quantity(q);
            } catch (const input_error& e) {
                throw scene_error(s.file.string() + ":" + std::to_string(s.predictions->line) +
                                  ": predictions.quantities: " + e.what());
            }
        }
        prediction_energies = expand(s.predictions->energies, "predictions.energies");
        for (int a : s.predictions->arms) {
            for (const auto& q : s.predictions->quantities) {
                if (needs_saddle_orbit(q)) want_orbits(a, prediction_energies, s.prec);
            }
        }
    }
    if (s.orbits) {
        const auto energies = expand(s.orbits->energies, "orbits.energies");
        for (int a : s.orbits->arms)
            want_orbits(a, energies, s.prec);
    }
    std::vector<std::vector<energy_entry>> ensemble_energies;
    for (std::size_t i = 0; i < s.ensembles.size(); ++i) {
        const auto& x = s.ensembles[i];
        ensemble_energies.push_back(
            expand(x.energies, "ensemble[" + std::to_string(i) + "].energies"));
        if (std::find(x.criteria.begin(), x.criteria.end(), "saddle") != x.criteria.end()) {
            want_orbits(x.arm, ensemble_energies.back(), precision{real_kind::double_});
        }
    }

    for (const auto& [key, energies] : family) {
        const auto [a, prec] = key;
        plan_step step{plan_step::kind::orbit_family, a, {}, {}, {}, 0, {}, prec};
        for (const auto& [v, text] : energies)
            step.energies.push_back(text);
        step.description = "saddle-orbit family of arm " + std::to_string(a) + " in " +
                           precision_name(prec) + " at " + range_text(step.energies) +
                           " (continuation from the saddle; cached on disk)";
        p.steps.push_back(step);
    }
    if (s.predictions) {
        plan_step step{plan_step::kind::predictions, 0, {}, {}, {}, 0, {}, s.prec};
        for (const auto& e : prediction_energies)
            step.energies.push_back(e.text);
        for (const auto& q : s.predictions->quantities) {
            if (!find_quantity(q).per_arm) {
                step.quantities.push_back(q);
                continue;
            }
            for (int a : s.predictions->arms)
                step.quantities.push_back(q + "@" + std::to_string(a));
        }
        step.description = "predictions " + join(step.quantities) + " at " +
                           range_text(step.energies) +
                           " (energies outside a quantity's domain are skipped and listed)";
        p.steps.push_back(step);
    }
    for (std::size_t i = 0; i < s.ensembles.size(); ++i) {
        const auto& x = s.ensembles[i];
        plan_step step{plan_step::kind::ensemble,    x.arm, {}, {}, x.criteria, i, {},
                       precision{real_kind::double_}};
        for (const auto& e : ensemble_energies[i])
            step.energies.push_back(e.text);
        step.description = "ensemble '" + x.name + "': arm " + std::to_string(x.arm) + ", " +
                           std::to_string(x.trajectories) + " trajectories x T = " + x.time +
                           " at " + range_text(step.energies) + ", criteria " + join(x.criteria) +
                           ", " + x.integrator + " rtol " + x.rtol + ", estimator " + x.estimator +
                           (x.chaos ? ", chaos indicator" : "");
        p.steps.push_back(step);
    }
    if (s.golden) {
        p.steps.push_back({plan_step::kind::golden,
                           0,
                           {},
                           s.golden->quantities,
                           {},
                           0,
                           "golden data -> " + s.golden->dir,
                           s.golden->value_precision});
    }
    if (s.accuracy) {
        p.steps.push_back({plan_step::kind::accuracy,
                           0,
                           {},
                           s.accuracy->quantities,
                           {},
                           0,
                           "accuracy report -> " + s.accuracy->out,
                           s.prec});
    }
    if (s.report) {
        p.steps.push_back({plan_step::kind::report,
                           0,
                           {},
                           {},
                           {},
                           0,
                           "reproduction report -> " + s.report->dir,
                           s.prec});
    }
    return p;
}

void print_plan(const scene& s, const plan& p, std::ostream& out) {
    out << "scene " << s.name << " (" << s.file.string() << "), precision "
        << precision_name(s.prec) << ", output " << s.output.string() << "\n";
    int i = 1;
    for (const auto& step : p.steps)
        out << "  " << i++ << ". " << step.description << "\n";
    out << "  saddle-orbit families: " << p.count(plan_step::kind::orbit_family)
        << ", ensembles: " << p.count(plan_step::kind::ensemble) << "\n";
}

}  // namespace flipflux
