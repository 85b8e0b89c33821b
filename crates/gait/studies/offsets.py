"""How the kinematic methods' offsets are chosen, and the touchdown method joined to the strike
mean, scored from an `events_eval --dump` CSV (docs/events.md, "How the offsets are chosen"
and "A physically defined strike").

    cargo run --release -p evals --bin events_eval -- --dump e.csv
    python3 crates/gait/studies/offsets.py choice e.csv      # pooled events vs per-lab medians, truths in doubt, per marker class
    python3 crates/gait/studies/offsets.py touchdown e.csv   # the strike mean with the touchdown estimate (heel trials)
    python3 crates/gait/studies/offsets.py grid              # the touchdown thresholds (runs events_eval per setting)

Strikes are simulated as the shipped mean: zeni-landing (which decides which strikes exist),
Zeni and Desailly joined within 0.2 s, each method's nearest error within 150 ms plus its
offset (an ankle standing in for the heel: zeni-landing is Zeni's + 20 ms). Offs: the
shipped error (Zeni, its -9.8 ms offset and the trial's stride shift) with the offset
replaced. Each variant's offsets are chosen on the tuning labs (c3d-samples) and scored on
each tuning lab left out of the choice in turn (leave one lab out), then on the held-out
labs with the offsets chosen on all the tuning labs. Standard library only.
"""
import csv, math, os, statistics as st, subprocess, sys

SHIP = {'zeni_refined': -0.0012, 'zeni_raw': 0.0225, 'desailly_03': 0.021}
SHIP_OFF = -0.0098
STRIKE = ['zeni_refined', 'zeni_raw', 'desailly_03']


def num(x):
    try:
        v = float(x)
        return v if math.isfinite(v) else None
    except ValueError:
        return None


def quantile(v, p):
    v = sorted(v)
    if not v:
        return float('nan')
    pos = (len(v) - 1) * p
    i, fr = int(pos), pos - int(pos)
    return v[i] * (1 - fr) + v[i + 1] * fr if i + 1 < len(v) else v[i]


def estimate(r, m):
    """Method m's signed error (s) at row r before any offset."""
    if r['kind'] == 'FootOff':
        v = num(r['shipped'])
        return None if v is None else v - SHIP_OFF
    if m == 'touchdown' and r['ankle'] == '1':
        return None  # no touchdown estimate where an ankle stands in for the heel
    v = num(r[m])
    if v is not None and m in ('zeni_refined', 'touchdown') and r['ankle'] == '1':
        v += 0.02
    return v


def offsets(train, methods, how='pooled', per_class=False):
    """Each method's offset: minus the median signed error over the training rows, pooled
    ('pooled'), as the median of per-lab medians ('labs') or of per-lab-and-truth medians
    ('labtruth'); per marker class (heel marker, ankle for heel) when per_class."""
    out = {}
    for cls in ('0', '1'):
        rows = [r for r in train if r['ankle'] == cls] if per_class else train
        for m in methods:
            groups = {}
            for r in rows:
                e = estimate(r, m)
                if e is None:
                    continue
                key = {'pooled': 0, 'labs': r['lab'], 'labtruth': (r['lab'], r['truth'])}[how]
                groups.setdefault(key, []).append(e)
            meds = [st.median(g) for g in groups.values()]
            out[(cls, m)] = -st.median(meds) if meds else 0.0
    return out


def combined(r, methods, off):
    cls = r['ankle']
    first = estimate(r, methods[0])
    if first is None:
        return None
    vals = [first + off[(cls, methods[0])]]
    for m in methods[1:]:
        v = estimate(r, m)
        if v is not None and abs(v + off[(cls, m)] - vals[0]) <= 0.2:
            vals.append(v + off[(cls, m)])
    return sum(vals) / len(vals)


def score(rows, kind, methods, choose, keep=lambda r: True):
    """(leave-one-lab-out on the tuning labs, held out), each {truth: [signed ms]}."""
    rows = [r for r in rows if r['kind'] == kind]
    tuning = [r for r in rows if r['group'] == 'tuning']
    lolo, held = {'lab': [], 'plate': []}, {'lab': [], 'plate': []}
    for lab in sorted({r['lab'] for r in tuning}):
        off = choose([r for r in tuning if r['lab'] != lab and keep(r)])
        for r in tuning:
            e = combined(r, methods, off) if r['lab'] == lab else None
            if e is not None and abs(e) <= 0.15:
                lolo[r['truth']].append(e * 1000)
    off = choose([r for r in tuning if keep(r)])
    for r in rows:
        e = combined(r, methods, off) if r['group'] == 'held_out' else None
        if e is not None and abs(e) <= 0.15:
            held[r['truth']].append(e * 1000)
    return lolo, held, off


