#!/usr/bin/env python3
"""A small double-pendulum simulator: one trajectory's flips, microcanonical sampling and flip
counts over an ensemble, written the way a simulator author writes one, to be validated with
flipflux (docs/validating.md).

The pendulum is the one of equations.py beside this file (m1 = m2 = L1 = L2 = g = 1), whose
Hamilton's equations `flipflux model --equations --language python` generated: the state is
(theta1, theta2, l1, l2), angles from the downward vertical, unwrapped (continuous), l the
conjugate momenta. Integration: scipy's solve_ivp, DOP853, rtol = atol = 1e-12 by default.

Flips (the "upright" criterion): arm i flips when theta_i crosses an odd multiple of pi, found as
the zeros of cos(theta_i / 2) by solve_ivp's event location; direction +1 when theta_i increases
through the crossing. Flips are counted in (0, T].

Usage (every output is CSV after a `# pendulum:` comment line):
  pendulum.py trajectory --state TH1,TH2,L1,L2 --time T --events EVENTS.csv
                         [--states STATES.csv --at 10,20,40] [--rtol R] [--atol A] [--bug]
      -> time,arm,criterion,direction         (and t,theta1,theta2,l1,l2 at the --at times and T)
  pendulum.py sample --energy E --trajectories M --seed S --out STATES.csv
      -> trajectory,energy,theta1,theta2,l1,l2
  pendulum.py ensemble (--initial-states STATES.csv | --energy E --trajectories M --seed S)
                       --time T --out COUNTS.csv [--paired] [--arm 1|2] [--rtol R] [--bug]
      -> criterion,arm,energy,trajectories,time,flips,flips_sq          (one row per arm, energy)
      -> trajectory,energy,theta1,theta2,l1,l2,time,arm,criterion,flips (--paired: per trajectory)

Check it with flipflux, e.g.
  flipflux validate --trajectories EVENTS.csv --reference data/golden/trajectories/events.csv \
      --state s01 --criteria upright
  flipflux validate --ensemble COUNTS.csv

--bug makes it the walkthrough's "wrong simulator": the coupling term k of Hamilton's equations
enters dl1/dt with the wrong sign (+k - alpha sin theta1). It still runs and looks plausible.
"""
import argparse
import csv
import math
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp

import equations  # found beside this script (Python puts the script's directory on sys.path)

PENDULUM = "# pendulum: m1=1 m2=1 L1=1 L2=1 g=1"
CRITERION = "upright"
STATE = ("theta1", "theta2", "l1", "l2")


def buggy_rhs(t, y):
    """Hamilton's equations with the sign of the coupling k flipped in dl1/dt (--bug)."""
    dy = equations.rhs(t, y)
    k = dy[3] + equations.beta * np.sin(y[1])  # dl2/dt = k - beta sin(theta2)
    dy[2] = k - equations.alpha * np.sin(y[0])  # correct: -k - alpha sin(theta1)
    return dy


def flip_event(arm):
    """cos(theta_i / 2): zero exactly where theta_i is an odd multiple of pi."""
    def event(t, y):
        return np.cos(y[arm - 1] / 2)
    event.terminal = False
    event.direction = 0  # both ways: direction is worked out from theta_i-dot, below
    return event


def integrate(y0, T, arms=(1, 2), rtol=1e-12, atol=1e-12, bug=False, t_eval=None):
    """Integrates y0 over [0, T]. Returns the flips [(time, arm, direction)] in time order and
    solve_ivp's solution (its .t/.y hold the states at t_eval when given)."""
    rhs = buggy_rhs if bug else equations.rhs
    sol = solve_ivp(rhs, (0.0, T), np.asarray(y0, dtype=float), method="DOP853", rtol=rtol,
                    atol=atol, events=[flip_event(arm) for arm in arms], t_eval=t_eval)
    if sol.status != 0:
        raise RuntimeError(f"solve_ivp failed from {y0}: {sol.message}")
    flips = []
    for arm, times, states in zip(arms, sol.t_events, sol.y_events):
        for t, y in zip(times, states):
            if t <= 0.0:
                continue  # flips count in (0, T]: a state starting upright has not flipped
            # The direction is the sign of theta_i-dot = w_i, NOT the sign of the event
            # function's slope: d/dt cos(theta/2) = -sin(theta/2) w / 2, and sin(theta/2) is +1
            # at theta = pi but -1 at 3 pi (and -pi), so the slope's sign says "increasing" at
            # one upright crossing and "decreasing" at the next for the same rotation.
            w = rhs(t, y)[arm - 1]
            flips.append((float(t), arm, 1 if w > 0 else -1))
    flips.sort()
    return flips, sol


