# Saddle-orbit families of random pendulums (2026-11-30):
#   python3 bench/results/orbit_family_scan.py FLIPFLUX SEED COUNT
# m1 in [0.1, 10], m2 in [0.1, 31.6], L1, L2 in [0.4, 2.5] (log-uniform), 40 % rigid first links,
# g = 9.81. For each pendulum and arm, `eval period` and `eval action` at 40 energies from E_s to
# 0.97 E_max: an orbit of another family shows as a step between neighbours whose action
# difference leaves the trapezoid's bound (dF/dE = T: within dE |dT| / 2 of dE (T0 + T1) / 2 while
# T is monotone between them), listed under its family as a jump. Energies not solved are counted
# by their error (since 2026-11-30, fifteenth session): beyond the family's end, too unstable, no
# convergence.
import subprocess, json, sys, random
FF=sys.argv[1]; random.seed(int(sys.argv[2])); N=int(sys.argv[3])
print('# bench/results/orbit_family_scan.py', ' '.join(sys.argv[1:]), subprocess.run([FF,'--version'],capture_output=True,text=True).stdout.strip(), flush=True)
KINDS=[("beyond the end of the arm-","beyond the family's end"),("too unstable","too unstable"),("no convergence","no convergence")]
errors={}
def ev(q, arm, E, P):
    r=subprocess.run(["timeout","60",FF,"eval",q,"--arm",arm,"--energy",repr(E)]+P,capture_output=True,text=True)
    if r.returncode:
        kind=next((k for s,k in KINDS if s in r.stderr), "other error")
        errors[kind]=errors.get(kind,0)+1
        return None
    return float(json.loads(r.stdout)["value"])
for trial in range(N):
    m1=10**random.uniform(-1,1); m2=10**random.uniform(-1,1.5); L1=10**random.uniform(-0.4,0.4); L2=10**random.uniform(-0.4,0.4)
    P=["--m1",f"{m1:.4g}","--m2",f"{m2:.4g}","--L1",f"{L1:.3g}","--L2",f"{L2:.3g}","--g","9.81"]
    if random.random()<0.4: P+=["--a1",f"{L1/2:.3g}","--I1",f"{m1*L1*L1/12:.4g}"]
    model=json.loads(subprocess.run([FF,"model"]+P,capture_output=True,text=True).stdout)
    k=model["model"]["coefficients"]; a=float(k["alpha"]); b=float(k["beta"]); Emax=2*a+2*b
    for arm in ["1","2"]:
        Es=2*a if arm=="1" else 2*b
        prev=None; bad=[]; fails=0; errors.clear()
        n=40
        for i in range(1,n+1):
            E=Es+(Emax-Es)*0.97*i/n
            T=ev("period",arm,E,P); F=ev("action",arm,E,P) if T is not None else None
            if T is None or F is None: fails+=1; prev=None; continue
            if prev:
                E0,T0,F0=prev; dF=F-F0; trap=(T+T0)/2*(E-E0)
                if abs(dF-trap) > 0.5*(E-E0)*abs(T-T0) + 1e-9*abs(F): bad.append(f"E {E0:.6g}->{E:.6g}: T {T0:.6g}->{T:.6g}, dF {dF:.6g} vs {trap:.6g}")
            prev=(E,T,F)
        # (an energy counts once under its first failing quantity's error)
        kinds="".join(f"; {c} {k}" for k,c in sorted(errors.items()))
        print(f"{' '.join(P)} arm {arm}: {n-fails}/{n} solved; {len(bad)} jumps{kinds}" + ("".join("\n   "+x for x in bad)), flush=True)
