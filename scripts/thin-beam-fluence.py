#!/usr/bin/env python3
"""An independent reference for the single-scattered fluence of a thin beam
(docs/model.md §9.8; src/model/beam_source.rs, `ScatteredBeam::fluence`):

  F(x) = albedo/(4π) ∫₀^∞ σe^{−σt} ⟨e^{−σd}/d²⟩_disk dt,

the disk average over the beam's cross-section of radius a at depth t, d the
distance from x. For a ≪ the distance p of x from the axis the average is
the mean-value series of the disk, φ(0) + (a²/8)Δ⊥φ + O(a⁴), Δ⊥ the
Laplacian across the axis (φ'' + φ'/p for φ radial about x's foot), so F is
a 1-D integral along the axis plus its a² term (here ≤ 6.4·10⁻⁹ relative;
the a⁴ term ≤ 5·10⁻¹⁷). No geometry is shared with the Rust shells.

The beam of the unit test `thin_beams_fluence_is_the_line_source`: disk
centre (−2, 0, 1), along +x, flux 1; σ = 1, albedo 0.8; the points (0, 0, x)
of the camera ray from the origin along +z, so depth τ = 2, p = |x − 1|.

Usage: python3 scripts/thin-beam-fluence.py   (mpmath, 40 digits, a few seconds)
"""
from mpmath import mp, mpf, quad, exp, pi, sqrt, inf, diff

mp.dps = 40
sigma, albedo = mpf(1), mpf("0.8")


def phi(s, r):
    d2 = s * s + r * r
    return exp(-sigma * sqrt(d2)) / d2


def laplacian(s, r):
    return diff(lambda q: phi(s, q), r, 2) + diff(lambda q: phi(s, q), r, 1) / r


def fluence(tau, p, a):
    pts = [0, tau, tau + 1, tau + 10, inf]
    line = quad(lambda t: sigma * exp(-sigma * t) * phi(t - tau, p), pts)
    second = quad(lambda t: sigma * exp(-sigma * t) * laplacian(t - tau, p), pts)
    return albedo / (4 * pi) * (line + a * a / 8 * second)


for a in ["1e-4", "1e-5", "1e-6", "1e-7", "1e-8"]:
    for x in ["0.3", "4"]:
        print(a, x, mp.nstr(fluence(mpf(2), abs(mpf(x) - 1), mpf(a)), 20))
