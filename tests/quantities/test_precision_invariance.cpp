// Every registered quantity at mp leaves Boost's process-wide default precision alone. In Boost
// 1.74 an expression whose operands carry another precision than the default sets the default to
// theirs while it is evaluated: a value kept from an earlier precision (e.g. a function-static made
// at its first call) then switches the precision under every other thread of the process, whose
// new numbers and tolerances come out in the wrong precision (golden --jobs 2 stalled so in
// Boost's toms748_solve, src/prediction/curve_flux.inst.cpp). A watcher thread reads the default
// while each quantity is evaluated in mp:20 after being evaluated in mp:40 (statics made at 50
// digits, used at 30).
#include <atomic>
#include <chrono>
#include <thread>

#include "flipflux/core/real.hpp"
#include "flipflux/model/energy_level.hpp"
#include "flipflux/model/model_text.hpp"
#include "flipflux/quantities/registry.hpp"
#include "support.hpp"

namespace flipflux {
namespace {

/// Evaluates every quantity's every method in the active precision (the egalitarian pendulum, arm
/// 2, between the saddle and the maximum, just below the maximum and above it; the orbit
/// quantities only between the saddle and the maximum: their solver's paths are the same just
/// below it, where an orbit costs several times more; the rates f1 / Omega and f2 / Omega by their
/// closed form only: their quadrature route is made of the phase volume's and the fluxes'
/// quadrature routes, evaluated here on their own), and the approximate curve's flux by both routes
/// for a pendulum with a light upper arm (m1 = 0.1, L2 = 2, decimal parameters) just below its
/// maximum, where the zeros of K along the curve are found (Boost's toms748_solve did it with its
/// static).
void evaluate_every_quantity() {
    const double_pendulum<mp> model;
    for (const quantity& q : quantities()) {
        for (const std::string& method : q.methods) {
            for (const char* e : {"4", "5.85", "7.5"}) {
                if (q.needs_saddle_orbit && std::string(e) != "4") continue;
                if (!q.needs_saddle_orbit && q.name.rfind("rate-", 0) == 0 &&
                    method != "closed-form")
                    continue;
                try {
                    q.evaluate(model, arm::two, parse_energy_level<mp>(e, "E"), method);
                } catch (const std::exception&) {
                    // a method outside its domain (e.g. a closed form that needs E >= E_max)
                }
            }
        }
    }
    model_text light;
    light.m1 = "0.1", light.L2 = "2";
    const double_pendulum<mp> light_model(parse_parameters<mp>(light));
    const quantity& approx = find_quantity("flux-approx");
    for (const std::string& method : approx.methods)
        approx.evaluate(light_model, arm::two, parse_energy_level<mp>("6.045", "E"), method);
}

TEST(PrecisionInvariance, NoQuantityChangesTheDefaultPrecisionAtMp) {
    {
        const precision_scope scope(mp_precision(40));
        evaluate_every_quantity();
    }
    const precision_scope scope(mp_precision(20));
    const unsigned expected = mp::default_precision();
    std::atomic<bool> done{false};
    std::atomic<unsigned> other{0};
    std::atomic<long> reads{0};
    std::thread watcher([&] {
        while (!done.load()) {
            const unsigned now = mp::default_precision();
            if (now != expected) other.store(now);
            reads.fetch_add(1);
            // lets a test that ctest runs beside this one have the core
            std::this_thread::yield();
        }
    });
    evaluate_every_quantity();
    done.store(true);
    watcher.join();
    EXPECT_EQ(other.load(), 0u) << "the default precision (" << expected
                                << " digits) was switched to " << other.load()
                                << " digits during an evaluation";
    EXPECT_GT(reads.load(), 1000);  // the watcher did watch
}

}  // namespace
}  // namespace flipflux
