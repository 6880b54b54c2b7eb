// The flip criteria: one registry, one registration per criterion. A criterion is a name, a
// dividing curve of (model, arm, energy) at every real type, the quantity that predicts its rate,
// and a line of help. Built in (the paper's three): "upright" (the flip angle equals pi), "approx"
// (the approximate saddle curve, a sine with the centre mode's slope), "saddle" (the saddle
// orbit's curve, from orbits/). Everything that names, lists, checks, detects or predicts a
// criterion reads this registry: the ensembles' detectors, the reference trajectories' curves,
// the scene planner, the CLI's and Python's checks, and the simulator validation.
//
// Adding a criterion is one call of register_criterion with define_criterion (see
// tests/study/test_criteria.cpp, which registers a toy one):
//
//     struct tilted { template <class Real> auto operator()(const double_pendulum<Real>&, arm a,
//                                                          const Real&) const { ... a curve ... }
//                                                          };
//     register_criterion(define_criterion<tilted>({.name = "tilted", .help = "...", ...}));
#pragma once

#include <array>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <tuple>
#include <vector>

#include "flipflux/core/error.hpp"
#include "flipflux/core/real.hpp"
#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/ensemble/flip_detector.hpp"
#include "flipflux/ensemble/pendulum_flow.hpp"
#include "flipflux/model/dividing_curve.hpp"
#include "flipflux/quantities/registry.hpp"

namespace flipflux {

/// A criterion's dividing curve at Real, type-erased: f = pi + h(s) on the domain of s, with its
/// slope h'(s) (the reference trajectories' event functions need both).
template <class Real>
struct any_curve {
    arm flip_arm = arm::two;
    std::function<Real(const Real&)> offset, slope;
    std::array<Real, 2> domain{};
};

/// The criterion does not exist at this energy (the saddle orbit beyond the solver's reach): a
/// reference trajectory skips it and says why; an ensemble reports it as bad input.
class criterion_unavailable : public input_error {
  public:
    explicit criterion_unavailable(const input_error& e) : input_error(e) {}
};

/// A criterion's curve maker at one real type.
template <class Real>
using curve_function =
    std::function<any_curve<Real>(const double_pendulum<Real>&, arm, const Real&)>;

/// What a registration states about a criterion.
struct criterion_info {
    std::string name;                 ///< its name in options, scene keys, CSV columns and reports
    std::string help;                 ///< one line for help texts and docs
    std::string rate_quantity;        ///< the registered quantity predicting its rate ("" if none)
    bool needs_saddle_orbit = false;  ///< the scene plans the saddle-orbit family for it
    bool is_reference = false;        ///< the other criteria's predictions are compared with it
    bool is_level = false;            ///< the curve is f = pi itself (a scene counts the others)
};

/// A registered criterion.
struct criterion_definition : criterion_info {
    /// The detector the ensembles use, at double.
    std::function<std::unique_ptr<flip_detector_base>(const double_pendulum<double>&, arm, double,
                                                      const pendulum_flow&)>
        detector;
    per_real_type<curve_function> curves;  ///< the curve makers, one per real type

    /// The dividing curve at Real; throws criterion_unavailable where it does not exist.
    template <class Real>
    any_curve<Real> curve(const double_pendulum<Real>& model, arm a, const Real& energy) const {
        return std::get<curve_function<Real>>(curves)(model, a, energy);
    }
};

/// The definition of a criterion whose curve is made by `Make{}(model, arm, energy)`, a curve of
/// the model's real type satisfying dividing_curve.
template <class Make>
criterion_definition define_criterion(criterion_info info) {
    criterion_definition d;
    static_cast<criterion_info&>(d) = std::move(info);
    d.detector = [](const double_pendulum<double>& model, arm a, double energy,
                    const pendulum_flow& flow) -> std::unique_ptr<flip_detector_base> {
        return make_flip_detector(Make{}(model, a, energy), flow);
    };
    std::apply(
        [](auto&... f) {
            (
                [&f] {
                    using fn = std::remove_reference_t<decltype(f)>;
                    f = fn([](const auto& model, arm a, const auto& energy) {
                        using Real = std::remove_cvref_t<decltype(energy)>;
                        const auto c = Make{}(model, a, energy);
                        const auto domain = c.domain();
                        return any_curve<Real>{c.flip_arm(),
                                               [c](const Real& s) { return Real(c.offset(s)); },
                                               [c](const Real& s) { return Real(c.slope(s)); },
                                               {Real(domain[0]), Real(domain[1])}};
                    });
                }(),
                ...);
        },
        d.curves);
    return d;
}

/// Every registered criterion, in registration order (the paper's three first).
const std::deque<criterion_definition>& criteria_registry();

/// Adds a criterion; std::logic_error if its name is taken or not a plain name. Not thread-safe:
/// register before computing.
const criterion_definition& register_criterion(criterion_definition definition);

/// The registered criterion `name`; input_error about `field` naming the known ones otherwise.
const criterion_definition& criterion(const std::string& name,
                                      const std::string& field = "criteria");

/// The known criterion names, in registration order.
std::vector<std::string> criterion_names();

/// "upright, approx, saddle": the names for a help text or an error message (or joined by another
/// separator: "upright,approx,saddle", the command line's default list).
std::string criterion_name_list(const std::string& separator = ", ");

/// "upright, approx or saddle": the names as alternatives in a sentence.
std::string criterion_alternatives();

/// The criterion a file from another simulator names without saying (no criterion column).
const std::string& default_criterion();

/// The known criterion a file or option names in any case ("Upright" is "upright"); nullopt
/// for anything else. Files from other simulators are read through it.
std::optional<std::string> criterion_named(const std::string& text);

/// Throws input_error naming `option` unless `name` is a known criterion.
void check_criterion_name(const std::string& name, const std::string& option = "criteria");

/// The lowest energy at which the criterion's curve is accessible: the saddle energy of `a`
/// (below it no flip of `a` is possible and the predicted rate vanishes).
double criterion_threshold(const double_pendulum<double>& model, arm a, const std::string& name);

/// The energy at and above which the criterion's curve does not exist: the potential's maximum
/// E_max for a criterion on the saddle orbit (its family ends there), +inf for the others.
double criterion_ceiling(const double_pendulum<double>& model, arm a, const std::string& name);

/// The refusal of `energy` at or above criterion `name`'s ceiling (criterion_ceiling), without
/// the name of the caller's key: one text for make_criterion and a scene's plan.
std::string criterion_ceiling_text(double energy, double ceiling, arm a, const std::string& name);

/// The criterion `name` for arm `a` at energy E (the saddle orbit depends on E). Throws
/// input_error for an unknown name, an energy at or below the threshold, or an energy where the
/// curve does not exist.
ensemble_criterion make_criterion(const double_pendulum<double>& model, arm a,
                                  const std::string& name, double energy);

/// The predicted rate f / Omega at double: the criterion's rate quantity from the quantity
/// registry; nullopt when it has none.
std::optional<quantity_value<double>> criterion_prediction(const double_pendulum<double>& model,
                                                           arm a, const std::string& name,
                                                           double energy);

}  // namespace flipflux
