"""What crosses the binding: the engine's defaults, each clearance joint as the engine
resolves it, engine errors in parts, and one compilation per load and run. Python repeats
none of these: each test holds the value Python shows against the core's."""

from __future__ import annotations

import json
from pathlib import Path

import jointgap
import pytest
from jointgap import ModelError, laws

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
FOUNDING = EXAMPLES / "slider_crank_clearance.toml"


def _engine() -> dict[str, object]:
    from jointgap import _jointgap

    defaults: dict[str, object] = json.loads(_jointgap.defaults())
    return defaults


def test_python_shows_the_engines_defaults(engine, write_model) -> None:
    from jointgap._engine import DEFAULT_OPTIONS, run_options

    defaults = _engine()
    # What a model without gravity means has not changed: a vertical plane, y up
    # (docs/model-file.md), in the builder, in a model file and in the engine's JSON.
    assert defaults["gravity"] == [0.0, -9.81]
    assert jointgap.Model().gravity == (0.0, -9.81)
    path = write_model(
        '[model]\nname = "no_gravity"\n[[body]]\nname = "puck"\nmass = 1\ninertia = 1\n'
    )
    assert jointgap.load(path).gravity == (0.0, -9.81)
    assert json.loads(jointgap.load(path).to_json())["gravity"] == [0.0, -9.81]
    assert DEFAULT_OPTIONS == defaults["options"]
    options = run_options("1 s")
    assert (options["rtol"], options["atol"], options["method"]) == (1e-8, 1e-11, "auto")
    assert laws.hertz().to_si() == {"type": "hertz", **{"exponent": 1.5}}
    assert laws.kelvin_voigt(3.0).to_si()["clip"] is True


def test_the_founding_case_resolves_as_docs_physics_says(engine) -> None:
    """docs/physics.md section 5: bearing radius 7.5 mm, journal radius 7.0 mm,
    K = 3.136e10 N/m^1.5, n = 1.5, d_max = 1e-5 m."""
    data = jointgap.load(FOUNDING).clearance_data()["rod_slider"]
    assert data["bearing_radius"] == pytest.approx(7.5e-3, rel=1e-12)
    assert data["journal_radius"] == pytest.approx(7.0e-3, rel=1e-12)
    assert data["clearance"] == pytest.approx(0.5e-3, rel=1e-9)
    assert data["stiffness"] == pytest.approx(3.136e10, rel=1e-3)
    assert (data["exponent"], data["d_max"]) == (1.5, 1e-5)
    assert data["normal_law"] == {
        "type": "adams_impact",
        "exponent": 1.5,
        "c_max": 27960.0,
        "d_max": 1e-5,
        "clip": True,
    }
    assert data["friction"]["type"] == "coulomb"


def _founding_with(law: laws.Law, **clearance: object) -> jointgap.Model:
    model = jointgap.load(FOUNDING)
    spec = dict(model.joints["rod_slider"]["clearance"], normal_law=law.to_si(), **clearance)
    data = model.to_dict()
    for joint in data["joints"]:
        if joint["name"] == "rod_slider":
            joint["clearance"] = spec
    return jointgap.Model.from_dict(data)


def test_d_max_left_out_is_the_bearing_materials_and_the_radius_rule_is_the_engines(
    engine,
) -> None:
    resolved = _founding_with(
        laws.adams_impact("100 N*s/m"), bearing_material="brass", journal_material="steel"
    ).clearance_data()["rod_slider"]
    assert resolved["d_max"] == 1e-5  # the library's d_max of brass
    assert resolved["normal_law"]["d_max"] == 1e-5
    # Journal radius and clearance given: the bearing radius is their sum.
    given = {"bearing_radius": None, "journal_radius": 7e-3, "clearance": 4e-4}
    resolved = _founding_with(laws.hunt_crossley(0.8), **given).clearance_data()["rod_slider"]
    assert resolved["bearing_radius"] == pytest.approx(7.4e-3, rel=1e-12)
    assert resolved["d_max"] is None  # a hysteresis law has none


