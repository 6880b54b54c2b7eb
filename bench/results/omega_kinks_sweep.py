# Omega's digits and estimates on random pendulums (2026-11-30, the marginal's kinks split off):
#   python3 bench/results/omega_kinks_sweep.py FLIPFLUX SEED COUNT
# m1 in [0.01, 3], m2 in [0.1, 3e6] (log-uniform), L1, L2 in [0.3, 3], 40 % rigid first links,
# g = 1; E uniform in (0.01, 1.2) E_max or (0.9, 1.05) E_max. Per pendulum: the value at double
# and quad against mp:45 (the same route: the digits' reference), |error| and the estimate in eps
# of the value, the seconds of the evaluation; flags an estimate below the error (UNDER) or more
# than 100x max(error, eps |value|) (>100x). The summary: the largest error and estimate in eps.
import subprocess, json, os, sys, random
from decimal import Decimal as D, getcontext; getcontext().prec=60
FF=sys.argv[1]
def ev(E, prec, P, q="omega", method=None):
    cmd=[FF,"eval",q,"--energy",repr(E),"--precision",prec]+P+(["--method",method] if method else [])
    j=json.loads(subprocess.run(cmd,capture_output=True,text=True,timeout=600).stdout)
    return D(j["value"]), float(j["error_estimate"]), float(j["seconds"])
random.seed(int(sys.argv[2]))
print('# bench/results/omega_kinks_sweep.py', ' '.join(sys.argv[1:]), subprocess.run([FF,'--version'],capture_output=True,text=True).stdout.strip())
max_rel={'double':0,'quad':0}; max_est={'double':0,'quad':0}; flags=0
worst={}
for trial in range(int(sys.argv[3])):
    m1=10**random.uniform(-2,0.5); m2=10**random.uniform(-1,6.5); L1=10**random.uniform(-0.5,0.5); L2=10**random.uniform(-0.5,0.5)
    P=["--m1",f"{m1:.6g}","--m2",f"{m2:.6g}","--L1",f"{L1:.4g}","--L2",f"{L2:.4g}","--g","1"]
    if random.random()<0.4: P+=["--a1",f"{L1/2:.4g}","--I1",f"{m1*L1*L1/12:.6g}"]
    model=json.loads(subprocess.run([FF,"model"]+P,capture_output=True,text=True).stdout)
    Emax=max(float(c["energy"]) for c in model["critical_points"])
    k=model["model"]["coefficients"]; mpar=float(D(k["C"])**2/D(k["D0"]))
    E=float(f"{random.choice([random.uniform(0.01,1.2), random.uniform(0.9,1.05)])*Emax:.8g}")
    ref=ev(E,"mp:45",P)[0]
    for prec in ["double","quad"]:
        v,e,s=ev(E,prec,P); act=abs(float(v-ref)); eps=2.2e-16 if prec=="double" else 1.93e-34
        rel=act/float(ref)/eps; est=e/float(ref)/eps
        flag = " UNDER" if e < act else (" >100x" if e > 100*max(act, eps*float(ref)) else "")
        print(f"{' '.join(P)} |m|={mpar:.3g} E={E} {prec}: rel {rel:.1f} eps est {est:.1f} eps {s:.3f}s{flag}", flush=True)
        max_rel[prec]=max(max_rel[prec],rel); max_est[prec]=max(max_est[prec],est); flags+=bool(flag)
print(f"summary: largest error double {max_rel['double']:.1f} eps, quad {max_rel['quad']:.1f} eps; largest estimate double {max_est['double']:.1f} eps, quad {max_est['quad']:.1f} eps; flagged {flags}")
