"""`flipflux model --equations`: the pasted Python and C blocks integrate to flipflux's trajectory.

The reference is `flipflux trajectory` (its own right-hand side, from model/double_pendulum.hpp),
integrated at double with rtol 1e-13; the blocks are integrated independently (scipy's DOP853 for
Python, a fixed-step RK4 in C) over T = 3 for a rigid-link pendulum with unequal everything. Both
integrators are accurate to ~1e-11 there, so 1e-8 separates them from a wrong coefficient: the
test also shows that a relative change of 1e-6 in one coefficient moves the final state by far
more than the tolerance (the check can fail). Run by ctest (tests/CMakeLists.txt):
FLIPFLUX_EXE and FLIPFLUX_SOURCE_DIR from the environment.
"""
import csv
import os
import pathlib
import subprocess
import sys
import tempfile

import numpy as np
from scipy.integrate import solve_ivp

EXE = os.environ["FLIPFLUX_EXE"]
SOURCE = pathlib.Path(os.environ["FLIPFLUX_SOURCE_DIR"])
MODEL = ["--m1", "0.7", "--m2", "1.3", "--L1", "1.1", "--L2", "0.8", "--a1", "0.6",
         "--a2", "0.5", "--I1", "0.05", "--I2", "0.02", "--g", "9.81"]
STATE = [0.4, 2.1, 0.3, -0.2]
T = 3.0
TOL = 1e-8


def flipflux(*args):
    r = subprocess.run([EXE, *args], capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"flipflux {' '.join(args)} failed: {r.stderr}")
    return r.stdout


def reference_final_state(work):
    out = work / "states.csv"
    flipflux("trajectory", "--state", ",".join(map(repr, STATE)), "--time", repr(T),
             "--rtol", "1e-13", "--criteria", "upright", "--out", str(out), *MODEL)
    rows = list(csv.DictReader(line for line in out.open() if not line.startswith("#")))
    last = rows[-1]
    assert abs(float(last["t"]) - T) < 1e-12, last
    return np.array([float(last[k]) for k in ("theta1", "theta2", "l1", "l2")])


def python_final_state(code, scale_A=1.0):
    ns = {}
    exec(code, ns)
    ns["A"] *= scale_A
    sol = solve_ivp(ns["rhs"], (0, T), STATE, method="DOP853", rtol=1e-13, atol=1e-13)
    assert sol.success
    y = sol.y[:, -1]
    h0 = ns["hamiltonian"](*STATE)
    h1 = ns["hamiltonian"](*y)
    return y, abs(h1 - h0)


def c_final_state(code, work):
    src = work / "rk4.c"
    src.write_text(code + r"""
#include <stdio.h>
int main(void) {
    double y[4] = {%r, %r, %r, %r}, k[4][4], z[4];
    const int n = 30000;
    const double h = %r / n;
    for (int step = 0; step < n; ++step) {
        rhs(y, k[0]);
        for (int i = 0; i < 4; ++i) z[i] = y[i] + h / 2 * k[0][i];
        rhs(z, k[1]);
        for (int i = 0; i < 4; ++i) z[i] = y[i] + h / 2 * k[1][i];
        rhs(z, k[2]);
        for (int i = 0; i < 4; ++i) z[i] = y[i] + h * k[2][i];
        rhs(z, k[3]);
        for (int i = 0; i < 4; ++i) y[i] += h / 6 * (k[0][i] + 2 * k[1][i] + 2 * k[2][i] + k[3][i]);
    }
    printf("%%.17g %%.17g %%.17g %%.17g %%.17g\n", y[0], y[1], y[2], y[3], hamiltonian(y));
    return 0;
}
""" % (*STATE, T))
    exe = work / "rk4"
    subprocess.run(["cc", "-O2", "-std=c99", "-Wall", "-Werror", "-Wno-unused-function",
                    "-o", str(exe), str(src), "-lm"], check=True)
    return np.array([float(v) for v in subprocess.run([str(exe)], capture_output=True,
                                                      text=True, check=True).stdout.split()[:4]])


def main():
    failures = []
    # the committed example is the generator's output for the paper's pendulum
    committed = (SOURCE / "examples/simulator/equations.py").read_text()
    if flipflux("model", "--equations", "--language", "python") != committed:
        failures.append("examples/simulator/equations.py is not the output of "
                        "`flipflux model --equations --language python`: regenerate it")
    with tempfile.TemporaryDirectory() as d:
        work = pathlib.Path(d)
        ref = reference_final_state(work)
        py = flipflux("model", "--equations", "--language", "python", *MODEL)
        y, drift = python_final_state(py)
        err = np.max(np.abs(y - ref))
        print(f"python block: max |y - flipflux| = {err:.3e} (tolerance {TOL:g}), "
              f"|H(T) - H(0)| = {drift:.3e}")
        if not err < TOL:
            failures.append(f"python block: final state differs by {err:.3e}")
        if not drift < 1e-10:
            failures.append(f"python block: H drifts by {drift:.3e}")
        y_bad, _ = python_final_state(py, scale_A=1 + 1e-6)
        bad = np.max(np.abs(y_bad - ref))
        print(f"python block with A * (1 + 1e-6): max |y - flipflux| = {bad:.3e}")
        if not bad > 10 * TOL:
            failures.append(f"a wrong coefficient is not seen ({bad:.3e}): the check is blind")
        c = flipflux("model", "--equations", "--language", "c", *MODEL)
        yc = c_final_state(c, work)
        err_c = np.max(np.abs(yc - ref))
        print(f"C block (RK4, 30000 steps): max |y - flipflux| = {err_c:.3e}")
        if not err_c < TOL:
            failures.append(f"C block: final state differs by {err_c:.3e}")
    for f in failures:
        print("FAIL:", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
