// Scene execution: runs each plan step and writes its outputs atomically under the scene's output
// directory.
#include <chrono>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flipflux/core/decimal.hpp"
#include "flipflux/core/version.hpp"
#include "flipflux/io/atomic_file.hpp"
#include "flipflux/quantities/registry.hpp"
#include "flipflux/scene/plan.hpp"

namespace flipflux {
namespace {

using json = nlohmann::ordered_json;

struct context {
    const scene& s;
    std::ostream& log;
    run_counters counters;
    json summary = json::object();

    void write(const std::filesystem::path& name, const std::string& content) {
        const auto path = s.output / name;
        write_file_atomically(path, content);
        counters.files.push_back(path.string());
        log << "  wrote " << path.string() << "\n";
    }
};

template <class Real>
void run_predictions(context& ctx, const plan_step& step) {
    const double_pendulum<Real> model = make_model<Real>(ctx.s.model);
    std::ostringstream csv;
    csv << "quantity,arm,energy,value,error_estimate,method\n";
    json skipped = json::array();
    for (const std::string& entry : step.quantities) {
        const auto at = entry.find('@');
        const std::string name = entry.substr(0, at);
        const arm a = at == std::string::npos || entry.substr(at + 1) == "2" ? arm::two : arm::one;
        const quantity& q = find_quantity(name);
        for (const std::string& text : step.energies) {
            const Real energy = parse_real<Real>(text, "energy");
            try {
                const quantity_value<Real> v = q.evaluate(model, a, energy, "");
                ++ctx.counters.quantity_evaluations;
                csv << name << "," << (q.per_arm ? to_string(a) : "") << "," << text << ","
                    << to_decimal(v.value) << "," << to_decimal(v.error_estimate, 3) << ","
                    << csv_field(v.method) << "\n";
            } catch (const input_error& e) {
                skipped.push_back({{"quantity", entry}, {"energy", text}, {"reason", e.what()}});
            }
        }
    }
    ctx.write("predictions.csv", csv.str());
    ctx.summary["predictions"] = {{"file", "predictions.csv"}, {"skipped", skipped}};
}

}  // namespace

run_counters execute_plan(const scene& s, const plan& p, std::ostream& log) {
    context ctx{s, log, {}};
    const auto start = std::chrono::steady_clock::now();
    for (const plan_step& step : p.steps) {
        log << "- " << step.description << "\n";
        switch (step.what) {
            case plan_step::kind::predictions:
                dispatch(s.prec, [&]<class Real>() { run_predictions<Real>(ctx, step); });
                break;
            default:
                throw scene_error(s.file.string() + ": " + step.description +
                                  ": not available in this build yet");
        }
    }
    ctx.summary["scene"] = s.name;
    ctx.summary["scene_file"] = s.file.string();
    ctx.summary["precision"] = precision_name(s.prec);
    ctx.summary["git_commit"] = git_commit();
    ctx.summary["seconds"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ctx.write("run.json", ctx.summary.dump(2) + "\n");
    return ctx.counters;
}

}  // namespace flipflux
