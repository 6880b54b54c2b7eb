# Coverage and pessimism of the error estimates in the cross-check rows, before (the rows' own
# estimate, binary of 06b6757) and after (rerun_tanh_sinh_scaled_*.jsonl, the tanh-sinh level
# difference scaled by the half-width). Pendulum E's first rows (cmp_E.jsonl) had a wrong
# reference at some energies, superseded by cmp_E2.jsonl: the last row of each (pendulum, label,
# quantity, precision) is used. Pessimism: estimate / max(actual error, eps |value|).
import json, sys, collections
eps = {'double': 2.220446049250313e-16, 'quad': 1.925929944387236e-34}
last = {}
for f in sys.argv[1:]:
    for line in open(f):
        r = json.loads(line)
        last[(r['pend'], r['label'], r['key'], r['prec'])] = r
stats = collections.defaultdict(lambda: [0, 0, 0, 0, 0, 0.0, 0.0])
for (pend, label, key, prec), r in sorted(last.items()):
    v = abs(float(r['new_value'])) or 1e-300
    floor = max(eps[prec] * v, 1e-300)
    po = float(r['est']) / max(float(r['absdiff']), floor)
    pn = float(r['new_est']) / max(float(r['new_absdiff']), floor)
    s = stats[(key, prec)]
    s[0] += 1
    s[1] += not r['covered']
    s[2] += not r['new_covered']
    s[3] += po > 100
    s[4] += pn > 100
    s[5] = max(s[5], po)
    s[6] = max(s[6], pn)
print('quantity precision rows | uncovered before after | >100x before after | max pessimism before after')
tot = [0] * 5
for k, s in sorted(stats.items()):
    print(k[0], k[1], s[0], '|', s[1], s[2], '|', s[3], s[4], '|', '%.3g' % s[5], '%.3g' % s[6])
    for i in range(5):
        tot[i] += s[i]
print('total rows', tot[0], 'uncovered before', tot[1], 'after', tot[2], '>100x before', tot[3], 'after', tot[4])
print('>100x after, by pendulum:', dict(collections.Counter(
    p for (p, l, k, pr), r in last.items()
    if float(r['new_est']) / max(float(r['new_absdiff']), max(eps[pr] * abs(float(r["new_value"])), 1e-300)) > 100)))
