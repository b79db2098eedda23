"""A toy renderer of the multiple-integration-spheres estimator in NumPy
(Ershov, Zhdanov & Voloboy 2019), written from ``docs/tracer.md`` and
``docs/conventions.md`` only, with bugs that can be planted one at a time:
the Python twin of ``examples/toy-renderer``.

One pixel, one homogeneous medium, one point light, uncollided light only
(scattering order 0). ``render(scene, bug, iterations, seed)`` returns one
pixel value L per iteration (paper eq. (6)), vectorised over iterations in
chunks; every draw is independent, so the iterations are too.
"""

from __future__ import annotations

import dataclasses
import enum
import math

import numpy as np


@dataclasses.dataclass(frozen=True)
class ToyScene:
    """Medium, one point light, one pixel's camera ray, the estimator's parameters."""

    sigma_ext: float = 1.0
    albedo: float = 0.8
    g: float = 0.5  # Henyey–Greenstein; the phase bug needs an anisotropic medium
    light_position: tuple[float, float, float] = (1.0, 0.0, 1.0)
    flux: float = 1.0
    camera_origin: tuple[float, float, float] = (0.0, 0.0, 0.0)
    camera_direction: tuple[float, float, float] = (0.0, 0.0, 1.0)
    radius: float = 0.2
    q: float = 0.5  # the q bugs need q < 1
    forward_rays: int = 20
    camera_rays: int = 4  # the shared-spheres bug needs several camera rays


class Bug(enum.Enum):
    """A bug planted in the estimator, or none."""

    NONE = "the estimator as documented"
    FORGET_Q = "weight C instead of q*C per sphere"
    R_SQUARED_AREA = "C divided by R^2 instead of pi R^2"
    SHARED_SPHERES = "the N_B camera rays share one set of spheres"
    SUB_STEPS_AT_SIGMA = "sub-steps ~ Exp(sigma_ext) instead of Exp(sigma_ext/q)"
    PHASE_AT_PLUS_COS = "the phase function at +u.v instead of the scattering-angle cosine -u.v"
    NO_ALBEDO = "the albedo left out of C"


def henyey_greenstein(g: float, c: np.ndarray) -> np.ndarray:
    """(1 - g^2) / (4 pi (1 + g^2 - 2 g c)^{3/2}), normalised to 1 over the sphere."""
    return (1.0 - g * g) / (4.0 * math.pi * (1.0 + g * g - 2.0 * g * c) ** 1.5)


def _sphere_distances(rng: np.random.Generator, rays: int, rate: float, q: float) -> tuple[np.ndarray, np.ndarray]:
    """Distances along the camera ray of the spheres of ``rays`` camera rays,
    and the ray each belongs to: sub-steps ~ Exp(rate), a sphere after each,
    then the ray ends with probability q (a geometric count of spheres)."""
    counts = rng.geometric(q, size=rays) if q < 1.0 else np.ones(rays, dtype=np.int64)
    ray = np.repeat(np.arange(rays), counts)
    steps = rng.exponential(1.0 / rate, size=ray.size)
    total = np.cumsum(steps)
    starts = np.cumsum(counts) - counts  # index of each ray's first sphere
    before = np.concatenate(([0.0], total))[starts]  # the running sum up to that ray
    return total - np.repeat(before, counts), ray


def _render_chunk(scene: ToyScene, bug: Bug, iterations: int, rng: np.random.Generator) -> np.ndarray:
    sigma, q, n_f, n_b = scene.sigma_ext, scene.q, scene.forward_rays, scene.camera_rays
    r2 = scene.radius**2
    u = np.asarray(scene.camera_direction, dtype=float)
    o = np.asarray(scene.camera_origin, dtype=float)
    p0 = np.asarray(scene.light_position, dtype=float)

    # Camera: every iteration's spheres, each tagged with its iteration.
    rate = sigma if bug is Bug.SUB_STEPS_AT_SIGMA else sigma / q
    if bug is Bug.SHARED_SPHERES:
        s, ray = _sphere_distances(rng, iterations, rate, q)  # one camera ray's spheres ...
        s, iteration = np.repeat(s, n_b), np.repeat(ray, n_b)  # ... used N_B times
    else:
        s, ray = _sphere_distances(rng, iterations * n_b, rate, q)
        iteration = ray // n_b

    # C = (sigma_sc/sigma_ext) f F/(pi R^2), times the sphere weight q.
    albedo = 1.0 if bug is Bug.NO_ALBEDO else scene.albedo
    area = r2 if bug is Bug.R_SQUARED_AREA else math.pi * r2
    weight = 1.0 if bug is Bug.FORGET_Q else q
    c_without_f = weight * albedo * scene.flux / area

    # Forward rays: isotropic emission, an uncollided segment of length ~ Exp(sigma).
    z = 1.0 - 2.0 * rng.random((iterations, n_f))
    phi = 2.0 * math.pi * rng.random((iterations, n_f))
    sin = np.sqrt(np.maximum(1.0 - z * z, 0.0))
    v = np.stack([sin * np.cos(phi), sin * np.sin(phi), z], axis=-1)  # (iterations, N_F, 3)
    length = rng.exponential(1.0 / sigma, size=(iterations, n_f))
    mu = v @ u
    cos_scattering = mu if bug is Bug.PHASE_AT_PLUS_COS else -mu
    c = c_without_f * henyey_greenstein(scene.g, cos_scattering)  # (iterations, N_F)

    # Each sphere against its iteration's forward rays: a hit when the
    # segment's closest point to the centre lies on it, within R.
    d = o + s[:, None] * u - p0  # (spheres, 3)
    tau = np.einsum("sk,sfk->sf", d, v[iteration])  # (spheres, N_F)
    hit = (tau >= 0.0) & (tau <= length[iteration]) & ((d * d).sum(axis=1)[:, None] - tau * tau <= r2)
    per_sphere = (hit * c[iteration]).sum(axis=1)
    return np.bincount(iteration, weights=per_sphere, minlength=iterations) / (n_f * n_b)


def render(scene: ToyScene, bug: Bug, iterations: int, seed: int, chunk: int = 20_000) -> np.ndarray:
    """``iterations`` pixel values L, one per iteration, from a NumPy
    ``Generator`` seeded with ``seed``, in chunks of ``chunk`` iterations
    (the memory is that of one chunk; the values are those of this seed and
    chunk size)."""
    rng = np.random.default_rng(seed)
    parts = [_render_chunk(scene, bug, min(chunk, iterations - start), rng) for start in range(0, iterations, chunk)]
    return np.concatenate(parts) if parts else np.zeros(0)
