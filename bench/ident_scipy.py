#!/usr/bin/env python3
# The same per-axis fit with scipy.optimize.least_squares (method 'trf', loss 'huber',
# analytic Jacobian) on the samples `c4g-ident fit --samples DIR` wrote: a linear
# least-squares start over the same 16-value grid of Stribeck velocities, the Huber scale
# 1.345 robust sigmas of the start's residuals, the same lower bounds. One robust solve and
# no covariance: less work than c4g-ident's fit does, so the ratio is on the safe side.
#   ident_scipy.py [--runs N] FILE.csv...   prints: file samples variant seconds Ja Fv Fc off Fs vs ga gb
import sys, time
import numpy as np
from scipy.optimize import least_squares

NAMES = ['Ja', 'Fv', 'Fc', 'off', 'Fs', 'vs', 'ga', 'gb']

def load(path):
    with open(path) as f:
        head = f.readline().split()
    variant = head[head.index('variant') + 1]
    eps = float(head[head.index('eps') + 1])
    d = np.loadtxt(path, delimiter=',', skiprows=2, ndmin=2)
    return variant, eps, d[:, 0], d[:, 1], d[:, 2], d[:, 3], d[:, 4]

def active(variant):
    act = ['Ja', 'Fv', 'Fc', 'off']
    if variant.startswith('stribeck'):
        act += ['Fs', 'vs']
    if variant.endswith('+gravity'):
        act += ['ga', 'gb']
    return act

def fit(variant, eps, v, a, i, cq, sq):
    S = np.tanh(v / eps)
    grav = variant.endswith('+gravity')
    stri = variant.startswith('stribeck')
    act = active(variant)

    def linear(vs):
        cols = [a, v, S, np.ones_like(v)]
        if vs > 0:
            E = np.exp(-(v / vs) ** 2)
            cols = [a, v, (1 - E) * S, np.ones_like(v), E * S]
        if grav:
            cols += [cq, sq]
        X = np.column_stack(cols)
        coef, *_ = np.linalg.lstsq(X, i, rcond=None)
        r = i - X @ coef
        return coef, float(r @ r)

    if stri:
        lo = max(10 * eps, 1e-6)
        hi = max(2 * lo, 0.5 * np.max(np.abs(v)))
        best = None
        for k in range(16):
            vs = lo * (hi / lo) ** (k / 15)
            coef, c = linear(vs)
            if best is None or c < best[1]:
                best = (coef, c, vs)
        coef, _, vs = best
        x0 = list(coef[:5]) + [vs] + list(coef[5:])
    else:
        coef, _ = linear(0.0)
        x0 = list(coef)
    x0 = np.array(x0, dtype=float)
    lower = np.full(len(act), -np.inf)
    for k, n in enumerate(act):
        if n == 'Ja':
            lower[k] = 1e-12
        elif n in ('Fv', 'Fc', 'Fs'):
            lower[k] = 0.0
        elif n == 'vs':
            lower[k] = 2 * eps
    x0 = np.maximum(x0, lower + 1e-12)

    def model(x):
        p = dict(zip(act, x))
        fs = p.get('Fs', p['Fc'])
        E = np.exp(-(v / p['vs']) ** 2) if 'vs' in p else 0.0
        f = p['Ja'] * a + p['Fv'] * v + (p['Fc'] + (fs - p['Fc']) * E) * S + p['off']
        if grav:
            f = f + p['ga'] * cq + p['gb'] * sq
        return f, p, E

    def res(x):
        return model(x)[0] - i

    def jac(x):
        _, p, E = model(x)
        cols = [a, v, (1 - E) * S if stri else S, np.ones_like(v)]
        if stri:
            cols += [E * S, (p['Fs'] - p['Fc']) * S * E * 2 * v * v / p['vs'] ** 3]
        if grav:
            cols += [cq, sq]
        return np.column_stack(cols)

    r0 = res(x0)
    sigma = 1.4826 * np.median(np.abs(r0))
    sol = least_squares(res, x0, jac=jac, method='trf', loss='huber', f_scale=1.345 * sigma,
                        bounds=(lower, np.full(len(act), np.inf)), x_scale='jac',
                        ftol=1e-9, xtol=1e-9, gtol=1e-12)
    out = dict.fromkeys(NAMES, 0.0)
    out.update(zip(act, sol.x))
    return out

def main():
    args = sys.argv[1:]
    runs = 3
    if len(args) > 1 and args[0] == '--runs':
        runs = max(1, int(args[1]))
        args = args[2:]
    for path in args:
        variant, eps, v, a, i, cq, sq = load(path)
        best = float('inf')
        for _ in range(runs):
            t0 = time.perf_counter()
            p = fit(variant, eps, v, a, i, cq, sq)
            best = min(best, time.perf_counter() - t0)
        print(path, len(i), variant, '%.6f' % best, ' '.join('%.9g' % p[n] for n in NAMES))

if __name__ == '__main__':
    main()
