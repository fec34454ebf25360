"""The engine's wear data through the model file and the Python result (docs/wear.md):
the keys ``length``, ``bearing_wear`` and ``journal_wear`` of a clearance_revolute joint
with their units, and ``Result.wear`` of a run with ``wear_cells``."""

from __future__ import annotations

from pathlib import Path

import jointgap
import numpy as np
import pytest

FOUNDING = Path(__file__).resolve().parent.parent / "examples" / "slider_crank_clearance.toml"


def _founding(extra: str) -> jointgap.Model:
    text = FOUNDING.read_text()
    return jointgap.loads(
        text.replace('clearance = "0.5 mm"\n', f'clearance = "0.5 mm"\n{extra}', 1)
    )


def test_wear_keys_take_their_units() -> None:
    model = _founding(
        'length = "20 mm"\nbearing_wear = ["1 um", "2 um", "3 um", "2 um", "1 um", 0, 0, 0]\n'
    )
    joint = next(j for j in model.to_dict()["joints"] if j["name"] == "rod_slider")
    assert joint["clearance"]["length"] == pytest.approx(0.02)
    assert joint["clearance"]["bearing_wear"] == pytest.approx(
        [1e-6, 2e-6, 3e-6, 2e-6, 1e-6, 0, 0, 0]
    )


def test_result_carries_the_wear_per_unit_coefficient() -> None:
    result = _founding('length = "20 mm"\n').simulate(0.05, rate=1000, wear_cells=36)
    assert result.status == "finished"
    wear = result.wear["rod_slider"]
    assert wear["angles"] == pytest.approx(np.arange(36) * 2 * np.pi / 36)
    cell = 2 * np.pi / 36 * 0.02
    for part, radius in (("bearing", 7.5e-3), ("journal", 7.0e-3)):
        depth = wear[f"{part}_depth"]
        assert depth.shape == (36,) and not depth.flags.writeable
        assert depth.sum() * radius * cell == pytest.approx(wear["load_distance"], rel=1e-12)
        assert wear[f"{part}_volume"] == pytest.approx(wear["load_distance"], rel=1e-12)
    assert wear["load_distance"] > 0
    assert result.summary()["wear"]["rod_slider"]["angles"][1] == pytest.approx(2 * np.pi / 36)
    assert _founding("").simulate(0.01, rate=1000).wear == {}


def test_wear_needs_a_length() -> None:
    with pytest.raises(ValueError, match="length"):
        _founding("").simulate(0.01, rate=1000, wear_cells=36)
