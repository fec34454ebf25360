"""Model files: loading, saving, and one test per kind of error.

Every error must name the file, the line, the element and the problem, as
``<file>:<line>: <kind> '<name>': <problem>``. The base model below is small so that the
line numbers in the expected messages can be read off it.
"""

from __future__ import annotations

import math
from pathlib import Path

import jointgap
import pytest
from jointgap import ModelError

BASE = """\
[model]
name = "two_links"
gravity = [0, "-9.81 m/s^2"]

[ground]
points = { O = [0, 0] }

[[body]]
name = "crank"
mass = "2.37 kg"
inertia = "0.01201 kg*m^2"
position = ["0.04 m", 0]
points = { O = ["-0.04 m", 0], A = ["0.04 m", 0] }

[[body]]
name = "rod"
mass = "0.72 kg"
inertia = "0.0006926 kg*m^2"
position = ["0.24 m", 0]
points = { A = ["-0.16 m", 0] }

[[joint]]
name = "ground_crank"
type = "revolute"
body_i = "ground"
point_i = "O"
body_j = "crank"
point_j = "O"

[[joint]]
name = "crank_rod"
type = "revolute"
body_i = "crank"
point_i = "A"
body_j = "rod"
point_j = "A"

[[driver]]
name = "motor"
joint = "ground_crank"
profile = { type = "linear_ramp", speed = "300 rpm", ramp_time = "0.2 s" }
"""


def load_error(write_model, old: str, new: str) -> tuple[Path, str]:
    """Writes BASE with `old` replaced by `new` (exactly once), loads it and returns the
    file and the error message."""
    assert BASE.count(old) == 1, f"{old!r} must occur once in BASE"
    path = write_model(BASE.replace(old, new))
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    return path, str(err.value)


# ---------------------------------------------------------------------- valid files


def test_base_model_loads_in_si(write_model, engine) -> None:
    path = write_model(BASE)
    model = jointgap.load(path)
    assert model.name == "two_links"
    assert model.source == str(path)
    assert model.gravity == (0.0, -9.81)
    assert list(model.bodies) == ["crank", "rod"]
    assert model.bodies["rod"]["mass"] == 0.72
    assert model.bodies["crank"]["points"] == {"O": [-0.04, 0.0], "A": [0.04, 0.0]}
    profile = model.drivers["motor"]["profile"]
    assert profile == {"type": "linear_ramp", "speed": 10 * math.pi, "ramp_time": 0.2}
    assert model.ground_points == {"O": (0.0, 0.0)}
    assert model.degrees_of_freedom() == 2
    assert model.degrees_of_freedom(with_drivers=True) == 1


def test_examples_load(examples, engine) -> None:
    crank = jointgap.load(examples / "slider_crank_ideal.toml")
    assert list(crank.bodies) == ["crank", "rod", "slider"]
    assert list(crank.joints) == ["ground_crank", "crank_rod", "rod_slider", "slider_guide"]
    assert crank.joints["rod_slider"]["body_i"] == "slider"
    assert crank.joints["rod_slider"]["body_j"] == "rod"
    assert crank.joints["slider_guide"]["axis"] == [1.0, 0.0]
    assert crank.bodies["slider"]["inertia"] == pytest.approx(2.28 * (0.05**2 * 2) / 12)
    assert crank.degrees_of_freedom(with_drivers=True) == 0
    pendulum = jointgap.load(examples / "pendulum.toml")
    assert pendulum.degrees_of_freedom() == 1
    four_bar = jointgap.load(examples / "four_bar.toml")
    assert four_bar.degrees_of_freedom() == 1
    assert "P" in four_bar.bodies["coupler"]["points"]
    assert four_bar.drivers["motor"]["profile"] == {"type": "constant_speed", "speed": 2 * math.pi}
    for model in (crank, pendulum, four_bar):
        assert all("shape" in body for body in model.bodies.values())


