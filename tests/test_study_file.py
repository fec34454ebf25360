"""Study files: parameters by path, ranges, distributions, sampling, and the errors an
invalid file gives before any case runs (file, line, key and value)."""

from __future__ import annotations

import math
import re

import jointgap
import numpy as np
import pytest
from jointgap.study import StudyError, load_study, run_study
from jointgap.study.sampling import Parameter, design
from jointgap.variants import with_parameters
from study_files import CLEARANCE, EXAMPLES, SMALL, grid_study, write_study

HEAD = f"""
[study]
model = "{CLEARANCE}"
t_end = "0.05 s"
"""
METRIC = '\n[metrics]\npeak = { stat = "peak", channel = "slider.ax" }\n'


def study_error(tmp_path, text: str) -> str:
    path = write_study(tmp_path, text)
    with pytest.raises(StudyError) as info:
        load_study(path)
    return str(info.value)


# ---------------------------------------------------------------- the design


def test_grid_cases_in_order_first_parameter_slowest(tmp_path, engine) -> None:
    text = HEAD + (
        "[parameters]\n"
        'rod_slider.clearance = { from = "0.1 mm", to = "0.5 mm", step = "0.1 mm" }\n'
        '"motor.speed" = ["100 rpm", "600 rpm"]\n'
        "gravity = 0\n" + METRIC
    )
    study = load_study(write_study(tmp_path, text))
    cases = study.cases()
    assert len(cases) == 10
    # 0.1 + 2 * 0.1 mm is 0.30000000000000004 mm in floating point: rounded to 0.3 mm
    assert [c["rod_slider.clearance"] for c in cases[::2]] == [1e-4, 2e-4, 3e-4, 4e-4, 5e-4]
    assert [c["motor.speed"] for c in cases[:2]] == pytest.approx([10 * math.pi / 3, 20 * math.pi])
    assert {c["gravity"] for c in cases} == {0.0}
    assert [p.path for p in study.parameters] == [
        "rod_slider.clearance",
        "motor.speed",
        "gravity",
    ]
    summary = study.to_dict()
    assert summary["sampling"] == "grid" and summary["n_cases"] == 10
    assert summary["parameters"][0] == {
        "path": "rod_slider.clearance",
        "kind": "range",
        "unit": "m",
        "from": 1e-4,
        "to": 5e-4,
        "step": 1e-4,
        "values": [1e-4, 2e-4, 3e-4, 4e-4, 5e-4],
    }
    assert summary["units"]["motor.speed"] == "rad/s"
    assert summary["metrics"] == ["peak"]


def test_compiled_is_a_run_option(tmp_path, engine) -> None:
    """``compiled = false`` runs the study's cases on the interpreted engine; left out,
    the runs take the engine's default (compiled)."""
    off = load_study(write_study(tmp_path, HEAD + "compiled = false\n" + METRIC))
    assert off.run["compiled"] is False
    assert "compiled" not in load_study(write_study(tmp_path, HEAD + METRIC)).run


def test_steps_range_includes_both_ends(tmp_path, engine) -> None:
    study = load_study(write_study(tmp_path, grid_study(6)))
    values = [c["rod_slider.clearance"] for c in study.cases()]
    assert values == pytest.approx([1e-4, 2e-4, 3e-4, 4e-4, 5e-4, 6e-4], rel=1e-12)


def test_monte_carlo_is_seeded_and_crossed_with_the_grid(tmp_path, engine) -> None:
    study = load_study(write_study(tmp_path, SMALL))
    cases = study.cases()
    assert len(cases) == 12
    mu = [c["rod_slider.mu_d"] for c in cases]
    # every grid point gets the same two draws (common random numbers)
    assert mu[0::2] == [mu[0]] * 6 and mu[1::2] == [mu[1]] * 6
    u = np.random.default_rng(7).random((2, 1))[:, 0]
    assert mu[:2] == pytest.approx(list(0.03 + 0.04 * u), rel=1e-15)
    assert load_study(write_study(tmp_path, SMALL, "again.toml")).cases() == cases


