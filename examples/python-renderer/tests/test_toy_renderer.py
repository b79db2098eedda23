"""The NumPy toy renderer against the oracle, as a Python renderer's own
pytest suite would be: the correct estimator passes, each planted bug fails
(a z-test beyond its limit, not a verdict that could not tell), with
ITERATIONS iterations and resolution targets they must meet, so that a pass
is not a pass by noise. ``pytest -s`` prints every verdict."""

from __future__ import annotations

import pathlib
import sys

import pytest

import mcrt_noise

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
from toy_renderer import Bug, ToyScene, render  # noqa: E402

ITERATIONS = 200_000
TARGETS = {"target_mean": 0.05, "target_variance": 0.10}


@pytest.fixture(scope="module")
def prediction() -> mcrt_noise.Prediction:
    t = ToyScene()
    scene = mcrt_noise.Scene.build(
        sigma_ext=t.sigma_ext,
        albedo=t.albedo,
        phase="henyey-greenstein",
        g=t.g,
        point_lights=[(t.light_position, t.flux)],
        camera_origin=t.camera_origin,
        camera_direction=t.camera_direction,
        radius=t.radius,
        q=t.q,
        forward_rays=t.forward_rays,
        camera_rays=t.camera_rays,
    )
    return mcrt_noise.predict(scene)


def verdict(prediction: mcrt_noise.Prediction, bug: Bug) -> mcrt_noise.Verdict:
    v = mcrt_noise.check(prediction, render(ToyScene(), bug, ITERATIONS, seed=42), **TARGETS)
    print(f"--- {bug.name}: {bug.value}\n{v}\n")
    return v


def test_the_correct_renderer_passes(prediction: mcrt_noise.Prediction) -> None:
    verdict(prediction, Bug.NONE).assert_pass()


@pytest.mark.parametrize("bug", [b for b in Bug if b is not Bug.NONE], ids=lambda b: b.name)
def test_each_planted_bug_fails(prediction: mcrt_noise.Prediction, bug: Bug) -> None:
    v = verdict(prediction, bug)
    assert v.status == "fail", f"{bug.name}:\n{v}"
    assert v.failures and all("beyond the limit" in f for f in v.failures), f"{bug.name}:\n{v}"


def test_the_values_are_reproducible_from_the_seed() -> None:
    # The stream is the seed's and the chunk size's (20 000 by default), not split-independent.
    a = render(ToyScene(), Bug.NONE, 30_000, seed=7)
    assert (a == render(ToyScene(), Bug.NONE, 30_000, seed=7)).all()
    assert (a > 0).any() and (a >= 0).all()
