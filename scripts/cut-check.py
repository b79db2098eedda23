#!/usr/bin/env python3
"""Reference values for `model::finite::start_density`'s test
`the_cut_and_the_pole_give_the_inverse_transform` (docs/model.md §10.1):
r C(r) of the order-2 density (aĉ₁)² and of every order from 2 on,
(aĉ₁)²/(1 − aĉ₁), at a = 0.8, σ = 1, by two routes — mpmath's oscillatory
quadrature of the inverse sine transform (independent: no contour, no cut)
and the branch cut plus the diffusion pole — printed side by side, and ν.
6 December 2026: they agree to all 20 digits.

Usage: python3 scripts/cut-check.py   (~1 minute)
"""
import mpmath as mp

mp.mp.dps=20
a=mp.mpf('0.8')
def c1hat(k): return mp.atan(k)/k
def radial_inverse(fhat, r):
    g = lambda k: k * mp.sin(k * r) * fhat(k)
    return mp.quadosc(g, [0, mp.inf], omega=r) / (2 * mp.pi**2 * r)
def zplus(u): return a*(mp.atanh(1/u)+1j*mp.pi/2)/u
def nu_of(a):
    return mp.findroot(lambda v: a*mp.atanh(v)/v-1, 0.7)
nu=nu_of(a)
def rC_cut(F, r):
    return mp.quad(lambda u: u*mp.exp(-u*r)*mp.im(F(zplus(u))), [1,1.001,2,10,mp.inf])/(2*mp.pi**2)
def pole(r):
    return nu**2*mp.exp(-nu*r)/(2*mp.pi*(a/(1-nu**2)-1))
for r in [mp.mpf('0.3'), mp.mpf(1), mp.mpf(3)]:
    ref_all = r*radial_inverse(lambda k: a*a*c1hat(k)**2/(1-a*c1hat(k)), r)
    got_all = rC_cut(lambda z: z*z/(1-z), r) + pole(r)
    ref2 = r*radial_inverse(lambda k: (a*c1hat(k))**2, r)
    got2 = rC_cut(lambda z: z*z, r)
    print(r, ref_all, got_all, ref2, got2)
print("nu", nu)
