"""The Python layer: scenes, predictions, the check and its errors.

Correct values come from the reference tracer (``reference_values``); a
renderer off by 10 % must fail. Run: ``pip install ./python && pytest python/tests``.
"""

from __future__ import annotations

import concurrent.futures
import multiprocessing
import pathlib
import re

import numpy as np
import pytest

import mcrt_noise as m

ROOT = pathlib.Path(__file__).resolve().parents[2]
README_SCENE = ROOT / "scenes" / "point-isotropic.toml"


@pytest.fixture(scope="module")
def scene() -> m.Scene:
    return m.Scene.from_file(README_SCENE)


@pytest.fixture(scope="module")
def prediction(scene: m.Scene) -> m.Prediction:
    return m.predict(scene)


@pytest.fixture(scope="module")
def values(scene: m.Scene) -> np.ndarray:
    return m.reference_values(scene, 200_000, seed=11)


def test_a_scene_reads_builds_and_round_trips(scene: m.Scene) -> None:
    d = scene.to_dict()
    assert d["albedo"] == 0.8 and d["forward_rays"] == 200 and d["scattering_orders"] == 0
    built = m.Scene.build(
        sigma_ext=d["sigma_ext"],
        albedo=d["albedo"],
        point_lights=[(light["position"], light["flux"]) for light in d["lights"]],
        camera_origin=d["camera_origin"],
        camera_direction=d["camera_direction"],
        radius=d["radius"],
        q=d["q"],
        forward_rays=d["forward_rays"],
        camera_rays=d["camera_rays"],
    )
    assert built.to_dict() == d
    assert m.Scene.from_toml(scene.to_toml()).to_dict() == d


def test_the_builder_covers_every_feature() -> None:
    s = m.Scene.build(
        sigma_ext=1.0,
        albedo=0.8,
        phase="henyey-greenstein",
        g=0.9,
        point_lights=[((1.0, 0.0, 1.0), 1.0)],
        beams=[((0.0, -2.0, 1.0), (0.0, 1.0, 0.0), 0.5, 2.0)],
        radius=0.2,
        q=0.5,
        forward_rays=20,
        camera_rays=4,
        scattering_orders="all",
    )
    d = s.to_dict()
    assert d["phase"] == "henyey-greenstein" and d["g"] == 0.9 and d["scattering_orders"] == "all"
    assert [light["kind"] for light in d["lights"]] == ["point", "beam"]
    assert d["lights"][1]["radius"] == 0.5


def test_an_invalid_scene_names_the_field_and_its_range() -> None:
    with pytest.raises(m.SceneError, match=r"estimator\.q = 1\.5: must be in \(0, 1\]"):
        m.Scene.build(
            sigma_ext=1.0, albedo=0.8, point_lights=[((1, 0, 1), 1.0)], radius=0.2, q=1.5, forward_rays=20, camera_rays=4
        )
    with pytest.raises(m.SceneError, match="scattering_orders"):
        m.Scene.build(
            sigma_ext=1.0,
            albedo=0.8,
            point_lights=[((1, 0, 1), 1.0)],
            radius=0.2,
            q=1.0,
            forward_rays=20,
            camera_rays=1,
            scattering_orders="most",
        )
    with pytest.raises(m.SceneError, match="cannot read"):
        m.Scene.from_file(ROOT / "no-such-scene.toml")
    assert issubclass(m.SceneError, ValueError)


def test_a_scene_the_oracle_cannot_predict_raises_predict_error(scene: m.Scene) -> None:
    text = scene.to_toml().replace("scattering_orders = 0", 'scattering_orders = "all"')
    text = text.replace('kind = "isotropic"', 'kind = "henyey-greenstein"\ng = 0.9')
    hg_all = m.Scene.from_toml(text)
    with pytest.raises(m.PredictError, match='medium.phase.kind = "henyey-greenstein"'):
        m.predict(hg_all)


def test_the_prediction_has_bars(prediction: m.Prediction) -> None:
    assert prediction.model == "finite-sphere"
    assert prediction.mean.value == pytest.approx(1.1114987e-3, rel=1e-6)
    assert 0 < prediction.mean.quadrature_bar < 1e-9 * prediction.mean.value
    assert prediction.variance.model_bar == 0.0
    d = prediction.to_dict()
    assert d["mean"]["value"] == prediction.mean.value


