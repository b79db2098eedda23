#!/usr/bin/env python3
"""An independent Monte Carlo witness of the same-path term of docs/model.md
§9.10 (src/model/finite/same_path_hg.rs), written by a reviewer who had not
seen the Rust code: J = E[f(−u·ω₀) f(−u·ω) 1{first hits} 1{second hits}]
for a point light at y, the sphere of radius R about (0, 0, s), the camera
ray along u = z, σ = 1 (the tracer's hit rule, reference/src/hits.rs).
ω₀ is drawn uniformly in the cone of directions from y that pass within R of
the centre (weight: its solid angle / 4π), r₁ = τ₁ + Exp(σ) (weight
e^{−στ₁}); ω either uniformly in the cone towards the centre from x₁ (weight
its solid angle times p(ω₀·ω); `cone`) or from the HG distribution about ω₀
(`hg`). The unit test `same_path_hg::tests::agrees_with_an_independent_monte_carlo`
pins the `cone` values this prints with fixed seeds.

Usage: python3 scripts/mc-same-path-hg.py cone 2e8   (~100 s per case, one core)
"""
import numpy as np, sys, time
sig, R = 1.0, 0.2
y = np.array([1.0, 0.0, 1.0]); u = np.array([0.0, 0.0, 1.0])

def f_hg(g, c):  # normalised over the sphere, at cosine c
    return (1 - g*g) / (4*np.pi*(1 + g*g - 2*g*c)**1.5)

def basis(a):  # a: (n,3) unit -> two orthonormal vectors
    t = np.where(np.abs(a[:, :1]) < 0.9, np.array([[1.0, 0, 0]]), np.array([[0, 1.0, 0]]))
    e1 = np.cross(a, t); e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(a, e1)
    return e1, e2

def about(a, cos, rng):
    n = len(cos); phi = 2*np.pi*rng.random(n); sin = np.sqrt(np.maximum(0, 1 - cos*cos))
    e1, e2 = basis(a)
    return cos[:, None]*a + (sin*np.cos(phi))[:, None]*e1 + (sin*np.sin(phi))[:, None]*e2

def uniform_cone(a, cmin, rng, n):  # uniform in cone cos >= cmin about a (a: (3,) or (n,3))
    cos = 1 - rng.random(n)*(1 - cmin)
    return about(np.broadcast_to(a, (n, 3)).copy() if a.ndim == 1 else a, cos, rng)

def hg_cos(g, xi):
    if g == 0: return 2*xi - 1
    return (1 + g*g - ((1 - g*g)/(1 - g + 2*g*xi))**2)/(2*g)

def chunk(g, s, n, rng, method):
    x = np.array([0.0, 0.0, s]); d = x - y; D = np.linalg.norm(d); wdir = d/D
    cpsi = np.sqrt(1 - (R/D)**2)
    w0 = uniform_cone(wdir, cpsi, rng, n)
    wt = (1 - cpsi)/2 * np.ones(n)
    tau1 = w0 @ d
    assert np.all(tau1 >= 0)
    wt *= np.exp(-sig*tau1)
    r1 = tau1 + rng.exponential(1/sig, n)
    x1 = y + r1[:, None]*w0
    wt *= f_hg(g, -(w0 @ u))
    q = x - x1; qn = np.linalg.norm(q, axis=1)
    if method == 'hg':
        om = about(w0, hg_cos(g, rng.random(n)), rng)
    else:  # cone from x1 toward x, weight p * solid angle; hemisphere if inside
        inside = qn <= R
        qd = q/qn[:, None]
        cmin = np.where(inside, -1.0, np.sqrt(np.maximum(0, 1 - (R/np.maximum(qn, R))**2)))
        om = about(qd, 1 - rng.random(n)*(1 - cmin), rng)
        wt *= 2*np.pi*(1 - cmin) * f_hg(g, np.sum(om*w0, axis=1))
    tau2 = np.sum(q*om, axis=1)
    perp2 = qn**2 - tau2**2
    hit = (tau2 >= 0) & (perp2 <= R*R)
    wt *= hit * np.exp(-sig*np.maximum(tau2, 0)) * f_hg(g, -(om @ u))
    return wt

def run(g, s, N, method, seed, csize=1_000_000):
    rng = np.random.default_rng(seed); S = S2 = 0.0; m = 0
    while m < N:
        w = chunk(g, s, csize, rng, method); S += w.sum(); S2 += (w*w).sum(); m += csize
    mean = S/m; se = np.sqrt((S2/m - mean**2)/(m - 1))
    return mean, se

SEEDS = {(0.9, 1.0): 11, (-0.5, 0.5): 12, (0.9, 2.0): 13}
code = {(0.9, 1.0): 1.02565533e-8, (-0.5, 0.5): 1.15871544e-6, (0.9, 2.0): 1.47582948e-9}
if __name__ == '__main__':
    method = sys.argv[1]; N = int(float(sys.argv[2]))
    for (g, s), c in code.items():
        t = time.time(); m, se = run(g, s, N, method, seed=SEEDS[(g, s)])
        print(f"{method} g={g} s={s}: MC {m:.6e} ± {se:.2e} ({se/m*100:.2f}%), code {c:.6e}, z={(m-c)/se:+.2f}  [{time.time()-t:.0f}s]", flush=True)
