#!/usr/bin/env python3
"""The hostile-user probe campaign of issue 20 (docs/limits.md), rerunnable.

Each probe runs one flipflux command in a fresh scratch folder with an expected outcome:

  refuse(TEXT)   exit status 2, exactly one line on stderr ("flipflux: error: ..."), containing
                 TEXT (the offending value or key), and no output file left behind;
  ok(CHECK)      exit status 0, no "nan"/"inf" number in stdout, and CHECK (e.g. a value against
                 an independent mpmath route) holds;
  status(N, ...) exit status N (validate's 1 for a failed comparison);
  io_error(TEXT) exit status 1 (an I/O failure: output that could not be written), exactly one
                 line on stderr containing TEXT (the path, or "stdout"), no new regular file left;
  fails(N, TEXT) exit status N with exactly one line on stderr containing TEXT.

A probe may also set up its environment (a special file, a FIFO with a reader, stdout on
/dev/full or closed, resource limits: address space, file size) and check the scratch folder
afterwards whatever the outcome (`after`: a device still a device, a symlink still a symlink).
The classes of issue 45 (output-checked ... environment-failures) and of issue 44 (model-equations,
initial-states, validate-states, validate-paired) run under a 4 GiB address-space limit, so that a
reader of /dev/zero fails fast instead of exhausting the shared machine.

Every probe also fails on a signal (crash), on its timeout (a hang: 60 s where a refusal is
expected), on "internal error", and on any file written outside its scratch folder's work/
directory (path traversal). Reference values come from mpmath (closed forms and a 2-D quadrature
of the phase volume of the paper's pendulum, written here independently of flipflux).

Usage: tools/probes.py [--flipflux build/release/flipflux] [--only CLASS[,CLASS...]] [--list] [--verbose]
Exit status 0 when every probe meets its expectation. Prints one line per probe and a count per
class (the numbers in issue 20's closing note).
"""
import argparse
import json
import os
import re
import resource
import shutil
import signal
import stat
import subprocess
import sys
import tempfile
import threading
import time

import mpmath as mp

mp.mp.dps = 120  # values are read with every digit they carry (mp:60 prints 62)
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# ---------------------------------------------------------------- independent references (mpmath)
# The paper's pendulum (m1 = m2 = L1 = L2 = g = 1): V = 2 (1 - cos t1) + (1 - cos t2),
# det M(t) = 2 - cos^2(t1 - t2); Omega(E) = 2 pi * integral over {V < E} of sqrt(det M) dt1 dt2
# (the momentum shell of a 2-dof quadratic kinetic energy has measure 2 pi sqrt(det M)).


def fill_orbit_cache(work, flipflux, scene):
    """Runs `scene` with --cache-dir cache in work (its outputs removed): the saddle-orbit cache
    entries the cache probes then mangle or replace. Returns the entries' paths."""
    write(os.path.join(work, "s.toml"), scene)
    subprocess.run([flipflux, "run", "s.toml", "--cache-dir", "cache"], cwd=work,
                   capture_output=True, timeout=300)
    shutil.rmtree(os.path.join(work, "out"), ignore_errors=True)
    return [os.path.join(d, n) for d, _, names in os.walk(os.path.join(work, "cache"))
            for n in names]


def omega_ref(E, dps=25):
    with mp.workdps(dps):
        E = mp.mpf(E)
        if E >= 6:
            return 16 * mp.pi**2 * mp.ellipe(-1)

        def inner(t1):
            rest = E - 2 * (1 - mp.cos(t1))  # room left for 1 - cos t2
            if rest <= 0:
                return mp.mpf(0)
            if rest >= 2:
                c = mp.pi
            else:
                c = mp.acos(1 - rest)
            return mp.quad(lambda t2: mp.sqrt(2 - mp.cos(t1 - t2)**2), [-c, 0, c])

        # the ends of the t1 range (V(t1, 0) = E) and the points where the t2 range saturates
        pts = [mp.mpf(0)]
        if E > 2:
            pts.append(mp.acos(1 - (E - 2) / 2))
        pts.append(mp.acos(1 - E / 2) if E < 4 else mp.pi)
        pts = sorted(set(pts))
        half = mp.quad(inner, pts)
        return 2 * mp.pi * 2 * half


def flux_upright_arm2_ref(E, dps=25):
    """f = 4 sqrt(A) * integral of sqrt(2 K(t1)) over {K > 0}, K = (E - 2) - 4 sin^2(t1/2), A = 2:
    32 sqrt(E - 2) E(phi | m), m = 4 / (E - 2), phi = pi/2 for m <= 1 else asin(1/sqrt m)."""
    with mp.workdps(dps):
        E = mp.mpf(E)
        if E <= 2:
            return mp.mpf(0)
        m = 4 / (E - 2)
        phi = mp.pi / 2 if m <= 1 else mp.asin(1 / mp.sqrt(m))
        return mp.re(32 * mp.sqrt(E - 2) * mp.ellipe(phi, m))


# ---------------------------------------------------------------- expectations


class Probe:
    def __init__(self, cls, args, expect, timeout=60, files=None, env=None, setup=None,
                 forbid=None, note="", stdout=None, rlimits=None, after=None):
        self.cls, self.args, self.expect, self.timeout = cls, args, expect, timeout
        self.files = files or {}
        self.env = env or {}
        self.setup = setup  # callable(work, flipflux) run before the probe
        self.forbid = forbid or []  # paths (relative to work) that must not exist afterwards
        self.note = note
        self.stdout = stdout  # None (captured), "full" (/dev/full) or "closed"
        self.rlimits = rlimits or {}  # resource.RLIMIT_* -> limit, set in the child
        self.after = after  # callable(work) -> message or None, checked whatever the outcome


def refuse(text, absent=(), clean=False):
    """Exit 2, one line naming `text` (a string, or a tuple of alternatives); none of `absent`
    in it; with clean, no control character in it (offending text quoted visibly)."""
    return ("refuse", text, {"absent": absent, "clean": clean})


def ok(check=None):
    return ("ok", check)


def status(n, check=None):
    """Exit status n (an int, or a tuple of acceptable statuses)."""
    return ("status", n, check)


def fails(n, text, clean_files=False, absent=()):
    """Exit status n with exactly one line on stderr naming `text` (a string or a tuple of
    alternatives); with clean_files, no new regular file left in the work folder."""
    return ("fails", n, text, {"clean_files": clean_files, "absent": absent})


def io_error(text):
    """An I/O failure reported as such: exit 1, one line naming the path (or stdout), and no
    half-written file left."""
    return fails(1, text, clean_files=True)


def with_err(fn):
    """Marks a check that also reads stderr: called as fn(out, work, err)."""
    fn.wants_err = True
    return fn


def names(line, text):
    return any(t in line for t in text) if isinstance(text, tuple) else text in line


CONTROL = re.compile(r"[\x00-\x09\x0b-\x1f\x7f-\x9f]")  # C0 (but newline), DEL, C1


def either(refusal, success):
    """Either outcome is right (an input a user may mean either way): a refusal, or a correct
    answer."""
    return ("either", refusal, success)


NUMBER_JUNK = re.compile(r'(?<![A-Za-z_])(nan|-?inf)(?![A-Za-z_])', re.I)


def json_value(out, key="value"):
    return mp.mpf(json.loads(out)[key])


def close_to(ref_fn, rtol, key="value"):
    """A check: the JSON field `key` of stdout agrees with ref_fn() to rtol (relative)."""

    def check(out, work):
        v = json_value(out, key)
        r = ref_fn()
        err = abs(v - r) / max(abs(r), mp.mpf("1e-300"))
        if err > rtol:
            return f"{key} = {mp.nstr(v, 20)}, reference {mp.nstr(r, 20)}: rel. error {mp.nstr(err, 3)} > {rtol}"
        return None

    return check


def all_of(*checks):
    def check(out, work):
        for c in checks:
            r = c(out, work)
            if r:
                return r
        return None

    return check


def stdout_has(text):
    return lambda out, work: None if text in out else f"stdout lacks {text!r}"


def file_has(path, text):
    def check(out, work):
        p = os.path.join(work, path)
        if not os.path.exists(p):
            return f"{path} was not written"
        with open(p, errors="replace") as f:
            return None if text in f.read() else f"{path} lacks {text!r}"

    return check


# ---------------------------------------------------------------- the probes


def write(path, text):
    os.makedirs(os.path.dirname(path) or ".", exist_ok=True)
    with open(path, "w") as f:
        f.write(text)


SCENE_HEAD = '[scene]\nname = "p"\noutput = "out"\n'
CAND_HEAD = "quantity,arm,energy,value\n"
OMEGA6 = "omega,,6.5,301.63072729295795\n"  # 16 pi^2 E(-1), 17 digits
ENS_HEAD = "criterion,arm,energy,trajectories,time,flips\n"
EV_HEAD = "time,arm,criterion,direction\n"


def golden_dir(rows):
    return {"g/golden.csv": "quantity,arm,energy,value,digits,method\n" + rows}


def scene_pair(cls, name, body, text, files=None):
    """The same bad scene must be refused by --dry-run and by run, with the same text."""
    f = {"s.toml": body}
    f.update(files or {})
    return [Probe(cls, ["run", "--dry-run", "s.toml"], refuse(text), files=f, note=name + " (dry run)"),
            Probe(cls, ["run", "s.toml"], refuse(text), files=f, note=name, forbid=["out/run.json"])]


