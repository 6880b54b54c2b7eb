"""The installation as a user sees it (ctest install_consumer, label unit):
  1. cmake --install BUILD --prefix TMP
  2. examples/consumer/ configured with -DCMAKE_PREFIX_PATH=TMP (find_package(flipflux CONFIG)),
     built and run; its values checked against independent or higher-precision references:
       Omega(10)  (E >= E_max = 6): 16 pi^2 E(-1) by mpmath at 50 digits, an independent route;
       Omega(3):  the golden row (data/golden, 100-digit arithmetic, 50 digits certified);
       T(3), arm 2: the value below, computed once by `flipflux eval period --energy 3 --arm 2
                  --precision mp:60` (git 701ce64); the quad orbit at E = 3 is checked against an
                  independent mpmath Taylor-series integration by verification/orbits_mpmath.py;
     each in double and quad, within 64 eps (Omega) and 1024 eps (T, a shooting solution) relative;
  3. a one-file program compiled with `pkg-config --cflags --libs flipflux` and run;
  4. the installed CLI run from another directory finds its golden data (validate) and its report
     generator (share/flipflux/report);
  5. the installed Python module imported from the prefix: the CLI's digits, the prefix's golden
     data.

usage: python3 test_install.py --build BUILD --source SOURCE [--cxx-flags F] [--linker-flags F]
                               [--python-preload LIBS]
"""
import argparse
import csv
import glob
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

import mpmath as mp

mp.mp.dps = 50
PERIOD_3 = mp.mpf("5.9748175560780088606878899606587099001531985636240407021945173")
EPS = {"double": mp.mpf(2) ** -52, "quad": mp.mpf(2) ** -112}

PKG_PROGRAM = r"""
#include <flipflux/core/decimal.hpp>
#include <flipflux/model/double_pendulum.hpp>
#include <flipflux/prediction/phase_volume.hpp>
#include <iostream>
int main() {
    const flipflux::double_pendulum<double> model;
    std::cout << flipflux::to_decimal(flipflux::phase_volume_above_maximum(model)) << "\n";
}
"""


def run(cmd, **kw):
    started = time.monotonic()
    r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    if r.returncode != 0:
        sys.exit(f"FAILED ({r.returncode}): {' '.join(cmd)}\n{r.stdout[-4000:]}\n{r.stderr[-4000:]}")
    print(f"  {time.monotonic() - started:6.1f} s  {' '.join(cmd)[:140]}")
    return r.stdout


def _glob_one(pattern):
    found = glob.glob(pattern)
    if len(found) != 1:
        sys.exit(f"expected one match of {pattern}, found {found}")
    return found[0]


def golden_omega(source, energy):
    with open(os.path.join(source, "data", "golden", "golden.csv")) as f:
        for row in csv.DictReader(f):
            if row["quantity"] == "omega" and mp.mpf(row["energy"]) == mp.mpf(energy):
                return mp.mpf(row["value"])
    sys.exit(f"no golden omega at E = {energy}")


