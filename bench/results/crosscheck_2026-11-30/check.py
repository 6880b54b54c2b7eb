#!/usr/bin/python3
"""Independent recomputation of flipflux simulate statistics from its CSVs.
usage: check.py JSON CSVDIR [--quiet]"""
import csv, json, math, os, random, sys

TOL = 1e-9
results = {'ok': 0, 'bad': [], 'maxrel': 0.0, 'approx': []}


def num(x):
    if x is None:
        return None
    if isinstance(x, (int, float)):
        return float(x)
    if isinstance(x, str):
        try:
            return float(x)
        except ValueError:
            return x
    return x


def cmp(path, prog, mine, tol=TOL, approx=False):
    p = num(prog)
    m = mine
    if m is None or (isinstance(m, float) and math.isnan(m)):
        if p is None or (isinstance(p, float) and math.isnan(p)):
            results['ok'] += 1
            return
        results['bad'].append((path, prog, mine))
        return
    if p is None or isinstance(p, str):
        results['bad'].append((path, prog, mine))
        return
    if math.isinf(m) or math.isinf(p):
        if m == p:
            results['ok'] += 1
        else:
            results['bad'].append((path, prog, mine))
        return
    d = abs(p - m)
    rel = d / max(abs(m), abs(p), 1e-300)
    ok = d <= tol * max(abs(m), abs(p)) or d <= 1e-15
    if approx:
        results['approx'].append((path, p, m, rel))
        return
    if ok:
        results['ok'] += 1
        if d > 1e-15:
            results['maxrel'] = max(results['maxrel'], rel)
    else:
        results['bad'].append((path, prog, mine))


def mean(x):
    return math.fsum(x) / len(x)


def summary(x):
    """count, mean, sample sd (n-1), se = sd/sqrt(n), skew m3/m2^1.5, kurt m4/m2^2 (plain)"""
    n = len(x)
    if n == 0:
        return dict(n=0, mean=None, sd=None, se=None, skew=None, kurt=None, max=None, min=None)
    m = mean(x)
    dev = [v - m for v in x]
    m2 = math.fsum(d * d for d in dev) / n
    m3 = math.fsum(d ** 3 for d in dev) / n
    m4 = math.fsum(d ** 4 for d in dev) / n
    sd = math.sqrt(m2 * n / (n - 1)) if n > 1 else None
    se = sd / math.sqrt(n) if sd is not None else None
    skew = m3 / m2 ** 1.5 if (n > 1 and m2 > 0) else None
    kurt = m4 / m2 ** 2 if (n > 1 and m2 > 0) else None
    return dict(n=n, mean=m, sd=sd, se=se, skew=skew, kurt=kurt, max=max(x), min=min(x), m2=m2, m3=m3, m4=m4)


def quantile(sorted_x, q):
    n = len(sorted_x)
    h = (n - 1) * q
    lo = math.floor(h)
    hi = min(lo + 1, n - 1)
    return sorted_x[lo] + (h - lo) * (sorted_x[hi] - sorted_x[lo])


def jackknife(groups):
    """groups: list of lists of values; jackknife se of the pooled mean (ratio estimator)."""
    groups = [g for g in groups if len(g) > 0]
    R = len(groups)
    if R < 2:
        return None
    tot = math.fsum(math.fsum(g) for g in groups)
    cnt = sum(len(g) for g in groups)
    loo = []
    for g in groups:
        c = cnt - len(g)
        loo.append((tot - math.fsum(g)) / c)
    mb = mean(loo)
    return math.sqrt((R - 1) / R * math.fsum((v - mb) ** 2 for v in loo))


def jackknife_values(loo):
    if any(v is None for v in loo):
        return None
    R = len(loo)
    if R < 2:
        return None
    mb = mean(loo)
    return math.sqrt((R - 1) / R * math.fsum((v - mb) ** 2 for v in loo))


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def hist_counts(values, bins_opt):
    n = len(values)
    if bins_opt:
        nb = bins_opt
    else:
        nb = min(200, max(10, math.ceil(math.sqrt(n))))
    return nb


