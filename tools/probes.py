#!/usr/bin/env python3
"""The hostile-user probe campaign of issue 20 (docs/limits.md), rerunnable.

Each probe runs one flipflux command in a fresh scratch folder with an expected outcome:

  refuse(TEXT)   exit status 2, exactly one line on stderr ("flipflux: error: ..."), containing
                 TEXT (the offending value or key), and no output file left behind;
  ok(CHECK)      exit status 0, no "nan"/"inf" number in stdout, and CHECK (e.g. a value against
                 an independent mpmath route) holds;
  status(N, ...) exit status N (validate's 1 for a failed comparison).

Every probe also fails on a signal (crash), on its timeout (a hang: 60 s where a refusal is
expected), on "internal error", and on any file written outside its scratch folder's work/
directory (path traversal). Reference values come from mpmath (closed forms and a 2-D quadrature
of the phase volume of the paper's pendulum, written here independently of flipflux).

Usage: tools/probes.py [--flipflux build/release/flipflux] [--only CLASS] [--list] [--verbose]
Exit status 0 when every probe meets its expectation. Prints one line per probe and a count per
class (the numbers in issue 20's closing note).
"""
import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import mpmath as mp

mp.mp.dps = 120  # values are read with every digit they carry (mp:60 prints 62)
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# ---------------------------------------------------------------- independent references (mpmath)
# The paper's pendulum (m1 = m2 = L1 = L2 = g = 1): V = 2 (1 - cos t1) + (1 - cos t2),
# det M(t) = 2 - cos^2(t1 - t2); Omega(E) = 2 pi * integral over {V < E} of sqrt(det M) dt1 dt2
# (the momentum shell of a 2-dof quadratic kinetic energy has measure 2 pi sqrt(det M)).


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
                 forbid=None, note=""):
        self.cls, self.args, self.expect, self.timeout = cls, args, expect, timeout
        self.files = files or {}
        self.env = env or {}
        self.setup = setup  # callable(work, flipflux) run before the probe
        self.forbid = forbid or []  # paths (relative to work) that must not exist afterwards
        self.note = note


def refuse(text):
    return ("refuse", text)


def ok(check=None):
    return ("ok", check)


def status(n, check=None):
    return ("status", n, check)


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
            write(os.path.join(work, "s.toml"), orbit_scene)
            subprocess.run([flipflux, "run", "s.toml", "--cache-dir", "cache"], cwd=work,
                           capture_output=True, timeout=300)
            shutil.rmtree(os.path.join(work, "out"), ignore_errors=True)
            for dirpath, _, names in os.walk(os.path.join(work, "cache")):
                for n in names:
                    p = os.path.join(dirpath, n)
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
    return P


# ---------------------------------------------------------------- the runner


def listing(root):
    out = set()
    for dirpath, dirs, names in os.walk(root):
        for n in dirs + names:
            out.add(os.path.relpath(os.path.join(dirpath, n), root))
    return out


def run_probe(p, flipflux, scratch, index):
    base = os.path.join(scratch, f"p{index:03d}")
    work = os.path.join(base, "work")
    os.makedirs(work)
    for name, text in p.files.items():
        write(os.path.join(work, name), text)
    if p.setup:
        p.setup(work, flipflux)
    before_outside = listing(base) - {x for x in listing(base) if x == "work" or x.startswith("work" + os.sep)}
    before_work = listing(work)
    env = {**os.environ, **p.env}
    t0 = time.time()
    try:
        r = subprocess.run([flipflux] + p.args, cwd=work, capture_output=True, timeout=p.timeout,
                           env=env)
    except subprocess.TimeoutExpired:
        return f"HANG (> {p.timeout} s)", time.time() - t0
    dt = time.time() - t0
    out = r.stdout.decode(errors="replace")
    err = r.stderr.decode(errors="replace")
    first = err.strip().splitlines()[0] if err.strip() else ""
    if r.returncode < 0 or r.returncode >= 128:
        return f"CRASH (status {r.returncode}): {first}", dt
    if "internal error" in err:
        return f"internal error: {first}", dt
    outside = {x for x in listing(base) if not (x == "work" or x.startswith("work" + os.sep))}
    if outside - before_outside:
        return f"wrote outside its directory: {sorted(outside - before_outside)}", dt
    for f in p.forbid:
        if os.path.exists(os.path.join(work, f)):
            return f"left {f} behind", dt
    expect = p.expect
    if expect[0] == "either":
        expect = expect[1] if r.returncode == 2 else expect[2]
    kind = expect[0]
    if kind == "refuse":
        lines = [l for l in err.splitlines() if l.strip()]
        if r.returncode != 2:
            return f"status {r.returncode}, expected 2: {first or out[:200]}", dt
        if len(lines) != 1:
            return f"{len(lines)} lines on stderr, expected 1: {err[:300]!r}", dt
        if expect[1] not in lines[0]:
            return f"error does not name {expect[1]!r}: {lines[0]}", dt
        created = listing(work) - before_work
        if created:
            return f"refusal left files: {sorted(created)[:5]}", dt
        return None, dt
    want = 0 if kind == "ok" else expect[1]
    check = expect[1] if kind == "ok" else expect[2]
    if r.returncode != want:
        return f"status {r.returncode}, expected {want}: {first or out[:200]}", dt
    if kind == "ok" and NUMBER_JUNK.search(out):
        return f"non-finite number in the output: {NUMBER_JUNK.search(out).group(0)}", dt
    if check:
        try:
            msg = check(out, work)
        except Exception as e:  # a check that cannot read the output is a failure
            msg = f"check failed: {type(e).__name__}: {e}"
        if msg:
            return msg, dt
    return None, dt


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--flipflux", default=os.path.join(ROOT, "build/release/flipflux"))
    ap.add_argument("--only", help="run one class only")
    ap.add_argument("--list", action="store_true")
    ap.add_argument("--verbose", action="store_true")
    a = ap.parse_args()
    flipflux = os.path.abspath(a.flipflux)
    all_probes = [p for p in probes() if not a.only or p.cls == a.only]
    if a.list:
        for i, p in enumerate(all_probes):
            print(f"{i:3d} {p.cls:28s} {p.expect[0]:7s} {' '.join(p.args)[:100]}")
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
            label = p.note or " ".join(repr(x) if (not x or " " in x) else x for x in p.args)[:90]
            print(f"{'FAIL' if msg else 'ok  '} {i:3d} [{p.cls}] {label} ({dt:.1f} s){': ' + msg if msg else ''}",
                  flush=True)
    shutil.rmtree(scratch, ignore_errors=True)
    print(f"\n{len(all_probes)} probes, {failures} failed")
    for cls, (n, bad) in per_class.items():
        print(f"  {cls:28s} {n:4d} probes, {bad:3d} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
