// What the ensemble's two lane kinds (the RK lanes of ensemble.cpp, the Taylor lanes of
// taylor_ensemble.cpp) do alike after their steps: one home for the angle reduction, the chaos
// indicator's random tangent vector and its renormalisation, and the detectors' bookkeeping.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numbers>
#include <span>
#include <vector>

#include "flipflux/ensemble/ensemble.hpp"
#include "flipflux/ensemble/random.hpp"

namespace flipflux::detail {

/// The shift by multiples of 2 pi that brings an angle which left [-pi, pi] during one step back.
/// NOTE: a step moves an angle by far less than 2 pi, so |th| < 4 pi and th -/+ 2 pi is exact
/// (Sterbenz); the loop handles anything else.
inline double angle_reduction(double th) {
    constexpr double pi = std::numbers::pi, two_pi = 2 * std::numbers::pi;
    double shift = 0;
    while (th + shift > pi)
        shift -= two_pi;
    while (th + shift < -pi)
        shift += two_pi;
    return shift;
}

/// The chaos indicator's initial tangent vector: a random unit vector from trajectory `index`'s
/// own stream (the same for every integrator).
inline std::array<double, 4> initial_tangent(const ensemble_options& o, std::uint64_t index) {
    philox_stream rng(o.seed, o.energy, index, random_purpose::tangent_vector);
    std::array<double, 4> v{};
    double norm2 = 0;
    for (double& x : v) {
        x = 2 * rng.uniform() - 1;
        norm2 += x * x;
    }
    const double norm = std::sqrt(norm2);
    for (double& x : v)
        x /= norm;
    return v;
}

/// The power of two by which to rescale a tangent vector of squared norm `norm2` (exactly) when
/// |v| leaves [2^-400, 2^400], or 0 when it need not be; `log_growth` gains e ln 2.
inline int tangent_rescaling(double norm2, double& log_growth) {
    if (!(norm2 > 0x1.0p800 || (norm2 < 0x1.0p-800 && norm2 > 0))) return 0;
    const int e = std::ilogb(norm2) / 2;
    log_growth += e * std::numbers::ln2;
    return e;
}

/// Per flip angle (th1, th2), the widest prefilter bound of the detectors testing it (-1: none
/// does): what the lanes' quiet tests (step_is_quiet, ranges_are_quiet) compare against.
inline std::array<double, 2> quiet_bounds(const std::vector<flip_detector_base*>& detectors) {
    std::array<double, 2> bound{-1, -1};
    for (const flip_detector_base* d : detectors) {
        const std::size_t i = d->flip_arm() == arm::two ? 1 : 0;
        bound[i] = std::max(bound[i], d->prefilter_bound());
    }
    return bound;
}

/// Runs each detector on the step and records its crossings in r (and, with keep_crossings, the
/// crossings themselves); `found` is scratch.
inline void detect(const std::vector<flip_detector_base*>& detectors, const step_view& view,
                   bool keep_crossings, std::vector<crossing>& found, trajectory_result& r) {
    for (std::size_t c = 0; c < detectors.size(); ++c) {
        found.clear();
        if (detectors[c]->step(view, found) > 0) {
            for (const crossing& x : found)
                r.crossing_times[c].push_back(x.time);
            if (keep_crossings)
                r.crossings[c].insert(r.crossings[c].end(), found.begin(), found.end());
        }
    }
}

/// A quiet step (the lane's quiet test passed): no detector is run, each only notes the step
/// (flip_detector_base::skip_step). Noting it again changes nothing, so after one quiet step
/// (`skipped`, which the lane clears when the detectors see a step) the next ones cost nothing.
inline void skip_detectors(const std::vector<flip_detector_base*>& detectors, bool& skipped) {
    if (skipped) return;
    for (flip_detector_base* d : detectors)
        d->skip_step();
    skipped = true;
}

/// One thread's share of an ensemble, for either runner (DOP853/DOPRI5 lanes, Taylor lanes):
/// `count` <= N lanes advanced together by `round(span of lanes)` (a null lane is idle), the next
/// index taken by `next_index(index)` whenever a lane finishes, its trajectory built by
/// `make(index, lane)`; `deliver` gets each finished (or abandoned) lane's result.
template <class Lane, std::size_t N, class Make, class Next, class Deliver, class Round>
void refill_lanes(std::size_t count, Make&& make, Next&& next_index, Deliver&& deliver,
                  Round&& round) {
    std::array<std::unique_ptr<Lane>, N> lanes;
    std::array<Lane*, N> view{};
    for (;;) {
        bool any = false;
        for (std::size_t l = 0; l < count; ++l) {
            if (lanes[l] && lanes[l]->finished()) {
                deliver(lanes[l]->result());
                lanes[l].reset();
            }
            if (!lanes[l]) {
                std::uint64_t index = 0;
                if (next_index(index)) lanes[l] = make(index, l);
            }
            view[l] = lanes[l].get();
            any = any || lanes[l] != nullptr;
        }
        if (!any) return;
        round(std::span<Lane* const>(view.data(), count));
    }
}

}  // namespace flipflux::detail
