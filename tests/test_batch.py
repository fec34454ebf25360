"""Batch runs: variants of the founding case run in parallel inside the engine give,
bit for bit, the results of serial runs; a bad variant leaves its error in its slot."""

from __future__ import annotations

import jointgap
import numpy as np
import pytest
from jointgap.variants import with_parameters

CLEARANCES = ("0.2 mm", "0.35 mm", "0.5 mm", "0.8 mm")


@pytest.fixture(scope="module")
def variants():
    base = jointgap.load("examples/slider_crank_clearance.toml")
    return [with_parameters(base, {"rod_slider.clearance": c}) for c in CLEARANCES]


def test_batch_equals_serial_exactly(variants, engine) -> None:
    options = {"rate": 2000, "rtol": 1e-6, "atol": 1e-9}
    serial = [m.simulate(0.3, **options) for m in variants]
    for threads in (1, 2, None):
        batch = jointgap.simulate_batch(variants, 0.3, threads=threads, **options)
        assert len(batch) == len(variants)
        for one, many in zip(serial, batch, strict=True):
            assert isinstance(many, jointgap.Result)
            assert many.channels == one.channels
            assert np.array_equal(many.time, one.time) and np.array_equal(many.data, one.data)
            assert many.impacts == one.impacts
            # Times, and whether the compiled code came from the process's cache, differ.
            timed = ("wall_time", "compile_time", "compiled")
            assert {k: v for k, v in many.stats.items() if k not in timed} == {
                k: v for k, v in one.stats.items() if k not in timed
            }
            assert many.stats["compiled"].startswith("native code")
    # The variants really differ: the clearance is in the results.
    gaps = [r.clearances["rod_slider"]["clearance"] for r in serial]
    assert gaps == pytest.approx([2e-4, 3.5e-4, 5e-4, 8e-4])


def test_a_bad_variant_does_not_stop_the_others(variants, engine) -> None:
    bad = with_parameters(variants[0], {"rod_slider.clearance": "8 mm"})  # journal radius < 0
    out = jointgap.simulate_batch([variants[0], bad, variants[2]], 0.05, rate=1000)
    assert isinstance(out[0], jointgap.Result) and out[0].ok
    assert isinstance(out[1], jointgap.ModelError) and "rod_slider" in str(out[1])
    assert isinstance(out[2], jointgap.Result) and out[2].ok
    with pytest.raises(ValueError, match="threads = 0"):
        jointgap.simulate_batch(variants, 0.05, threads=0)


def test_with_parameters_converts_units_and_names_errors(variants) -> None:
    base = variants[0]
    m = with_parameters(base, {"rod_slider.c_max": "20 kN*s/m", "rod_slider.mu_d": 0.07})
    spec = m.joints["rod_slider"]["clearance"]
    assert spec["normal_law"]["c_max"] == 20_000.0 and spec["friction"]["mu_d"] == 0.07
    with pytest.raises(ValueError, match="unknown quantity 'gap'"):
        with_parameters(base, {"rod_slider.gap": 1})
    with pytest.raises(ValueError, match="no joint 'pin'"):
        with_parameters(base, {"pin.mu_d": 0.1})
