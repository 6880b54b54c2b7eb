"""An independent third route, outside C++: Omega, the upright flux f1 and the approximate-curve
flux f2 of both arms, computed with mpmath at 45 digits from the formulas derived in
docs/theory.md (written again here, not shared with the C++ code), compared with
`flipflux eval ... --precision quad` for three pendulums (egalitarian, unequal point masses,
uniform rigid rods). Fails when any relative difference exceeds 1e-30.

The energies of arm a are E = E_s + x (E_max - E_s) for the fractions x given (E_s the arm's saddle
energy): below the maximum (x < 1) and above it. CI runs 0.55, 0.97 and 1.4 (ctest
verify_mpmath_reference); `bash setup.sh verify` adds 0.3 and 0.8 (verify_mpmath_reference_more),
the slowest for mpmath (its incomplete elliptic integral E at 45 digits costs ~3 ms a call).

usage: python3 mpmath_reference.py path/to/flipflux [--fractions 0.55,0.97,1.4]
"""
import mpmath as mp, json, subprocess, sys
mp.mp.dps = 45
def coeffs(m1=1,m2=1,L1=1,L2=1,a1=None,a2=None,I1=0,I2=0,g=1):
    a1 = L1 if a1 is None else a1; a2 = L2 if a2 is None else a2
    m1,m2,L1,L2,a1,a2,I1,I2,g = [mp.mpf(str(x)) for x in (m1,m2,L1,L2,a1,a2,I1,I2,g)]
    A = I1+m1*a1**2+m2*L1**2; B = I2+m2*a2**2; C = m2*L1*a2
    al = g*(m1*a1+m2*L1); be = g*m2*a2; D0 = A*B-C**2
    return A,B,C,al,be,D0
def omega(E, k):
    A,B,C,al,be,D0 = k; m = -C**2/D0
    def inner(t1):
        R = E - al*(1-mp.cos(t1))
        if R <= 0: return mp.mpf(0)
        t = mp.pi if R >= 2*be else mp.acos(1-R/be)
        return mp.sqrt(D0)*(mp.ellipe(t-t1, m)+mp.ellipe(t+t1, m))
    pts = [-mp.pi, 0, mp.pi]
    for c in (1-E/al, 1-(E-2*be)/al):
        if -1 < c < 1:
            x = mp.acos(c); pts += [x, -x]
    pts = sorted(set(pts))
    return 2*mp.pi*mp.quad(inner, pts)
def centre_ratio(k, e1, e2):
    A,B,C,al,be,D0 = k; e = e1*e2
    b = e1*al*B + e2*be*A; c0 = e*al*be
    disc = b*b - 4*D0*c0
    xs = [(b+mp.sqrt(disc))/(2*D0), (b-mp.sqrt(disc))/(2*D0)]
    x = max(xs)
    return x*C*e/(e2*be - x*B)
def curve_flux(E, k, arm, amp):
    A,B,C,al,be,D0 = k
    def f(s):
        if arm == 2:
            t1, t2, hp = s, mp.pi+amp*mp.sin(s), amp*mp.cos(s)
            q = B*hp**2 + 2*C*mp.cos(t1-t2)*hp + A
        else:
            t2, t1, hp = s, mp.pi+amp*mp.sin(s), amp*mp.cos(s)
            q = B + 2*C*mp.cos(t1-t2)*hp + A*hp**2
        K = E - al*(1-mp.cos(t1)) - be*(1-mp.cos(t2))
        return 4*mp.sqrt(2*K)*mp.sqrt(q) if K > 0 else mp.mpf(0)
    # zeros of K along the curve
    def K(s):
        t1, t2 = (s, mp.pi+amp*mp.sin(s)) if arm == 2 else (mp.pi+amp*mp.sin(s), s)
        return E - al*(1-mp.cos(t1)) - be*(1-mp.cos(t2))
    pts = [-mp.pi, mp.pi]
    N = 400
    grid = [-mp.pi + 2*mp.pi*i/N for i in range(N+1)]
    for i in range(N):
        if K(grid[i])*K(grid[i+1]) < 0:
            pts.append(mp.findroot(K, (grid[i], grid[i+1]), solver='anderson'))
    pts = sorted(pts)
    return mp.quad(f, pts)
if __name__ == "__main__":
    exe = sys.argv[1]
    fractions = ("0.55", "0.97", "1.4")
    if len(sys.argv) == 4 and sys.argv[2] == "--fractions":
        fractions = tuple(sys.argv[3].split(","))
    elif len(sys.argv) != 2:
        sys.exit("usage: mpmath_reference.py path/to/flipflux [--fractions X,Y,...]")
    cases = [dict(), dict(m1=2, m2=0.5, L1=1.3, L2=0.7, g=9.81), dict(m1=1, m2=1, L1=1, L2=1, a1=0.5, a2=0.5, I1=0.0833333333333333333, I2=0.0833333333333333333)]
    worst = 0
    for par in cases:
        k = coeffs(**par); A,B,C,al,be,D0 = k
        Emax = 2*(al+be)
        opts = " ".join(f"--{n} {v}" for n,v in par.items())
        for frac in fractions:
            for arm in (1,2):
                Es = 2*be if arm == 2 else 2*al
                E = Es + (Emax-Es)*mp.mpf(frac)
                Es_txt = mp.nstr(E, 40)
                r2 = centre_ratio(k, 1, -1); r1 = centre_ratio(k, -1, 1)
                amp = r2 if arm == 2 else 1/r1
                ref = {"omega": omega(E,k), "flux-upright": curve_flux(E,k,arm,0), "flux-approx": curve_flux(E,k,arm,amp)}
                for q, v in ref.items():
                    out = subprocess.run(f"{exe} eval {q} --energy {Es_txt} --arm {arm} --precision quad {opts}", shell=True, capture_output=True, text=True)
                    if out.returncode != 0: print("ERR", q, out.stderr.strip()); continue
                    got = mp.mpf(json.loads(out.stdout)["value"])
                    rel = abs(got-v)/abs(v)
                    worst = max(worst, rel)
                    if rel > 1e-30: print(f"{par} arm {arm} E={mp.nstr(E,8)} {q}: rel {mp.nstr(rel,3)} got {mp.nstr(got,20)} ref {mp.nstr(v,20)}")
    print("worst relative difference", mp.nstr(worst, 3))
    sys.exit(0 if worst <= 1e-30 else 1)
