"""Predict the mean and noise of a multiple-integration-sphere MCRT pixel,
and check a renderer's per-iteration values against the prediction.

A thin layer over the Rust library ``mcrt-noise`` (its ``docs/library.md``
says what the check computes and what a pass proves)::

    import mcrt_noise

    scene = mcrt_noise.Scene.from_file("scenes/point-isotropic.toml")
    prediction = mcrt_noise.predict(scene)
    values = my_renderer(scene, iterations=200_000)   # one pixel value per iteration
    mcrt_noise.check(prediction, values).assert_pass()
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Union

import numpy as np

from ._native import (
    OptionsError,
    Plan,
    PredictError,
    Predicted,
    Prediction,
    SampleError,
    Samples,
    Scene,
    SceneError,
    Verdict,
    _check_samples,
    _plan_samples,
    predict,
    reference_values,
)

__all__ = [
    "OptionsError",
    "Plan",
    "PredictError",
    "Predicted",
    "Prediction",
    "SampleError",
    "Samples",
    "Scene",
    "SceneError",
    "Verdict",
    "check",
    "plan",
    "predict",
    "reference_values",
    "samples_of",
]

Values = Union[Samples, np.ndarray, Iterable[float]]


def samples_of(values: Values) -> Samples:
    """The exact power sums of ``values`` (a NumPy array, any iterable of
    floats, or ``Samples`` as they are)."""
    if isinstance(values, Samples):
        return values
    samples = Samples()
    samples.extend(values)
    return samples


def check(
    prediction: Prediction,
    values: Values,
    *,
    false_alarm_rate: float = 1e-3,
    power: float = 0.9,
    target_mean: float = 0.1,
    target_variance: float = 0.2,
) -> Verdict:
    """Checks a renderer's per-iteration pixel values against ``prediction``.

    ``values``: a NumPy array, any iterable of floats, or ``Samples``
    accumulated in chunks. The verdict is PASS, FAIL or NOT RESOLVED at the
    family-wise false-alarm rate ``false_alarm_rate``; a pass can detect
    relative errors of ``target_mean`` (mean) and ``target_variance`` (Var L)
    with probability ``power``. ``str(verdict)`` is the CLI's text and
    ``verdict.assert_pass()`` raises ``AssertionError`` with it.
    """
    return _check_samples(
        prediction,
        samples_of(values),
        false_alarm_rate=false_alarm_rate,
        power=power,
        target_mean=target_mean,
        target_variance=target_variance,
    )


def plan(
    prediction: Prediction,
    pilot: Values,
    *,
    false_alarm_rate: float = 1e-3,
    power: float = 0.9,
    target_mean: float = 0.1,
    target_variance: float = 0.2,
) -> Plan:
    """About how many values ``check`` needs with these options, from a pilot
    of the renderer's values. Check once, at a count chosen beforehand."""
    return _plan_samples(
        prediction,
        samples_of(pilot),
        false_alarm_rate=false_alarm_rate,
        power=power,
        target_mean=target_mean,
        target_variance=target_variance,
    )
