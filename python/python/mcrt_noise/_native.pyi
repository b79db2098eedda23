"""Type stubs of the extension module (the Rust layer in ``src/lib.rs``)."""

import os
from collections.abc import Iterable, Sequence
from typing import Any, Optional, Union

import numpy as np
import numpy.typing as npt

class SceneError(ValueError):
    """An invalid scene: every invalid value named, with its range."""

class PredictError(RuntimeError):
    """The oracle cannot predict this scene (not covered, not converged within its budget, or beyond f64)."""

class SampleError(ValueError):
    """A value that cannot be a pixel value (negative, not finite), or power sums no values have."""

class OptionsError(ValueError):
    """An invalid check option, named with its allowed range."""

Vec3 = Sequence[float]

class Scene:
    """A scene: medium, lights, camera, estimator, scattering orders."""

    @staticmethod
    def from_file(path: Union[str, "os.PathLike[str]"]) -> Scene: ...
    @staticmethod
    def from_toml(text: str) -> Scene: ...
    @staticmethod
    def build(
        *,
        sigma_ext: float,
        albedo: float,
        radius: float,
        q: float,
        forward_rays: int,
        camera_rays: int,
        point_lights: Optional[Sequence[tuple[Vec3, float]]] = None,
        beams: Optional[Sequence[tuple[Vec3, Vec3, float, float]]] = None,
        camera_origin: Optional[Vec3] = None,
        camera_direction: Optional[Vec3] = None,
        phase: str = "isotropic",
        g: Optional[float] = None,
        scattering_orders: Union[int, str, None] = None,
    ) -> Scene: ...
    def to_toml(self) -> str: ...
    def to_dict(self) -> dict[str, Any]: ...

class Predicted:
    """A predicted quantity: its value and two bounds on its error."""

    @property
    def value(self) -> float: ...
    @property
    def quadrature_bar(self) -> float: ...
    @property
    def model_bar(self) -> float: ...
    @property
    def total_bar(self) -> float: ...

class Prediction:
    """The mean and Var L of one iteration, with their bars, the model and the bias."""

    @property
    def mean(self) -> Predicted: ...
    @property
    def variance(self) -> Predicted: ...
    @property
    def model(self) -> str: ...
    @property
    def bias(self) -> Optional[tuple[float, float]]: ...
    def to_dict(self) -> dict[str, Any]: ...

class Samples:
    """Exact power sums of per-iteration values; chunks, merges and threads give the same bits."""

    def __init__(self) -> None: ...
    def push(self, value: float) -> None: ...
    def extend(self, values: Union[npt.ArrayLike, Iterable[float]]) -> None: ...
    def merge(self, other: Samples) -> Samples: ...
    @staticmethod
    def from_power_sums(count: int, sums: Sequence[float], sums_relative_error: float = 0.0) -> Samples: ...
    @property
    def count(self) -> int: ...
    @property
    def nonzero(self) -> Optional[int]: ...
    @property
    def mean(self) -> Optional[tuple[float, float]]: ...
    @property
    def variance(self) -> Optional[tuple[float, float]]: ...
    def __len__(self) -> int: ...

class Verdict:
    """PASS, FAIL or NOT RESOLVED, with z-scores, limits and detectable errors; str() is the CLI's text."""

    @property
    def status(self) -> str: ...
    @property
    def passed(self) -> bool: ...
    @property
    def resolved(self) -> bool: ...
    @property
    def z_mean(self) -> Optional[float]: ...
    @property
    def z_variance(self) -> Optional[float]: ...
    @property
    def z_limit(self) -> float: ...
    @property
    def detectable_mean_error(self) -> Optional[float]: ...
    @property
    def detectable_variance_error(self) -> Optional[float]: ...
    @property
    def failures(self) -> list[str]: ...
    @property
    def unresolved(self) -> list[str]: ...
    def assert_pass(self) -> None: ...
    def to_dict(self) -> dict[str, Any]: ...
    def __bool__(self) -> bool: ...

class Plan:
    """About how many values a check needs, from a pilot."""

    @property
    def samples(self) -> Optional[float]: ...
    @property
    def pilot_samples(self) -> int: ...
    def to_dict(self) -> dict[str, Any]: ...

def predict(scene: Scene, *, rel_tol: Optional[float] = None) -> Prediction: ...
def reference_values(scene: Scene, count: int, *, seed: int = 1, start: int = 0) -> np.ndarray: ...
def _check_samples(
    prediction: Prediction,
    samples: Samples,
    *,
    false_alarm_rate: float = ...,
    power: float = ...,
    target_mean: float = ...,
    target_variance: float = ...,
) -> Verdict: ...
def _plan_samples(
    prediction: Prediction,
    pilot: Samples,
    *,
    false_alarm_rate: float = ...,
    power: float = ...,
    target_mean: float = ...,
    target_variance: float = ...,
) -> Plan: ...