def test_save_round_trips_through_load(examples, tmp_path, engine) -> None:
    model = jointgap.load(examples / "slider_crank_ideal.toml")
    saved = tmp_path / "saved.toml"
    model.save(saved)
    again = jointgap.load(saved)
    assert again.to_dict() == model.to_dict()
    text = saved.read_text()
    assert "speed = 31.41592653589793" in text  # SI numbers, radians
    assert 'shape = { type = "bar", from = "O", to = "A", width = 0.02 }' in text


def test_loads_reads_text(engine) -> None:
    model = jointgap.loads(BASE, "inline.toml")
    assert model.source == "inline.toml"
    assert len(model.joints) == 2


def test_missing_file_raises_file_not_found(tmp_path) -> None:
    with pytest.raises(FileNotFoundError):
        jointgap.load(tmp_path / "nowhere.toml")


# ---------------------------------------------------------------------- errors


def test_unknown_key_lists_the_allowed_ones(write_model) -> None:
    path, msg = load_error(write_model, 'mass = "0.72 kg"', 'mas = "0.72 kg"')
    assert msg == (
        f"{path}:17: body 'rod': unknown key 'mas' (allowed: name, mass, inertia, com, "
        "position, angle, velocity, omega, points, shape)"
    )


def test_unknown_key_in_a_nested_table(write_model) -> None:
    path, msg = load_error(write_model, 'ramp_time = "0.2 s"', 'ramp = "0.2 s"')
    assert msg == (
        f"{path}:41: driver 'motor': unknown key 'profile.ramp' for a linear_ramp profile "
        "(allowed: type, speed, ramp_time)"
    )


def test_unknown_key_in_model_section(write_model) -> None:
    path, msg = load_error(write_model, 'name = "two_links"', 'title = "two_links"')
    assert msg == f"{path}:2: model: unknown key 'title' (allowed: name, gravity)"


def test_axis_on_a_revolute_joint_is_an_unknown_key(write_model) -> None:
    path, msg = load_error(write_model, 'point_j = "A"\n', 'point_j = "A"\naxis = [1, 0]\n')
    assert msg.startswith(
        f"{path}:37: joint 'crank_rod': unknown key 'axis' for a revolute joint (allowed: "
    )


def test_missing_field(write_model) -> None:
    path, msg = load_error(write_model, 'inertia = "0.0006926 kg*m^2"\n', "")
    assert msg == f"{path}:16: body 'rod': missing field 'inertia'"


def test_missing_name_names_the_element_by_position(write_model) -> None:
    path, msg = load_error(write_model, 'name = "rod"\n', "")
    assert msg == f"{path}:15: body #2: missing field 'name'"


def test_prismatic_joint_needs_an_axis(write_model) -> None:
    old = 'name = "crank_rod"\ntype = "revolute"'
    path, msg = load_error(write_model, old, 'name = "crank_rod"\ntype = "prismatic"')
    assert msg == f"{path}:31: joint 'crank_rod': missing field 'axis'"


def test_joint_naming_an_unknown_body(write_model, engine) -> None:
    path, msg = load_error(write_model, 'body_j = "rod"', 'body_j = "rodd"')
    assert msg.startswith(f"{path}:35: joint 'crank_rod': body_j 'rodd' is not a body")


def test_joint_naming_an_unknown_point(write_model, engine) -> None:
    path, msg = load_error(
        write_model, 'body_j = "rod"\npoint_j = "A"', 'body_j = "rod"\npoint_j = "B"'
    )
    assert msg.startswith(f"{path}:36: joint 'crank_rod': point_j 'B' is not a point of body 'rod'")


def test_driver_naming_an_unknown_joint(write_model, engine) -> None:
    path, msg = load_error(write_model, 'joint = "ground_crank"', 'joint = "crank_ground"')
    assert msg.startswith(f"{path}:40: driver 'motor': joint 'crank_ground' is not a joint")


