#!/usr/bin/python3
"""Randomized (seeded) sweep of `flipflux eval QUANTITY --certify --max-seconds S`.
Property: exit 0 (JSON on stdout) or exit 2 with a one-line error naming --max-seconds
(other exit-2 refusals, e.g. energy out of range, are recorded but not violations),
and CPU (user+sys) <= S + 1.0 + 0.3.
One process at a time."""
import json, os, random, resource, shlex, subprocess, sys, time

F = "/work/main/build/release/flipflux"
ENV = dict(os.environ, FLIPFLUX_PLUGIN_DIR="/work/main/build/release/plugins")
SEED = int(sys.argv[1]) if len(sys.argv) > 1 else 20251202
N = int(sys.argv[2]) if len(sys.argv) > 2 else 80
LOG = sys.argv[3] if len(sys.argv) > 3 else "/tmp/certsweep/log.jsonl"
SLACK = 1.3

QUANTITIES = ["omega", "flux-upright", "flux-approx", "rate-upright", "rate-approx", "period",
              "action", "flux-saddle", "rate-saddle", "multiplier", "stability-index"]
PRECISIONS = ["double", "quad", "mp:60", "mp:150", "mp:300", "mp:500"]
MAXS = [0.5, 1, 2, 4]


def run(cmd, S):
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.monotonic()
    p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, env=ENV)
    hang = False
    try:
        out, err = p.communicate(timeout=3 * S + 20)
    except subprocess.TimeoutExpired:
        p.kill()
        out, err = p.communicate()
        hang = True
    wall = time.monotonic() - t0
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
    return p.returncode, out.decode(errors="replace"), err.decode(errors="replace"), cpu, wall, hang


def critical(model_args):
    out = subprocess.run([F, "model"] + model_args, capture_output=True, env=ENV, text=True).stdout
    d = json.loads(out)
    return {c["name"]: float(c["energy"]) for c in d["critical_points"]}


def main():
    rng = random.Random(SEED)
    pendulums = [[]]
    for _ in range(3):
        m = ["--m1", f"{rng.uniform(0.3, 3):.3g}", "--m2", f"{rng.uniform(0.3, 3):.3g}",
             "--L1", f"{rng.uniform(0.5, 2):.3g}", "--L2", f"{rng.uniform(0.5, 2):.3g}",
             "--g", f"{rng.choice([1, 9.81, 2.5])}"]
        if rng.random() < 0.5:
            m += ["--I1", f"{rng.uniform(0, 0.5):.3g}", "--I2", f"{rng.uniform(0, 0.5):.3g}"]
        if rng.random() < 0.5:
            L1 = float(m[5]); m += ["--a1", f"{rng.uniform(0.3, 1) * L1:.3g}"]
        pendulums.append(m)
    crit = [critical(p) for p in pendulums]
    print("pendulums:", json.dumps(list(zip([" ".join(p) for p in pendulums], crit))), flush=True)
    log = open(LOG, "a")
    nviol = 0
    for i in range(N):
        pi = 0 if rng.random() < 0.55 else rng.randrange(1, len(pendulums))
        pend, c = pendulums[pi], crit[pi]
        q = rng.choice(QUANTITIES)
        arm = rng.choice(["1", "2"])
        prec = rng.choice(PRECISIONS)
        S = rng.choice(MAXS)
        lo = c["down-up"] if arm == "2" else c["up-down"]
        hi = c["up-up"]
        lo2, hi2 = min(lo, hi), max(lo, hi)
        u = rng.random()
        if u < 0.1:
            E = lo2 + (hi2 - lo2) * rng.uniform(0.001, 0.02)   # near lower end
        elif u < 0.2:
            E = hi2 - (hi2 - lo2) * rng.uniform(0.001, 0.02)   # near upper end
        else:
            E = rng.uniform(lo2 + 0.03 * (hi2 - lo2), hi2 - 0.03 * (hi2 - lo2))
        cmd = [F, "eval", q, "--arm", arm, "--energy", f"{E:.6g}", "--precision", prec,
               "--certify", "--max-seconds", f"{S:g}"] + pend
        if rng.random() < 0.15 and q in ("period", "action", "flux-saddle", "rate-saddle", "multiplier", "stability-index"):
            cmd[cmd.index("--certify"):cmd.index("--certify")] = ["--integrator", rng.choice(["taylor", "gauss-legendre"])]
        rc, out, err, cpu, wall, hang = run(cmd, S)
        lines = [l for l in err.splitlines() if l.strip()]
        last = lines[-1] if lines else ""
        problems = []
        if hang:
            problems.append("hang (killed)")
        if rc == 0:
            try:
                json.loads(out)
            except Exception:
                problems.append("exit 0 but stdout not JSON")
        elif rc == 2:
            if len(lines) != 1:
                problems.append(f"exit 2 with {len(lines)} stderr lines")
        elif rc == 1:
            problems.append("exit 1 (certification failed?)")
        else:
            problems.append(f"exit status {rc}")
        if cpu > S + SLACK:
            problems.append(f"CPU {cpu:.2f} > S+{SLACK}")
        timeout_msg = rc == 2 and "--max-seconds" in last
        rec = dict(i=i, cmd=shlex.join(cmd), rc=rc, stderr_last=last, stderr_lines=len(lines),
                   cpu=round(cpu, 3), wall=round(wall, 3), S=S, timeout_msg=timeout_msg,
                   ok=not problems, problems=problems)
        log.write(json.dumps(rec) + "\n"); log.flush()
        nviol += bool(problems)
        print(f"{i:3d} rc={rc} cpu={cpu:6.2f} wall={wall:6.2f} S={S:<3g} {'OK ' if not problems else 'BAD'} "
              f"{' '.join(cmd[2:])} | {last[:110]} {problems if problems else ''}", flush=True)
    print(f"runs={N} problems={nviol}")


if __name__ == "__main__":
    main()
