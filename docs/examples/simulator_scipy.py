#!/usr/bin/env python3
"""A small flip-rate simulator of the paper's pendulum (m1 = m2 = L1 = L2 = g = 1, point masses),
written independently of flipflux with scipy's solve_ivp, for docs/validating.md: its output is
the candidate of `flipflux validate --ensemble`.

H(theta, l) = 1/2 l^T M^-1 l + 2 (1 - cos theta1) + (1 - cos theta2), M = [[2, c], [c, 1]],
c = cos(theta1 - theta2) (angles from the downward vertical, l the conjugate momenta).

Microcanonical sampling at energy E: integrating delta(E - H) over the momenta leaves the angle
density proportional to 2 pi sqrt(det M(theta)) on {V(theta) < E} (the ellipse K(l) = k has
perimeter measure 2 pi sqrt(det M) for every k > 0), so theta is drawn uniformly and accepted with
probability sqrt(det M / 2); then l = sqrt(2 (E - V)) L u, M = L L^T, u uniform on the unit circle.

Flips (the upright criterion): arm i's angle crosses pi (mod 2 pi), i.e. a zero of cos(theta_i / 2),
located by solve_ivp's event detection. The trajectories are integrated in segments of length 0.25
(a simulator that records its state regularly). Output: one CSV row per (arm, energy) with the
columns criterion, arm, energy, trajectories, time, flips, flips_sq (sum of squared per-trajectory
counts).

--bug: a guard meant to avoid counting a crossing twice where two segments meet drops every event
within 0.1 of a segment's start -- it misses the crossings in the first steps after each
boundary (a bug seen in real simulators; the correct guard is none: solve_ivp reports a root in
the segment where it lies, and a segment's start is not tested).

Usage: simulator_scipy.py [--bug] [--energies 5.5,8] [--trajectories 100] [--time 10] [--seed 1]
       simulator_scipy.py [--bug] --state TH1,TH2,L1,L2 --time T   (one trajectory's flips)
"""
import argparse
import math
import sys

import numpy as np
from scipy.integrate import solve_ivp

SEGMENT = 0.25
GUARD = 0.1


def potential(t1, t2):
    return 2 * (1 - math.cos(t1)) + (1 - math.cos(t2))


def rhs(_t, y):
    t1, t2, l1, l2 = y
    s, c = math.sin(t1 - t2), math.cos(t1 - t2)
    d = 2 - c * c
    w1 = (l1 - c * l2) / d  # theta1 dot = (M^-1 l)_1
    w2 = (2 * l2 - c * l1) / d
    # K = (l1^2 - 2 c l1 l2 + 2 l2^2) / (2 d) depends on the angles through c only, with
    # dK/dc = -w1 w2 (differentiate and compare); dc/dtheta1 = -s, dc/dtheta2 = s.
    dk = w1 * w2 * s  # dK/dtheta1 = -dK/dtheta2
    return [w1, w2, -(dk + 2 * math.sin(t1)), -(-dk + math.sin(t2))]


def sample(E, rng):
    while True:
        t1, t2 = rng.uniform(-math.pi, math.pi, 2)
        V = potential(t1, t2)
        if V >= E:
            continue
        c = math.cos(t1 - t2)
        if rng.uniform() * math.sqrt(2) > math.sqrt(2 - c * c):
            continue
        phi = rng.uniform(0, 2 * math.pi)
        r = math.sqrt(2 * (E - V))
        u1, u2 = r * math.cos(phi), r * math.sin(phi)
        # M = L L^T, L = [[sqrt2, 0], [c / sqrt2, sqrt(1 - c^2 / 2)]]
        a = math.sqrt(2)
        return [t1, t2, a * u1, c / a * u1 + math.sqrt(1 - c * c / 2) * u2]


def arm1(_t, y):
    return math.cos(y[0] / 2)


def arm2(_t, y):
    return math.cos(y[1] / 2)


def flip_events(y0, T, bug, rtol=1e-9):
    """[(time, arm, direction)] in time order; direction +1 when the angle increases."""
    events = []
    t, y = 0.0, y0
    while t < T - 1e-12:
        t1 = min(T, t + SEGMENT)
        s = solve_ivp(rhs, (t, t1), y, method="DOP853", rtol=rtol, atol=rtol,
                      events=(arm1, arm2))
        for i in range(2):
            for x, state in zip(s.t_events[i], s.y_events[i]):
                if bug and x - t <= GUARD:
                    continue
                events.append((x, i + 1, 1 if rhs(x, state)[i] > 0 else -1))
        t, y = t1, s.y[:, -1]
    return sorted(events)


def flips(y0, T, bug):
    counts = [0, 0]
    for _, arm, _ in flip_events(y0, T, bug):
        counts[arm - 1] += 1
    return counts


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--bug", action="store_true")
    p.add_argument("--energies", default="5.5,8")
    p.add_argument("--trajectories", type=int, default=100)
    p.add_argument("--time", type=float, default=10)
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--state", help="one trajectory from TH1,TH2,L1,L2: print its upright flips "
                   "(time,arm,criterion,direction) instead of an ensemble")
    a = p.parse_args()
    if a.state:
        print("time,arm,criterion,direction")
        y0 = [float(x) for x in a.state.split(",")]
        for time, arm, direction in flip_events(y0, a.time, a.bug, rtol=1e-12):
            print(f"{time!r},{arm},upright,{direction}")
        return
    rng = np.random.default_rng(a.seed)
    print("criterion,arm,energy,trajectories,time,flips,flips_sq")
    for text in a.energies.split(","):
        E = float(text)
        n = [[], []]
        for _ in range(a.trajectories):
            c = flips(sample(E, rng), a.time, a.bug)
            n[0].append(c[0])
            n[1].append(c[1])
        for arm in (2, 1):
            if arm == 1 and E <= 4:
                continue  # arm 1 cannot flip below its saddle energy 4
            k = n[arm - 1]
            print(f"upright,{arm},{text},{a.trajectories},{a.time:g},{sum(k)},"
                  f"{sum(x * x for x in k)}")
    sys.stdout.flush()


if __name__ == "__main__":
    main()