@pytest.mark.parametrize(
    ("field", "value", "line", "problem"),
    [
        ("mass", "0", 17, "mass must be positive, got 0 kg"),
        ("mass", '"-0.72 kg"', 17, "mass must be positive, got -0.72 kg"),
        (
            "inertia",
            "0",
            18,
            "inertia = 0 (a point mass) needs its rotation fixed by its joints, but its "
            "rotation is free: no prismatic or fixed joint ties it to the ground or to a body "
            "that cannot turn (its joints: 'crank_rod' revolute); give its moment of inertia",
        ),
        ("inertia", '"-1e-4 kg*m^2"', 18, "inertia must not be negative, got -1e-4 kg*m^2"),
    ],
)
def test_zero_or_negative_mass_and_inertia(write_model, field, value, line, problem) -> None:
    old = {"mass": 'mass = "0.72 kg"', "inertia": 'inertia = "0.0006926 kg*m^2"'}[field]
    path, msg = load_error(write_model, old, f"{field} = {value}")
    assert msg == f"{path}:{line}: body 'rod': {problem}"


@pytest.mark.parametrize(
    ("old", "new", "line", "problem"),
    [
        (
            'mass = "0.72 kg"',
            'mass = "0.72 m"',
            17,
            "body 'rod': mass '0.72 m': expected a mass [kg], got a length [m]",
        ),
        (
            'position = ["0.24 m", 0]',
            'position = ["0.24 s", 0]',
            19,
            "body 'rod': position '0.24 s': expected a length [m], got a time [s]",
        ),
        (
            'speed = "300 rpm"',
            'speed = "300 N"',
            41,
            "driver 'motor': profile.speed '300 N': expected an angular speed [rad/s] or a "
            "speed [m/s], got a force [N]",
        ),
        (
            "points = { O = [0, 0] }",
            'points = { O = [0, "1 kg"] }',
            6,
            "ground: points.O '1 kg': expected a length [m], got a mass [kg]",
        ),
        (
            'gravity = [0, "-9.81 m/s^2"]',
            'gravity = [0, "-9.81 m/s"]',
            3,
            "model 'two_links': gravity '-9.81 m/s': expected an acceleration [m/s^2], got a "
            "speed [m/s]",
        ),
    ],
)
def test_unit_of_the_wrong_dimension(write_model, old, new, line, problem) -> None:
    path, msg = load_error(write_model, old, new)
    assert msg == f"{path}:{line}: {problem}"


def test_linear_profile_on_a_revolute_joint(write_model) -> None:
    path, msg = load_error(write_model, 'speed = "300 rpm"', 'speed = "3 m/s"')
    assert msg == (
        f"{path}:41: driver 'motor': profile is given in linear units (m) but joint "
        "'ground_crank' is revolute: use angular units (rad, deg, rpm)"
    )


@pytest.mark.parametrize("value", ['"0,72 kg"', '"0.7.2 kg"', '"kg 0.72"'])
def test_malformed_number(write_model, value) -> None:
    path, msg = load_error(write_model, 'mass = "0.72 kg"', f"mass = {value}")
    assert msg == f"{path}:17: body 'rod': mass '{value.strip(chr(34))}': malformed number"


def test_vector_of_the_wrong_length(write_model) -> None:
    path, msg = load_error(write_model, 'position = ["0.24 m", 0]', 'position = ["0.24 m"]')
    assert msg == f"{path}:19: body 'rod': position must be a vector [x, y], got ['0.24 m']"


def test_duplicate_name(write_model) -> None:
    path, msg = load_error(write_model, 'name = "rod"', 'name = "crank"')
    assert (
        msg == f"{path}:16: body 'crank': duplicate name 'crank', already used by a body on line 9"
    )


