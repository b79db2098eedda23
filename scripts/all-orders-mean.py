#!/usr/bin/env python3
"""Groundwork for issue 21 (every scattering order; docs/model.md §10): the
small-sphere (R → 0) mean of every scattering order for one point light in
an infinite isotropic medium, σ = 1, through the collision densities'
Fourier transforms. Not the oracle: a prototype that checks the route.

  c₁(r) = e^{−r}/(4πr²), ĉ₁(k) = arctan(k)/k (3-D radial transform),
  a^m c_m = a^m c₁^{*m} has transform (aĉ₁)^m, and Σ_{m≥1} a^m ĉ₁^m = aĉ₁/(1 − aĉ₁).

As R → 0, §9.5's ⟨𝒞⟩_n(s) → (1/4π) a^{n+1} c_{n+1}(D), D = |y − x(s)|, so

  μ_{≤N}(0) = (1/4π) ∫ e^{−s} Σ_{m=1}^{N+1} a^m c_m(D(s)) ds,

with a^m c_m (m ≥ 2) and Σ_{m≥2} a^m c_m from f(r) = (1/(2π²r)) ∫₀^∞ k sin(kr) f̂(k) dk
(mpmath's quadosc; the m = 1 term c₁ in closed form, so the transforms
left decay like 1/k², the sine integrals' integrands like 1/k). A prototype:
it prints no bars (the inner transforms carry none, and the outer
quadrature's estimate lies below the working precision). Its checks: the
orders-≤-1 line must equal the oracle's small-sphere order-1 mean of
`point-isotropic-order1` (2.2429356708736e-3 ± 7e-9 at --rel-tol 1e-4; this
prints 2.242935671e-3), which tests the inverse transform of ĉ₁²; the
every-order line, whose resummed transform has a pole at k ≈ 0.71i for
a = 0.8, only the tracer checks (docs/model.md §10: z = −1.2 at 0.2 %).

Usage: python3 scripts/all-orders-mean.py [albedo]   (~6 minutes on one core)
"""
import sys
import mpmath as mp

mp.mp.dps = 20
a = mp.mpf(sys.argv[1]) if len(sys.argv) > 1 else mp.mpf("0.8")
light = (1, 0, 1)  # the bundled scenes' point light; camera at the origin along +z


def c1hat(k):
    return mp.atan(k) / k if k != 0 else mp.mpf(1)


def c1(r):
    return mp.exp(-r) / (4 * mp.pi * r * r)


def radial_inverse(fhat, r):
    g = lambda k: k * mp.sin(k * r) * fhat(k)
    return mp.quadosc(g, [0, mp.inf], omega=r) / (2 * mp.pi**2 * r)


def order(m):
    return lambda r: radial_inverse(lambda k: a**m * c1hat(k) ** m, r)


def beyond_first(r):
    return radial_inverse(lambda k: a * a * c1hat(k) ** 2 / (1 - a * c1hat(k)), r)


def mean(density):
    d = lambda s: mp.sqrt(light[0] ** 2 + light[1] ** 2 + (s - light[2]) ** 2)
    value, error = mp.quad(lambda s: mp.exp(-s) * density(d(s)), [0, light[2], 3, 10, 30, mp.inf], error=True)
    return value / (4 * mp.pi), error / (4 * mp.pi)


def show(label, v):
    print(f"{label}: {mp.nstr(v[0], 10)} (prototype, no bar: see the docstring)")


if __name__ == "__main__":
    m0 = mean(lambda r: a * c1(r))
    show("order 0", m0)
    m1 = mean(order(2))
    show("orders ≤ 1", (m0[0] + m1[0], m0[1] + m1[1]))
    rest = mean(beyond_first)
    show(f"every order (albedo {a})", (m0[0] + rest[0], m0[1] + rest[1]))