def iqi_pqi(samples, scale=None):
    """samples: list of (mean, pred, spread). returns IQI, PQI"""
    if not samples:
        return None, None
    R2 = [(m / p - 1) ** 2 for m, p, s in samples]
    S2 = [(s / p) ** 2 * (scale if scale else 1) for m, p, s in samples]
    return math.sqrt(mean(R2)), math.sqrt(mean([a + b for a, b in zip(R2, S2)]))


def bootstrap(samples, B=4000, scale=None, seed=12345):
    """samples: (mean, pred, s, n, m3, m4). parametric bootstrap sd of IQI and PQI."""
    rng = random.Random(seed)
    iq, pq = [], []
    for _ in range(B):
        R2, Q = [], []
        for (m, p, s, n, m3, m4, se) in samples:
            v11 = se * se
            v22 = (m4 - s ** 4 * (n - 3) / (n - 1)) / n
            v12 = m3 / n
            # cholesky
            a = math.sqrt(v11)
            b = v12 / a if a > 0 else 0.0
            c2 = v22 - b * b
            c = math.sqrt(max(c2, 0.0))
            z1, z2 = rng.gauss(0, 1), rng.gauss(0, 1)
            mm = m + a * z1
            ss2 = s * s + b * z1 + c * z2
            S = math.sqrt(max(ss2, 0)) / p
            r2 = (mm / p - 1) ** 2
            R2.append(r2)
            Q.append(r2 + S * S * (scale if scale else 1))
        iq.append(math.sqrt(mean(R2)))
        pq.append(math.sqrt(mean(Q)))
    return summary(iq)['sd'], summary(pq)['sd']


REG = {}
def in_regime(E, reg):
    if reg['regime'] == 'all': return True
    lo, up = REG[reg['regime']]
    return lo <= E < up