def check(name, value, reference, eps_multiple, precision):
    rel = abs(mp.mpf(value) - reference) / abs(reference)
    tol = eps_multiple * EPS[precision]
    status = "ok" if rel <= tol else "FAIL"
    print(f"  {status:4s} {name:14s} {value:>42s}  rel.err {mp.nstr(rel, 3):>9s} <= {mp.nstr(tol, 3)}")
    return rel <= tol


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", required=True)
    ap.add_argument("--source", required=True)
    ap.add_argument("--cxx", default="c++", help="the build's C++ compiler")
    ap.add_argument("--cxx-flags", default="")
    ap.add_argument("--linker-flags", default="")
    ap.add_argument("--python-preload", default="", help="LD_PRELOAD for python3 (sanitizers)")
    ap.add_argument("--python", action=argparse.BooleanOptionalAction, default=True,
                    help="check the installed Python module (FLIPFLUX_PYTHON)")
    a = ap.parse_args()
    tmp = tempfile.mkdtemp(prefix="flipflux-install-")
    try:
        prefix = os.path.join(tmp, "prefix")
        run(["cmake", "--install", a.build, "--prefix", prefix])

        # 2. the consumer project, with the build's own flags (sanitizers in CI)
        consumer = os.path.join(tmp, "consumer")
        run(["cmake", "-S", os.path.join(a.source, "examples", "consumer"), "-B", consumer,
             "-G", "Ninja", "-DCMAKE_BUILD_TYPE=None", "-DCMAKE_PREFIX_PATH=" + prefix,
             "-DCMAKE_CXX_COMPILER=" + a.cxx,
             "-DCMAKE_CXX_FLAGS=" + a.cxx_flags, "-DCMAKE_EXE_LINKER_FLAGS=" + a.linker_flags])
        run(["cmake", "--build", consumer])
        values = dict(line.split() for line in run([os.path.join(consumer, "consumer")]).splitlines())
        omega_10 = 16 * mp.pi ** 2 * mp.ellipe(-1)  # D0 = AB - C^2 = 1, C^2/D0 = 1
        omega_3 = golden_omega(a.source, "3")
        ok = True
        for p in ("double", "quad"):
            ok &= check(f"omega {p} 10", values[f"omega_{p}_10"], omega_10, 64, p)
            ok &= check(f"omega {p} 3", values[f"omega_{p}_3"], omega_3, 64, p)
            ok &= check(f"period {p} 3", values[f"period_{p}_3"], PERIOD_3, 1024, p)

        # 3. pkg-config
        env = dict(os.environ, PKG_CONFIG_PATH=os.path.join(prefix, "lib", "pkgconfig"))
        flags = run(["pkg-config", "--cflags", "--libs", "flipflux"], env=env).split()
        src = os.path.join(tmp, "pkg.cpp")
        with open(src, "w") as f:
            f.write(PKG_PROGRAM)
        exe = os.path.join(tmp, "pkg")
        run([a.cxx, src, "-o", exe] + a.cxx_flags.split() + a.linker_flags.split() + flags)
        ok &= check("omega pkg >max", run([exe]).strip(), omega_10, 64, "double")

        # 4. the installed CLI, run from elsewhere
        cli = os.path.join(prefix, "bin", "flipflux")
        candidate = os.path.join(tmp, "candidate.csv")
        with open(os.path.join(a.source, "data", "golden", "golden.csv")) as f, \
                open(candidate, "w") as out:
            out.write("quantity,arm,energy,value\n")
            for row in csv.DictReader(f):
                if row["quantity"] == "omega":
                    out.write(f"omega,,{row['energy']},{row['value'][:22]}\n")
        report = run([cli, "validate", "candidate.csv", "--rtol", "1e-15"], cwd=tmp)
        print("  " + report.strip().splitlines()[-1])
        for path in ("share/flipflux/golden/golden.csv", "share/flipflux/report/make_report.py",
                     "include/flipflux/core/real.hpp", "lib/cmake/flipflux/flipflux-config.cmake",
                     # the plugins (core/plugin.hpp); the consumer's T(3) above loaded Ceres' from
                     # there (an installed object never looks in the build tree)
                     "lib/flipflux/libflipflux_ceres.so", "lib/flipflux/libflipflux_mpi.so"):
            if not os.path.isfile(os.path.join(prefix, path)):
                print(f"  FAIL missing {path}")
                ok = False
        # 5. the installed Python module (its RPATH finds PREFIX/lib): the CLI's digits
        if a.python:
            ok &= check_python(prefix, cli, tmp, a.python_preload)
        print("install_consumer:", "passed" if ok else "FAILED")
        return 0 if ok else 1
    finally:
        shutil.rmtree(tmp, ignore_errors=True)


def check_python(prefix, cli, tmp, preload):
    """The installed Python module: the CLI's digits, the prefix's golden data."""
    ok = True
    site = _glob_one(os.path.join(prefix, "lib", "python3*", "dist-packages"))
    env = dict(os.environ, PYTHONPATH=site, PYTHONDONTWRITEBYTECODE="1")
    if preload:
        env.update(LD_PRELOAD=preload, ASAN_OPTIONS="detect_leaks=0")
    code = ("import flipflux, os; print(flipflux.evaluate('omega', '3', precision='quad').text);"
            " print(os.path.realpath(flipflux.golden_dir())); print(flipflux.__file__)")
    text, golden, module = run(["/usr/bin/python3", "-c", code], env=env, cwd=tmp).split()
    expected = json.loads(run([cli, "eval", "omega", "--energy", "3", "--precision", "quad"],
                              cwd=tmp))["value"]
    for what, good in (("python value", text == expected),
                       ("python golden", golden == os.path.realpath(
                           os.path.join(prefix, "share", "flipflux", "golden"))),
                       ("python module", module.startswith(site))):
        print(f"  {'ok' if good else 'FAIL':4s} {what}")
        ok &= good
    return ok


if __name__ == "__main__":
    sys.exit(main())