def potential(theta1, theta2):
    return equations.alpha * (1 - np.cos(theta1)) + equations.beta * (1 - np.cos(theta2))


def sample_state(E, rng):
    """One state from the microcanonical ensemble on H = E.

    Why this is exact (docs/theory.md, "Microcanonical sampling"): with M(q) = R R^T and
    y = R^-1 l, H = |y|^2 / 2 + V(q) and d^2l = sqrt(det M) d^2y, so integrating the momenta out
    of delta(H - E) leaves  sqrt(det M(q)) * integral d^2y delta(|y|^2/2 - K) = 2 pi sqrt(det M(q))
    for K = E - V(q) > 0 and 0 otherwise. In two degrees of freedom the momentum shell's measure
    does not depend on K (no K^((n-2)/2) factor), so q has density proportional to sqrt(det M(q))
    on {V < E}: rejection from the uniform torus with acceptance sqrt(det M) / max sqrt(det M),
    max det M = D0 + C^2. Given q, y is uniform on the circle |y| = sqrt(2K), so
    l = sqrt(2K) R (cos phi, sin phi), phi uniform (any other factor of M only rotates phi).
    """
    A, C, D0 = equations.A, equations.C, equations.D0
    while True:
        theta1, theta2 = rng.uniform(-math.pi, math.pi, 2)
        K = E - potential(theta1, theta2)
        det = D0 + (C * math.sin(theta1 - theta2)) ** 2  # det M = A B - C^2 cos^2
        if K <= 0 or rng.uniform() * math.sqrt(D0 + C * C) >= math.sqrt(det):
            continue
        c = math.cos(theta1 - theta2)
        # lower Cholesky factor of M = [[A, C c], [C c, B]]: R R^T = M
        R = np.array([[math.sqrt(A), 0.0], [C * c / math.sqrt(A), math.sqrt(det / A)]])
        phi = rng.uniform(0.0, 2 * math.pi)
        l1, l2 = math.sqrt(2 * K) * R @ np.array([math.cos(phi), math.sin(phi)])
        return [float(theta1), float(theta2), float(l1), float(l2)]


def sampled(energy_text, M, seed):
    """[(trajectory, energy text, [4 state texts])] for M sampled states (as `sample` writes)."""
    rng = np.random.default_rng(seed)
    E = float(energy_text)
    return [(str(i), energy_text, [repr(x) for x in sample_state(E, rng)]) for i in range(1, M + 1)]


def read_states(path):
    """The rows of a `sample` file (comment lines skipped), texts kept exactly as read."""
    with open(path) as f:
        rows = csv.DictReader(line for line in f if not line.startswith("#"))
        return [(r["trajectory"], r["energy"], [r[k].strip() for k in STATE]) for r in rows]


def floats(text, n=None):
    values = [float(x) for x in text.split(",")]
    if n is not None and len(values) != n:
        raise SystemExit(f"pendulum.py: expected {n} comma-separated numbers, got '{text}'")
    return values


def write_csv(path, header, rows):
    with open(path, "w") as f:
        f.write(PENDULUM + "\n" + header + "\n")
        for row in rows:
            f.write(",".join(str(x) for x in row) + "\n")


def cmd_trajectory(args):
    T = float(args.time)
    # the --at times up to T, and T itself: the states say where the integration ended
    at = sorted({t for t in floats(args.at) if t <= T} | {T}) if args.states else None
    flips, sol = integrate(floats(args.state, 4), T, rtol=args.rtol, atol=args.atol, bug=args.bug,
                           t_eval=at)
    write_csv(args.events, "time,arm,criterion,direction",
              [(repr(t), arm, CRITERION, d) for t, arm, d in flips])
    if args.states:
        states = zip(sol.t, np.transpose(sol.y))  # the t_eval times (sol.y is [] when none)
        write_csv(args.states, "t,theta1,theta2,l1,l2",
                  [[repr(float(t))] + [repr(float(x)) for x in y] for t, y in states])


