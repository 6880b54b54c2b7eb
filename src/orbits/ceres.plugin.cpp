// The Ceres plugin, libflipflux_ceres.so (orbits/least_squares.hpp): Levenberg-Marquardt with a
// dense QR for the small problems of the saddle orbits' shooting. It calls nothing of flipflux.
#include <ceres/ceres.h>
#include <glog/logging.h>

#include <cmath>
#include <cstring>
#include <exception>

#include "flipflux/orbits/least_squares.hpp"

namespace {

/// r(x) and its Jacobian through the problem's callback.
class callback_cost final : public ceres::CostFunction {
  public:
    explicit callback_cost(const flipflux_least_squares_problem& p) : p_(p) {
        set_num_residuals(p.residuals);
        mutable_parameter_block_sizes()->push_back(p.parameters);
    }
    bool Evaluate(double const* const* parameters, double* residuals,
                  double** jacobians) const override {
        return p_.evaluate(p_.context, parameters[0], residuals,
                           jacobians != nullptr ? jacobians[0] : nullptr) != 0;
    }

  private:
    const flipflux_least_squares_problem& p_;
};

// NOTE: Ceres logs through glog, and some of its messages ignore logging_type = SILENT (e.g.
// "Terminating: Residual and Jacobian evaluation failed." when the callback stops at a CPU
// budget). With glog never initialised they go to stderr, where a one-line error must stand
// alone: everything below FATAL is dropped (the solver's outcome reaches the caller through the
// summary's report). Set before the first solve; the plugin is glog's only user in the process.
const bool glog_quiet = [] {
    FLAGS_minloglevel = google::GLOG_FATAL;
    return true;
}();

void write_report(flipflux_least_squares_summary* s, const std::string& text) {
    const std::size_t n = std::min(text.size(), sizeof s->report - 1);
    std::memcpy(s->report, text.data(), n);
    s->report[n] = '\0';
}

}  // namespace

extern "C" __attribute__((visibility("default"))) int flipflux_least_squares_solve(
    const flipflux_least_squares_problem* problem, flipflux_least_squares_summary* summary) {
    try {
        const auto& p = *problem;
        ceres::Problem::Options problem_options;
        problem_options.cost_function_ownership = ceres::TAKE_OWNERSHIP;
        ceres::Problem ceres_problem(problem_options);
        ceres_problem.AddResidualBlock(new callback_cost(p), nullptr, p.x);
        if (p.lower != nullptr)
            for (int i = 0; i < p.parameters; ++i)
                if (p.lower[i] > -HUGE_VAL)
                    ceres_problem.SetParameterLowerBound(p.x, i, p.lower[i]);
        ceres::Solver::Options options;
        options.linear_solver_type = ceres::DENSE_QR;
        options.logging_type = ceres::SILENT;
        options.minimizer_progress_to_stdout = false;
        options.max_num_iterations = p.settings.max_iterations;
        options.function_tolerance = p.settings.function_tolerance;
        options.gradient_tolerance = p.settings.gradient_tolerance;
        options.parameter_tolerance = p.settings.parameter_tolerance;
        options.num_threads = 1;
        ceres::Solver::Summary s;
        ceres::Solve(options, &ceres_problem, &s);
        summary->usable = s.IsSolutionUsable() ? 1 : 0;
        summary->iterations = static_cast<int>(s.iterations.size());
        summary->final_cost = s.final_cost;
        write_report(summary, s.BriefReport());
        return 0;
    } catch (const std::exception& e) {
        write_report(summary, std::string("Ceres failed: ") + e.what());
        return -1;
    }
}