def probes():
    P = []
    # ---- numeric text
    for bad in ["nan", "NaN", "inf", "-inf", "1e", "0x10", "3e+", "1e99999", "", " ", "1_000",
                "3,5", "\uff13", "\u22123", "3\u00a0", "--5", "5..0", ".", "e5", "1e-99999x"]:
        P.append(Probe("numeric text", ["eval", "omega", "--energy", bad], refuse("--energy"),
                       note=f"--energy {bad!r}"))
    for good in [" 7", "7 ", "+7", "7.", ".7e1", "7000e-3", "0007", "7E0"]:
        P.append(Probe("numeric text", ["eval", "omega", "--energy", good],
                       either(refuse("--energy"), ok(close_to(lambda: omega_ref(7), 1e-14))),
                       note=f"--energy {good!r}"))
    for opt in ["--m2", "--g", "--L1", "--I1", "--a2"]:
        P.append(Probe("numeric text", ["eval", "omega", "--energy", "3", opt, "nan"], refuse(opt)))
    P.append(Probe("numeric text", ["simulate", "--energy", "3:nan:0.1", "--trajectories", "2",
                                    "--time", "1"], refuse("--energy")))
    P.append(Probe("numeric text", ["trajectory", "--state", "1,2,inf,0", "--time", "1"],
                   refuse("--state")))
    P.append(Probe("numeric text", ["trajectory", "--state", "1,2,0", "--time", "1"],
                   refuse("--state")))
    # ---- precisions
    for bad in ["mp:0", "mp:-3", "mp:abc", "mp:1000001", "mp:", "mp:1e3", "mp:30 ", "MP:30",
                "float", "quad128", "mp:+30", "mp:3.5", "mp:99999999999999999999"]:
        P.append(Probe("precisions", ["eval", "omega", "--energy", "7", "--precision", bad],
                       refuse("--precision"), note=f"--precision {bad!r}"))
    P.append(Probe("precisions", ["eval", "omega", "--energy", "7", "--precision", "mp:1"],
                   ok(close_to(lambda: omega_ref(7), 1e-1)), note="mp:1 (1 digit asked)"))
    P.append(Probe("precisions", ["eval", "omega", "--energy", "7", "--precision", "mp:60"],
                   ok(close_to(lambda: omega_ref(7, 80), mp.mpf("1e-59")))))
    P.append(Probe("precisions", ["eval", "omega", "--energy", "3", "--precision", "quad"],
                   ok(close_to(lambda: omega_ref(3, 40), 1e-30))))
    P.append(Probe("precisions", ["orbit", "--energy", "4", "--precision", "mp:0"],
                   refuse("--precision")))
    P.append(Probe("precisions", ["trajectory", "--state", "1,2,0,0", "--time", "1",
                                  "--precision", "mp:-3"], refuse("--precision")))
    # ---- overflow and extreme energies / parameters (references: mpmath)
    for E in ["6", "6.5", "12", "1e6", "1e30", "3e38"]:
        P.append(Probe("extreme energies", ["eval", "omega", "--energy", E],
                       ok(close_to(lambda E=E: omega_ref(E), 1e-14)), note=f"omega E = {E}"))
        P.append(Probe("extreme energies", ["eval", "flux-upright", "--arm", "2", "--energy", E],
                       ok(close_to(lambda E=E: flux_upright_arm2_ref(E), 1e-13)),
                       note=f"flux-upright arm 2 E = {E}"))
        P.append(Probe("extreme energies", ["eval", "rate-upright", "--arm", "2", "--energy", E],
                       ok(close_to(lambda E=E: flux_upright_arm2_ref(E) / omega_ref(E), 1e-13)),
                       note=f"rate-upright arm 2 E = {E}"))
    for E in ["2", "2.0000000001", "4", "5.999999999999", "3.5", "1e-4"]:
        P.append(Probe("extreme energies", ["eval", "omega", "--energy", E],
                       ok(close_to(lambda E=E: omega_ref(E), 1e-12)), note=f"omega E = {E}"))
        P.append(Probe("extreme energies", ["eval", "rate-upright", "--arm", "2", "--energy", E],
                       ok(close_to(lambda E=E: flux_upright_arm2_ref(E) / omega_ref(E), 1e-12)
                          if E not in ("2", "1e-4") else
                          lambda out, w: None if json_value(out) == 0 else "rate is not 0"),
                       note=f"rate-upright arm 2 E = {E}"))
    P.append(Probe("extreme energies", ["eval", "omega", "--energy", "1e-20", "--precision", "mp:30"],
                   ok(close_to(lambda: 2 * mp.sqrt(2) * mp.pi**2 * mp.mpf("1e-20"), 1e-18)),
                   note="omega at 1e-20: the harmonic limit 2 sqrt2 pi^2 E"))
    P.append(Probe("extreme energies", ["eval", "omega", "--energy", "1e-300", "--precision", "mp:30"],
                   ok(close_to(lambda: 2 * mp.sqrt(2) * mp.pi**2 * mp.mpf("1e-300"), 1e-28))))
    P.append(Probe("extreme energies", ["eval", "omega", "--energy", "1e300", "--precision", "mp:30"],
                   ok(close_to(lambda: omega_ref(7, 40), 1e-29))))
    # refused in double (its magnitude range), the value named as parsed
    for E, named in [("1e300", "e+300"), ("5e307", "e+307"), ("1e-300", "e-300"), ("1e309", "1e309")]:
        P.append(Probe("extreme energies", ["eval", "rate-upright", "--energy", E], refuse(named)))
    P.append(Probe("extreme energies", ["eval", "omega", "--energy", "-1"], refuse("-1")))
    P.append(Probe("extreme energies", ["eval", "omega", "--energy", "0"],
                   either(refuse("'0'"), ok(lambda out, w: None if json_value(out) == 0 else "Omega(0) is not 0"))))
    P.append(Probe("extreme energies", ["eval", "flux-approx", "--arm", "1", "--energy", "5e307"],
                   refuse("e+307")))
    for opt, v in [("--m2", "1e300"), ("--m2", "1e-300"), ("--g", "0"), ("--g", "-1"), ("--L1", "0"),
                   ("--I1", "-1"), ("--a1", "0"), ("--m1", "1e39")]:
        P.append(Probe("extreme energies", ["eval", "omega", "--energy", "3", opt, v], refuse(opt)))
    # every prediction quantity exactly at each critical energy (2, 4, 6): finite, >= 0; 0 where
    # the arm cannot flip yet (at its saddle energy)
    def nonneg(zero):
        def check(out, work):
            v = json_value(out)
            if v < 0 or (zero and v != 0):
                return f"value {v}, expected {'0' if zero else '>= 0'}"
            return None
        return check
    for q in ["flux-upright", "flux-approx", "rate-upright", "rate-approx", "omega"]:
        for E in ["2", "4", "6"]:
            for arm in ["1", "2"]:
                at_saddle = (arm == "2" and E == "2") or (arm == "1" and E in ("2", "4"))
                P.append(Probe("extreme energies", ["eval", q, "--arm", arm, "--energy", E],
                               ok(nonneg(at_saddle and q != "omega")), note=f"{q} arm {arm} at E = {E}"))
    # saddle orbits at and near the ends of their families
    for E in ["2", "6", "1.999", "6.0000001"]:
        P.append(Probe("extreme energies", ["eval", "period", "--arm", "2", "--energy", E], refuse(E)))
    for E, arm in [("4", "1"), ("6", "1")]:
        P.append(Probe("extreme energies", ["eval", "rate-saddle", "--arm", arm, "--energy", E],
                       refuse(E)))
    for E, arm in [("5.999999", "2"), ("5.999999", "1"), ("2.000001", "2"), ("4.000001", "1")]:
        P.append(Probe("extreme energies", ["eval", "period", "--arm", arm, "--energy", E],
                       ok(lambda out, w: None if json_value(out) > 0 else "period <= 0"),
                       note=f"period arm {arm} E = {E}"))
    P.append(Probe("extreme energies", ["eval", "rate-saddle", "--arm", "2", "--energy", "5.99",
                                        "--precision", "mp:50"], ok(), timeout=300,
                   note="mp:50 rate-saddle at 5.99 (issue 20: did not finish in 5 min)"))
    P.append(Probe("extreme energies", ["simulate", "--energy", "1e300", "--trajectories", "2",
                                        "--time", "1"], refuse("e+300")))
    P.append(Probe("extreme energies", ["trajectory", "--state", "0,0,1e200,0", "--time", "1"],
                   refuse("--")))
    # ---- allocation sizes
    sim = ["simulate", "--energy", "3", "--time", "1"]
    for args, text in [(["--trajectories", "2", "--bins", "1000000000"], "--bins"),
                       (["--trajectories", "2", "--bins", "1000001"], "--bins"),
                       (["--trajectories", "2", "--bins", "-1"], "--bins"),
                       (["--trajectories", "4294967297"], "--trajectories"),
                       (["--trajectories", "1e30"], "--trajectories"),
                       (["--trajectories", "0"], "--trajectories"),
                       (["--trajectories", "-2"], "--trajectories"),
                       (["--trajectories", "18446744073709551617"], "--trajectories"),
                       (["--trajectories", "2", "--sample-interval", "1e-300", "--csv-dir", "c"],
                        "--sample-interval")]:
        P.append(Probe("allocation sizes", sim + args, refuse(text), forbid=["c"]))
    P.append(Probe("allocation sizes", sim + ["--trajectories", "100000"], refuse("--trajectories"),
                   env={"FLIPFLUX_MEMORY_LIMIT": "1000000"}, note="memory limit 1 MB"))
    P.append(Probe("allocation sizes", ["simulate", "--energy", "0:100:1e-9", "--trajectories", "2",
                                        "--time", "1"], refuse("--energy")))
    P.append(Probe("allocation sizes", ["trajectory", "--state", "1,2,0,0", "--time", "1",
                                        "--sample-interval", "1e-12", "--out", "s.csv"],
                   refuse("--sample-interval"), forbid=["s.csv"]))
    for args, text in [(["--energies", "1001"], "--energies"), (["--samples", "100001"], "--samples"),
                       (["--grid", "10"], "--grid"), (["--grid", "100000003"], "--grid"),
                       (["--energies", "0"], "--energies")]:
        P.append(Probe("allocation sizes", ["viewer", "--out", "v"] + args, refuse(text), forbid=["v"]))
    P.append(Probe("allocation sizes", ["orbit", "--energy", "4", "--samples", "1000000000000"],
                   refuse("--samples")))
    P.append(Probe("allocation sizes", ["golden", "--out", "g", "--max-rows", "-1"],
                   refuse("--max-rows"), forbid=["g"]))
    # ---- threads
    for args, text in [(sim + ["--trajectories", "2", "--threads", "100000"], "--threads"),
                       (sim + ["--trajectories", "2", "--threads", "-1"], "--threads"),
                       (sim + ["--trajectories", "2", "--threads", "1.5"], "--threads"),
                       (sim + ["--trajectories", "2", "--threads", "abc"], "--threads"),
                       (["golden", "--out", "g", "--jobs", "100000"], "--jobs"),
                       (["golden", "--out", "g", "--jobs", "-1"], "--jobs")]:
        P.append(Probe("threads", args, refuse(text)))
    P.append(Probe("threads", ["run", "--threads", "100000", os.path.join(ROOT, "data/scenes/default.toml"),
                               "--dry-run"], refuse("--threads")))
    P.append(Probe("threads", sim + ["--trajectories", "4", "--threads", "3", "--no-timing"],
                   ok(stdout_has('"failed_trajectories"'))))
    # ---- tolerances and budgets
    for args, text in [(["--rtol", "1e-19"], "--rtol"), (["--rtol", "1e-300"], "--rtol"),
                       (["--rtol", "0"], "--rtol"), (["--rtol", "-1"], "--rtol"),
                       (["--rtol", "nan"], "--rtol"), (["--rtol", "0.5"], "--rtol"),
                       (["--estimator", "short", "--short-time", "1e300"], "--short-time"),
                       (["--estimator", "short", "--short-time", "0"], "--short-time"),
                       (["--chaos-threshold", "nan"], "--chaos-threshold"),
                       (["--checkpoint-interval", "inf"], "--checkpoint-interval"),
                       (["--reference-time", "inf"], "--reference-time"),
                       (["--seed", "-1"], "--seed")]:
        P.append(Probe("tolerances and budgets", sim + ["--trajectories", "2"] + args, refuse(text)))
    for T in ["inf", "1e300", "0", "-1"]:
        P.append(Probe("tolerances and budgets", ["simulate", "--energy", "3", "--trajectories", "2",
                                                  "--time", T], refuse("--time")))
    P.append(Probe("tolerances and budgets", ["trajectory", "--state", "1,2,0,0", "--time", "1e300",
                                              "--precision", "mp:30"], refuse("--time")))
    P.append(Probe("tolerances and budgets", ["trajectory", "--state", "1,2,0,0", "--time", "1",
                                              "--rtol", "1e-20"], refuse("--rtol")))
    P.append(Probe("tolerances and budgets", ["accuracy", "--min-seconds", "inf"], refuse("--min-seconds")))
    P.append(Probe("tolerances and budgets", ["accuracy", "--max-seconds", "-1"], refuse("--max-seconds")))
    P.append(Probe("tolerances and budgets", ["validate", "--trajectories", "c.csv", "--reference", "c.csv",
                                              "--time-tol", "0"], refuse("--time-tol"),
                   files={"c.csv": EV_HEAD}))
    P.append(Probe("tolerances and budgets", ["validate", "--trajectories", "c.csv", "--reference", "c.csv",
                                              "--until", "-1"], refuse("--until"), files={"c.csv": EV_HEAD}))
    P.append(Probe("tolerances and budgets", ["validate", "c.csv", "--rtol", "1"], refuse("--rtol"),
                   files={"c.csv": CAND_HEAD + OMEGA6}))
    P.append(Probe("tolerances and budgets", ["validate", "--ensemble", "e.csv", "--pilot", "1e17"],
                   refuse("--pilot"), files={"e.csv": ENS_HEAD + "upright,2,5,100,10,100\n"}))
    P.append(Probe("tolerances and budgets", ["validate", "--ensemble", "e.csv"],
                   status(1, stdout_has("malformed")),
                   files={"e.csv": ENS_HEAD + "upright,2,5,100,1e300,100\n"},
                   note="candidate time 1e300: refused row, no hang"))
    # ---- failed trajectories: an rtol at the floor finishes; failures are never counted as data
    P.append(Probe("failed trajectories", sim + ["--trajectories", "4", "--rtol", "2.3e-14", "--no-timing"],
                   ok(lambda out, w: None if json.loads(out)["energies"][0].get("failed_trajectories", 0) in (0, "0")
                      else "trajectories failed at the rtol floor")))
    P.append(Probe("failed trajectories", sim + ["--trajectories", "4", "--method", "dopri5", "--rtol",
                                                 "2.3e-14", "--no-timing"], ok()))
    # ---- corrupt caches: checkpoints and the orbit cache
    def checkpoint_setup(mangle):
        def setup(work, flipflux):
            # an interrupted run leaves its checkpoint (a finished one removes it)
            proc = subprocess.Popen([flipflux] + sim[:-1] + ["50", "--trajectories", "20000",
                                                            "--checkpoint", "c.ckpt",
                                                            "--checkpoint-interval", "0"],
                                    cwd=work, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
            path = os.path.join(work, "c.ckpt")
            for _ in range(100):
                time.sleep(0.1)
                if os.path.exists(path) and os.path.getsize(path) > 2000:
                    break
            proc.send_signal(2)
            proc.wait(timeout=60)
            with open(path, "rb") as f:
                data = f.read()
            with open(path, "wb") as f:
                f.write(mangle(data))
        return setup

    # a checkpoint cut mid-record is what a kill -9 during an append leaves: resuming from its
    # complete records is right (the run then finishes: status 0), refusing it too
    P.append(Probe("corrupt caches", sim[:-1] + ["50", "--trajectories", "20000", "--checkpoint", "c.ckpt",
                                                 "--no-timing"],
                   either(refuse("c.ckpt"), ok(stdout_has('"trajectories"'))), timeout=180,
                   setup=checkpoint_setup(lambda d: d[: len(d) // 2]), note="checkpoint truncated"))
    for name, mangle in [("garbage", lambda d: b"\x00\xff" * 100),
                         ("flipped digit", lambda d: d.replace(b"1", b"2", 1)),
                         ("huge line", lambda d: b"x" * 5_000_000)]:
        P.append(Probe("corrupt caches", sim[:-1] + ["50", "--trajectories", "20000", "--checkpoint",
                                                     "c.ckpt"],
                       refuse("c.ckpt"), setup=checkpoint_setup(mangle), note=f"checkpoint {name}"))
    P.append(Probe("corrupt caches", sim + ["--trajectories", "6", "--checkpoint", "d"],
                   refuse("d"), setup=lambda w, f: os.mkdir(os.path.join(w, "d")),
                   note="checkpoint is a directory"))
    P.append(Probe("corrupt caches", ["simulate", "--energy", "5", "--time", "50", "--trajectories",
                                      "20000", "--checkpoint", "c.ckpt"], refuse("c.ckpt"),
                   setup=checkpoint_setup(lambda d: d), note="checkpoint of another run (E = 3 vs 5)"))
    orbit_scene = (SCENE_HEAD + '[orbits]\narms = [2]\nenergies = [3]\n')

    def cache_setup(mangle):
        def setup(work, flipflux):
            for p in fill_orbit_cache(work, flipflux, orbit_scene):
                with open(p, "rb") as f:
                    data = f.read()
                with open(p, "wb") as f:
                    f.write(mangle(data))
        return setup

    def recomputed(out, work):
        with open(os.path.join(work, "out", "run.json")) as f:
            rj = json.load(f)
        c = rj.get("counters", {}).get("orbit_cache_rejected", 0)
        return None if int(c) >= 1 else f"orbit_cache_rejected = {c}"

    for name, mangle in [("truncated", lambda d: d[: len(d) // 2]), ("garbage", lambda d: b"\x00" * 64),
                         ("empty", lambda d: b""),
                         ("edited period", lambda d: re.sub(rb"(\d)\.(\d)", rb"7.\2", d, count=1)),
                         ("huge", lambda d: d + b"9" * 3_000_000)]:
        P.append(Probe("corrupt caches", ["run", "s.toml", "--cache-dir", "cache"], ok(recomputed),
                       setup=cache_setup(mangle), timeout=300, note=f"orbit cache {name}"))
    # ---- golden and candidate files
    for name, text, exp in [
            ("empty", "", refuse("c.csv")),
            ("header only", CAND_HEAD, status(1)),
            ("BOM", "\ufeff" + CAND_HEAD + OMEGA6, ok()),
            ("duplicate", CAND_HEAD + OMEGA6 + OMEGA6, status(1, stdout_has("duplicate"))),
            ("NaN value", CAND_HEAD + "omega,,6.5,nan\n", status(1, stdout_has("malformed"))),
            ("inf value", CAND_HEAD + "omega,,6.5,inf\n", status(1, stdout_has("malformed"))),
            ("nan energy", CAND_HEAD + "omega,,nan,1\n", status(1, stdout_has("malformed"))),
            ("binary", "\x00\x01\x02\xff" * 100, refuse("c.csv")),
            ("unterminated quote", CAND_HEAD + 'omega,,"6.5,1\n', refuse("c.csv")),
            ("wrong header", "a,b,c\n1,2,3\n", refuse("c.csv")),
            ("arm 3", CAND_HEAD + "rate-upright,3,6.5,1\n", status(1)),
            ("huge value text", CAND_HEAD + "omega,,6.5,1" + "0" * 100000 + "\n", status(1)),
            ("huge energy exponent", CAND_HEAD + "omega,,6.5e999999999999,1\n", status(1)),
            ("CRLF", (CAND_HEAD + OMEGA6).replace("\n", "\r\n"), ok()),
            ("unknown quantity", CAND_HEAD + "bogus,,6.5,1\n", status(1))]:
        P.append(Probe("golden and candidate files", ["validate", "c.csv", "--allow-missing"], exp,
                       files={"c.csv": text}, note=f"candidate {name}"))
    P.append(Probe("golden and candidate files", ["validate", "c.csv", "--allow-missing"],
                   status(1), setup=lambda w, f: write(os.path.join(w, "c.csv"),
                                                        CAND_HEAD + "omega,,6.5,301.6\n" * 200000),
                   note="candidate 200000 duplicate rows"))
    P.append(Probe("golden and candidate files", ["validate", "dir"], refuse("dir"),
                   setup=lambda w, f: os.mkdir(os.path.join(w, "dir")), note="candidate is a directory"))
    P.append(Probe("golden and candidate files", ["validate", "missing.csv"], refuse("missing.csv")))
    P.append(Probe("golden and candidate files", ["validate", "/dev/null"], refuse("/dev/null")))
    for name, rows, text in [
            ("digits -5", "omega,,6.5,301.6307,-5,m\n", "digits"),
            ("digits 0", "omega,,6.5,301.6307,0,m\n", "digits"),
            ("digits huge", "omega,,6.5,301.6307,99999999999,m\n", "digits"),
            ("value nan", "omega,,6.5,nan,30,m\n", "nan"),
            ("duplicate rows", "omega,,6.5,301.6307,30,m\nomega,,6.50,301.6307,30,m\n", "twice"),
            ("arm 7", "rate-upright,7,6.5,1,30,m\n", "arm")]:
        P.append(Probe("golden and candidate files", ["validate", "c.csv", "--golden", "g"],
                       refuse(text), files={"c.csv": CAND_HEAD + OMEGA6, **golden_dir(rows)},
                       note=f"golden {name}"))
    P.append(Probe("golden and candidate files", ["validate", "c.csv", "--golden", "nowhere"],
                   refuse("nowhere"), files={"c.csv": CAND_HEAD + OMEGA6}))
    P.append(Probe("golden and candidate files", ["validate", "c.csv", "--pendulum", "../.."],
                   refuse("--pendulum"), files={"c.csv": CAND_HEAD + OMEGA6}))
    for name, row in [("nan energy", "upright,2,nan,100,10,5"), ("trajectories 1", "upright,2,5,1,10,5"),
                      ("negative flips", "upright,2,5,100,10,-5"), ("arm 3", "upright,3,5,100,10,5"),
                      ("time inf", "upright,2,5,100,inf,5"), ("bogus criterion", "bogus,2,5,100,10,5"),
                      ("trajectories 1e30", "upright,2,5,1e30,10,5")]:
        P.append(Probe("golden and candidate files", ["validate", "--ensemble", "e.csv"],
                       status(1, stdout_has("malformed")), files={"e.csv": ENS_HEAD + row + "\n"},
                       note=f"ensemble candidate {name}"))
    for name, row in [("direction 2", "1.5,2,upright,2"), ("arm 3", "1.5,3,upright,1"),
                      ("time nan", "nan,2,upright,1"), ("criterion bogus", "1.5,2,bogus,1")]:
        P.append(Probe("golden and candidate files", ["validate", "--trajectories", "t.csv",
                                                      "--reference", "r.csv"], refuse("t.csv"),
                       files={"t.csv": EV_HEAD + row + "\n", "r.csv": EV_HEAD + "1.5,2,upright,1\n"},
                       note=f"events candidate {name}"))
    # ---- paths
    for args, text, forbid in [
            (["trajectory", "--state", "1,2,0,0", "--time", "1", "--out", "d"], "d", []),
            (["trajectory", "--state", "1,2,0,0", "--time", "1", "--events", "/proc/x"], "/proc/x", []),
            (["orbit", "--energy", "4", "--out", "d"], "d", []),
            (["orbit", "--energy", "4", "--out", "/proc/self/x"], "/proc", []),
            (["orbit", "--energy", "4", "--out", "f/x.csv"], "f", []),
            (sim + ["--trajectories", "2", "--csv-dir", "f"], "f", []),
            (sim + ["--trajectories", "2", "--checkpoint", "/proc/x"], "/proc/x", []),
            (["golden", "--out", "/proc/g", "--max-rows", "1"], "/proc/g", []),
            (["golden", "--out", "f", "--max-rows", "1"], "f", []),
            (["viewer", "--out", "f", "--energies", "1"], "f", []),
            (["accuracy", "--out", "d"], "d", []),
            (["accuracy", "--out", "/proc/x/a.md"], "/proc/x", []),
            (["orbit", "--energy", "4", "--out", "x" * 300 + ".csv"], "xxxx", []),
    ]:
        def setup(work, flipflux):
            os.mkdir(os.path.join(work, "d"))
            write(os.path.join(work, "f"), "a file\n")
        P.append(Probe("paths", args, refuse(text), setup=setup, forbid=forbid))
    P.append(Probe("paths", ["trajectory", "--state", "1,2,0,0", "--time", "1", "--out", "nodir/x/s.csv"],
                   either(refuse("nodir"), ok(file_has("nodir/x/s.csv", "theta1"))),
                   note="--out in folders to be created"))
    for name, ens_name in [("traversal", "../../x"), ("slash", "a/b"), ("dot dot", ".."),
                           ("hidden", ".h"), ("empty", ""), ("too long", "n" * 101)]:
        P += scene_pair("paths", f"ensemble name {name}",
                        SCENE_HEAD + f'[[ensemble]]\nname = "{ens_name}"\narm = 2\ncriteria = ["upright"]\n'
                        'energies = [3]\ntrajectories = 2\ntime = 1\n', "name")
    P += scene_pair("paths", "two ensembles, one name",
                    SCENE_HEAD + ('[[ensemble]]\nname = "a"\narm = 2\ncriteria = ["upright"]\n'
                                  'energies = [3]\ntrajectories = 2\ntime = 1\n') * 2, "already")
    P += scene_pair("paths", "output /proc", SCENE_HEAD.replace('"out"', '"/proc/x"') +
                    '[predictions]\nquantities = ["omega"]\nenergies = [3]\n', "/proc/x")
    P += scene_pair("paths", "output is a file", SCENE_HEAD.replace('"out"', '"f"') +
                    '[predictions]\nquantities = ["omega"]\nenergies = [3]\n', "f",
                    files={"f": "a file\n"})
    # ---- scene files: what run refuses, --dry-run refuses
    pred = '[predictions]\nquantities = ["omega"]\nenergies = [3]\n'
    for name, body, text in [
            ("arm-1 ensemble below its saddle", SCENE_HEAD + '[[ensemble]]\nname = "a"\narm = 1\n'
             'criteria = ["saddle"]\nenergies = [3]\ntrajectories = 2\ntime = 1\n', "3"),
            ("m2 = 1e300", SCENE_HEAD + '[model]\nm2 = 1e300\n' + pred, "m2"),
            ("report without inputs", SCENE_HEAD + '[report]\ndir = "r"\n', "report"),
            ("golden bogus quantity", SCENE_HEAD + '[golden]\ndir = "g"\nquantities = ["bogus"]\n', "bogus"),
            ("unknown key", SCENE_HEAD + 'bogus = 1\n' + pred, "bogus"),
            ("bad TOML", SCENE_HEAD + '[predictions\n', "s.toml"),
            ("empty file", "", "s.toml"),
            ("trajectories 1e9", SCENE_HEAD + '[[ensemble]]\nname = "a"\narm = 2\ncriteria = ["upright"]\n'
             'energies = [3]\ntrajectories = 1000000000\ntime = 1\n', "trajectories"),
            ("rtol 1e-20", SCENE_HEAD + '[[ensemble]]\nname = "a"\narm = 2\ncriteria = ["upright"]\n'
             'energies = [3]\ntrajectories = 2\ntime = 1\nrtol = 1e-20\n', "rtol"),
            ("energy 'abc'", SCENE_HEAD + '[predictions]\nquantities = ["omega"]\nenergies = ["abc"]\n', "abc"),
            ("energy nan", SCENE_HEAD + '[predictions]\nquantities = ["omega"]\nenergies = [nan]\n', "energies"),
            ("duplicate energies", SCENE_HEAD + '[predictions]\nquantities = ["omega"]\nenergies = [3, 3.0]\n', "twice"),
            ("duplicate arms", SCENE_HEAD + '[predictions]\nquantities = ["rate-upright"]\narms = [2, 2]\n'
             'energies = [3]\n', "twice"),
            ("precision mp:0", SCENE_HEAD + 'precision = "mp:0"\n' + pred, "precision"),
            ("grid of 1e9 energies", SCENE_HEAD + '[predictions]\nquantities = ["omega"]\n'
             'energies = { from = 0, to = 1, step = 1e-9 }\n', "energies"),
            ("time 1e300 at E = 1e300", SCENE_HEAD + '[[ensemble]]\nname = "a"\narm = 2\ncriteria = ["upright"]\n'
             'energies = [1e300]\ntrajectories = 2\ntime = 1\n', "1e"),
            ("short estimator longer than time", SCENE_HEAD + '[[ensemble]]\nname = "a"\narm = 2\n'
             'criteria = ["upright"]\nenergies = [3]\ntrajectories = 2\ntime = 1\nestimator = "short"\n'
             'short_time = 5\n', "short"),
            ("viewer grid 10", SCENE_HEAD + '[viewer]\ngrid = 10\n', "grid"),
    ]:
        P += scene_pair("scene files", name, body, text)
    def orbit_skipped(out, work):
        with open(os.path.join(work, "out", "run.json")) as f:
            skipped = json.load(f).get("orbits", {}).get("skipped", [])
        return None if any(x.get("energy") == "6.5" for x in skipped) else "E = 6.5 not listed as skipped"
    P.append(Probe("scene files", ["run", "s.toml"], ok(orbit_skipped),
                   files={"s.toml": SCENE_HEAD + '[orbits]\narms = [2]\nenergies = [6.5]\n'},
                   note="saddle orbit above E_max: skipped and listed in run.json"))
    P.append(Probe("scene files", ["run", "--dry-run", "s.toml"], ok(),
                   files={"s.toml": "\ufeff" + SCENE_HEAD + pred}, note="BOM accepted (dry run)"))
    P.append(Probe("scene files", ["run", "s.toml"], ok(file_has("out/predictions.csv", "omega")),
                   files={"s.toml": "\ufeff" + SCENE_HEAD + pred}, note="BOM accepted"))
    # ---- command line
    P.append(Probe("command line", ["evall"], refuse("evall")))
    P.append(Probe("command line", [], refuse("subcommand")))
    P.append(Probe("command line", ["eval", "bogus", "--energy", "3"], refuse("bogus")))
    P.append(Probe("command line", ["eval", "omega"], refuse("--energy")))
    P.append(Probe("command line", ["eval", "omega", "--energy", "3", "--energy", "4"], refuse("--energy")))
    P.append(Probe("command line", ["eval", "rate-upright", "--energy", "3", "--arm", "3"], refuse("--arm")))
    P += probes_issue45()
    P += probes_issue44()
    return P


# ---------------------------------------------------------------- issue 45: the second round

FLIPFLUX = os.path.join(ROOT, "build/release/flipflux")  # set by main(); checks run flipflux too
MEM_LIMIT = 4 << 30  # address space of every issue-45 probe: /dev/zero readers fail fast
IS_ROOT = os.geteuid() == 0
DEFAULT_SCENE = os.path.join(ROOT, "data/scenes/default.toml")
SIM = ["simulate", "--energy", "3", "--trajectories", "2", "--time", "1"]
STDOUT = ("stdout", "standard output")  # how an error may name the standard output
TRAJ = ["trajectory", "--state", "1,2,0,0", "--time", "1"]
FLIPPING_STATE = ["2.5", "0.5", "1"]  # theta2, l1, l2 of a state whose arm 2 flips within T = 5


def P45(cls, args, expect, **kw):
    """A probe of issue 45's classes (and the later ones): under the address-space limit, 60 s
    unless told."""
    rl = kw.pop("rlimits", {})
    return Probe(cls, args, expect, rlimits={resource.RLIMIT_AS: MEM_LIMIT, **rl}, **kw)


def pair45(cls, name, body, text, files=None, setup=None, extra=(), env=None, timeout=60,
           dry=None, full=None, absent=()):
    """A bad scene refused by run --dry-run and by run with the same text (or the expectations
    given as dry/full)."""
    f = {"s.toml": body, **(files or {})}
    return [P45(cls, ["run", "--dry-run", "s.toml", *extra], dry or refuse(text, absent=absent),
                files=f, setup=setup, env=env, timeout=timeout, note=name + " (dry run)"),
            P45(cls, ["run", "s.toml", *extra], full or refuse(text, absent=absent), files=f,
                setup=setup, env=env, timeout=timeout, note=name,
                forbid=[] if full else ["out/run.json"])]


def fnv1a64_hex(text):
    h = 0xcbf29ce484222325
    for b in text.encode():
        h = ((h ^ b) * 0x100000001b3) & 0xFFFFFFFFFFFFFFFF
    return f"{h:016x}"


def make_special(work, name, kind):
    """A special file in the scratch folder: 'null', 'full', 'zero' (character devices made by
    mknod when root; else symlinks to the system's, which a non-root process cannot replace)."""
    path = os.path.join(work, name)
    minor = {"null": 3, "full": 7, "zero": 5}[kind]
    if IS_ROOT:
        os.mknod(path, 0o666 | stat.S_IFCHR, os.makedev(1, minor))
    else:
        os.symlink("/dev/" + kind, path)


def still_device(work, name, kind):
    """An after-check: the special file `name` is still what make_special made."""
    minor = {"null": 3, "full": 7, "zero": 5}[kind]
    path = os.path.join(work, name)
    if IS_ROOT:
        try:
            st = os.lstat(path)
        except FileNotFoundError:
            return f"the device '{name}' was removed"
        if not stat.S_ISCHR(st.st_mode) or st.st_rdev != os.makedev(1, minor):
            return f"the device '{name}' was replaced (now mode {oct(st.st_mode)})"
        return None
    if not os.path.islink(path):
        return f"the symlink '{name}' -> /dev/{kind} was replaced"
    st = os.stat("/dev/" + kind)
    if not stat.S_ISCHR(st.st_mode):
        return f"/dev/{kind} is no longer a character device"
    return None


def still_link(name, target):
    def after(work):
        path = os.path.join(work, name)
        if not os.path.islink(path):
            return f"the symlink '{name}' was replaced by a {'folder' if os.path.isdir(path) else 'file'}"
        if os.readlink(path) != target:
            return f"the symlink '{name}' now points to {os.readlink(path)!r}"
        return None
    return after


def still_fifo(name):
    def after(work):
        path = os.path.join(work, name)
        if not os.path.lexists(path) or not stat.S_ISFIFO(os.lstat(path).st_mode):
            return f"the FIFO '{name}' was replaced or removed"
        return None
    return after


def afters(*fns):
    def after(work):
        msgs = [m for m in (f(work) for f in fns) if m]
        return "; ".join(msgs) or None
    return after


class FifoReader:
    """A FIFO in the work folder with a reader thread (what `--out fifo` with a consumer is)."""

    def __init__(self, name):
        self.name, self.data, self.thread = name, None, None

    def setup(self, work, flipflux=None):
        self.path = os.path.join(work, self.name)
        os.mkfifo(self.path)
        self.thread = threading.Thread(target=self._read, daemon=True)
        self.thread.start()

    def _read(self):
        try:
            with open(self.path, "rb") as f:
                self.data = f.read()
        except OSError:
            self.data = b""

    def finish(self, work):
        if self.thread and self.thread.is_alive():  # a reader still waiting in open(): release it
            try:
                os.close(os.open(self.path, os.O_WRONLY | os.O_NONBLOCK))
            except OSError:
                pass
            self.thread.join(2)
        return still_fifo(self.name)(work)

    def got(self, text):
        def check(out, work):
            self.thread.join(5)
            return None if self.data and text.encode() in self.data else \
                f"the FIFO's reader got {(self.data or b'')[:80]!r}, not {text!r}"
        return check


def golden_set(work, flipflux, name="g", rows=1):
    """A small valid golden set (quad: seconds) made by flipflux itself."""
    r = subprocess.run([flipflux, "golden", "--out", name, "--max-rows", str(rows), "--quantities",
                        "omega", "--precision", "quad"], cwd=work, capture_output=True, timeout=120)
    if r.returncode != 0:
        raise RuntimeError(f"golden set: {r.stderr.decode()[:200]}")


def reduced_angle(text):
    with mp.workdps(len(text) + 400):
        x = mp.mpf(text)
        r = x - 2 * mp.pi * mp.floor(x / (2 * mp.pi))
        return mp.nstr(r, 25)


def events_of(out):
    rows = [l.split(",") for l in out.strip().splitlines()[1:] if l.strip()]
    return [(float(r[0]), r[1], r[2], r[3]) for r in rows]


def same_events_as(args):
    """A check: the events equal those of the same command with its angles reduced exactly
    (mpmath, from the decimal text) into [0, 2 pi)."""
    def check(out, work):
        i = args.index("--state")
        st = args[i + 1].split(",")
        st[0], st[1] = reduced_angle(st[0]), reduced_angle(st[1])
        ref_args = args[:i + 1] + [",".join(st)] + args[i + 2:]
        r = subprocess.run([FLIPFLUX] + ref_args, capture_output=True, timeout=120, cwd=work)
        if r.returncode != 0:
            return f"reference run ({','.join(st)}) failed: {r.stderr.decode()[:100]}"
        got, ref = events_of(out), events_of(r.stdout.decode())
        if len(got) != len(ref) or any(g[1:] != e[1:] or abs(g[0] - e[0]) > 1e-6 for g, e in zip(got, ref)):
            return f"events {got[:3]}... differ from the reduced state's {ref[:3]}... ({len(got)} vs {len(ref)})"
        return None
    return check


_default_modes = {}


def omega_squared(out):
    return [mp.mpf(x) for x in re.findall(r'"omega_squared": "([^"]+)"', out)]


def modes_as_default(out, work):
    """A check: the normal modes' omega^2 equal the paper pendulum's (a scale-free change of
    m, L and g leaves them unchanged)."""
    if "ref" not in _default_modes:
        _default_modes["ref"] = omega_squared(subprocess.run([FLIPFLUX, "model"], capture_output=True,
                                                             timeout=60).stdout.decode())
    got, ref = omega_squared(out), _default_modes["ref"]
    if len(got) != len(ref):
        return f"{len(got)} normal modes, the paper pendulum has {len(ref)}"
    for g, r in zip(got, ref):
        if abs(g - r) > 1e-12 * max(1, abs(r)):
            return f"omega_squared {mp.nstr(g, 17)}, expected {mp.nstr(r, 17)}"
    return None


def flipflux_value(args):
    """A reference by another route of flipflux itself (e.g. the elliptic method)."""
    r = subprocess.run([FLIPFLUX] + args, capture_output=True, timeout=120)
    return json_value(r.stdout.decode())


def within_estimate(ref_fn):
    """A check: the value agrees with ref_fn() within its own error_estimate (and 1e-12)."""
    def check(out, work):
        j = json.loads(out)
        v, r = mp.mpf(j["value"]), ref_fn()
        est = mp.mpf(j.get("error_estimate") or 0)
        if abs(v - r) > max(est, 1e-12 * abs(r)):
            return f"value = {mp.nstr(v, 17)}, reference {mp.nstr(r, 17)}: |difference| " \
                   f"{mp.nstr(abs(v - r), 3)} exceeds its error_estimate {mp.nstr(est, 3)}"
        return None
    return check


def probes_issue45():
    P = []
    # ---- output-checked: every write and the final flush of stdout checked
    cls = "output-checked"
    stdout_cmds = [(["eval", "omega", "--energy", "3"], {}),
                   (["model"], {}),
                   (["orbit", "--energy", "4", "--samples", "3"], {}),
                   (SIM, {}),
                   (TRAJ, {}),
                   (["run", "--dry-run", DEFAULT_SCENE], {}),
                   (["validate", "c.csv", "--allow-missing"], {"c.csv": CAND_HEAD + OMEGA6}),
                   (["--version"], {}),
                   (["eval", "--help"], {})]
    for mode in ["full", "closed"]:
        for args, files in stdout_cmds:
            P.append(P45(cls, args, io_error(STDOUT), files=files, stdout=mode, timeout=60,
                         note=f"{' '.join(a if a != DEFAULT_SCENE else 'default.toml' for a in args)} "
                              f"{'> /dev/full' if mode == 'full' else '>&-'}"))
    P.append(P45(cls, ["run", "s.toml"], fails(1, STDOUT), stdout="full",
                 files={"s.toml": SCENE_HEAD + '[predictions]\nquantities = ["omega"]\nenergies = [3]\n'},
                 note="run s.toml > /dev/full"))
    fsz = resource.RLIMIT_FSIZE
    for args, limit, text in [
            (["orbit", "--energy", "4", "--samples", "200", "--out", "o.csv"], 1000, "o.csv"),
            (["trajectory", "--state", "0.5," + ",".join(FLIPPING_STATE), "--time", "5",
              "--sample-interval", "0.01", "--out", "s.csv"], 2000, "s.csv"),
            (["trajectory", "--state", "0.5," + ",".join(FLIPPING_STATE), "--time", "50",
              "--events", "e.csv"], 200, "e.csv"),
            (["simulate", "--energy", "3", "--trajectories", "50", "--time", "1", "--csv-dir", "cc"],
             500, "cc"),
            (["simulate", "--energy", "3", "--trajectories", "200", "--time", "1", "--checkpoint",
              "c.ckpt", "--checkpoint-interval", "0"], 300, "c.ckpt"),
            (["accuracy", "--out", "a.md", "--quantities", "omega", "--precisions", "double",
              "--min-seconds", "0.01"], 100, "a.md"),
            (["golden", "--out", "g", "--max-rows", "3", "--quantities", "omega", "--precision", "quad"],
             100, ("golden.csv", "provenance.json")),
            (["viewer", "--out", "v", "--energies", "1", "--samples", "8", "--grid", "7"], 1000,
             "viewer.html")]:
        P.append(P45(cls, args, io_error(text), rlimits={fsz: limit},
                     note=f"{' '.join(args)} (file size limit {limit} bytes: a full disk)"))

    # ---- special-destinations: atomic replacement only for regular files and new paths
    cls = "special-destinations"
    dests = [(["orbit", "--energy", "4", "--samples", "3", "--out"], "t,theta1"),
             (["trajectory", "--state", "1,2,0,0", "--time", "1", "--out"], "t,theta1"),
             (["trajectory", "--state", "1,2,0,0", "--time", "1", "--events"], "time,arm"),
             (["accuracy", "--quantities", "omega", "--precisions", "double", "--min-seconds",
               "0.01", "--out"], "omega")]
    for cmd, header in dests:
        what = f"{cmd[0]} {cmd[-1]}"
        # a character device like /dev/null (the issue's `mknod nul c 1 3`)
        P.append(P45(cls, cmd + ["nul"], either(refuse("nul"), ok()),
                     setup=lambda w, f: make_special(w, "nul", "null"),
                     after=lambda w: still_device(w, "nul", "null"), note=f"{what} nul (device 1,3)"))
        # a device that fails every write, like /dev/full
        P.append(P45(cls, cmd + ["full"], either(refuse("full"), io_error("full")),
                     setup=lambda w, f: make_special(w, "full", "full"),
                     after=lambda w: still_device(w, "full", "full"), note=f"{what} full (device 1,7)"))
        # a symlink to a regular file: followed (the target written) or refused; never replaced
        def link_setup(w, f):
            write(os.path.join(w, "target.csv"), "old\n")
            os.symlink("target.csv", os.path.join(w, "link"))
        P.append(P45(cls, cmd + ["link"], either(refuse("link"), ok(file_has("target.csv", header))),
                     setup=link_setup, after=still_link("link", "target.csv"),
                     note=f"{what} link -> target.csv"))
        # a symlink to a device
        def link_dev_setup(w, f):
            make_special(w, "nul", "null")
            os.symlink("nul", os.path.join(w, "lnul"))
        P.append(P45(cls, cmd + ["lnul"], either(refuse("lnul"), ok()), setup=link_dev_setup,
                     after=afters(still_link("lnul", "nul"), lambda w: still_device(w, "nul", "null")),
                     note=f"{what} lnul -> nul (device)"))
        # a FIFO with a reader: written in place (the reader gets it) or refused
        fr = FifoReader("fifo")
        P.append(P45(cls, cmd + ["fifo"], either(refuse("fifo"), ok(fr.got(header))), setup=fr.setup,
                     after=fr.finish, timeout=30, note=f"{what} fifo (with a reader)"))
        # what /dev/stdout is: a symlink to /proc/self/fd/1 (here a local one: never the system's)
        P.append(P45(cls, cmd + ["so"], either(refuse("so"), ok(stdout_has(header))),
                     setup=lambda w, f: os.symlink("/proc/self/fd/1", os.path.join(w, "so")),
                     after=still_link("so", "/proc/self/fd/1"), note=f"{what} so -> /proc/self/fd/1"))
    P.append(P45(cls, SIM + ["--checkpoint", "nul"], either(refuse("nul"), ok()),
                 setup=lambda w, f: make_special(w, "nul", "null"),
                 after=lambda w: still_device(w, "nul", "null"), note="simulate --checkpoint nul (device)"))

    # ---- special-inputs: every reader takes regular files only (or bounds its read), never
    # blocks on a FIFO
    cls = "special-inputs"

    def specials(w, f):
        os.mkfifo(os.path.join(w, "fifo"))
        make_special(w, "zero", "zero")
        os.symlink("zero", os.path.join(w, "zl"))
        os.symlink("/dev/urandom", os.path.join(w, "url"))
        write(os.path.join(w, "c.csv"), CAND_HEAD + OMEGA6)
        write(os.path.join(w, "r.csv"), EV_HEAD + "1.5,2,upright,1\n")
    for args, text in [(["run", "--dry-run", "/dev/zero"], "/dev/zero"),
                       (["run", "--dry-run", "/dev/urandom"], "/dev/urandom"),
                       (["run", "--dry-run", "zl"], "zl"),
                       (["run", "--dry-run", "fifo"], "fifo"),
                       (["run", "fifo"], "fifo"),
                       (["run", "url"], "url"),
                       (["validate", "fifo", "--allow-missing"], "fifo"),
                       (["validate", "zl", "--allow-missing"], "zl"),
                       (["validate", "url", "--allow-missing"], "url"),
                       (["validate", "--ensemble", "fifo"], "fifo"),
                       (["validate", "--ensemble", "zl"], "zl"),
                       (["validate", "--trajectories", "fifo", "--reference", "r.csv"], "fifo"),
                       (["validate", "--trajectories", "r.csv", "--reference", "fifo"], "fifo"),
                       (["validate", "--trajectories", "r.csv", "--reference", "zl"], "zl"),
                       (SIM + ["--checkpoint", "fifo"], "fifo"),
                       (SIM + ["--checkpoint", "zl"], "zl"),
                       (SIM + ["--checkpoint", "zero"], "zero")]:
        P.append(P45(cls, args, refuse(text, absent=(f"--{text}:",)), setup=specials, timeout=30))
    for kind, make in [("a FIFO", lambda p: os.mkfifo(p)),
                       ("-> zero", lambda p: (make_special(os.path.dirname(p), "zero", "zero"),
                                              os.symlink("../zero", p))),
                       ("-> /dev/urandom", lambda p: os.symlink("/dev/urandom", p))]:
        def golden_special(w, f, make=make):
            os.makedirs(os.path.join(w, "g"))
            make(os.path.join(w, "g", "golden.csv"))
            write(os.path.join(w, "c.csv"), CAND_HEAD + OMEGA6)
        P.append(P45(cls, ["validate", "c.csv", "--golden", "g"], refuse("golden.csv"),
                     setup=golden_special, timeout=30, note=f"validate --golden g: g/golden.csv {kind}"))

        def golden_existing(w, f, make=make, which="provenance.json"):
            golden_set(w, f)
            os.remove(os.path.join(w, "g", which))
            make(os.path.join(w, "g", which))
        for which in ["provenance.json", "golden.csv"]:
            P.append(P45(cls, ["golden", "--out", "g", "--certify-existing", "--precision", "quad"],
                         refuse(which),
                         setup=lambda w, f, make=make, which=which: golden_existing(w, f, make, which),
                         timeout=30, note=f"golden --certify-existing: g/{which} {kind}"))
    acc = (SCENE_HEAD + '[accuracy]\nout = "acc.md"\nquantities = ["omega"]\nprecisions = ["double"]\n'
           'max_seconds = 1\nappendices = ["{}"]\n')
    for app, setup in [("/dev/zero", None), ("/dev/urandom", None),
                       ("fifo", lambda w, f: os.mkfifo(os.path.join(w, "fifo"))),
                       ("zl", lambda w, f: (make_special(w, "zero", "zero"),
                                            os.symlink("zero", os.path.join(w, "zl"))))]:
        P += pair45(cls, f"[accuracy] appendices = [{app!r}]", acc.format(app), app, setup=setup)
    orbit_scene = SCENE_HEAD + '[orbits]\narms = [2]\nenergies = [3]\n'

    def cache_entry_special(make):
        def setup(work, flipflux):
            for entry in fill_orbit_cache(work, flipflux, orbit_scene):
                os.remove(entry)
                make(work, entry)
        return setup

    def rejected(out, work):
        with open(os.path.join(work, "out", "run.json")) as f:
            c = json.load(f).get("counters", {}).get("orbit_cache_rejected", 0)
        return None if int(c) >= 1 else f"orbit_cache_rejected = {c}"
    for kind, make in [("a FIFO", lambda w, p: os.mkfifo(p)),
                       ("-> zero", lambda w, p: (make_special(w, "zero", "zero"),
                                                 os.symlink(os.path.join(w, "zero"), p)))]:
        P.append(P45(cls, ["run", "s.toml", "--cache-dir", "cache"], ok(rejected),
                     setup=cache_entry_special(make), note=f"orbit cache entry {kind}"))

    # ---- toml-depth: the scene reader caps key and header depth (a stack overflow before)
    cls = "toml-depth"
    for name, body in [
            ("dotted key, 50000 parts", SCENE_HEAD + "a." * 50000 + "b = 1\n"),
            ("table header, 50000 parts", SCENE_HEAD + "[" + "a." * 50000 + "b]\nx = 1\n"),
            ("array-of-tables header, 50000 parts", SCENE_HEAD + "[[" + "a." * 50000 + "b]]\nx = 1\n"),
            ("quoted dotted key, 50000 parts", SCENE_HEAD + '"a".' * 50000 + "b = 1\n"),
            ("dotted key in an inline table, 50000 parts", SCENE_HEAD + "x = { " + "a." * 50000 + "b = 1 }\n"),
            ("dotted key, 5000 parts", SCENE_HEAD + "a." * 5000 + "b = 1\n"),
            ("dotted key, 300 parts", SCENE_HEAD + "a." * 300 + "b = 1\n"),
            ("table header, 300 parts", SCENE_HEAD + "[" + "a." * 300 + "b]\nx = 1\n")]:
        P += pair45(cls, name, body, "s.toml")

    # ---- orbit-cache-tamper: a resealed entry (valid checksum, a doubled value) is re-verified
    # on load and recomputed
    cls = "orbit-cache-tamper"

    def tamper(path_in_json):
        state = {}

        def setup(work, flipflux):
            write(os.path.join(work, "s.toml"), orbit_scene)
            subprocess.run([flipflux, "run", "s.toml", "--cache-dir", "cache"], cwd=work,
                           capture_output=True, timeout=300)
            shutil.rmtree(os.path.join(work, "out"), ignore_errors=True)
            entries = [os.path.join(d, n) for d, _, ns in os.walk(os.path.join(work, "cache")) for n in ns]
            if len(entries) != 1:
                raise RuntimeError(f"{len(entries)} cache entries, expected 1")
            with open(entries[0]) as f:
                text = f.read()
            j = json.loads(text)
            seal = j.pop("checksum")
            if fnv1a64_hex(json.dumps(j, separators=(",", ":"))) != seal:
                raise RuntimeError("cannot reproduce the entry's checksum (the record format changed)")
            node = j
            for k in path_in_json[:-1]:
                node = node[k]
            state["orig"] = node[path_in_json[-1]]
            node[path_in_json[-1]] = repr(float(state["orig"]) * 2)
            j["checksum"] = fnv1a64_hex(json.dumps(j, separators=(",", ":")))
            with open(entries[0], "w") as f:
                f.write(json.dumps(j, separators=(",", ":")) + ("\n" if text.endswith("\n") else ""))

        column = path_in_json[-1]  # the orbits-arm2.csv column of the tampered field

        def check(out, work):
            msg = rejected(out, work)
            if msg:
                return msg + " (the tampered entry was believed)"
            import csv
            with open(os.path.join(work, "out", "orbits-arm2.csv")) as f:
                row = next(csv.DictReader(f))
            if column in row and row[column] not in ("", None):
                v, o = mp.mpf(row[column]), mp.mpf(state["orig"])
                if abs(v - o) > 1e-10 * abs(o):
                    return f"{column} = {row[column]} in orbits-arm2.csv, the untampered entry has {state['orig']}"
            return None
        return setup, check
    for field in [("action",), ("period",), ("period_derivative",), ("floquet", "multiplier"),
                  ("floquet", "stability_index")]:
        setup, check = tamper(field)
        P.append(P45(cls, ["run", "s.toml", "--cache-dir", "cache"], ok(check), setup=setup,
                     note=f"orbit cache entry with {'.'.join(field)} doubled and resealed"))

    # ---- huge-angles: reduced exactly from the decimal text, or refused with the bound named
    cls = "huge-angles"
    for state, T in [("1e17,0,0,0", "5"), ("1e10,0,0,0", "5"),
                     ("1e17," + ",".join(FLIPPING_STATE), "5"), ("-1e17," + ",".join(FLIPPING_STATE), "5"),
                     ("1e10," + ",".join(FLIPPING_STATE), "5"),
                     ("0.5,1e17,0.5,1", "5"),
                     ("123456789012345678901234567890.5," + ",".join(FLIPPING_STATE), "5"),
                     ("1e300," + ",".join(FLIPPING_STATE), "5")]:
        args = ["trajectory", "--state", state, "--time", T]
        P.append(P45(cls, args, either(refuse("--state"), ok(same_events_as(args)))))
    args = ["trajectory", "--state", "1e17," + ",".join(FLIPPING_STATE), "--time", "2", "--precision", "quad"]
    P.append(P45(cls, args, either(refuse("--state"), ok(same_events_as(args)))))
    P += pair45(cls, "[[trajectory]] state angle 1e17",
                SCENE_HEAD + '[[trajectory]]\nname = "x"\nstate = [1e17, 2.5, 0.5, 1]\ntime = 5\n',
                "state", dry=either(refuse("state"), ok()), full=either(refuse("state"), ok()))

    # ---- precision-bound: an estimate first, a --max-seconds bound whose default refuses the
    # absurd
    cls = "precision-bound"
    bound = ("--precision", "--max-seconds")
    for args in [["eval", "omega", "--energy", "3", "--precision", "mp:20000"],
                 ["eval", "rate-upright", "--arm", "2", "--energy", "5", "--precision", "mp:10001"],
                 ["eval", "omega", "--energy", "3", "--precision", "mp:1000000"],
                 ["eval", "period", "--arm", "2", "--energy", "4", "--precision", "mp:5000"],
                 ["trajectory", "--state", "1,2,0,0", "--time", "1", "--precision", "mp:100000"]]:
        P.append(P45(cls, args, either(refuse(bound, absent=("not expected",)), ok())))
    P.append(P45(cls, ["eval", "omega", "--energy", "3", "--precision", "mp:20000", "--max-seconds", "1"],
                 refuse("--max-seconds", absent=("not expected",)),
                 note="eval omega mp:20000 --max-seconds 1 (the estimate exceeds the bound)"))

    # ---- no-files-before-checks: every option checked before a file or folder is created
    cls = "no-files-before-checks"
    for args, text in [(SIM + ["--sample-interval", "-1", "--csv-dir", "c"], "--sample-interval"),
                       (SIM + ["--csv-dir", "c", "--bins", "-1"], "--bins"),
                       (SIM + ["--csv-dir", "c", "--rtol", "0"], "--rtol"),
                       (SIM + ["--csv-dir", "c", "--criteria", "bogus"], "bogus"),
                       (["simulate", "--energy", "3", "--trajectories", "2", "--time", "-1",
                         "--csv-dir", "c/d"], "--time"),
                       (SIM + ["--checkpoint", "c/x.ckpt", "--seed", "-1"], "--seed"),
                       (SIM + ["--checkpoint", "c/x.ckpt", "--csv-dir", "c/d", "--threads", "-1"], "--threads"),
                       (TRAJ + ["--out", "c/s.csv", "--rtol", "0"], "--rtol"),
                       (TRAJ + ["--events", "c/e.csv", "--criteria", "bogus"], "bogus"),
                       (TRAJ + ["--out", "c/s.csv", "--sample-interval", "-1"], "--sample-interval"),
                       (["orbit", "--energy", "4", "--out", "c/o.csv", "--samples", "1"], "--samples"),
                       (["orbit", "--energy", "1", "--out", "c/o.csv"], "--energy"),
                       (["accuracy", "--out", "c/a.md", "--min-seconds", "-1"], "--min-seconds"),
                       (["accuracy", "--out", "c/a.md", "--quantities", "bogus"], "bogus"),
                       (["golden", "--out", "c", "--precision", "mp:0"], "--precision"),
                       (["golden", "--out", "c", "--quantities", "bogus"], "bogus"),
                       (["viewer", "--out", "c", "--samples", "1"], "--samples")]:
        P.append(P45(cls, args, refuse(text), forbid=["c"]))
    P += pair45(cls, "scene output with a bad ensemble", SCENE_HEAD.replace('"out"', '"o/p"') +
                '[[ensemble]]\nname = "a"\narm = 2\ncriteria = ["upright"]\nenergies = [3]\n'
                'trajectories = 2\ntime = -1\n', "time")

    # ---- number-grammar: one number grammar; underflow to 0 and overflow to inf refused
    cls = "number-grammar"
    acc_cmd = ["accuracy", "--out", "a.md", "--quantities", "omega", "--precisions", "double"]
    ev = {"c.csv": EV_HEAD + "1.5,2,upright,1\n"}
    cand = {"c.csv": CAND_HEAD + OMEGA6}
    for args, text, files in [
            (SIM + ["--reference-time", "1e-400"], "--reference-time", {}),
            (acc_cmd + ["--min-seconds", "1e-400"], "--min-seconds", {}),
            (["validate", "c.csv", "--rtol", "4.9e-324"], "--rtol", cand),
            (["validate", "c.csv", "--rtol", "1e-400"], "--rtol", cand),
            (["simulate", "--energy", "3", "--trajectories", "2", "--time", "1e-400"], "--time", {}),
            (["trajectory", "--state", "1,2,0,0", "--time", "1e-400"], "--time", {}),
            (SIM + ["--sample-interval", "1e-400", "--csv-dir", "c"], "--sample-interval", {}),
            (SIM + ["--chaos-threshold", "1e-400"], "--chaos-threshold", {}),
            (SIM + ["--checkpoint", "c.ckpt", "--checkpoint-interval", "1e-400"], "--checkpoint-interval", {}),
            (SIM + ["--estimator", "short", "--short-time", "1e-400"], "--short-time", {}),
            (["run", "--checkpoint-interval", "1e-400", "--dry-run", DEFAULT_SCENE], "--checkpoint-interval", {}),
            (["run", "--checkpoint-interval", "1e400", "--dry-run", DEFAULT_SCENE], "--checkpoint-interval", {}),
            (acc_cmd + ["--max-seconds", "1e-400"], "--max-seconds", {}),
            (acc_cmd + ["--max-seconds", "1e400"], "--max-seconds", {}),
            (acc_cmd + ["--min-seconds", "1e400"], "--min-seconds", {}),
            (["validate", "--trajectories", "c.csv", "--reference", "c.csv", "--time-tol", "1e-400"],
             "--time-tol", ev),
            (["validate", "--trajectories", "c.csv", "--reference", "c.csv", "--until", "1e-400"],
             "--until", ev),
            (["validate", "--trajectories", "c.csv", "--reference", "c.csv", "--time-tol", "1e400"],
             "--time-tol", ev),
            (["eval", "omega", "--energy", "3", "--m2", "1e-400"], "--m2", {}),
            (["eval", "omega", "--energy", "1e-400"], "--energy", {}),
            (["eval", "rate-upright", "--energy", "4.9e-324"], "--energy", {})]:
        P.append(P45(cls, args, refuse(text), files=files, forbid=["c", "a.md", "c.ckpt"]))
    ens = (SCENE_HEAD + '[[ensemble]]\nname = "a"\narm = 2\ncriteria = ["upright"]\nenergies = [3]\n'
           'trajectories = 2\ntime = 1\n')
    P += pair45(cls, "ensemble reference_time = 1e-400", ens + "reference_time = 1e-400\n", "reference_time")
    P += pair45(cls, "ensemble time = \"1e-400\"", ens.replace("time = 1\n", 'time = "1e-400"\n'), "time")
    P += pair45(cls, "ensemble rtol = 4.9e-324", ens + "rtol = 4.9e-324\n", "rtol")
    P += pair45(cls, "trajectory time = 1e-400", SCENE_HEAD + '[[trajectory]]\nname = "x"\n'
                'state = [1, 2, 0, 0]\ntime = 1e-400\n', "time")

    # ---- integer-grammar: one integer grammar for every option
    cls = "integer-grammar"
    for opt_args, opt in [(["run", "--dry-run", DEFAULT_SCENE, "--threads"], "--threads"),
                          (["run", "--dry-run", DEFAULT_SCENE, "--checkpoint-interval"], "--checkpoint-interval"),
                          (["golden", "--out", "g", "--max-rows", "1", "--quantities", "omega",
                            "--precision", "quad", "--jobs"], "--jobs"),
                          (acc_cmd + ["--min-seconds", "0.01", "--threads"], "--threads"),
                          (acc_cmd + ["--min-seconds"], "--min-seconds"),
                          (acc_cmd + ["--max-seconds"], "--max-seconds"),
                          (SIM + ["--threads"], "--threads"),
                          (SIM + ["--seed"], "--seed"),
                          (SIM + ["--bins"], "--bins"),
                          (SIM + ["--first-index"], "--first-index"),
                          (SIM + ["--replicates"], "--replicates"),
                          (["orbit", "--energy", "4", "--samples"], "--samples"),
                          (["viewer", "--out", "v", "--samples", "8", "--grid", "7", "--energies"], "--energies"),
                          (["golden", "--out", "g", "--quantities", "omega", "--precision", "quad",
                            "--max-rows"], "--max-rows")]:
        for v in ["0x10", "0b11", "0o7"]:
            if opt in ("--samples", "--energies") and v == "0x10":
                v = "0x3"
            P.append(P45(cls, opt_args + [v], refuse(opt, absent=("17976931348623157",)),
                         forbid=["g", "a.md", "v"], note=f"{opt_args[0]} {opt} {v}"))
    P.append(P45(cls, ["run", "--dry-run", DEFAULT_SCENE, "--threads", "1e1"], refuse("--threads")))
    P.append(P45(cls, SIM + ["--trajectories", "0x2"], refuse("--trajectories"), note="simulate --trajectories 0x2"))

    # ---- control-chars: offending text quoted with control characters escaped, one line
    cls = "control-chars"
    for args, text in [(["eval", "omega", "--energy", "3\nflipflux: ok"], "--energy"),
                       (["eval", "omega", "--energy", "3\rflipflux: ok"], "--energy"),
                       (["eval", "omega", "--energy", "3\x1b[2J"], "--energy"),
                       (["eval", "omega", "--energy", "3\x7f"], "--energy"),
                       (["eval", "omega", "--energy", "3\u0085flipflux: ok"], "--energy"),
                       (["eval", "omega", "--energy", "3\tx"], "--energy"),
                       (["eval", "omega\nflipflux: ok", "--energy", "3"], "omega"),
                       (["evall\nflipflux: ok"], "evall"),
                       (["eval", "omega", "--energy", "3", "--precision", "mp:\n5"], "--precision"),
                       (SIM + ["--criteria", "upright,\nbogus"], "bogus"),
                       (["run", "no\nsuch.toml"], "no"),
                       (["eval", "omega", "--energy", "3", "--foo\nflipflux: ok"], "--foo")]:
        P.append(P45(cls, args, refuse(text, clean=True)))
    P.append(P45(cls, ["validate", "c.csv"], refuse("c.csv", clean=True),
                 files={"c.csv": "quantity\x1b[2J,arm,energy,value\nomega,,6.5,1\n"},
                 note="candidate header with an escape sequence"))
    P.append(P45(cls, ["validate", "c.csv", "--golden", "g"], refuse("golden.csv", clean=True),
                 files={"c.csv": CAND_HEAD + OMEGA6,
                        **golden_dir("omega,,6.5\r\x1b[2J,301.63,30,m\n")},
                 note="golden row with control characters"))
    for name, body in [("key with a newline", SCENE_HEAD + '"a\\nflipflux: ok" = 1\n'),
                       ("energy string with a newline", SCENE_HEAD + '[predictions]\nquantities = ["omega"]\n'
                        'energies = ["3\\nflipflux: ok"]\n'),
                       ("ensemble name with an escape", SCENE_HEAD + '[[ensemble]]\nname = "a\\u001b[2J"\n'
                        'arm = 2\ncriteria = ["upright"]\nenergies = [3]\ntrajectories = 2\ntime = 1\n')]:
        for p in pair45(cls, name, body, "s.toml"):
            p.expect = refuse("s.toml", clean=True)
            P.append(p)

    # ---- duplicate-energies: refused, or merged with a note
    cls = "duplicate-energies"

    @with_err
    def merged(out, work, err):
        n = len(json.loads(out)["energies"])
        if n != 1:
            return f"{n} ensembles computed for one energy"
        return None if re.search(r"note|warning", err, re.I) else "merged without a note on stderr"
    for energies, named in [("3,3.0", "3.0"), ("3,3", "3"), ("3,3.00000000000000001", "3.00000000000000001"),
                            ("3,30e-1", "30e-1"), ("3.0,3", "3")]:
        P.append(P45(cls, ["simulate", "--energy", energies, "--trajectories", "2", "--time", "1",
                           "--no-timing"], either(refuse(named), ok(merged))))
    P += pair45(cls, "ensemble energies [3, 3.0]", ens.replace("energies = [3]", "energies = [3, 3.0]"), "twice")
    P += pair45(cls, "orbits energies [3, 3.0]", SCENE_HEAD + '[orbits]\narms = [2]\nenergies = [3, 3.0]\n',
                "twice", extra=("--no-cache",))
    P += pair45(cls, "predictions energies '3' and '3.(41 zeros)1': one energy in mp:30",
                SCENE_HEAD + 'precision = "mp:30"\n[predictions]\nquantities = ["omega"]\n'
                'energies = ["3", "3.000000000000000000000000000000000000000001"]\n', "twice",
                dry=either(refuse("twice"), ok()), full=either(refuse("twice"), ok()))

    # ---- extreme-parameters: computed correctly, or refused naming the parameter
    cls = "extreme-parameters"
    for args, param in [(SIM + ["--m1", "2e-16"], "--m1"),
                        (TRAJ + ["--m1", "2e-16"], "--m1"),
                        (["simulate", "--energy", "1", "--trajectories", "2", "--time", "1", "--criteria",
                          "upright", "--m2", "2e-16"], "--m2"),
                        (SIM + ["--L1", "2e-16"], "--L1"),
                        (SIM + ["--a2", "2e-16"], "--a2"),
                        (SIM + ["--m1", "1e-300"], "--m1"),
                        (TRAJ + ["--g", "1e-16"], "--g"),
                        (TRAJ + ["--I1", "1e16"], "--I1"),
                        (["eval", "rate-upright", "--arm", "2", "--energy", "3", "--m1", "2e-16"], "--m1"),
                        (["orbit", "--energy", "3", "--samples", "3", "--m1", "2e-16"], "--m1")]:
        # the parameter named, or the pendulum's parameters together (a mass matrix too
        # ill-conditioned for the precision); never an infinite bound
        P.append(P45(cls, args, either(refuse((param, "pendulum:"), absent=(" inf ",)), ok())))

    # ---- output-collisions: the plan knows every path it writes, refuses collisions before
    # computing
    cls = "output-collisions"
    traj = '[[trajectory]]\nname = "{}"\nstate = [1.4, 2.2, 0.2, 0.8]\ntime = 1\n'
    ens_n = ('[[ensemble]]\nname = "{}"\narm = 2\ncriteria = ["upright"]\nenergies = [3]\n'
             'trajectories = 2\ntime = 1\nseed = {}\n')
    acc_out = '[accuracy]\nout = "{}"\nquantities = ["omega"]\nprecisions = ["double"]\nmax_seconds = 1\n'
    for name, body, text in [
            ("trajectories x and x-events", SCENE_HEAD + traj.format("x") + traj.format("x-events"), "x-events"),
            ("accuracy.out = out/run.json", SCENE_HEAD + acc_out.format("out/run.json"), "run.json"),
            ("accuracy.out = out/predictions.csv", SCENE_HEAD + acc_out.format("out/predictions.csv") +
             '[predictions]\nquantities = ["omega"]\nenergies = [3]\n', "predictions.csv"),
            ("accuracy.out = out/./run.json", SCENE_HEAD + acc_out.format("out/./run.json"), "run.json"),
            ("ensembles a and a.json", SCENE_HEAD + ens_n.format("a", 1) + ens_n.format("a.json", 2), "a.json"),
            ("accuracy.out = out/ensemble-a.json", SCENE_HEAD + acc_out.format("out/ensemble-a.json") +
             ens_n.format("a", 1), "ensemble-a.json"),
            ("accuracy.out = out/trajectory-x.csv", SCENE_HEAD + acc_out.format("out/trajectory-x.csv") +
             traj.format("x"), "trajectory-x.csv"),
            ("golden.dir = out/ensemble-a (the ensemble's CSV folder)", SCENE_HEAD + ens_n.format("a", 1) +
             '[golden]\ndir = "out/ensemble-a"\nquantities = ["omega"]\nprecision = "quad"\n', "ensemble-a")]:
        P += pair45(cls, name, body, text)
    for args, text, setup in [
            (TRAJ + ["--out", "f.csv", "--events", "f.csv"], "f.csv", None),
            (TRAJ + ["--out", "f.csv", "--events", "./f.csv"], "f.csv", None),
            (TRAJ + ["--out", "f.csv", "--events", "sub/../f.csv"], "f.csv",
             lambda w, f: os.mkdir(os.path.join(w, "sub"))),
            (SIM + ["--csv-dir", "d", "--checkpoint", "d/trajectories_E3.csv"], "trajectories_E3.csv", None),
            (SIM + ["--csv-dir", ".", "--checkpoint", "trajectories_E3.csv"], "trajectories_E3.csv", None),
            (SIM + ["--csv-dir", "d", "--checkpoint", "d/rate_histogram_E3_upright.csv"],
             "rate_histogram_E3_upright.csv", None),
            (SIM + ["--csv-dir", "d", "--checkpoint", "d"], "d", None)]:
        P.append(P45(cls, args, refuse(text), setup=setup, forbid=["f.csv", "d", "trajectories_E3.csv"]))

    # ---- dry-run-parity: run --dry-run refuses what run would refuse, in the scene's terms
    cls = "dry-run-parity"
    viewer = SCENE_HEAD + '[viewer]\narms = [2]\nenergies_per_arm = 1\nsamples = 8\ngrid = 7\n'
    P += pair45(cls, "out/viewer.html is a folder", viewer, "viewer.html",
                setup=lambda w, f: os.makedirs(os.path.join(w, "out", "viewer.html")), extra=("--no-cache",))
    P += pair45(cls, "out/trajectory-x-events.csv is a folder", SCENE_HEAD + traj.format("x"),
                "trajectory-x-events.csv",
                setup=lambda w, f: os.makedirs(os.path.join(w, "out", "trajectory-x-events.csv")))
    P += pair45(cls, "[[trajectory]] sample_interval = 1e-300", SCENE_HEAD + traj.format("x") +
                "sample_interval = 1e-300\n", "sample_interval", absent=("--sample-interval",))
    P += pair45(cls, "[[trajectory]] time = 1e300", SCENE_HEAD + traj.format("x").replace("time = 1", "time = 1e300"),
                "time", absent=("--time",))
    P += pair45(cls, "[[trajectory]] state angle 1e300", SCENE_HEAD +
                traj.format("x").replace("[1.4,", "[1e300,"), "state",
                dry=either(refuse("state", absent=("--state",)), ok()),
                full=either(refuse("state", absent=("--state",)), ok()))
    P += pair45(cls, "missing appendix", acc.format("missing.md"), "missing.md")
    P += pair45(cls, "appendix is a folder", acc.format("dir"), "dir",
                setup=lambda w, f: os.mkdir(os.path.join(w, "dir")))
    P += pair45(cls, "accuracy.out is a folder", SCENE_HEAD + acc_out.format("d"), "d",
                setup=lambda w, f: os.mkdir(os.path.join(w, "d")))
    P += pair45(cls, "golden.dir/golden.csv is a folder", SCENE_HEAD +
                '[golden]\ndir = "gd"\nquantities = ["omega"]\nprecision = "quad"\n', "golden.csv",
                setup=lambda w, f: os.makedirs(os.path.join(w, "gd", "golden.csv")))
    P += pair45(cls, "report script missing", SCENE_HEAD + '[predictions]\nquantities = ["omega"]\n'
                'energies = [3]\n[report]\ndir = "r"\n', "report", env={"FLIPFLUX_REPORT_SCRIPT": "/nonexistent/make_report.py"})
    P += pair45(cls, "ensemble sample count beyond memory via replicates", SCENE_HEAD +
                ens_n.format("a", 1).replace("trajectories = 2", "trajectories = 1000000000") +
                "replicates = 1000\n", "trajectories")

    # ---- beyond-double: numbers beyond double's range where the precision reaches them;
    # scale-free parameters that do not overflow
    cls = "beyond-double"
    omega_big = lambda: omega_ref(7, 40)
    for E in ["1e400", "1e4000"]:
        P.append(P45(cls, ["eval", "omega", "--energy", E, "--precision", "quad"],
                     either(refuse((E, "e+" + E.split("e")[1])), ok(close_to(omega_big, 1e-30)))))
    P.append(P45(cls, ["eval", "omega", "--energy", "1e5000", "--precision", "quad"],
                 either(refuse(("1e5000", "e+5000")), ok(close_to(omega_big, 1e-30))),
                 note="omega E = 1e5000 in quad (beyond its range: Omega is constant above E_max)"))
    P.append(P45(cls, ["eval", "rate-upright", "--arm", "2", "--energy", "1e400", "--precision", "quad"],
                 either(refuse(("1e400", "e+400")), ok(close_to(lambda: flux_upright_arm2_ref("1e400", 40) /
                                                     omega_ref(7, 40), 1e-30)))))
    P.append(P45(cls, ["eval", "omega", "--energy", "1e-400", "--precision", "quad"],
                 ok(close_to(lambda: 2 * mp.sqrt(2) * mp.pi**2 * mp.mpf("1e-400"), 1e-30))))
    P.append(P45(cls, ["trajectory", "--state", "1,2,1e400,0", "--time", "1", "--precision", "quad"],
                 refuse("--"), note="trajectory momentum 1e400 in quad: a bound, not an internal error"))
    for scale in ["1e30", "1e-30", "1e150", "1e-150"]:
        args = ["model"] + [x for k in ["--m1", "--m2", "--L1", "--L2", "--g"] for x in (k, scale)]
        P.append(P45(cls, args, either(refuse("--"), ok(modes_as_default)), note=f"model, m, L, g all {scale}"))
    P.append(P45(cls, ["model", "--m1", "1e30", "--m2", "1e30", "--L1", "1e30", "--L2", "1e30", "--g", "1e30",
                       "--precision", "quad"], ok(modes_as_default), note="model, m, L, g all 1e30 in quad"))
    P.append(P45(cls, ["model", "--L1", "1e30", "--L2", "1e30", "--g", "1e30"], either(refuse("--"), ok(modes_as_default)),
                 note="model, L and g 1e30"))
    P.append(P45(cls, ["eval", "rate-upright", "--arm", "2", "--energy", "3e-30", "--m1", "1e-30", "--m2", "1e-30"],
                 either(refuse("--"), ok(close_to(lambda: flux_upright_arm2_ref(3) / omega_ref(3), 1e-12))),
                 note="rate-upright with masses 1e-30 at E = 3e-30 (= the paper's E = 3)"))

    # ---- unbounded-work: bounded, or refused, within 60 s
    cls = "unbounded-work"
    for m in [("--m1", "1e-8"), ("--m1", "1e-6"), ("--m2", "1e-8")]:
        args = ["eval", "omega", "--energy", "3", *m]
        P.append(P45(cls, args + ["--method", "quadrature-2d"],
                     either(refuse((m[0], "quadrature-2d", "--method")),
                            ok(within_estimate(lambda args=args: flipflux_value(args)))),
                     note=f"omega quadrature-2d {m[0]} {m[1]} (against the elliptic method, within "
                          "its error estimate)"))
    P.append(P45(cls, ["validate", "c.csv", "--allow-missing"], either(refuse("c.csv"), status((0, 1))),
                 setup=lambda w, f: write(os.path.join(w, "c.csv"),
                                          CAND_HEAD + "omega,,6.5,301.63072729295795" + "1" * 4_000_000 + "\n"),
                 note="candidate value of 4 million digits"))
    P.append(P45(cls, ["validate", "c.csv", "--allow-missing"], either(refuse("c.csv"), status((0, 1))),
                 setup=lambda w, f: write(os.path.join(w, "c.csv"),
                                          CAND_HEAD + "omega,,6." + "4" * 4_000_000 + ",301.63\n"),
                 note="candidate energy of 4 million digits"))
    P.append(P45(cls, ["validate", "c.csv", "--allow-missing"], either(refuse("c.csv"), status((0, 1))),
                 setup=lambda w, f: write(os.path.join(w, "c.csv"), CAND_HEAD + "".join(
                     "omega,,6.5,301.63072729295795" + "1" * 100_000 + "\n" for _ in range(40))),
                 note="candidate: 40 rows of 100,000 digits"))
    for args in [["simulate", "--energy", "1:2:0.00001", "--trajectories", "2", "--time", "1"],
                 ["simulate", "--energy", "0.00001:1.00001:0.00001", "--trajectories", "2", "--time", "1"]]:
        P.append(P45(cls, args, refuse("--energy"), note=f"simulate --energy {args[2]} (100,001 energies)"))
    P += pair45(cls, "predictions grid of 100,001 energies", SCENE_HEAD +
                '[predictions]\nquantities = ["omega"]\nenergies = { from = 1, to = 2, step = 0.00001 }\n', "energies")
    P += pair45(cls, "ensemble grid of 100,001 energies", ens.replace(
        "energies = [3]", "energies = { from = 1, to = 2, step = 0.00001 }"), "energies")

    # ---- environment-failures: reported as what they are, never "internal error"
    cls = "environment-failures"
    P.append(P45(cls, ["run", "s.toml"], io_error("predictions.csv"), rlimits={fsz: 500},
                 files={"s.toml": SCENE_HEAD + '[predictions]\nquantities = ["omega"]\n'
                        'energies = { from = 0.1, to = 5, step = 0.1 }\n'},
                 note="run with a full disk (file size limit 500 bytes)"))
    P.append(P45(cls, ["run", "s.toml"], io_error(("ensemble-a", "checkpoint")), rlimits={fsz: 300},
                 files={"s.toml": ens.replace("trajectories = 2", "trajectories = 200")},
                 note="run an ensemble with a full disk (file size limit 300 bytes)"))
    for which in ["golden.csv", "provenance.json"]:
        P.append(P45(cls, ["golden", "--out", "g", "--max-rows", "1", "--quantities", "omega",
                           "--precision", "quad"], refuse(which),
                     setup=lambda w, f, which=which: os.makedirs(os.path.join(w, "g", which)),
                     note=f"golden --out g with g/{which} a folder"))
    P.append(P45(cls, ["run", "s.toml"], fails(1, "report"),
                 files={"s.toml": SCENE_HEAD + '[predictions]\nquantities = ["omega"]\nenergies = [3]\n'
                        '[report]\ndir = "r"\n', "fail.py": "import sys\nsys.exit(1)\n"},
                 setup=lambda w, f: None, env={"FLIPFLUX_REPORT_SCRIPT": "fail.py"},
                 note="a failing report script (exit 1): one line, not an internal error"))
    for name, garbage in [("hello", "hello\n"), ("binary", "\x00\x01\x02\xff\x00\x01"), ("empty", ""),
                          ("wrong header", "a,b,c,d,e,f\n")]:
        def garbage_setup(w, f, garbage=garbage):
            golden_set(w, f)
            write(os.path.join(w, "g", "golden.csv"), garbage)

        def unchanged(w, garbage=garbage):
            with open(os.path.join(w, "g", "golden.csv"), errors="surrogateescape") as fh:
                return None if fh.read() == garbage else "g/golden.csv was rewritten"
        P.append(P45(cls, ["golden", "--out", "g", "--certify-existing", "--precision", "quad"],
                     refuse("golden.csv"), setup=garbage_setup, after=unchanged,
                     note=f"golden --certify-existing, golden.csv {name}"))
    for name, row in [("energy 1e400", "omega,,1e400,301.63,30,m\n"),
                      ("energy 1e99999", "omega,,1e99999,301.63,30,m\n"),
                      ("energy -1e400", "omega,,-1e400,301.63,30,m\n")]:
        P.append(P45(cls, ["validate", "c.csv", "--golden", "g"], refuse("golden.csv:2"),
                     files={"c.csv": CAND_HEAD + OMEGA6, **golden_dir(row)}, note=f"golden row {name}"))

    def planted(w, f):
        os.makedirs(os.path.join(w, "out"))
        os.makedirs(os.path.join(os.path.dirname(w), "elsewhere"))
        os.symlink("../../elsewhere", os.path.join(w, "out", "ensemble-a"))

    def elsewhere_empty(out, work):
        left = os.listdir(os.path.join(os.path.dirname(work), "elsewhere"))
        return f"wrote through the planted symlink: {left[:3]}" if left else None
    P += pair45(cls, "symlink planted: out/ensemble-a -> ../../elsewhere", ens, "ensemble-a", setup=planted,
                dry=either(refuse("ensemble-a"), ok()), full=either(refuse("ensemble-a"), ok(elsewhere_empty)))
    for args, typo in [(["eval", "omega", "--energyy", "3"], "--energyy"),
                       (["eval", "omega", "--energy", "3", "--precison", "mp:30"], "--precison"),
                       (["orbit", "--energyy", "4"], "--energyy"),
                       (["simulate", "--energy", "3", "--trajectories", "2", "--tme", "1"], "--tme"),
                       (["trajectory", "--stat", "1,2,0,0", "--time", "1"], "--stat")]:
        P.append(P45(cls, args, refuse(typo)))
    return P


# ---------------------------------------------------------------- issue 44: the simulator-validation features

GOLDEN_TRAJECTORIES = os.path.join(ROOT, "data/golden/trajectories")
ST_HEAD = "t,theta1,theta2,l1,l2\n"  # a candidate's states (validate --states)
# the valid base of the initial-states and paired probes (the command of docs/validating.md, small)
INIT_CMD = ["simulate", "--energy", "5", "--trajectories", "4", "--time", "2", "--arm", "both",
            "--criteria", "upright", "--no-chaos"]
E1_STATES = ("trajectory,energy,theta1,theta2,l1,l2\n"  # H = 1 - cos(pi/2): below both arms' thresholds
             "0,1,0,1.5707963267948966,0,0\n1,1,0,-1.5707963267948966,0,0\n")
E3_STATE = "9,3,0,0,2.449489742783178,0"  # H = l1^2 / 2 = 3


def golden_trajectory(state, which):
    """The golden reference of `state` as a candidate writes it: which = "events" (CSV time, arm,
    criterion, direction) or "states" (CSV t, theta1, theta2, l1, l2)."""
    with open(os.path.join(GOLDEN_TRAJECTORIES, which + ".csv")) as f:
        lines = [l.rstrip("\n") for l in f if not l.startswith("#")]
    head = lines[0].split(",")
    cols = (EV_HEAD if which == "events" else ST_HEAD).strip().split(",")
    rows = [l.split(",") for l in lines[1:] if l.startswith(state + ",")]
    return ",".join(cols) + "\n" + "".join(",".join(r[head.index(c)] for c in cols) + "\n" for r in rows)


def edit_csv(drop=(), row=0, extra=None, **fields):
    """A mangle of a CSV text (its `#` lines kept): the columns `drop` removed, `fields` (column ->
    text) set in data row `row` (0: the first), `extra` appended to that row as one more field."""
    def mangle(text):
        out, head, k = [], None, 0
        for line in text.splitlines():
            if line.startswith("#"):
                out.append(line)
                continue
            cells = line.split(",")
            if head is None:
                head = cells
            else:
                if k == row:
                    for name, v in fields.items():
                        cells[head.index(name)] = v
                k += 1
            kept = [c for i, c in enumerate(cells) if i >= len(head) or head[i] not in drop]
            if head is not cells and k - 1 == row and extra is not None:
                kept.append(extra)
            out.append(",".join(kept))
        return "\n".join(out) + "\n"
    return mangle


def paired_candidate(text):
    """The paired candidate (docs/validating.md) of an initial-states file: each state with time 2,
    arm 2, criterion upright and no flips (what flipflux counts on INIT_CMD's states)."""
    out = []
    for line in text.splitlines():
        out.append(line if line.startswith("#") else
                   line + (",time,arm,criterion,flips" if line.startswith("trajectory,") else ",2,2,upright,0"))
    return "\n".join(out) + "\n"


def initial_states_setup(name="init.csv", mangle=None, paired=False):
    """Writes `name` in the work folder: the initial states flipflux writes for INIT_CMD (a
    `# pendulum:` line, the header, 4 states at E = 5: data rows from line 3), as a paired
    candidate when asked, passed through mangle(text)."""
    def setup(work, flipflux):
        r = subprocess.run([flipflux] + INIT_CMD + ["--write-initial-states", "base.csv"], cwd=work,
                           capture_output=True, timeout=120)
        if r.returncode != 0:
            raise RuntimeError(f"initial states: {r.stderr.decode()[:200]}")
        with open(os.path.join(work, "base.csv")) as f:
            text = f.read()
        os.remove(os.path.join(work, "base.csv"))
        if paired:
            text = paired_candidate(text)
        write(os.path.join(work, name), mangle(text) if mangle else text)
    return setup


def pasted_constants_finite(out, work):
    """A check: every coefficient of the pasted C or Python block is a finite double, nonzero
    unless its text is zero (a constant beyond double's range pastes as inf or 0)."""
    consts = re.findall(r"^(?:static const double )?(A|B|C|alpha|beta|D0) = ([^;#\s]+)", out, re.M)
    if not consts:
        return "no coefficients in the output"
    for name, text in consts:
        x = float(text)
        if x != x or x in (float("inf"), float("-inf")) or (x == 0 and mp.mpf(text) != 0):
            return f"{name} = {text} is {x!r} as a double (the pasted code computes with inf or 0)"
    return None


def python_block_ok(out, work):
    """A check: the Python block parses and defines hamiltonian() and rhs()."""
    import ast
    try:
        tree = ast.parse(out)
    except SyntaxError as e:
        return f"the Python block does not parse: {e}"
    defs = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    return None if {"hamiltonian", "rhs"} <= defs else f"the Python block defines {sorted(defs)}"


def probes_issue44():
    P = []
    fsz = resource.RLIMIT_FSIZE

    # ---- model-equations: model --equations [--language text|c|python]
    cls = "model-equations"
    EQ = ["model", "--equations"]
    P.append(P45(cls, EQ, ok(stdout_has("Hamilton's equations"))))
    P.append(P45(cls, EQ + ["--language", "text"], ok(stdout_has("Hamilton's equations"))))
    P.append(P45(cls, EQ + ["--language", "c"], ok(stdout_has("static void rhs"))))
    P.append(P45(cls, EQ + ["--language", "python"], ok(python_block_ok)))
    P.append(P45(cls, EQ + ["--precision", "quad"], ok(stdout_has("Hamilton's equations"))))
    for lang in [None, "python"]:
        args = EQ + ["--precision", "mp:30"] + (["--language", lang] if lang else [])
        P.append(P45(cls, args, ok(python_block_ok if lang else stdout_has("Hamilton's equations")),
                     note=" ".join(args) + " (every digit of mp:30)"))
    for bad in ["fortran", "py", "c,python", "", " c", "text "]:
        P.append(P45(cls, EQ + ["--language", bad], refuse("--language"), note=f"--language {bad!r}"))
    for case in ["C", "PYTHON"]:
        P.append(P45(cls, EQ + ["--language", case], either(refuse("--language"), ok())))
    P.append(P45(cls, EQ + ["--language", "c", "--language", "python"], refuse("--language")))
    P.append(P45(cls, EQ + ["--language", "c\nflipflux: ok"], refuse("--language", clean=True)))
    P.append(P45(cls, ["model", "--language", "c"], refuse("--language"), note="--language without --equations"))
    P.append(P45(cls, ["model", "--language", "bogus"], refuse("--language"),
                 note="--language bogus without --equations"))
    for opt, v in [("--m1", "0"), ("--m1", "-1"), ("--I1", "-1"), ("--m1", "1e400"), ("--m2", "1e-400"),
                   ("--g", "nan"), ("--L1", "inf"), ("--a2", "0"), ("--I2", "abc"), ("--L2", "")]:
        P.append(P45(cls, EQ + [opt, v], refuse(opt), note=f"model --equations {opt} {v!r}"))
    P.append(P45(cls, EQ + ["--language", "python", "--m1", "1e400"], refuse("--m1")))
    P.append(P45(cls, EQ + ["--language", "c", "--I1", "-1"], refuse("--I1")))
    P.append(P45(cls, EQ + ["--precision", "mp:0"], refuse("--precision")))
    # coefficients beyond double's range, in a precision that holds them: the pasted blocks are
    # double code (refused, or constants a double holds)
    for scale in ["1e200", "1e-200"]:
        params = [x for k in ["--m1", "--m2", "--L1", "--L2", "--g"] for x in (k, scale)]
        for lang in ["python", "c"]:
            P.append(P45(cls, EQ + ["--precision", "quad", "--language", lang] + params,
                         either(refuse("--"), ok(pasted_constants_finite)),
                         note=f"--equations --language {lang} in quad, m, L, g all {scale} (A ~ {scale}^3)"))
    P.append(P45(cls, EQ, io_error(STDOUT), stdout="full", note="model --equations > /dev/full"))
    P.append(P45(cls, EQ + ["--language", "python"], io_error(STDOUT), stdout="closed",
                 note="model --equations --language python >&-"))

    # ---- initial-states: simulate --initial-states / --write-initial-states, --arm both
    cls = "initial-states"
    SIS = ["simulate", "--initial-states", "init.csv", "--time", "2", "--criteria", "upright", "--no-chaos"]
    base = initial_states_setup()
    P.append(P45(cls, INIT_CMD + ["--write-initial-states", "init.csv"],
                 ok(all_of(file_has("init.csv", "# pendulum:"), file_has("init.csv", "trajectory,energy,theta1")))))
    P.append(P45(cls, SIS + ["--arm", "both"], ok(stdout_has('"studies"')), setup=base,
                 note="--initial-states (written by flipflux) --arm both"))
    P.append(P45(cls, SIS, ok(stdout_has('"trajectories": 4')), setup=initial_states_setup(
        mangle=lambda t: t.replace("\n", "\r\n")), note="--initial-states with CRLF line ends"))

    def input_specials(w, f):
        os.mkdir(os.path.join(w, "d"))
        os.mkfifo(os.path.join(w, "fifo"))
        make_special(w, "zero", "zero")
        os.symlink("/dev/urandom", os.path.join(w, "url"))
    for name in ["missing.csv", "d", "fifo", "zero", "url"]:
        args = ["simulate", "--initial-states", name, "--time", "2"]
        P.append(P45(cls, args, refuse(name, absent=(f"--{name}:",)), setup=input_specials, timeout=30))
    P.append(P45(cls, ["simulate", "--initial-states", "", "--time", "2"], refuse("--initial-states"),
                 note="--initial-states ''"))
    P.append(P45(cls, SIS, refuse("init.csv"), files={"init.csv": ""}, note="empty file"))
    P.append(P45(cls, SIS, refuse("init.csv:2"), setup=initial_states_setup(mangle=edit_csv(drop=("energy",))),
                 note="header without energy (line 2, after the # pendulum: line)"))
    P.append(P45(cls, SIS, refuse("init.csv:1"), files={"init.csv": "trajectory,theta1,theta2,l1,l2\n0,1,2,0,0\n"},
                 note="header without energy (no # pendulum: line)"))
    P.append(P45(cls, SIS, refuse("init.csv:2"), setup=initial_states_setup(mangle=edit_csv(drop=("l2",))),
                 note="header without l2"))
    P.append(P45(cls, SIS, refuse("init.csv:3"), setup=initial_states_setup(mangle=edit_csv(extra="7")),
                 note="a row with one field too many"))
    P.append(P45(cls, SIS, refuse("init.csv"), setup=initial_states_setup(
        mangle=lambda t: "".join(l for l in t.splitlines(True) if not l[0].isdigit())), note="header only"))
    for col, bad in [("theta1", "abc"), ("theta1", "inf"), ("theta2", "nan"), ("l1", "1e400"), ("l2", ""),
                     ("theta1", "0x10"), ("energy", "1e400"), ("energy", "abc"), ("energy", "0"),
                     ("energy", "-5"), ("energy", "6"), ("l1", "2.7")]:
        P.append(P45(cls, SIS, refuse("init.csv:3"), setup=initial_states_setup(mangle=edit_csv(**{col: bad})),
                     note=f"first state's {col} {bad!r}" + (" (H differs from its energy column)"
                                                            if (col, bad) in (("energy", "6"), ("l1", "2.7")) else "")))
    P.append(P45(cls, SIS, refuse("init.csv"), setup=initial_states_setup(mangle=lambda t: t + E3_STATE + "\n"),
                 note="4 states at E = 5, 1 at E = 3"))
    for name, old, new, text, absent in [
            ("another pendulum (m1=2)", "m1=1 ", "m1=2 ", "init.csv:1", ()),
            ("m1=abc", "m1=1 ", "m1=abc ", "init.csv:1", ()),
            ("zz=1", "m1=1 ", "zz=1 ", "init.csv:1", ()),
            ("no parameters", " m1=1 m2=1 L1=1 L2=1 a1=1 a2=1 I1=0 I2=0 g=1", "", "init.csv:1", ()),
            # an invalid declared parameter named as invalid, not asked for ("give its parameters")
            ("m1=0", "m1=1 ", "m1=0 ", "init.csv:1", ("give its parameters",)),
            ("m1=1e400", "m1=1 ", "m1=1e400 ", "init.csv:1", ("give its parameters",))]:
        P.append(P45(cls, SIS, refuse(text, absent=absent),
                     setup=initial_states_setup(mangle=lambda t, old=old, new=new: t.replace(old, new, 1)),
                     note=f"# pendulum: line {name}"))
    P.append(P45(cls, SIS + ["--m1", "2"], refuse("init.csv:1"), setup=base,
                 note="--m1 2 against the file's # pendulum: m1=1"))
    for extra, text in [(["--energy", "5"], "--energy"), (["--trajectories", "4"], "--trajectories"),
                        (["--replicates", "2"], "--replicates"), (["--estimator", "short", "--short-time", "1"],
                                                                  "estimator")]:
        P.append(P45(cls, SIS + extra, refuse(text), setup=base, note=f"--initial-states with {' '.join(extra)}"))
    P.append(P45(cls, ["simulate", "--initial-states", "init.csv", "--time", "1"], refuse(("init.csv", "--time")),
                 files={"init.csv": "trajectory,energy,theta1,theta2,l1,l2\n0,1e300,0,0,1.4142135623730951e150,0\n"},
                 note="a state at E = 1e300 (the turns bound)"))
    # --arm both and --arm: energies below the thresholds, from --energy or from the file
    P.append(P45(cls, ["simulate", "--energy", "1", "--trajectories", "2", "--time", "1", "--arm", "both"],
                 refuse("--energy"), note="--arm both --energy 1 (below both arms' thresholds)"))
    P.append(P45(cls, ["simulate", "--initial-states", "e1.csv", "--time", "1", "--arm", "both"],
                 refuse(("e1.csv", "--initial-states")), files={"e1.csv": E1_STATES},
                 note="--arm both, --initial-states at E = 1 (the file's energies named, not --energy)"))
    P.append(P45(cls, ["simulate", "--initial-states", "e1.csv", "--time", "1"],
                 refuse(("e1.csv", "--initial-states")), files={"e1.csv": E1_STATES},
                 note="--arm 2, --initial-states at E = 1 (the file's energies named, not --energy)"))
    for v in ["3", "0", "", "1,2", "both,1"]:
        P.append(P45(cls, SIM + ["--arm", v], refuse("--arm"), note=f"simulate --arm {v!r}"))
    P.append(P45(cls, SIM + ["--arm", "BOTH"], either(refuse("--arm"), ok(stdout_has('"studies"')))))
    # --write-initial-states
    W = SIM + ["--write-initial-states"]
    P.append(P45(cls, W + ["nodir/x/w.csv"], either(refuse("nodir"), ok(file_has("nodir/x/w.csv", "theta1"))),
                 note="--write-initial-states in folders to be created"))
    P.append(P45(cls, W + ["d"], refuse("d"), setup=lambda w, f: os.mkdir(os.path.join(w, "d")),
                 note="--write-initial-states onto a folder"))
    P.append(P45(cls, W + ["full"], either(refuse("full"), io_error("full")),
                 setup=lambda w, f: make_special(w, "full", "full"),
                 after=lambda w: still_device(w, "full", "full"), note="--write-initial-states full (device 1,7)"))
    P.append(P45(cls, W + ["/dev/full"], either(refuse("/dev/full"), io_error("/dev/full")),
                 note="--write-initial-states /dev/full"))
    P.append(P45(cls, ["simulate", "--energy", "3", "--trajectories", "200", "--time", "1", "--no-chaos",
                       "--write-initial-states", "w.csv"], io_error("w.csv"), rlimits={fsz: 1000},
                 note="--write-initial-states w.csv (file size limit 1000 bytes: a full disk)"))
    P.append(P45(cls, W + ["/proc/x.csv"], refuse("/proc/x.csv")))
    P.append(P45(cls, W + [""], refuse("--write-initial-states"), note="--write-initial-states ''"))
    P.append(P45(cls, W + ["c.ckpt", "--checkpoint", "c.ckpt"], refuse("c.ckpt"),
                 note="--write-initial-states onto the --checkpoint file"))
    P.append(P45(cls, W + ["d/trajectories_E3.csv", "--csv-dir", "d"], refuse("trajectories_E3.csv"),
                 note="--write-initial-states onto a --csv-dir output"))
    P.append(P45(cls, SIS + ["--write-initial-states", "init.csv"],
                 either(refuse("init.csv"), ok(file_has("init.csv", "trajectory,energy,theta1"))), setup=base,
                 note="--write-initial-states onto its own --initial-states file"))
    for args, text in [(["simulate", "--energy", "3", "--trajectories", "2", "--time", "-1",
                         "--write-initial-states", "c/w.csv"], "--time"),
                       (W + ["c/w.csv", "--criteria", "bogus"], "bogus"),
                       (SIS + ["--rtol", "0", "--write-initial-states", "c/w.csv"], "--rtol")]:
        P.append(P45(cls, args, refuse(text), setup=base, forbid=["c"]))
    P.append(P45(cls, SIS + ["--write-initial-states", "c/w.csv"], refuse("init.csv:3"), forbid=["c"],
                 setup=initial_states_setup(mangle=edit_csv(theta1="abc")),
                 note="a bad --initial-states file with --write-initial-states c/w.csv"))

    # ---- validate-states: validate --trajectories EV --state sNN with the candidate's states
    cls = "validate-states"
    ev, st = golden_trajectory("s04", "events"), golden_trajectory("s04", "states")
    VT = ["validate", "--trajectories", "ev.csv", "--state", "s04"]
    VS = VT + ["--states", "st.csv"]
    good = {"ev.csv": ev, "st.csv": st}
    P.append(P45(cls, VS, ok(stdout_has("agrees")), files=good, note="golden s04 as the candidate: agrees"))
    P.append(P45(cls, VS + ["--reference-states", "rs.csv"], ok(stdout_has("agrees")), files={**good, "rs.csv": st}))
    P.append(P45(cls, VS, status(1), files={"ev.csv": ev, "st.csv": edit_csv(row=1, theta1="0.5")(st)},
                 note="a state 1 rad off at t = 20: differs"))
    for name, text, where in [
            ("missing column l2", edit_csv(drop=("l2",))(st), "st.csv:1"),
            ("missing column t", edit_csv(drop=("t",))(st), "st.csv:1"),
            ("header without l2 after a # pendulum: line", "# pendulum: m1=1 m2=1 L1=1 L2=1 g=1\n" +
             edit_csv(drop=("l2",))(st), "st.csv:2"),
            ("a field missing", ST_HEAD + "10,1,2,3\n", "st.csv:2"),
            ("a field too many", edit_csv(extra="5")(st), "st.csv:2"),
            ("theta1 abc", edit_csv(theta1="abc")(st), "st.csv:2"),
            ("theta1 nan", edit_csv(theta1="nan")(st), "st.csv:2"),
            ("l2 inf", edit_csv(l2="inf")(st), "st.csv:2"),
            ("l1 1e400", edit_csv(l1="1e400")(st), "st.csv:2"),
            ("t abc", edit_csv(t="abc")(st), "st.csv:2"),
            ("t 1e400", edit_csv(t="1e400")(st), "st.csv:2"),
            ("t -1 (the only state: before the start)", ST_HEAD + "-1,1,2,3,4\n", "st.csv:2"),
            ("empty file", "", "st.csv")]:
        P.append(P45(cls, VS, refuse(where), files={"ev.csv": ev, "st.csv": text}, note=f"--states {name}"))
    P.append(P45(cls, VS, either(refuse("st.csv"), status(1)), files={"ev.csv": ev, "st.csv": ST_HEAD},
                 note="--states header only: no state compared is no agreement"))
    P.append(P45(cls, VS + ["--reference-states", "rs.csv"], refuse("rs.csv:2"),
                 files={**good, "rs.csv": edit_csv(theta1="abc")(st)}, note="--reference-states theta1 abc"))

    def state_specials(w, f):
        write(os.path.join(w, "ev.csv"), ev)
        input_specials(w, f)
    for name in ["missing.csv", "d", "fifo", "zero"]:
        P.append(P45(cls, VT + ["--states", name], refuse(name, absent=(f"--{name}:",)), setup=state_specials,
                     timeout=30, note=f"--states {name}"))
    P.append(P45(cls, VT + ["--states", "st.csv", "--reference-states", "fifo"], refuse("fifo"),
                 setup=lambda w, f: (state_specials(w, f), write(os.path.join(w, "st.csv"), st)), timeout=30))
    P.append(P45(cls, VT + ["--reference-states", "st.csv"], refuse("--reference-states"), files=good,
                 note="--reference-states without --states"))
    for v in ["-1", "abc", "nan", "inf", "1e400", "1e-400", "0x1", ""]:
        P.append(P45(cls, VS + ["--state-tol", v], refuse("--state-tol"), files=good, note=f"--state-tol {v!r}"))
    P.append(P45(cls, VT + ["--state-tol", "1e-3"], refuse("--state-tol"), files=good,
                 note="--state-tol without --states (as --reference-states needs --states)"))
    P.append(P45(cls, ["validate", "c.csv", "--states", "st.csv", "--allow-missing"], refuse("--states"),
                 files={"c.csv": CAND_HEAD + OMEGA6, "st.csv": st}, note="--states without --trajectories"))
    for name, row, where in [("direction 0.5", "0.89471471020462507,2,upright,0.5", "ev.csv:2"),
                             ("arm 2.5", "0.89471471020462507,2.5,upright,1", "ev.csv:2"),
                             ("criterion 'bogus'", "0.89471471020462507,2,bogus,1", "ev.csv:2")]:
        P.append(P45(cls, VS, refuse(where), files={"ev.csv": EV_HEAD + row + "\n", "st.csv": st},
                     note=f"candidate event {name}"))
    P.append(P45(cls, VS, refuse("ev.csv:1"), files={"ev.csv": edit_csv(drop=("direction",))(ev), "st.csv": st},
                 note="candidate events without a direction column"))
    P.append(P45(cls, VT[:-1] + ["s99"], refuse("s99"), files=good, note="--state s99 (no such golden state)"))

    # ---- validate-paired: validate --ensemble F --paired
    cls = "validate-paired"
    VP = ["validate", "--ensemble", "p.csv", "--paired"]

    def paired(mangle=None):
        return initial_states_setup(name="p.csv", mangle=mangle, paired=True)
    P.append(P45(cls, VP, ok(stdout_has("PASSED")), setup=paired(), note="the paired candidate of INIT_CMD's states"))
    P.append(P45(cls, VP, status(1, stdout_has("FAILED")),
                 setup=paired(lambda t: t.replace(",upright,0\n", ",upright,5\n")),
                 note="5 flips per trajectory where flipflux counts none"))
    for col in ["flips", "time", "arm", "energy", "l2"]:
        P.append(P45(cls, VP, refuse("p.csv:2"), setup=paired(edit_csv(drop=(col,))),
                     note=f"without the {col} column (the header is line 2, after the # pendulum: line)"))
    P.append(P45(cls, VP, refuse("p.csv:1"), setup=paired(
        lambda t: edit_csv(drop=("flips",))("\n".join(t.splitlines()[1:]) + "\n")),
                 note="without the flips column, no # pendulum: line"))
    for col, bad in [("flips", "-1"), ("flips", "1.5"), ("flips", "abc"), ("flips", "1e30"), ("flips", "nan"),
                     ("arm", "3"), ("arm", "0"), ("arm", "2.5"), ("criterion", "bogus"),
                     ("time", "0"), ("time", "-1"), ("time", "inf"), ("time", "abc"),
                     ("energy", "6"), ("theta1", "1e400")]:
        P.append(P45(cls, VP, refuse("p.csv:3"), setup=paired(edit_csv(**{col: bad})), timeout=30,
                     note=f"first row's {col} {bad!r}"))
    for T in ["1e300", "1e9"]:
        P.append(P45(cls, VP, refuse("p.csv:3", absent=("--time",)), setup=paired(edit_csv(time=T)), timeout=30,
                     note=f"time {T}: refused at once, naming the file's line (no --time was given)"))
    P.append(P45(cls, VP, refuse("p.csv:3"), setup=paired(
        edit_csv(energy="0", theta1="0", theta2="0", l1="0", l2="0")),
                 note="a state at E = 0 (simulate --initial-states refuses energy 0)"))
    P.append(P45(cls, VP, refuse("p.csv:3"), setup=paired(edit_csv(extra="7")), note="a row with a field too many"))
    P.append(P45(cls, VP, refuse("p.csv"), files={"p.csv": ""}, note="empty file"))
    P.append(P45(cls, VP, refuse("p.csv"), setup=paired(
        lambda t: "".join(l for l in t.splitlines(True) if not l[0].isdigit())), note="header only"))
    P.append(P45(cls, VP, refuse("p.csv"), files={"p.csv": ENS_HEAD + "upright,2,5,100,10,5\n"},
                 note="an unpaired ensemble file with --paired"))
    P.append(P45(cls, VP, refuse("p.csv:1"), setup=paired(lambda t: t.replace("m1=1 ", "m1=abc ", 1)),
                 note="# pendulum: m1=abc"))
    P.append(P45(cls, VP + ["--m1", "2"], refuse("p.csv:1"), setup=paired(),
                 note="--m1 2 against the file's # pendulum: m1=1"))
    for name in ["missing.csv", "d", "fifo", "zero"]:
        P.append(P45(cls, ["validate", "--ensemble", name, "--paired"], refuse(name, absent=(f"--{name}:",)),
                     setup=input_specials, timeout=30))
    P.append(P45(cls, ["validate", "--paired"], refuse(("--paired", "--ensemble")), note="--paired alone"))
    P.append(P45(cls, ["validate", "c.csv", "--paired", "--allow-missing"], refuse("--paired"),
                 files={"c.csv": CAND_HEAD + OMEGA6}, note="--paired with a golden-values candidate"))
    P.append(P45(cls, VT + ["--paired"], refuse("--paired"), files={"ev.csv": ev},
                 note="--paired with --trajectories"))
    P.append(P45(cls, VP, io_error(STDOUT), setup=paired(), stdout="full", note="validate --paired > /dev/full"))
    return P


# ---------------------------------------------------------------- the runner


def listing(root):
    out = set()
    for dirpath, dirs, names in os.walk(root):
        for n in dirs + names:
            out.add(os.path.relpath(os.path.join(dirpath, n), root))
    return out


def visible(text):
    """Text with its control characters escaped (for this script's own report lines)."""
    return re.sub(r"[\x00-\x1f\x7f-\x9f\u2028\u2029]", lambda m: repr(m.group(0))[1:-1], text)


def run_probe(p, flipflux, scratch, index):
    base = os.path.join(scratch, f"p{index:03d}")
    work = os.path.join(base, "work")
    os.makedirs(work)
    for name, text in p.files.items():
        write(os.path.join(work, name), text)
    if p.setup:
        try:
            p.setup(work, flipflux)
        except Exception as e:
            return f"setup failed: {type(e).__name__}: {e}", 0.0
    msg, dt = run_and_judge(p, flipflux, base, work)
    if p.after:
        try:
            late = p.after(work)
        except Exception as e:
            late = f"after-check failed: {type(e).__name__}: {e}"
        if late:
            msg = f"{msg}; {late}" if msg else late
    return msg, dt


def run_and_judge(p, flipflux, base, work):
    before_outside = listing(base) - {x for x in listing(base) if x == "work" or x.startswith("work" + os.sep)}
    before_work = listing(work)
    env = {**os.environ, **p.env}
    rlimits, close_stdout = dict(p.rlimits), p.stdout == "closed"

    def preexec():
        for res, lim in rlimits.items():
            resource.setrlimit(res, (lim, lim))
        if resource.RLIMIT_FSIZE in rlimits:  # a write beyond the limit fails (EFBIG): a full disk
            signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        if close_stdout:
            os.close(1)

    stdout_file = open("/dev/full", "wb") if p.stdout == "full" else None
    t0 = time.time()
    try:
        r = subprocess.run([flipflux] + p.args, cwd=work, timeout=p.timeout, env=env,
                           stdout=stdout_file or subprocess.PIPE, stderr=subprocess.PIPE,
                           preexec_fn=preexec if (rlimits or close_stdout) else None)
    except subprocess.TimeoutExpired:
        return f"HANG (> {p.timeout} s)", time.time() - t0
    finally:
        if stdout_file:
            stdout_file.close()
    dt = time.time() - t0
    out = (r.stdout or b"").decode(errors="replace")
    err = r.stderr.decode(errors="replace")
    first = visible(err.strip().splitlines()[0]) if err.strip() else ""
    if r.returncode < 0 or r.returncode >= 128:
        return f"CRASH (status {r.returncode}): {first}", dt
    if "internal error" in err:
        return f"internal error: {first}", dt
    outside = {x for x in listing(base) if not (x == "work" or x.startswith("work" + os.sep))}
    if outside - before_outside:
        return f"wrote outside its directory: {sorted(outside - before_outside)}", dt
    for f in p.forbid:
        if os.path.lexists(os.path.join(work, f)):
            return f"left {f} behind (status {r.returncode}{': ' + first if first else ''})", dt
    expect = p.expect
    if expect[0] == "either":
        expect = expect[1] if r.returncode == 2 else expect[2]
    kind = expect[0]
    if kind in ("refuse", "fails"):
        want, text, opts = (2, expect[1], expect[2]) if kind == "refuse" else expect[1:]
        lines = [l for l in err.splitlines() if l.strip()]
        if kind == "fails":  # notes and progress lines may precede a failure found while working
            lines = [l for l in lines if re.search(r"error", l, re.I)
                     or (l.startswith("flipflux:") and not re.match(r"flipflux: (note|warning):", l))]
        if r.returncode != want:
            return f"status {r.returncode}, expected {want}: {first or visible(out[:200])}", dt
        if len(lines) != 1:
            return f"{len(lines)} lines on stderr, expected 1: {err[:300]!r}", dt
        if not names(lines[0], text):
            return f"error does not name {text!r}: {visible(lines[0])}", dt
        for a in opts.get("absent", ()):
            if a in lines[0]:
                return f"error contains {a!r}: {visible(lines[0])}", dt
        if opts.get("clean") and CONTROL.search(err.rstrip("\n")):
            return f"raw control character in the error: {err[:300]!r}", dt
        created = listing(work) - before_work
        if kind == "refuse" and created:
            return f"refusal left files: {sorted(created)[:5]}", dt
        if opts.get("clean_files"):
            files = [x for x in created if os.path.isfile(os.path.join(work, x))
                     and not os.path.islink(os.path.join(work, x))]
            if files:
                return f"failure left files: {sorted(files)[:5]}", dt
        return None, dt
    want = 0 if kind == "ok" else expect[1]
    check = expect[1] if kind == "ok" else expect[2]
    if r.returncode not in (want if isinstance(want, tuple) else (want,)):
        return f"status {r.returncode}, expected {want}: {first or visible(out[:200])}", dt
    if kind == "ok" and NUMBER_JUNK.search(out):
        return f"non-finite number in the output: {NUMBER_JUNK.search(out).group(0)}", dt
    if check:
        try:
            msg = check(out, work, err) if getattr(check, "wants_err", False) else check(out, work)
        except Exception as e:  # a check that cannot read the output is a failure
            msg = f"check failed: {type(e).__name__}: {e}"
        if msg:
            return msg, dt
    return None, dt


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--flipflux", default=os.path.join(ROOT, "build/release/flipflux"))
    ap.add_argument("--only", help="run only these classes (comma-separated)")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args()
    flipflux = os.path.abspath(a.flipflux)
    global FLIPFLUX
    FLIPFLUX = flipflux
    only = set(a.only.split(",")) if a.only else None
    all_probes = [p for p in probes() if not only or p.cls in only]
    if a.list:
        for i, p in enumerate(all_probes):
            print(f"{i:3d} {p.cls:28s} {p.expect[0]:7s} {visible(' '.join(p.args)[:100])}")
        return 0
    scratch = tempfile.mkdtemp(prefix="flipflux-probes-")
    per_class = {}
    failures = 0
    for i, p in enumerate(all_probes):
        msg, dt = run_probe(p, flipflux, scratch, i)
        c = per_class.setdefault(p.cls, [0, 0])
        c[0] += 1
        if msg:
            c[1] += 1
            failures += 1
        if msg or a.verbose:
            label = visible(p.note or " ".join(repr(x) if (not x or " " in x) else x for x in p.args)[:90])
            print(f"{'FAIL' if msg else 'ok  '} {i:3d} [{p.cls}] {label} ({dt:.1f} s){': ' + msg if msg else ''}",
                  flush=True)
    shutil.rmtree(scratch, ignore_errors=True)
    print(f"\n{len(all_probes)} probes, {failures} failed")
    for cls, (n, bad) in per_class.items():
        print(f"  {cls:28s} {n:4d} probes, {bad:3d} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
