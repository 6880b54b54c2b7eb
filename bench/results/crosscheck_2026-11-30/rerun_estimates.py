import json,glob,subprocess,sys,os
from concurrent.futures import ThreadPoolExecutor
import mpmath
mpmath.mp.dps=60
rows=[json.loads(l) for f in sorted(glob.glob('/work/main/bench/results/crosscheck_2026-11-30/cmp_*.jsonl')) for l in open(f)]
precs=sys.argv[1].split(',')
rows=[r for r in rows if r['prec'] in precs and r.get('rc')==0]
env=dict(os.environ, FLIPFLUX_PLUGIN_DIR='/tmp/ffnew/plugins')
def run(r):
    cmd=r['cmd'].replace('/tmp/ffx/flipflux','/tmp/ffnew/flipflux').split()
    p=subprocess.run(cmd,capture_output=True,text=True,env=env)
    if p.returncode!=0: return dict(r, new_rc=p.returncode, new_err=p.stderr.strip()[:200])
    j=json.loads(p.stdout)
    v=j['value']; e=j['error_estimate']
    d=abs(mpmath.mpf(v)-mpmath.mpf(r['ref']))
    return dict(r, new_value=v, new_est=e, new_absdiff=mpmath.nstr(d,3), new_covered=bool(mpmath.mpf(e)>=d))
with ThreadPoolExecutor(2) as ex:
    out=list(ex.map(run,rows))
with open(sys.argv[2],'w') as f:
    for o in out: f.write(json.dumps(o)+'\n')
