import json,subprocess,os,sys,glob,mpmath
mpmath.mp.dps=50
env=dict(os.environ, FLIPFLUX_PLUGIN_DIR='/work/main/build/release/plugins')
B=sys.argv[1]
rows=[json.loads(l) for f in sorted(glob.glob('/work/main/bench/results/crosscheck_2026-11-30/cmp_*.jsonl')) for l in open(f)]
last={}
for r in rows:
    if r['key']=='omega' and r['prec'] in ('double','quad'): last[(r['pend'],r['label'],r['prec'])]=r
worst={}
for (p,l,pr),r in sorted(last.items()):
    cmd=r['cmd'].replace('/tmp/ffx/flipflux',B).split()+['--method','quadrature-2d']
    q=subprocess.run(cmd,capture_output=True,text=True,env=env,timeout=600)
    if q.returncode: print(p,l,pr,'rc',q.returncode,q.stderr[:100]); continue
    j=json.loads(q.stdout); d=abs(mpmath.mpf(j['value'])-mpmath.mpf(r['ref'])); e=mpmath.mpf(j['error_estimate'])
    eps={'double':2.2e-16,'quad':1.93e-34}[pr]
    ratio=d/e
    pess=e/max(d,eps*abs(mpmath.mpf(j['value'])))
    k=(p,pr); w=worst.get(k,(0,0)); worst[k]=(max(w[0],float(ratio)),max(w[1],float(pess)))
    if ratio>1: print('UNCOVERED',p,l,pr,'diff',mpmath.nstr(d,3),'est',j['error_estimate'])
for k,v in sorted(worst.items()): print(k,'max diff/est %.3g'%v[0],'max pessimism %.3g'%v[1])
