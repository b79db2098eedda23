#!/usr/bin/env python3
"""An independent reference for one spherical shell of a beam's volume
integral (src/model/beam_source.rs, `BeamPoint::shell`; docs/model.md §9.8):

  shell(d) = ∫ Θ(d sin ψ) kernel(τ ± d cos ψ, d) sin ψ dψ  over both
  hemispheres, where the point lies past the disk (τ ± d cos ψ ≥ 0),

Θ(ρ) the angle of the circle of radius ρ about x's foot (p from the disk's
centre) inside the disk of radius a, from the plain law of cosines, and the
kernel e^{−(t + d)} (σ = 1). mpmath at 40 digits, the kinks asin(|a ∓ p|/d)
and the plane acos(|τ|/d) as breakpoints: no rounding of the geometry.

The cases of the unit test `shells_match_a_high_precision_reference`: thin
beams (the band ψ ∈ [ψ_near, ψ_far] ~2a/d wide), shells next to d = a + p
and d = p ± a, points inside the cylinder, and the plane clipping next to
d = |τ| (a review's cases, 6 December 2026).

Usage: python3 scripts/beam-shell-reference.py   (~1 min)
"""
from mpmath import mp, mpf, quad, acos, asin, cos, sin, exp, pi

mp.dps = 40

CASES = [
    (3.5, 1e-06, 3.0, 20.0),
    (3.1, 1e-06, 3.0, 2.0),
    (5.0, 1e-06, 3.0, 2.0),
    (5.0, 1e-06, 3.0, -2.0),
    (3.0000005, 1e-06, 3.0, 2.0),
    (2.2, 1e-06, 0.7, 2.0),
    (3.3, 0.0001, 3.0, 2.0),
    (0.46308312212305114, 0.023688568132613393, 0.0029326911916445356, 0.4626176917049918),
    (1.360489448764782, 1.1810102685111198e-06, 4.0397141947864127e-07, 0.286512970138692),
    (0.06274575631073427, 0.025241092605923676, 0.02524109263116477, -0.0627457562479885),
    (2.6265554570098772, 0.01535236502284712, 0.000476861776813688, -2.6265130702878743),
    (0.016941797063026627, 0.008470893799589168, 0.008470893808060062, 0.11038114279656641),
    (0.048942818182833726, 0.0009581450234462407, 0.00019912102880355326, 0.04893692731643107),
    (0.34729147069702954, 0.898117194668231, 0.11225667130873342, -0.34729147034973806),
    (1.3257170670155456, 0.19189955003387432, 0.1763885988873664, -1.3256261919054464),
    (1.7268345029260879, 0.8634172045535414, 0.8634172054169587, -0.4577133516515037),
    (5.271237199996143, 1.2675652188919044e-05, 2.647178390814971, -0.237321813698593),
    (0.02337374397832287, 0.0064399996570876795, 0.0007391068026577507, -0.023373743954949122),
    (4.385545292840757, 0.0006019638209253365, 1.5727991014853842, 0.6201944419838634),
    (2.0447675378749555, 1.0812453387762717e-06, 2.0447654312444747, 0.1880530726763533),
    (1.8609059031125306, 0.3213420305640646, 0.32134203088540664, -1.8609057170219587),
    (1.7541694633737164, 0.8770847252915991, 0.8770847261686839, 0.031029758968002696),
    (2.7236617239450203, 3.9984164132786494e-07, 7.746432551396445e-08, 2.723661451578856),
    (2.8334467342048977, 0.00015270679195812715, 4.252093337142745e-05, 2.833446731371451),
    (2.9918037631195897, 0.6649807136817506, 0.5085776140804965, -2.9918037601277856),
    (1.2294535790085561, 0.4655590021137357, 0.7638933563583232, -0.6715083154641746),
    (0.4582298022831361, 0.09140628501075385, 0.09140628510216015, -0.45822980182490625),
    (1.8949985303064965, 0.16559786335435817, 0.012471845139449492, 1.8888015073600641),
    (0.4736383488231834, 0.8893008951094772, 0.8784726158670854, -0.473638348349545),
    (1.1479419042520964, 0.5739704633904394, 0.57397046396441, 1.4234936313836153),
]


def shell(d, a, p, tau):
    d, a, p, tau = map(mpf, (d, a, p, tau))

    def theta(rho):
        if rho + p <= a:
            return 2 * pi
        if rho <= abs(a - p) or rho >= a + p:
            return mpf(0)
        return 2 * acos((rho * rho + p * p - a * a) / (2 * rho * p))

    def f(psi, sign):
        t = tau + sign * d * cos(psi)
        return 0 if t < 0 else theta(d * sin(psi)) * exp(-(t + d)) * sin(psi)

    pts = {mpf(0), pi / 2}
    pts |= {asin(m / d) for m in (abs(a - p), a + p) if m < d}
    if abs(tau) < d:
        pts.add(acos(abs(tau) / d))
    pts = sorted(pts)
    return quad(lambda x: f(x, 1), pts) + quad(lambda x: f(x, -1), pts)


for case in CASES:
    print(f"({case[0]!r}, {case[1]!r}, {case[2]!r}, {case[3]!r}, {mp.nstr(shell(*case), 22)}),")