def test_correct_values_pass_and_values_off_by_ten_percent_fail(
    prediction: m.Prediction, values: np.ndarray
) -> None:
    verdict = m.check(prediction, values)
    verdict.assert_pass()
    assert verdict.passed and verdict.resolved and verdict.status == "pass" and bool(verdict)
    assert abs(verdict.z_mean) < verdict.z_limit and abs(verdict.z_variance) < verdict.z_limit
    assert verdict.detectable_mean_error <= 0.1 and verdict.detectable_variance_error <= 0.2
    assert str(verdict).startswith("PASS: 200000 samples")

    wrong = m.check(prediction, 1.1 * values)
    assert wrong.status == "fail" and not wrong.passed
    assert wrong.z_mean > wrong.z_limit
    with pytest.raises(AssertionError, match=r"^FAIL: 200000 samples"):
        wrong.assert_pass()


def test_streamed_chunks_give_the_same_verdict_as_one_array(prediction: m.Prediction, values: np.ndarray) -> None:
    whole = m.check(prediction, values)
    samples = m.Samples()
    for chunk in np.array_split(values, 7):
        samples.extend(chunk)
    halves = m.Samples()
    halves.extend(values[:1000])
    rest = m.Samples()
    rest.extend(values[1000:])
    from_iterator = m.check(prediction, (float(v) for v in values))
    for other in (samples, halves.merge(rest), from_iterator):
        verdict = other if isinstance(other, m.Verdict) else m.check(prediction, other)
        assert (verdict.z_mean, verdict.z_variance) == (whole.z_mean, whole.z_variance)
    assert len(samples) == samples.count == values.size


def test_too_few_values_are_not_resolved_and_say_what_would(prediction: m.Prediction, values: np.ndarray) -> None:
    verdict = m.check(prediction, values[:2000])
    assert verdict.status == "not resolved" and not verdict.resolved
    assert verdict.unresolved and any(re.search(r"about [0-9.e]+ samples would", u) for u in verdict.unresolved)


def test_the_planner_says_how_many_values(prediction: m.Prediction, values: np.ndarray) -> None:
    plan = m.plan(prediction, values[:20_000], target_mean=0.03, target_variance=0.05)
    assert plan.pilot_samples == 20_000
    assert plan.samples is not None and plan.samples > 200_000
    assert "samples" in str(plan)


def test_bad_values_and_options_are_named(prediction: m.Prediction, values: np.ndarray) -> None:
    bad = values.copy()
    bad[70_000] = -1.0
    with pytest.raises(m.SampleError, match="70000"):
        m.check(prediction, bad)
    with pytest.raises(m.SampleError, match="one-dimensional"):
        m.check(prediction, values.reshape(2, -1))
    with pytest.raises(m.SampleError):
        m.check(prediction, [0.1, float("nan")])
    with pytest.raises(m.OptionsError, match="false_alarm_rate"):
        m.check(prediction, values, false_alarm_rate=2.0)
    with pytest.raises(m.OptionsError, match="power"):
        m.check(prediction, values, power=1.5)


def test_inputs_that_are_not_real_numbers_are_refused(prediction: m.Prediction) -> None:
    refused = {
        "text": ["0.1", "0.2"],
        "None in an object array": np.array([1.0, None], dtype=object),
        "masked": np.ma.array([0.1, 0.2], mask=[0, 1]),
        "complex": np.array([0.1 + 1j, 0.2]),
        "boolean": np.array([True, False]),
        "a dict": {1: 2},
        "a float": 0.5,
        "0-d": np.float64(3.0),
        "ragged": [[0.1], [0.2, 0.3]],
    }
    for what, values in refused.items():
        with pytest.raises(m.SampleError, match="^values"):
            m.check(prediction, values)
            pytest.fail(f"{what} accepted")
    assert m.samples_of(np.arange(10, dtype=np.int32)).count == 10  # integers are real numbers