def test_latin_hypercube_puts_one_draw_in_each_stratum() -> None:
    clearance = Parameter(
        "rod_slider.clearance",
        "truncated_normal",
        settings={"mean": 5e-4, "std": 5e-5, "low": 4e-4, "high": 6e-4},
    )
    restitution = Parameter("rod_slider.restitution", "uniform", settings={"low": 0.4, "high": 0.8})
    cases = design([clearance, restitution], "latin_hypercube", 50, seed=3)
    r = np.array([c["rod_slider.restitution"] for c in cases])
    strata = np.floor((r - 0.4) / 0.4 * 50).astype(int)
    assert sorted(strata) == list(range(50))
    c = np.array([c["rod_slider.clearance"] for c in cases])
    assert c.min() >= 4e-4 and c.max() <= 6e-4
    # the truncated normal's strata: the distribution function at each draw
    from scipy import stats

    cdf = stats.truncnorm.cdf(c, -2.0, 2.0, loc=5e-4, scale=5e-5)
    assert sorted(np.floor(cdf * 50).astype(int)) == list(range(50))


def test_normal_quantiles() -> None:
    p = Parameter("rod_slider.restitution", "normal", settings={"mean": 0.6, "std": 0.1})
    q = p.quantile(np.array([0.5, 0.8413447460685429]))
    assert q == pytest.approx([0.6, 0.7], rel=1e-9)


def test_bare_dotted_keys_read_as_paths(tmp_path, engine) -> None:
    text = HEAD + "[parameters]\nrod_slider.restitution = 0.5\nrod_slider.mu_d = [0.04, 0.06]\n"
    with pytest.raises(StudyError, match="adams_impact law of 'rod_slider' has no restitution"):
        load_study(write_study(tmp_path, text + METRIC))
    study = load_study(
        write_study(tmp_path, HEAD + "[parameters]\nrod_slider.mu_d = [0.04]\n" + METRIC)
    )
    assert [p.path for p in study.parameters] == ["rod_slider.mu_d"]


# ---------------------------------------------------------------- variants it relies on


def test_speed_gravity_and_every_clearance_joint_set_by_path(engine) -> None:
    base = jointgap.load(EXAMPLES / "slider_crank_two_clearances.toml")
    model = with_parameters(
        base, {"*.clearance": "0.2 mm", "motor.speed": "600 rpm", "gravity": "5 m/s^2"}
    )
    joints = model.to_dict()["joints"]
    assert [j["clearance"]["clearance"] for j in joints if "clearance" in j] == [2e-4, 2e-4]
    assert model.drivers["motor"]["profile"]["speed"] == pytest.approx(20 * math.pi)
    assert model.drivers["motor"]["profile"]["ramp_time"] == 0.2
    assert model.gravity == (0.0, -5.0)
    with pytest.raises(ValueError, match="no driver 'crank'"):
        with_parameters(base, {"crank.speed": 1.0})


# ---------------------------------------------------------------- errors before any run


def test_unknown_parameter_path_names_file_line_key_and_value(tmp_path, engine) -> None:
    text = HEAD + '[parameters]\n"rod_slider.clearnce" = ["0.1 mm"]\n' + METRIC
    message = study_error(tmp_path, text)
    assert message.startswith(f"{tmp_path / 'study.toml'}:5: [parameters] ")
    assert 'rod_slider.clearnce = ["0.1 mm"]' in message
    assert "unknown quantity 'clearnce'" in message
    text = HEAD + '[parameters]\n"rod_sider.clearance" = ["0.1 mm"]\n' + METRIC
    message = study_error(tmp_path, text)
    assert "no joint 'rod_sider' in the model (clearance joints: rod_slider)" in message
    assert "model slider_crank_clearance.toml" in message


def test_empty_range_is_an_error(tmp_path, engine) -> None:
    for spec in (
        '{ from = "600 rpm", to = "100 rpm", step = "100 rpm" }',
        '{ from = "100 rpm", to = "600 rpm", steps = 0 }',
        '{ from = "100 rpm", to = "600 rpm", step = "-100 rpm" }',
    ):
        message = study_error(tmp_path, HEAD + f'[parameters]\n"motor.speed" = {spec}\n' + METRIC)
        assert f"[parameters] motor.speed = {spec}: empty range" in message
        assert re.match(rf"{re.escape(str(tmp_path / 'study.toml'))}:5: ", message)


