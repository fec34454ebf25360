"""Damping calibration (the founding paper's Eq. 10-11): the loop on the founding case
stops by its rule, the answer satisfies Eq. 10-11 with the V_avg recomputed here from
the impact list, the inverse is exact, and bad input is named."""

from __future__ import annotations

import math

import jointgap
import pytest
from jointgap.calibration import (
    CalibrationError,
    ImpactSelection,
    calibrate_damping,
    damping_from_restitution,
    restitution_from_damping,
)
from jointgap.cli import EXIT_NOT_CONVERGED, main

K_FOUNDING = 3.136e10  # docs/physics.md section 5, to the paper's four digits
D_MAX, N = 1e-5, 1.5


def test_paper_pairs_of_table_iv_are_consistent() -> None:
    """Eq. 10-11 written out here: C_max = 3 K (1 - r^2) / (4 V) d^n. The paper's last
    trial (27960 N s/m for r = 0.55) implies V_avg = 0.0186 m/s, inside the 0.014 to
    0.019 m/s that docs/physics.md derives from Table IV."""
    v = 3 * K_FOUNDING * (1 - 0.55**2) / (4 * 27960) * D_MAX**N
    assert v == pytest.approx(0.01856, rel=1e-3)
    assert damping_from_restitution(0.55, v, K_FOUNDING, D_MAX, N) == pytest.approx(27960)
    assert restitution_from_damping(27960, v, K_FOUNDING, D_MAX, N) == pytest.approx(0.55)


@pytest.mark.parametrize("r", [0.05, 0.3, 0.55, 0.8, 0.999, 1.0])
def test_restitution_to_damping_and_back(r: float) -> None:
    c = damping_from_restitution(r, 0.03, K_FOUNDING, D_MAX, N)
    assert restitution_from_damping(c, 0.03, K_FOUNDING, D_MAX, N) == pytest.approx(r, abs=1e-12)


def test_more_than_plastic_damping_is_refused() -> None:
    with pytest.raises(ValueError, match="exceeds the plastic limit"):
        restitution_from_damping(27960, 0.037, K_FOUNDING, D_MAX, N)
    for bad in (0.0, -0.2, 1.2, math.nan):
        with pytest.raises(ValueError, match="restitution"):
            damping_from_restitution(bad, 0.03, K_FOUNDING, D_MAX, N)


@pytest.fixture(scope="module")
def founding_calibration():
    model = jointgap.load("examples/slider_crank_clearance.toml")
    return calibrate_damping(model, "rod_slider", 0.55, 0.5, rate=1000)


def test_founding_case_calibration_converges_by_the_integer_rule(
    founding_calibration, engine
) -> None:
    cal = founding_calibration
    assert cal.converged
    runs = [it.c_max for it in cal.iterations]
    assert cal.iterations[0].c_max == 27960.0  # started from the model's C_max
    # The stopping rule: the last two runs share the integer part of C_max, or the
    # last run's own update does.
    last = cal.iterations[-1]
    assert math.floor(runs[-2]) == math.floor(runs[-1]) or math.floor(last.update) == math.floor(
        last.c_max
    )
    # Each row's update is Eq. 10-11 at that row's V_avg.
    for it in cal.iterations:
        assert it.update == pytest.approx(
            3 * cal.stiffness * (1 - 0.55**2) / (4 * it.v_avg) * D_MAX**N, rel=1e-12
        )


def test_calibrated_c_max_satisfies_eq_10_11_with_the_last_runs_impacts(
    founding_calibration, engine
) -> None:
    cal = founding_calibration
    impacts = cal.result.impacts["rod_slider"]
    v_avg = sum(i.onset_speed for i in impacts) / len(impacts)
    h_avg = 3 * cal.stiffness * (1 - 0.55**2) / (4 * v_avg)
    assert cal.c_max == pytest.approx(h_avg * D_MAX**N, rel=1e-12)
    assert cal.stiffness == pytest.approx(K_FOUNDING, rel=1e-3)
    last, before = cal.iterations[-1], cal.iterations[-2]
    if math.floor(last.c_max) == math.floor(cal.c_max):
        # The last run used (almost) the answer: within the noise of V_avg against C_max.
        assert cal.c_max == pytest.approx(last.c_max, rel=2e-3)
        assert not cal.notes
    else:
        # V_avg jumps with C_max at the answer (an impact more or less): bisection closed
        # the bracket on the jump. Its ends (the largest C_max whose update went up, the
        # smallest whose update went down) share the integer part of C_max, differ by an
        # impact, and their restitutions lie on either side of the target.
        below = max((it for it in cal.iterations if it.update >= it.c_max), key=lambda it: it.c_max)
        above = min((it for it in cal.iterations if it.update < it.c_max), key=lambda it: it.c_max)
        assert math.floor(before.c_max) == math.floor(last.c_max)
        assert math.floor(below.c_max) == math.floor(above.c_max)
        assert below.impacts != above.impacts
        implied = [
            restitution_from_damping(it.c_max, it.v_avg, cal.stiffness, D_MAX, N)
            for it in (above, below)
        ]
        assert min(implied) < 0.55 < max(implied)
        last_r = restitution_from_damping(last.c_max, last.v_avg, cal.stiffness, D_MAX, N)
        assert cal.notes and f"r = {last_r:.4f}" in cal.notes[0]
    # The calibrated model carries the answer and nothing else changed.
    joints = {j["name"]: j for j in cal.model.to_dict()["joints"]}
    assert joints["rod_slider"]["clearance"]["normal_law"]["c_max"] == cal.c_max
    original = jointgap.load("examples/slider_crank_clearance.toml").to_dict()
    joints["rod_slider"]["clearance"]["normal_law"]["c_max"] = 27960.0
    assert list(joints.values()) == original["joints"]