def cmd_sample(args):
    write_csv(args.out, "trajectory,energy,theta1,theta2,l1,l2",
              [[name, energy] + state for name, energy, state in
               sampled(args.energy, args.trajectories, args.seed)])


def cmd_ensemble(args):
    if args.initial_states:
        states = read_states(args.initial_states)
    elif args.energy is not None and args.trajectories and args.seed is not None:
        states = sampled(args.energy, args.trajectories, args.seed)
    else:
        raise SystemExit("pendulum.py ensemble: give --initial-states, or --energy, "
                         "--trajectories and --seed")
    arms = (args.arm,) if args.arm else (1, 2)
    T, start = float(args.time), time.time()
    paired, totals = [], {}  # totals[(energy, arm)] = [trajectories, flips, flips_sq]
    for i, (name, energy, texts) in enumerate(states, 1):
        flips, _ = integrate([float(x) for x in texts], T, arms, args.rtol, args.atol, args.bug)
        for arm in arms:
            n = sum(1 for _, a, _ in flips if a == arm)  # every flip, either direction
            paired.append([name, energy] + texts + [args.time, arm, CRITERION, n])
            total = totals.setdefault((energy, arm), [0, 0, 0])
            total[0], total[1], total[2] = total[0] + 1, total[1] + n, total[2] + n * n
        if i % 10 == 0 or i == len(states):
            print(f"pendulum.py: {i}/{len(states)} trajectories, {time.time() - start:.1f} s",
                  file=sys.stderr)
    if args.paired:
        write_csv(args.out, "trajectory,energy," + ",".join(STATE) + ",time,arm,criterion,flips",
                  paired)
    else:
        write_csv(args.out, "criterion,arm,energy,trajectories,time,flips,flips_sq",
                  [[CRITERION, arm, energy, m, args.time, n, n2]
                   for (energy, arm), (m, n, n2) in totals.items()])


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = parser.add_subparsers(dest="command", required=True)

    def integration_options(p):
        p.add_argument("--rtol", type=float, default=1e-12, help="solve_ivp rtol (1e-12)")
        p.add_argument("--atol", type=float, default=1e-12, help="solve_ivp atol (1e-12)")
        p.add_argument("--bug", action="store_true",
                       help="the wrong simulator: the sign of k in dl1/dt flipped")

    p = sub.add_parser("trajectory", help="one trajectory's flips (and states)")
    p.add_argument("--state", required=True, help="TH1,TH2,L1,L2")
    p.add_argument("--time", required=True, help="T: integrate over [0, T]")
    p.add_argument("--events", required=True, help="events CSV to write")
    p.add_argument("--states", help="states CSV to write, at the --at times and T")
    p.add_argument("--at", default="10,20,40", help="times of --states (those <= T)")
    integration_options(p)
    p.set_defaults(run=cmd_trajectory)

    p = sub.add_parser("sample", help="microcanonical initial states")
    p.add_argument("--energy", required=True)
    p.add_argument("--trajectories", type=int, required=True)
    p.add_argument("--seed", type=int, required=True)
    p.add_argument("--out", required=True)
    p.set_defaults(run=cmd_sample)

    p = sub.add_parser("ensemble", help="flip counts of an ensemble")
    p.add_argument("--initial-states", help="a CSV written by `sample`")
    p.add_argument("--energy")
    p.add_argument("--trajectories", type=int)
    p.add_argument("--seed", type=int)
    p.add_argument("--time", required=True)
    p.add_argument("--out", required=True)
    p.add_argument("--paired", action="store_true", help="one row per trajectory and arm")
    p.add_argument("--arm", type=int, choices=(1, 2), help="only this arm (default both)")
    integration_options(p)
    p.set_defaults(run=cmd_ensemble)

    args = parser.parse_args()
    args.run(args)


if __name__ == "__main__":
    main()
