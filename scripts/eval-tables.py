#!/usr/bin/env python3
"""Pools the `metamoran eval --samples` files of a folder into the README's issue #17 tables.

    for s in "parking-lot cascade 9801 80" "parking-lot xwr18xx 9802 80" "moving cascade 9803 80" \
             "long-range cascade 9804 48" "moving xwr18xx 9805 48" "far-moving cascade 9806 48"; do
      set -- $s; metamoran simulate --preset $1 --radar $2 --seed $3 --count $4 --out f/$1-$2
      metamoran eval f/$1-$2 --modes metamoran --samples f/$1-$2.json
    done
    python3 scripts/eval-tables.py f

Prints markdown: the issue's goal sets, every set, every class and range bin, and the
reliability of the confidence (predicted against observed within 1 m). "> 1 m" is a share of the
detected objects, "confidently wrong" (detected and more than 3 m off) a share of all objects.
Standard library only.
"""
import json, glob, sys
def load(d):
    sets = {}
    for f in sorted(glob.glob(d + '/*.json')):
        if f.endswith('.eval.json'): continue
        sets[f.split('/')[-1][:-5]] = json.load(open(f))
    return sets
def stats(xs):
    n = len(xs); det = [x for x in xs if x['error_m'] is not None]
    e = sorted(abs(x['error_m']) for x in det)
    med = e[len(e)//2] if e else float('nan')
    mh = sorted(x['mhd_m'] for x in det if x.get('mhd_m') is not None)
    mhd = mh[len(mh)//2] if mh else float('nan')
    cw = sum(v > 3 for v in e)
    return n, med, 100*sum(v > 1 for v in e)/max(len(e),1), 100*len(det)/max(n,1), 100*cw/max(n,1), mhd
def row(name, xs, mhd=True):
    n, med, g1, det, cw, m = stats(xs)
    r = f"| {name} | {n} | {med:.2f} m | {g1:.1f} % | {det:.1f} % | {cw:.1f} % |"
    return r + (f" {m:.2f} m |" if mhd else "")
d = sys.argv[1]
S = load(d); g = lambda k: S.get(k, [])
allx = [x for v in S.values() for x in v]
print("| goal set | objects | median | > 1 m | detected | confidently wrong | median MHD |\n|---|---|---|---|---|---|---|")
print(row("cascade-86, car/person/sign 3–60 m (goal ≤ 0.10 m, ≤ 5 %, ≥ 95 %, ≤ 2 %)", [x for x in g('parking-lot-cascade') if x['truth_m'] <= 60]))
print(row("8 elements, 3–40 m (goal ≤ 0.5 m, ≤ 15 %, ≥ 85 %, ≤ 2 %)", [x for x in g('parking-lot-xwr18xx') + g('moving-xwr18xx') if x['truth_m'] <= 40]))
print(row("cascade movers 100–300 m, cars (goal ≥ 90 %, ≤ 1.0 m)", [x for x in g('moving-cascade') + g('far-moving-cascade') if x['class']=='car' and x['truth_m'] >= 100]))
print(row("cascade movers 100–230 m, people (goal ≥ 70 %)", [x for x in g('moving-cascade') + g('far-moving-cascade') if x['class']=='person' and 100 <= x['truth_m'] <= 230]))
print(row("cascade static cars 60–90 m (goal ≤ 0.15 m)", [x for x in g('long-range-cascade') if x['truth_m'] >= 60]))
print(row("cascade static cars 10–90 m (MHD goal ≤ 0.12 m)", g('long-range-cascade')))
print(row("every object", allx))
print()
print("| set | objects | median | > 1 m (of detected) | detected | confidently wrong |\n|---|---|---|---|---|---|")
for k, v in S.items(): print(row(k, v, False))
print()
print("| class / range | objects | median | > 1 m | detected | confidently wrong |\n|---|---|---|---|---|---|")
for c in ['car', 'person', 'sign']: print(row(c, [x for x in allx if x['class'] == c], False))
for lo, hi in [(0,20),(20,40),(40,60),(60,90),(90,150),(150,230),(230,300)]:
    print(row(f"{lo}–{hi} m", [x for x in allx if lo <= x['truth_m'] < hi], False))
print()
print("| confidence | objects | predicted | observed within 1 m |\n|---|---|---|---|")
for lo, hi in [(0,0.2),(0.2,0.5),(0.5,0.8),(0.8,0.95),(0.95,1.0001)]:
    xs = [x for x in allx if x['confidence'] is not None and lo <= x['confidence'] < hi]
    if not xs: continue
    pred = sum(x['confidence'] for x in xs)/len(xs)
    obs = sum(x['judged_error_m'] is not None and abs(x['judged_error_m']) <= 1 for x in xs)/len(xs)
    print(f"| {lo:.2f}–{min(hi,1):.2f} | {len(xs)} | {100*pred:.0f} % | {100*obs:.0f} % |")