def fmt(res):
    return ' | '.join(
        f"{t} {len(v):2} {quantile([abs(x) for x in v], .5):5.1f} / {quantile([abs(x) for x in v], .95):5.1f} ({quantile(v, .5):+5.1f})"
        for t, v in res.items())


def in_doubt(rows):
    """Tuning truths in doubt: a lab event and a plate event of the same trial, foot and kind
    more than 30 ms apart (sample_04's sub_labels, both left out), and sample_14's plates
    (its analog blocks are written out of order). --without-contradicted marks none of the
    tuning labs' events (only RBWH's two held-out strikes)."""
    key = lambda r: (r['file'], r['side'], r['kind'])
    plates = {}
    for p in rows:
        if p['truth'] == 'plate':
            plates.setdefault(key(p), []).append(p)
    doubt = set()
    for r in rows:
        if r['truth'] == 'lab':
            for p in plates.get(key(r), []):
                if 0.03 < abs(float(p['time']) - float(r['time'])) < 0.15:
                    doubt.update((id(r), id(p)))
        if r['lab'].endswith('sample_14') and r['truth'] == 'plate':
            doubt.add(id(r))
    return doubt


def choice(path):
    rows = list(csv.DictReader(open(path)))
    doubt = in_doubt(rows)
    for kind, methods in (('FootStrike', STRIKE), ('FootOff', ['zeni_raw'])):
        for how in ('pooled', 'labs', 'labtruth'):
            for per_class in (False, True):
                for drop in (False, True):
                    lolo, held, off = score(
                        rows, kind, methods,
                        lambda t: offsets(t, methods, how, per_class),
                        (lambda r: id(r) not in doubt) if drop else (lambda r: True))
                    shown = ' '.join(f"{'ankle:' if c == '1' else ''}{m} {v * 1000:+.1f}"
                                     for (c, m), v in off.items() if per_class or c == '0')
                    print(f"{kind} offsets: {how}{', per marker class' if per_class else ''}{', truths in doubt left out' if drop else ''}: {shown}")
                    print(f"   tuning, each lab left out: {fmt(lolo)}")
                    print(f"   held out:                  {fmt(held)}")


TOUCHDOWN = ['zeni_refined', 'touchdown', 'zeni_raw', 'desailly_03']


def shipped(train):
    return {(c, m): v for c in '01' for m, v in SHIP.items()}


def with_touchdown(train):
    """The shipped offsets, and the touchdown's own: minus its median over the training rows
    (heel trials: it gives no estimate where an ankle stands in for the heel)."""
    off = shipped(train)
    td = [e for e in (estimate(r, 'touchdown') for r in train) if e is not None]
    off[('0', 'touchdown')] = off[('1', 'touchdown')] = -st.median(td)
    return off


def touchdown(path):
    rows = list(csv.DictReader(open(path)))
    lolo, held, _ = score(rows, 'FootStrike', STRIKE, shipped)
    print(f"strikes, shipped mean\n   tuning, each lab left out: {fmt(lolo)}\n   held out:                  {fmt(held)}")
    lolo, held, off = score(rows, 'FootStrike', TOUCHDOWN, with_touchdown)
    print(f"strikes, mean with touchdown (heel trials, offset {off[('0', 'touchdown')] * 1000:+.1f} ms)\n   tuning, each lab left out: {fmt(lolo)}\n   held out:                  {fmt(held)}")


def grid():
    """The touchdown's strike thresholds: one events_eval --dump per setting (under a second
    each), scored as the strike mean with the touchdown joined, ordered by the sum of the
    tuning labs' four leave-one-lab-out figures (median and p95 against lab events and
    plates)."""
    ex = os.path.join(os.path.dirname(os.path.abspath(__file__)), '../../../target/release/events_eval')
    results = []
    for mm in (2, 3, 5, 8, 12):
        for speed in (20, 30, 50, 100, 200):
            for hz in (10, 15, 20):
                out = f'/tmp/touchdown_{mm}_{speed}_{hz}.csv'
                subprocess.run([ex, '--dump', out, '--touchdown-mm', str(mm), '--touchdown-speed', str(speed),
                                '--touchdown-hz', str(hz)], stdout=subprocess.DEVNULL, check=True)
                rows = list(csv.DictReader(open(out)))
                lolo, held, _ = score(rows, 'FootStrike', TOUCHDOWN, with_touchdown)
                total = sum(quantile([abs(x) for x in lolo[t]], p) for t in lolo for p in (.5, .95))
                results.append((total, f"{mm:2} mm {speed:3} mm/s {hz} Hz: tuning LOLO {fmt(lolo)} || held out {fmt(held)}"))
    for _, line in sorted(results):
        print(line)


if __name__ == '__main__':
    {'choice': lambda: choice(sys.argv[2]), 'touchdown': lambda: touchdown(sys.argv[2]), 'grid': grid}[sys.argv[1]]()
