"""The README's Python snippet, run verbatim: it passes on the reference
tracer's values and fails on values 10 % high."""

from __future__ import annotations

import pathlib
import re

import pytest

README = pathlib.Path(__file__).resolve().parents[2] / "README.md"


def readme_snippet() -> str:
    blocks = re.findall(r"```python\n(.*?)```", README.read_text(encoding="utf-8"), flags=re.S)
    assert len(blocks) == 1, "the README has one Python snippet"
    return blocks[0]


def run_snippet(scale: float) -> None:
    namespace: dict = {}
    exec(compile(readme_snippet(), str(README), "exec"), namespace)
    if scale != 1.0:
        correct = namespace["my_renderer"]
        namespace["my_renderer"] = lambda scene, iterations: scale * correct(scene, iterations)
    namespace["test_pixel_mean_and_noise_match_the_oracle"]()


def test_the_readme_snippet_passes_on_correct_values() -> None:
    run_snippet(1.0)


def test_the_readme_snippet_fails_on_values_ten_percent_high() -> None:
    with pytest.raises(AssertionError, match=r"^FAIL: 200000 samples"):
        run_snippet(1.1)