def test_duplicate_name_across_kinds(write_model) -> None:
    path, msg = load_error(write_model, 'name = "crank_rod"', 'name = "rod"')
    assert msg == f"{path}:31: joint 'rod': duplicate name 'rod', already used by a body on line 16"


def test_reserved_name(write_model) -> None:
    path, msg = load_error(write_model, 'name = "rod"', 'name = "ground"')
    assert msg == f"{path}:16: body #2: the name 'ground' is reserved"


def test_unknown_joint_type(write_model) -> None:
    old = 'name = "crank_rod"\ntype = "revolute"'
    path, msg = load_error(write_model, old, 'name = "crank_rod"\ntype = "hinge"')
    assert msg == (
        f"{path}:32: joint 'crank_rod': unknown joint type 'hinge' "
        "(allowed: revolute, prismatic, fixed, clearance_revolute, lubricated_revolute, "
        "clearance_translational, revolute_with_play, prismatic_with_play, gear_pair)"
    )


def test_unknown_profile_type(write_model) -> None:
    path, msg = load_error(write_model, 'type = "linear_ramp"', 'type = "ramp"')
    assert msg == (
        f"{path}:41: driver 'motor': unknown profile type 'ramp' (allowed: constant_speed, "
        "linear_ramp, smooth_ramp, table_angle, table_speed)"
    )


def test_unknown_force_type(write_model) -> None:
    extra = '\n[[force]]\nname = "push"\ntype = "gust"\nbody = "rod"\n'
    path = write_model(BASE + extra)
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    assert str(err.value) == (
        f"{path}:45: force 'push': unknown force type 'gust' (allowed: spring_damper, "
        "rotational_spring_damper, applied_force, applied_torque)"
    )


def test_unknown_section(write_model) -> None:
    path = write_model(BASE + '\n[[bodies]]\nname = "x"\n')
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    assert str(err.value) == (
        f"{path}:43: unknown section 'bodies' "
        "(allowed: model, ground, body, joint, driver, force, marker)"
    )


def test_single_table_instead_of_an_array(write_model) -> None:
    path, msg = load_error(write_model, "[[driver]]", "[driver]")
    assert msg == f"{path}:38: write [[driver]] (one table per driver), not [driver]"


def test_invalid_toml_names_the_line(write_model) -> None:
    path, msg = load_error(write_model, 'mass = "0.72 kg"', "mass = 0.72 kg")
    assert msg.startswith(f"{path}:17: invalid TOML: ")
    assert "(at line 17, column 13)" in msg


def test_model_error_carries_its_parts(write_model) -> None:
    path = write_model(BASE.replace('mass = "0.72 kg"', 'mass = "0.72 m"'))
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    e = err.value
    assert isinstance(e, ValueError)
    assert (e.file, e.line, e.kind, e.name, e.index, e.key) == (
        str(path),
        17,
        "body",
        "rod",
        1,
        "mass",
    )
    assert e.element == "body 'rod'"
    assert e.problem == "mass '0.72 m': expected a mass [kg], got a length [m]"


def test_docs_field_reference_matches_the_schema() -> None:
    from jointgap._schema import reference_markdown

    docs = (Path(__file__).resolve().parent.parent / "docs" / "model-file.md").read_text()
    begin, end = "<!-- reference:begin -->\n", "<!-- reference:end -->"
    section = docs[docs.index(begin) + len(begin) : docs.index(end)]
    assert section.strip() == reference_markdown().strip(), (
        "docs/model-file.md is out of date: paste jointgap._schema.reference_markdown() "
        "between the reference markers"
    )


def test_sub_tables_and_their_lines(write_model) -> None:
    path = write_model(
        """
        [[body]]
        name = "bob"
        mass = 1
        inertia = 0.001

        [body.points]
        pivot = ["-1 m", 0]
        tip = ["1 m", "2 s"]
        """
    )
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    assert str(err.value) == (
        f"{path}:8: body 'bob': points.tip '2 s': expected a length [m], got a time [s]"
    )
