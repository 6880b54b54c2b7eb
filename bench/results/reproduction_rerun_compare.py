# The regenerated reproduction's run JSONs against the ones they replaced (commit 74e90e6, the run of
# 7697971 on an Intel Xeon): fields that differ, ignoring timing, the binary's name and the
# heavy-tail check's new fields; the largest relative change. Run from the repository root:
#   python3 bench/results/reproduction_rerun_compare.py
import collections, json, re, subprocess
skip = {'seconds', 'cpu_seconds', 'threads', 'processes', 'flipflux', 'error_ratio_range',
        'degrees_of_freedom'}
def load(rev, path):
    return json.loads(subprocess.run(['git', 'show', f'{rev}:{path}'], capture_output=True,
                                     text=True, check=True).stdout)
def walk(a, b, path, out):
    if isinstance(a, dict) and isinstance(b, dict):
        for k in sorted(set(a) | set(b)):
            if k in skip:
                continue
            if k not in a or k not in b:
                out.append((path + '/' + k, 'missing', ''))
            else:
                walk(a[k], b[k], path + '/' + k, out)
    elif isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        for i, (x, y) in enumerate(zip(a, b)):
            walk(x, y, '%s[%d]' % (path, i), out)
    elif a != b:
        out.append((path, a, b))
worst = 0.0
for f in ['ensemble-arm2.json', 'ensemble-arm1.json', 'ensemble-census-arm1.json',
          'ensemble-census-arm2.json', 'ensemble-residence-E5.json']:
    d = []
    walk(load('74e90e6', 'docs/reproduction/run/' + f), load('2193cc6', 'docs/reproduction/run/' + f), '', d)
    kinds = collections.Counter(re.sub(r'\[\d+\]', '', p).split('/')[-1] for p, _, _ in d)
    rel = [abs(float(y) / float(x) - 1) for _, x, y in d
           if isinstance(x, str) and isinstance(y, str) and float(x) != 0]
    worst = max([worst] + rel)
    print(f, len(d), 'fields differ; by name:', dict(kinds))
print('largest relative change: %.2e' % worst)