@pytest.mark.parametrize(
    ("spec", "problem"),
    [
        ('{ distribution = "uniform", low = 0.8, high = 0.4 }', "bad bounds: low 0.8"),
        (
            '{ distribution = "truncated_normal", mean = 0.6, std = 0.1, low = 0.9, high = 0.3 }',
            "bad bounds: low 0.9 must be below high 0.3",
        ),
        ('{ distribution = "normal", mean = 0.6, std = 0 }', "bad std 0: must be > 0"),
        ('{ distribution = "normal", mean = 0.6 }', "a normal distribution takes mean, std"),
        ('{ distribution = "lognormal", mean = 0.6 }', "distribution 'lognormal'"),
        ('{ distribution = "truncated_normal", mean = 0.6, std = 0.1 }', "needs low, high"),
    ],
)
def test_bad_distribution_is_an_error(tmp_path, spec, problem, engine) -> None:
    head = HEAD + "sampling = 'monte_carlo'\nsamples = 4\n"
    message = study_error(tmp_path, head + f'[parameters]\n"rod_slider.mu_d" = {spec}\n' + METRIC)
    assert f"[parameters] rod_slider.mu_d = {spec}: " in message
    assert problem in message


@pytest.mark.parametrize(
    ("text", "expected"),
    [
        (HEAD + "rtol = 'fine'\n" + METRIC, '[study] rtol = "fine": option rtol'),
        (HEAD + "compiled = 'no'\n" + METRIC, '[study] compiled = "no": must be true or false'),
        (HEAD + "samples = 3\n" + METRIC, "[study] samples = 3: a grid takes no samples"),
        (HEAD + "colour = 1\n" + METRIC, "[study] colour = 1: unknown key"),
        (
            HEAD
            + "sampling = 'grid'\n"
            + '[parameters]\n"rod_slider.mu_d" = { distribution = "uniform", low = 0, high = 1 }\n'
            + METRIC,
            'needs sampling = "monte_carlo" or "latin_hypercube"',
        ),
        (
            HEAD + "[metrics]\nx = { stat = 'peak', channel = 'slider.az' }\n",
            '[metrics] x = { stat = "peak", channel = "slider.az" }: the model has no '
            "channel 'slider.az' (slider.x",
        ),
        (
            HEAD
            + "[metrics]\nx = { stat = 'rms', channel = 'slider.ax', window = ['0 s', '1 s'] }\n",
            "the window ends after t_end = 0.05 s",
        ),
        (
            HEAD + "[metrics]\nx = { stat = 'deviation_rms', channel = 'rod_slider.fn' }\n",
            "the ideal mechanism has no channel 'rod_slider.fn'",
        ),
        (HEAD + "[metrics]\nx = 'impact_count'\n", "stat 'impact_count': must be one of"),
        (HEAD + "[metrics]\ncase = 'impacts'\n", "case is a column of every study"),
        (HEAD.replace("t_end", "t_stop") + METRIC, "[study] t_stop"),
        (
            HEAD.replace("model =", "# model =")
            + "[parameters]\nmodel = ['nowhere.toml']\n"
            + METRIC,
            '[parameters] model = "nowhere.toml": no such file',
        ),
        (HEAD + "[parameters]\nmodel = ['x.toml']\n" + METRIC, "give them there only"),
    ],
)
def test_invalid_study_files(tmp_path, text, expected, engine) -> None:
    assert expected in study_error(tmp_path, text)


def test_nothing_runs_for_an_invalid_study(tmp_path, engine) -> None:
    path = write_study(tmp_path, HEAD + '[parameters]\n"motor.sped" = [1]\n' + METRIC)
    with pytest.raises(StudyError):
        run_study(path, tmp_path / "out", progress=None)
    assert not (tmp_path / "out").exists()