def check_study(d, csvdir, tag, bins_opt=0):
    T = num(d['time'])
    R = d.get('replicates', {}).get('count', 1) if isinstance(d.get('replicates'), dict) else 1
    first = d.get('first_index', 0)
    thr = num(d['chaos']['threshold_rate']) if 'chaos' in d and d['chaos'] else None
    crit_names = None
    if not d.get('chaos') or d['chaos'].get('indicator') in (None, 'none', 'off') or 'threshold_rate' not in d['chaos']:
        thr = None
    REG.clear()
    for rg in d.get('regimes', []):
        REG[rg['regime']] = (num(rg['lower']), num(rg['upper']))
    per_crit_energy = {}  # crit -> list of dicts for quality/agreement
    for e in d['energies']:
        label = e['energy']
        E = num(label)
        tpath = os.path.join(csvdir, 'trajectories_E%s.csv' % label)
        if not os.path.exists(tpath):
            results['bad'].append((tag + ' missing csv', tpath, None))
            continue
        rows = read_csv(tpath)
        okrows = [r for r in rows if r['status'] == 'ok']
        cmp(f'{tag} E{label}.failed_trajectories', e['failed_trajectories'], float(len(rows) - len(okrows)))
        if okrows:
            cmp(f'{tag} E{label}.max_energy_drift', e['max_energy_drift'], max(float(r['max_energy_drift']) for r in okrows))
        crit_names = list(e['criteria'].keys())
        # chaos flag vs lyapunov
        if thr is not None and okrows and okrows[0].get('lyapunov'):
            for r in okrows:
                lam = float(r['lyapunov'])
                if (lam > thr) != (r['chaotic'] == '1'):
                    results['bad'].append((f'{tag} E{label} traj {r["index"]} chaotic flag', r['chaotic'], lam))
                else:
                    results['ok'] += 1
        rates_by_c = {}
        for c, cj in e['criteria'].items():
            p = f'{tag} E{label}.{c}'
            flips = [int(r['flips_' + c]) for r in okrows]
            rates = [float(r['rate_' + c]) for r in okrows]
            for fl, ra in zip(flips, rates):
                if abs(fl / T - ra) > 1e-15 * max(1, ra):
                    results['bad'].append((p + ' csv rate != flips/T', ra, fl / T))
            rates = [fl / T for fl in flips]
            rates_by_c[c] = rates
            s = summary(rates)
            pred = num(cj.get('predicted_rate'))
            cmp(p + '.mean_rate', cj.get('mean_rate'), s['mean'])
            cmp(p + '.std', cj.get('std'), s['sd'])
            cmp(p + '.standard_error', cj.get('standard_error'), s['se'])
            cmp(p + '.skewness', cj.get('skewness'), s['skew'])
            cmp(p + '.kurtosis', cj.get('kurtosis'), s['kurt'])
            z = (s['mean'] - pred) / s['se'] if (s['se'] and pred is not None) else None
            if s['se'] == 0 and pred is not None:
                z = None  # expectation: undefined
            cmp(p + '.z_score', cj.get('z_score'), z)
            cmp(p + '.flips', cj.get('flips'), float(sum(flips)))
            cmp(p + '.max_rate', cj.get('max_rate'), s['max'])
            chaotic_rows = [r for r in okrows if r.get('chaotic') == '1']
            if thr is not None:
                cf = len(chaotic_rows) / len(okrows) if okrows else None
                cmp(p + '.chaotic_fraction', cj.get('chaotic_fraction'), cf)
                cr = [int(r['flips_' + c]) / T for r in chaotic_rows]
                sc = summary(cr)
                ch = cj.get('chaotic') or {}
                cmp(p + '.chaotic.trajectories', ch.get('trajectories'), float(len(cr)))
                cmp(p + '.chaotic.mean_rate', ch.get('mean_rate'), sc['mean'])
                cmp(p + '.chaotic.std', ch.get('std'), sc['sd'])
                cmp(p + '.chaotic.standard_error', ch.get('standard_error'), sc['se'])
                cmp(p + '.chaotic.skewness', ch.get('skewness'), sc['skew'])
                cmp(p + '.chaotic.kurtosis', ch.get('kurtosis'), sc['kurt'])
                zc = (sc['mean'] - pred) / sc['se'] if (sc['se'] and pred is not None) else None
                cmp(p + '.chaotic.z_score', ch.get('z_score'), zc)
            else:
                if 'chaotic' in cj:
                    results['bad'].append((p + '.chaotic present with --no-chaos', cj['chaotic'], None))
                sc = None
            # rate histogram
            rh = cj.get('rate_histogram')
            if rh and rates:
                nb = len(rh['counts'])
                exp_nb = bins_opt or min(200, max(10, math.ceil(math.sqrt(len(rates)))))
                cmp(p + '.rate_histogram.nbins', float(nb), float(exp_nb))
                lo, up = num(rh['lower']), num(rh['upper'])
                cmp(p + '.rate_histogram.upper~max', up, max(rates), tol=1e-12)
                w = (up - lo) / nb
                cnt = [0] * nb
                for v in rates:
                    k = int((v - lo) / w)
                    if k >= nb: k = nb - 1
                    cnt[k] += 1
                if cnt != rh['counts']:
                    results['bad'].append((p + '.rate_histogram.counts', rh['counts'], cnt))
                else:
                    results['ok'] += 1
                hp = os.path.join(csvdir, f'rate_histogram_E{label}_{c}.csv')
                if os.path.exists(hp):
                    hr = read_csv(hp)
                    cc = [int(r['count']) for r in hr]
                    if cc != rh['counts']:
                        results['bad'].append((p + ' rate_histogram csv counts', cc, rh['counts']))
                    for r in hr:
                        bw = float(r['bin_upper']) - float(r['bin_lower'])
                        cmp(p + ' rate_histogram csv density', r['density'], int(r['count']) / (len(rates) * bw) if rates else 0, tol=1e-9)
            # residence
            rp = os.path.join(csvdir, f'residence_E{label}_{c}.csv')
            res_all, res_ch = [], []
            rt = cj.get('residence_times')
            if os.path.exists(rp):
                rr = read_csv(rp)
                chaotic_idx = set(r['index'] for r in chaotic_rows)
                ok_idx = set(r['index'] for r in okrows)
                last = {}
                for r in rr:
                    tr = r['trajectory']
                    ct, rt_ = float(r['crossing_time']), float(r['residence_time'])
                    if tr in last:
                        if abs((ct - last[tr]) - rt_) > 1e-12 * max(1, ct):
                            results['bad'].append((p + f' residence != diff crossing (traj {tr})', rt_, ct - last[tr]))
                    last[tr] = ct
                    if tr not in ok_idx:
                        continue
                    res_all.append(rt_)
                    if tr in chaotic_idx:
                        res_ch.append(rt_)
                # count check: flips - trajectories with >=1 flip
                exp_count = sum(f - 1 for f in flips if f > 0)
                cmp(p + '.residence count vs flips', float(len(res_all)), float(exp_count))
            if rt is not None:
                cmp(p + '.residence_times.count', rt.get('count'), float(len(res_all)))
                if res_all:
                    sr = sorted(res_all)
                    cmp(p + '.residence_times.min', rt.get('min'), sr[0])
                    cmp(p + '.residence_times.q0.001', rt.get('q0.001'), quantile(sr, 0.001))
                    cmp(p + '.residence_times.q0.01', rt.get('q0.01'), quantile(sr, 0.01))
                    cmp(p + '.residence_times.median', rt.get('median'), quantile(sr, 0.5))
                    cmp(p + '.residence_times.mean', rt.get('mean'), mean(sr))
                else:
                    for k in ('min', 'q0.001', 'q0.01', 'median', 'mean'):
                        if rt.get(k) is not None:
                            results['bad'].append((p + '.residence_times.' + k + ' with no residence times', rt.get(k), None))
            # residence histogram csv
            hp = os.path.join(csvdir, f'residence_histogram_E{label}_{c}.csv')
            if os.path.exists(hp) and res_all:
                hr = read_csv(hp)
                nb = len(hr)
                exp_nb = bins_opt or min(200, max(10, math.ceil(math.sqrt(len(res_all)))))
                cmp(p + '.residence_histogram.nbins', float(nb), float(exp_nb))
                up = float(hr[-1]['bin_upper'])
                w = up / nb
                cnt = [0] * nb
                for v in res_all:
                    k = int(v / w)
                    if k >= nb: k = nb - 1
                    cnt[k] += 1
                cc = [int(r['count']) for r in hr]
                if cc != cnt:
                    results['bad'].append((p + '.residence_histogram counts', cc, cnt))
                else:
                    results['ok'] += 1
                cmp(p + '.residence_histogram upper~max', up, max(res_all), tol=1e-12)
                for r in hr:
                    bw = float(r['bin_upper']) - float(r['bin_lower'])
                    cmp(p + ' residence_histogram density', r['density'], int(r['count']) / (len(res_all) * bw), tol=1e-9)
            # flip_counts
            fc = cj.get('flip_counts')
            if fc is not None and os.path.exists(rp):
                # reconstruct crossing times per trajectory
                times = {r['index']: [] for r in okrows}
                rr = read_csv(rp)
                firsts = {}
                for r in rr:
                    tr = r['trajectory']
                    if tr not in times: continue
                    if not times[tr]:
                        times[tr].append(float(r['crossing_time']) - float(r['residence_time']))
                    times[tr].append(float(r['crossing_time']))
                nflips = {r['index']: int(r['flips_' + c]) for r in okrows}
                windows = []
                w = T
                while w >= 1 - 1e-12 and len(windows) < 5:
                    windows.append(w)
                    w = w / 10
                cmp(p + '.flip_counts.fano.len', float(len(fc['fano'])), float(len(windows)))
                for wi, wj in zip(windows, fc['fano']):
                    cmp(p + f'.fano[w={wj["window"]}].window', wj['window'], wi)
                    nw = int(math.floor(T / wi + 1e-9))
                    for sub, rowsel, suf in ((okrows, None, ''), (chaotic_rows, None, '_chaotic')):
                        if thr is None and suf:
                            continue
                        counts = []
                        for r in sub:
                            tr = r['index']
                            nf = nflips[tr]
                            if nf == 1:
                                cs = [0] * nw
                                cs[0] = 1  # position irrelevant for var/mean (assumes flip in [0, nw*w))
                                counts.extend(cs)
                            else:
                                cs = [0] * nw
                                for t in times[tr]:
                                    k = int(t / wi)
                                    if k < nw: cs[k] += 1
                                counts.extend(cs)
                        cmp(p + f'.fano[w={wj["window"]}].windows{suf}', wj['windows' + suf], float(len(counts)))
                        if counts:
                            ssum = summary([float(x) for x in counts])
                            cmp(p + f'.fano[w={wj["window"]}].mean_count{suf}', wj['mean_count' + suf], ssum['mean'])
                            fano = ssum['sd'] ** 2 / ssum['mean'] if (ssum['sd'] is not None and ssum['mean'] > 0) else None
                            cmp(p + f'.fano[w={wj["window"]}].fano{suf}', wj['fano' + suf], fano)
                s_res = summary(res_all)
                cv2 = s_res['sd'] ** 2 / s_res['mean'] ** 2 if s_res['sd'] is not None else None
                cmp(p + '.inter_flip_cv2', fc.get('inter_flip_cv2'), cv2)
                if thr is not None:
                    s_rc = summary(res_ch)
                    cv2c = s_rc['sd'] ** 2 / s_rc['mean'] ** 2 if s_rc['sd'] is not None else None
                    cmp(p + '.inter_flip_cv2_chaotic', fc.get('inter_flip_cv2_chaotic'), cv2c)
                surv = fc.get('inter_flip_survival') or []
                if res_all:
                    mn, mx = min(res_all), max(res_all)
                    if len(surv) == 24:
                        for k, (t, sv, svc) in enumerate(surv):
                            tk = mn * (mx / mn) ** (k / 23)
                            cmp(p + f'.survival[{k}].time', t, tk, tol=1e-12)
                            t = float(t)
                            cmp(p + f'.survival[{k}].P', sv, sum(1 for v in res_all if v > t) / len(res_all))
                            if thr is not None:
                                cmp(p + f'.survival[{k}].P_chaotic', svc, (sum(1 for v in res_ch if v > t) / len(res_ch)) if res_ch else None)
                    else:
                        results['bad'].append((p + '.survival len', len(surv), 24))
            # replicates
            rep = cj.get('replicates')
            if R > 1:
                N = len(rows) // R
                blocks = [[] for _ in range(R)]
                blocks_c = [[] for _ in range(R)]
                for r in okrows:
                    k = (int(r['index']) - first) // N
                    blocks[k].append(int(r['flips_' + c]) / T)
                    if r.get('chaotic') == '1':
                        blocks_c[k].append(int(r['flips_' + c]) / T)
                for key, bl, sfull in (('all_trajectories', blocks, s), ('chaotic_trajectories', blocks_c, sc)):
                    if thr is None and key == 'chaotic_trajectories':
                        continue
                    rj = rep[key]
                    se = jackknife(bl)
                    cmp(p + f'.replicates.{key}.standard_error', rj.get('standard_error'), se)
                    zz = (sfull['mean'] - pred) / se if (se and pred is not None) else None
                    cmp(p + f'.replicates.{key}.z_score', rj.get('z_score'), zz)
                    er = se / sfull['se'] if (se is not None and sfull['se']) else None
                    cmp(p + f'.replicates.{key}.error_ratio', rj.get('error_ratio'), er)
                    if rj.get('trajectories') != [len(b) for b in bl]:
                        results['bad'].append((p + f'.replicates.{key}.trajectories', rj.get('trajectories'), [len(b) for b in bl]))
                    for k, b in enumerate(bl):
                        cmp(p + f'.replicates.{key}.means[{k}]', rj['means'][k] if k < len(rj['means']) else None, mean(b) if b else None)
            # store for quality
            per_crit_energy.setdefault(c, []).append(dict(E=E, pred=pred, s=s, sc=sc, rates=rates,
                                                        blocks=blocks if R > 1 else None,
                                                        blocks_c=blocks_c if R > 1 else None))
        # paired differences
        for pd in e.get('paired_differences', []):
            a, b = pd['criteria']
            diff = [x - y for x, y in zip(rates_by_c[a], rates_by_c[b])]
            sd_ = summary(diff)
            pp = f'{tag} E{label}.paired[{a}-{b}]'
            cmp(pp + '.mean', pd['mean'], sd_['mean'])
            cmp(pp + '.std', pd['std'], sd_['sd'])
            cmp(pp + '.standard_error', pd['standard_error'], sd_['se'])
    # prediction differences
    for pd in d.get('prediction_differences', []):
        a, b = pd['criteria']
        vals = []
        for ea, eb in zip(per_crit_energy.get(a, []), per_crit_energy.get(b, [])):
            if ea['pred'] is not None and eb['pred'] is not None:
                vals.append((ea['pred'] / eb['pred'] - 1) ** 2)
        cmp(f'{tag} prediction_differences[{a}-{b}].energies', float(pd['energies']), float(len(vals)))
        cmp(f'{tag} prediction_differences[{a}-{b}].rms_relative', pd['rms_relative'], math.sqrt(mean(vals)) if vals else None)
    # quality & agreement
    refq = None
    for c, lst in per_crit_energy.items():
        for key in ('all_trajectories', 'chaotic_trajectories'):
            if thr is None and key == 'chaotic_trajectories':
                continue
            sk = 's' if key == 'all_trajectories' else 'sc'
            for q in d['quality'][c][key]:
                reg = q['regime']
                sel = [x for x in lst if in_regime(x['E'], q) and x['pred'] is not None and x['pred'] > 0
                       and x[sk]['mean'] is not None]
                pq = f'{tag} quality.{c}.{key}[{reg}]'
                # energies with n>=2 (spread defined)
                sel2 = [x for x in sel if x[sk]['sd'] is not None]
                cmp(pq + '.energies', float(q['energies']), float(len(sel2)))
                smp = [(x[sk]['mean'], x['pred'], x[sk]['sd']) for x in sel2]
                iq, pqv = iqi_pqi(smp)
                cmp(pq + '.IQI', q.get('IQI'), iq)
                cmp(pq + '.PQI', q.get('PQI'), pqv)
                nf = math.sqrt(mean([(x[sk]['se'] / x['pred']) ** 2 for x in sel2])) if sel2 else None
                cmp(pq + '.noise_floor', q.get('noise_floor'), nf)
                rs = math.sqrt(mean([(x[sk]['sd'] / x['pred']) ** 2 for x in sel2])) if sel2 else None
                cmp(pq + '.rms_S', q.get('rms_S'), rs)
                if sel2:
                    bs = [(x[sk]['mean'], x['pred'], x[sk]['sd'], x[sk]['n'], x[sk]['m3'], x[sk]['m4'], x[sk]['se']) for x in sel2]
                    bi, bp = bootstrap(bs, B=3000)
                    cmp(pq + '.IQI_sd', q.get('IQI_sd'), bi, approx=True)
                    cmp(pq + '.PQI_sd', q.get('PQI_sd'), bp, approx=True)
                    if 'reference' in q:
                        Tref = num(q['reference']['time'])
                        _, pr = iqi_pqi(smp, scale=T / Tref)
                        cmp(pq + '.reference.PQI', q['reference'].get('PQI'), pr)
                        _, brp = bootstrap(bs, B=3000, scale=T / Tref)
                        cmp(pq + '.reference.PQI_sd', q['reference'].get('PQI_sd'), brp, approx=True)
                if R > 1 and sel2:
                    rq = q.get('replicates')
                    bk = 'blocks' if key == 'all_trajectories' else 'blocks_c'
                    own_i, own_p, loo_i, loo_p = [], [], [], []
                    for k in range(R):
                        smpk = []
                        smpl = []
                        for x in sel2:
                            b = x[bk][k]
                            if len(b) >= 2:
                                sb = summary(b)
                                smpk.append((sb['mean'], x['pred'], sb['sd']))
                            rest = [v for j in range(R) if j != k for v in x[bk][j]]
                            if len(rest) >= 2:
                                sb = summary(rest)
                                smpl.append((sb['mean'], x['pred'], sb['sd']))
                        a1, a2 = iqi_pqi(smpk)
                        own_i.append(a1); own_p.append(a2)
                        a1, a2 = iqi_pqi(smpl)
                        loo_i.append(a1); loo_p.append(a2)
                    if None in loo_i: print('NOTE', pq, 'LOO with no energies', loo_i, 'prog IQI_se', rq.get('IQI_se'))
                    for k in range(R):
                        cmp(pq + f'.replicates.IQI[{k}]', rq['IQI'][k], own_i[k])
                        cmp(pq + f'.replicates.PQI[{k}]', rq['PQI'][k], own_p[k])
                    cmp(pq + '.replicates.IQI_se', rq.get('IQI_se'), jackknife_values(loo_i))
                    cmp(pq + '.replicates.PQI_se', rq.get('PQI_se'), jackknife_values(loo_p))
            # agreement
            ag = d['agreement'][c][key]
            pa = f'{tag} agreement.{c}.{key}'
            zs, rel = [], []
            for x in lst:
                st = x[sk]
                if x['pred'] is None or st['se'] is None or not st['se'] > 0:
                    continue
                zs.append((st['mean'] - x['pred']) / st['se'])
                rel.append(abs(st['mean'] / x['pred'] - 1))
            cmp(pa + '.energies', float(ag['energies']), float(len(zs)))
            cmp(pa + '.chi2', ag['chi2'], math.fsum(z * z for z in zs))
            cmp(pa + '.worst_z', ag['worst_z'], max(zs, key=abs) if zs else None)
            cmp(pa + '.max_relative_deviation', ag['max_relative_deviation'], max(rel) if rel else None)
            if R > 1:
                ar = ag['replicates']
                bk = 'blocks' if key == 'all_trajectories' else 'blocks_c'
                zr, ratios = [], []
                for x in lst:
                    se = jackknife(x[bk])
                    if x['pred'] is None or se is None or not se > 0:
                        continue
                    zr.append((x[sk]['mean'] - x['pred']) / se)
                    if x[sk]['se']:
                        ratios.append(se / x[sk]['se'])
                cmp(pa + '.replicates.energies', float(ar['energies']), float(len(zr)))
                cmp(pa + '.replicates.chi2', ar['chi2'], math.fsum(z * z for z in zr))
                cmp(pa + '.replicates.expected_chi2', ar['expected_chi2'], len(zr) * (R - 1) / (R - 3) if R > 3 else None)
                cmp(pa + '.replicates.worst_z', ar['worst_z'], max(zr, key=abs) if zr else None)
                cmp(pa + '.replicates.max_error_ratio', ar['max_error_ratio'], max(ratios) if ratios else None)
                cmp(pa + '.replicates.min_error_ratio', ar['min_error_ratio'], min(ratios) if ratios else None)
                cmp(pa + '.replicates.error_mismatches', float(ar['error_mismatches']), float(sum(1 for r_ in ratios if r_ > 2 or r_ < 0.5)))
                for k in range(R):
                    zz = []
                    for x in lst:
                        b = x[bk][k]
                        if len(b) < 2 or x['pred'] is None: continue
                        sb = summary(b)
                        if not sb['se'] > 0: continue
                        zz.append(((sb['mean'] - x['pred']) / sb['se']) ** 2)
                    cmp(pa + f'.replicates.chi2_of_replicates[{k}]', ar['chi2_of_replicates'][k], math.fsum(zz))


def main():
    jpath, csvdir = sys.argv[1], sys.argv[2]
    bins = int(sys.argv[3]) if len(sys.argv) > 3 else 0
    d = json.load(open(jpath))
    if 'studies' in d:
        for st in d['studies']:
            a = st['arm']
            check_study(st, os.path.join(csvdir, 'arm' + str(a)), 'arm' + str(a), bins)
    else:
        check_study(d, csvdir, 'arm' + str(d['arm']), bins)
    print(f"OK comparisons: {results['ok']}, max rel diff among agreeing: {results['maxrel']:.3g}")
    print(f"DISAGREEMENTS: {len(results['bad'])}")
    for b in results['bad'][:60]:
        print('  BAD', b)
    worst = sorted(results['approx'], key=lambda x: -x[3])[:4]
    print(f"bootstrap sd (approx, {len(results['approx'])}): worst rel diffs", [(w[0].split('quality.')[-1], round(w[1], 5), round(w[2], 5), round(w[3], 3)) for w in worst])


main()