def test_extend_adds_all_values_or_none(values: np.ndarray) -> None:
    samples = m.Samples()
    samples.extend(values[:100])
    bad = values.copy()
    bad[170_000] = float("inf")
    with pytest.raises(m.SampleError, match="170000"):
        samples.extend(bad)
    assert samples.count == 100


def test_an_iterator_is_read_in_blocks(values: np.ndarray) -> None:
    many = np.tile(values, 6)  # 1.2e6 values: two blocks of 2^20
    from_array, from_iterator = m.samples_of(many), m.samples_of(iter(many.tolist()))
    assert from_iterator.count == many.size
    assert (from_iterator.mean, from_iterator.variance) == (from_array.mean, from_array.variance)


def test_threads_may_extend_one_samples(prediction: m.Prediction, values: np.ndarray) -> None:
    shared = m.Samples()
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        list(pool.map(shared.extend, np.array_split(values, 16)))
    whole = m.check(prediction, values)
    assert shared.count == values.size
    assert (m.check(prediction, shared).z_mean, shared.variance) == (whole.z_mean, m.samples_of(values).variance)


def test_counts_stay_below_2_to_the_53(values: np.ndarray) -> None:
    sums = [1.0, 1.0, 1.0, 1.0, 1.0, 1.0]
    for count in (0, -1, 2**53 + 1, 2**64 - 1):
        with pytest.raises(m.SampleError, match=r"count = .*: must be in \[1, 2\^53"):
            m.Samples.from_power_sums(count, sums, 1e-6)
    full = m.Samples.from_power_sums(2**53, [2.0**53] * 6, 0.0)
    with pytest.raises(m.SampleError, match="at most 2\\^53"):
        full.push(1.0)
    with pytest.raises(m.SampleError, match="at most 2\\^53"):
        full.merge(m.samples_of(values[:10]))
    assert full.count == 2**53


def test_out_of_range_arguments_are_named(scene: m.Scene) -> None:
    with pytest.raises(m.OptionsError, match=r"rel_tol = 0e0: must be in \(0, 1\)"):
        m.predict(scene, rel_tol=0.0)
    base = dict(sigma_ext=1.0, albedo=0.8, point_lights=[((1, 0, 1), 1.0)], radius=0.2, q=1.0, camera_rays=1)
    with pytest.raises(m.SceneError, match=r"estimator.forward_rays = -1: must be an integer >= 1"):
        m.Scene.build(forward_rays=-1, **base)
    with pytest.raises(m.SceneError, match=r"estimator.forward_rays = True"):
        m.Scene.build(forward_rays=True, **base)
    with pytest.raises(m.SceneError, match=r"point_lights\[0\] position: .*must be three real numbers"):
        m.Scene.build(**{**base, "point_lights": [((1, 0), 1.0)]}, forward_rays=20)
    with pytest.raises(m.SceneError, match=r"beams\[0\]: .*must be \(\(x, y, z\) centre"):
        m.Scene.build(**base, forward_rays=20, beams=[((0, 0, 0), 1.0)])
    with pytest.raises(m.SceneError, match="scattering_orders = True"):
        m.Scene.build(**base, forward_rays=20, scattering_orders=True)
    with pytest.raises(ValueError, match=r"count = 4294967296: must be in \[0, 100000000\]"):
        m.reference_values(scene, 2**32)
    with pytest.raises(ValueError, match="seed = -1"):
        m.reference_values(scene, 10, seed=-1)


def _predict_in_a_child(path: str) -> str:
    try:
        m.predict(m.Scene.from_file(path))
    except RuntimeError as e:
        return str(e)
    return "no error"


def test_a_forked_child_gets_an_error_not_a_hang(prediction: m.Prediction) -> None:
    # The parent has run parallel work (the fixtures); rayon's threads are not in a forked child.
    with multiprocessing.get_context("fork").Pool(1) as pool:
        message = pool.apply_async(_predict_in_a_child, (str(README_SCENE),)).get(timeout=120)
    assert "before it forked this process" in message and '"spawn"' in message, message
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        assert pool.apply_async(_predict_in_a_child, (str(README_SCENE),)).get(timeout=300) == "no error"
