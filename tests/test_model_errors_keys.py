"""An engine error about a model file's value points at the value's line: the engine
builds each error in parts (element, key as the file writes it, problem), and
:class:`jointgap.ModelError` locates the key in the file; nothing reads the message."""

from __future__ import annotations

import json
from pathlib import Path

import jointgap
import pytest
from jointgap import ModelError

FOUNDING = Path(__file__).resolve().parent.parent / "examples" / "slider_crank_clearance.toml"

SPRING = """
[[force]]
name = "spring"
type = "spring_damper"
body_i = "ground"
point_i = [0, 0]
body_j = "rod"
point_j = "Q"
stiffness = "10 N/m"
"""

MARKER = """
[[marker]]
name = "tip"
body = "rod"
point = "B"
frame = "nowhere"
"""

# (what the founding file says, what the broken file says instead, kind, element, key)
CASES = [
    (
        'normal_law = { type = "adams_impact", exponent = 1.5, c_max = "27960 N*s/m", '
        'd_max = "1e-5 m" }',
        'normal_law = { type = "hunt_crossley", restitution = 1.5 }',
        "joint",
        "rod_slider",
        "normal_law.restitution",
    ),
    ('v_s = "0.0001 m/s"', 'v_s = "0.1 m/s"', "joint", "rod_slider", "friction.v_s"),
    ('clearance = "0.5 mm"', 'clearance = "8 mm"', "joint", "rod_slider", "clearance"),
    (
        'bearing_material = { youngs_modulus = "97 GPa", poisson_ratio = 0.3 }',
        'bearing_material = { youngs_modulus = "97 GPa", poisson_ratio = 0.7 }',
        "joint",
        "rod_slider",
        "bearing_material.poisson_ratio",
    ),
    # The body named twice is named a second time on body_j's line, not on the name's.
    (
        'body_j = "rod"                          #',
        'body_j = "slider" #',
        "joint",
        "rod_slider",
        "body_j",
    ),
    ('inertia = "0.0006926 kg*m^2"', "inertia = 0", "body", "rod", "inertia"),
    ('joint = "ground_crank"', 'joint = "rod_slider"', "driver", "motor", "joint"),
    ("", SPRING, "force", "spring", "point_j"),
    ("", MARKER, "marker", "tip", "frame"),
]


@pytest.mark.parametrize(
    ("given", "broken", "kind", "name", "key"), CASES, ids=[c[4] for c in CASES]
)
def test_a_bad_value_is_located_at_its_line(
    engine, write_model, given: str, broken: str, kind: str, name: str, key: str
) -> None:
    text = FOUNDING.read_text(encoding="utf-8")
    if given:
        assert text.count(given) == 1, given
        text = text.replace(given, broken)
    else:
        text += broken
    path = write_model(text)
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    e = err.value
    assert (e.kind, e.name, e.key) == (kind, name, key), str(e)
    lines = path.read_text(encoding="utf-8").splitlines()
    # The broken value's line: the line changed, or the key's line in the element added.
    leaf = key.split(".")[-1]
    if given:
        wanted = [n + 1 for n, line in enumerate(lines) if broken in line]
    else:
        start = len(lines) - len(broken.strip().splitlines())
        wanted = [n + 1 for n in range(start, len(lines)) if lines[n].startswith(f"{leaf} =")]
    assert len(wanted) == 1 and e.line == wanted[0], (e.line, wanted, str(e))
    assert f"{leaf} =" in lines[e.line - 1]
    assert str(e).startswith(f"{path}:{e.line}: {kind} '{name}': ")


def test_the_parts_come_from_the_engine_unparsed(engine, write_model) -> None:
    """The located error carries the parts of the binding's exception as they are."""
    from jointgap._jointgap import EngineError, check_model

    data = jointgap.load(FOUNDING).to_dict()
    next(j for j in data["joints"] if j["name"] == "rod_slider")["body_j"] = "slider"
    with pytest.raises(EngineError) as raw:
        check_model(json.dumps(data))
    assert (raw.value.category, raw.value.kind, raw.value.element, raw.value.key) == (
        "model",
        "joint",
        "rod_slider",
        "body_j",
    )
    assert str(raw.value) == "joint 'rod_slider': connects body 'slider' to itself"
    given, broken = CASES[4][:2]
    path = write_model(FOUNDING.read_text(encoding="utf-8").replace(given, broken))
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    assert (err.value.key, err.value.problem) == (raw.value.key, raw.value.problem)