def test_engine_errors_carry_their_parts(engine) -> None:
    from jointgap._jointgap import EngineError, check_model, simulate

    with pytest.raises(EngineError) as err:
        check_model(json.dumps({"bodies": [{"name": "b", "mass": 0.0, "inertia": 1.0}]}))
    e = err.value
    assert str(e) == "body 'b': mass = 0 kg must be positive"
    assert (e.category, e.kind, e.element, e.key) == ("model", "body", "b", "mass")
    assert e.problem == "mass = 0 kg must be positive"

    model = _founding_with(laws.hunt_crossley(1.5)).to_json()
    with pytest.raises(EngineError) as err:
        check_model(model)
    e = err.value
    assert str(e) == "joint 'rod_slider': restitution = 1.5 must lie in (0, 1]"
    assert (e.kind, e.element, e.key) == ("joint", "rod_slider", "normal_law.restitution")

    with pytest.raises(EngineError) as err:
        simulate(jointgap.load(FOUNDING).to_json(), json.dumps({"t_end": 0.1, "rtol": 2.0}))
    e = err.value
    assert (e.category, e.kind, e.element, e.key) == ("options", None, None, "rtol")
    assert e.problem == str(e) == "option rtol = 2: must lie in (0, 1)"


def test_model_error_takes_the_engines_parts(engine, write_model) -> None:
    model = _founding_with(laws.hunt_crossley(1.5))
    with pytest.raises(ModelError) as err:
        model.check()
    e = err.value
    assert str(e) == "joint 'rod_slider': restitution = 1.5 must lie in (0, 1]"
    assert (e.kind, e.name, e.key, e.problem) == (
        "joint",
        "rod_slider",
        "normal_law.restitution",
        "restitution = 1.5 must lie in (0, 1]",
    )
    # In a batch, each model's error is an engine error in parts too.
    (slot,) = jointgap.simulate_batch([model], t_end=0.01)
    assert isinstance(slot, ModelError) and slot.key == "normal_law.restitution"


def test_one_load_and_run_compiles_the_model_once(engine, write_model) -> None:
    from jointgap._jointgap import compilations

    # A model of its own (its name), which no earlier test has compiled.
    text = FOUNDING.read_text(encoding="utf-8").replace(
        'name = "slider_crank_clearance"', 'name = "compiled_once"'
    )
    assert "compiled_once" in text
    path = write_model(text)
    before = compilations()
    model = jointgap.load(path)  # checks the model: compiles it
    result = model.simulate("2 ms", rate="10 kHz")  # estimates its output size, runs it
    assert result.ok
    assert compilations() - before == 1


def test_a_built_model_run_at_a_rate_compiles_once(engine) -> None:
    from jointgap._jointgap import compilations

    model = (
        jointgap.Model("built_once")
        .add_body("bob", mass=1, inertia=1e-3, position=(1, 0), points={"pivot": (-1, 0)})
        .add_ground_point("O", (0, 0))
        .add_revolute("hinge", "ground", "bob", point_i="O", point_j="pivot")
    )
    before = compilations()
    assert model.simulate("10 ms", rate="1 kHz").ok  # its output size estimated, then run
    assert compilations() - before == 1


def test_a_batch_at_a_rate_compiles_each_model_once(engine) -> None:
    """Estimating a batch's output size prepares each model and the batch runs those
    prepared models: N distinct models (more than the binding keeps for single runs), N
    compilations; results as the single runs'."""
    from jointgap._jointgap import compilations

    def pendulum(name: str, length: float) -> jointgap.Model:
        return (
            jointgap.Model(name)
            .add_body(
                "bob", mass=1, inertia=1e-3, position=(length, 0), points={"pivot": (-length, 0)}
            )
            .add_ground_point("O", (0, 0))
            .add_revolute("hinge", "ground", "bob", point_i="O", point_j="pivot")
        )

    models = [pendulum(f"batch_once_{k}", 0.5 + 0.1 * k) for k in range(12)]
    before = compilations()
    results = jointgap.simulate_batch(models, "10 ms", rate="1 kHz", threads=2)
    assert compilations() - before == len(models)
    for model, result in zip(models, results, strict=True):
        assert isinstance(result, jointgap.Result) and result.ok
        single = model.simulate("10 ms", rate="1 kHz")
        assert single.channels == result.channels
        assert (single.time == result.time).all() and (single.data == result.data).all()