def test_impact_selection_rules() -> None:
    impacts = [
        jointgap.results.Impact("j", t, v, 1.0, 1e-6, 1e-4)
        for t, v in ((0.1, 0.01), (0.25, 0.05), (0.3, 0.002), (0.45, 0.04))
    ]
    assert [i.onset_time for i in impacts if ImpactSelection().accepts(i)] == [0.1, 0.25, 0.3, 0.45]
    steady = ImpactSelection(start=0.2)
    assert [i.onset_time for i in impacts if steady.accepts(i)] == [0.25, 0.3, 0.45]
    fast = ImpactSelection(min_speed=0.005, end=0.4)
    assert [i.onset_time for i in impacts if fast.accepts(i)] == [0.1, 0.25]
    assert "onset speed >= 0.005 m/s" in fast.describe()
    with pytest.raises(ValueError, match="end must follow start"):
        ImpactSelection(start=0.3, end=0.2)


def test_calibration_names_bad_joints(engine) -> None:
    model = jointgap.load("examples/slider_crank_clearance.toml")
    with pytest.raises(CalibrationError, match="no joint 'gap'.*rod_slider"):
        calibrate_damping(model, "gap", 0.55, 0.1)
    with pytest.raises(CalibrationError, match="'crank_rod' is a revolute joint"):
        calibrate_damping(model, "crank_rod", 0.55, 0.1)
    with pytest.raises(CalibrationError, match="no impact matches"):
        calibrate_damping(model, "rod_slider", 0.55, 0.1, selection=ImpactSelection(start=0.09))


def test_calibrate_command_writes_table_and_model(tmp_path, capsys, engine) -> None:
    out = tmp_path / "calibrated.toml"
    table = tmp_path / "table.csv"
    status = main(
        [
            "calibrate",
            "examples/slider_crank_clearance.toml",
            "--restitution",
            "0.55",
            "--t-end",
            "0.5",
            "--window",
            "0.2",
            "end",
            "--tolerance",
            "100",
            "--write",
            str(out),
            "--table",
            str(table),
        ]
    )
    text = capsys.readouterr().out
    assert status == 0, text
    assert "V_avg over impacts with onsets from 0.2 s to end" in text
    assert "converged: C_max =" in text
    assert "iteration" in text.splitlines()[1]
    c_max = float(text.split("converged: C_max = ")[1].split()[0])
    law = jointgap.load(out).joints["rod_slider"]["clearance"]["normal_law"]
    assert law["c_max"] == pytest.approx(c_max, abs=0.01)
    assert table.read_text().splitlines()[0] == "iteration,c_max,v_avg,impacts,update"


def test_calibrate_command_inverse_and_budget(capsys, engine) -> None:
    assert (
        main(
            [
                "calibrate",
                "examples/slider_crank_clearance.toml",
                "--c-max",
                "27960 N*s/m",
                "--v-avg",
                "18.56 mm/s",
                "--t-end",
                "0.5",
            ]
        )
        == 0
    )
    # K from the materials is 3.1359e10, a hair below the paper's rounded 3.136e10.
    r = float(capsys.readouterr().out.split("restitution r = ")[1])
    assert r == pytest.approx(0.55, abs=5e-4)
    status = main(
        [
            "calibrate",
            "examples/slider_crank_clearance.toml",
            "--restitution",
            "0.55",
            "--t-end",
            "0.5",
            "--rate",
            "1000",
            "--max-iterations",
            "2",
        ]
    )
    assert status == EXIT_NOT_CONVERGED
    assert "NOT converged" in capsys.readouterr().out
