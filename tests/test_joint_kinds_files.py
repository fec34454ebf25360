"""The planar joint kinds of issue 24 from the Python side: each read from a model file
with units (checked in SI), built with the builder and written back, bad values located
at their line, a joint switching kind by its ``type`` line alone (keeping the tables it
does not use, which the engine warns about), the units of the new channels and a report
for a short run of each kind. The physics of each kind is tested in the core."""

from __future__ import annotations

import math
from pathlib import Path

import jointgap
import pytest
from jointgap import ModelError, laws
from jointgap.report import run_report_data, write_run_report
from jointgap.results import channel_unit, impact_units

pytestmark = pytest.mark.usefixtures("engine")

FOUNDING = (
    Path(__file__).resolve().parent.parent / "examples" / "slider_crank_clearance.toml"
).read_text(encoding="utf-8")
CLEARANCE_TYPE = 'type = "clearance_revolute"'
FRICTION = 'friction = { type = "coulomb"'
PRISMATIC = """type = "prismatic"
body_i = "ground"
point_i = "O"
body_j = "slider"
point_j = "B"
axis = [1, 0]                           # slides along x"""

LUBRICATED = FOUNDING.replace(CLEARANCE_TYPE, 'type = "lubricated_revolute"').replace(
    FRICTION,
    'lubrication = { length = "20 mm", viscosity = "40 cP", film = "long", roughness = "0.5 um" }\n'
    + FRICTION,
)
TRANSLATIONAL = FOUNDING.replace(CLEARANCE_TYPE, 'type = "revolute"').replace(
    PRISMATIC,
    """type = "clearance_translational"
body_i = "ground"
point_i = "O"
body_j = "slider"
point_j = "B"
axis = [1, 0]
block_length = "50 mm"
block_height = "50 mm"
clearance = "0.2 mm"
stiffness = "1e9 N/m^1.5"
normal_law = { type = "hunt_crossley", restitution = 0.8 }""",
)
PENDULUM = """
[model]
name = "pendulum_with_play"

[[body]]
name = "arm"
mass = "1 kg"
inertia = "0.01 kg*m^2"
position = ["0.1 m", "0 m"]
points = { O = ["-0.1 m", "0 m"], T = ["0.1 m", "0 m"] }
shape = { type = "bar", from = "O", to = "T" }

[[joint]]
name = "pivot"
type = "revolute_with_play"
body_i = "ground"
point_i = [0, 0]
body_j = "arm"
point_j = "O"

[joint.play]
play = "2 deg"
centre = "30 arcmin"
stiffness = "1e4 N*m/rad"
normal_law = { type = "hunt_crossley", restitution = 0.7, exponent = 1 }
"""
DROP = """
[model]
name = "block_with_play"

[[body]]
name = "block"
mass = "1 kg"
inertia = "0.001 kg*m^2"
shape = { type = "block", width = "20 mm", height = "20 mm" }

[[joint]]
name = "guide"
type = "prismatic_with_play"
body_i = "ground"
point_i = [0, 0]
body_j = "block"
point_j = [0, 0]
axis = [0, 1]

[joint.play]
play = "1 mm"
stiffness = "1 kN/mm"
normal_law = { type = "hunt_crossley", restitution = 0.7, exponent = 1 }
"""
GEARS = """
[model]
name = "gear_pair"
gravity = [0, 0]

[[body]]
name = "pinion"
mass = "0.5 kg"
inertia = "1e-4 kg*m^2"
shape = { type = "disk", radius = "50 mm" }

[[body]]
name = "wheel"
mass = "2 kg"
inertia = "2e-3 kg*m^2"
position = ["150 mm", "0 m"]
shape = { type = "disk", radius = "100 mm" }

[[joint]]
name = "pinion_shaft"
type = "revolute"
body_i = "ground"
point_i = [0, 0]
body_j = "pinion"
point_j = [0, 0]

[[joint]]
name = "wheel_shaft"
type = "revolute"
body_i = "ground"
point_i = ["150 mm", "0 m"]
body_j = "wheel"
point_j = [0, 0]

[[joint]]
name = "mesh"
type = "gear_pair"
body_i = "pinion"
point_i = [0, 0]
body_j = "wheel"
point_j = [0, 0]

[joint.gear]
ratio = 2
pitch_radius = "50 mm"
backlash = "0.1 mm"
pressure_angle = "20 deg"
mesh_stiffness = { angle = ["0 deg", "9 deg", "18 deg"], value = ["1e8 N/m", "2e8 N/m", "1e8 N/m"] }
normal_law = { type = "hunt_crossley", restitution = 0.8, exponent = 1 }

[[driver]]
name = "motor"
joint = "pinion_shaft"
profile = { type = "linear_ramp", speed = "100 rpm", ramp_time = "0.05 s" }
"""

KINDS = {
    "lubricated_revolute": (LUBRICATED, "rod_slider"),
    "clearance_translational": (TRANSLATIONAL, "slider_guide"),
    "revolute_with_play": (PENDULUM, "pivot"),
    "prismatic_with_play": (DROP, "guide"),
    "gear_pair": (GEARS, "mesh"),
}


def _joint(model: jointgap.Model, name: str) -> dict:
    return next(j for j in model.to_dict()["joints"] if j["name"] == name)


def test_each_kind_reads_its_units_into_si(write_model) -> None:
    lub = _joint(jointgap.load(write_model(LUBRICATED)), "rod_slider")
    assert lub["type"] == "lubricated_revolute"
    film = lub["lubrication"]
    assert film["film"] == "long"
    assert (film["length"], film["viscosity"], film["roughness"]) == pytest.approx(
        (0.02, 0.04, 5e-7), rel=1e-15
    )
    assert lub["clearance"]["bearing_radius"] == pytest.approx(0.0075, rel=1e-15)

    block = _joint(jointgap.load(write_model(TRANSLATIONAL)), "slider_guide")["clearance"]
    assert (block["block_length"], block["block_height"]) == pytest.approx((0.05, 0.05), 1e-15)
    assert block["clearance"] == pytest.approx(2e-4, rel=1e-15)
    assert block["stiffness"] == pytest.approx(1e9, rel=1e-15)

    play = _joint(jointgap.load(write_model(PENDULUM)), "pivot")["play"]
    assert play["play"] == pytest.approx(math.radians(2.0), rel=1e-15)
    assert play["centre"] == pytest.approx(math.radians(0.5), rel=1e-15)  # 30 arcmin
    assert play["stiffness"] == pytest.approx(1e4, rel=1e-15)

    travel = _joint(jointgap.load(write_model(DROP)), "guide")["play"]
    assert (travel["play"], travel["stiffness"]) == pytest.approx((1e-3, 1e6), rel=1e-15)

    gear = _joint(jointgap.load(write_model(GEARS)), "mesh")["gear"]
    assert (gear["ratio"], gear["pitch_radius"], gear["backlash"]) == pytest.approx(
        (2.0, 0.05, 1e-4), rel=1e-15
    )
    assert gear["pressure_angle"] == pytest.approx(math.radians(20.0), rel=1e-15)
    table = gear["mesh_stiffness"]
    assert table["angle"] == pytest.approx([0.0, math.radians(9.0), math.radians(18.0)], 1e-15)
    assert table["value"] == pytest.approx([1e8, 2e8, 1e8], rel=1e-15)


def test_a_stiffness_takes_the_laws_exponent_and_the_plays_rotation(write_model) -> None:
    """A rotation's play is stiff in N*m/rad^n, n its law's exponent; a force per length
    there is a unit error naming play.stiffness."""
    text = PENDULUM.replace('"1e4 N*m/rad"', '"2 N*m/mrad^1.5"').replace(
        "exponent = 1 }", "exponent = 1.5 }"
    )
    play = _joint(jointgap.load(write_model(text)), "pivot")["play"]
    assert play["stiffness"] == pytest.approx(2 * 1e3**1.5, rel=1e-12)
    path = write_model(PENDULUM.replace('"1e4 N*m/rad"', '"1e4 N/m"'))
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    line = PENDULUM.lstrip("\n").splitlines().index('stiffness = "1e4 N*m/rad"') + 1
    assert (err.value.name, err.value.key, err.value.line) == ("pivot", "play.stiffness", line)
    assert "expected a rotational stiffness [N*m/rad]" in str(err.value)


def _built() -> jointgap.Model:
    """A model holding one joint of each new kind, made with the builder."""
    m = jointgap.Model("kinds", gravity=(0, 0))
    for name in ("a", "b", "c", "d", "e", "f", "g"):
        m.add_body(name, mass=1.0, inertia=0.01)
    law = laws.hunt_crossley(0.8, exponent=1)
    m.add_lubricated_revolute(
        "lub",
        "ground",
        "a",
        [0, 0],
        [0, 0],
        length="20 mm",
        viscosity="40 cP",
        film="short_pi",
        bearing_radius="10 mm",
        clearance="50 um",
        stiffness="1e10 N/m^1.5",
        normal_law=laws.hunt_crossley(0.8),
    )
    m.add_clearance_translational(
        "slide",
        "ground",
        "b",
        [1, 0],
        [0, 0],
        [0, 0],
        block_length="40 mm",
        guide_width="30 mm",
        clearance="0.1 mm",
        stiffness="1e9 N/m^1.5",
        normal_law=laws.hunt_crossley(0.8),
        friction=laws.coulomb(0.1, 0.08, "0.1 mm/s", "1 mm/s"),
    )
    m.add_revolute_with_play(
        "pin", "ground", "c", [0, 0], [0, 0], play="1 deg", stiffness="1e3 N*m/rad", normal_law=law
    )
    m.add_prismatic_with_play(
        "rail",
        "ground",
        "d",
        [0, 1],
        [0, 0],
        [0, 0],
        play="2 mm",
        centre="0.5 mm",
        stiffness="1e6 N/m",
        normal_law=law,
    )
    m.add_revolute("shaft_1", "ground", "e", [0, 0], [0, 0])
    m.add_body("wheel", mass=2.0, inertia=0.02, position=("0.3 m", 0))
    m.add_revolute("shaft_2", "ground", "wheel", ["0.3 m", 0], [0, 0])
    m.add_gear_pair(
        "teeth",
        "e",
        "wheel",
        [0, 0],
        [0, 0],
        ratio=2,
        pitch_radius="100 mm",
        backlash="50 um",
        mesh_stiffness={"angle": ["0 deg", "10 deg"], "value": [1e8, 1.5e8]},
        normal_law=law,
    )
    return m


def test_the_builder_makes_each_kind_and_the_writer_reads_back(tmp_path) -> None:
    m = _built()
    data = m.to_dict()
    kinds = {j["name"]: j["type"] for j in data["joints"]}
    assert kinds == {
        "lub": "lubricated_revolute",
        "slide": "clearance_translational",
        "pin": "revolute_with_play",
        "rail": "prismatic_with_play",
        "shaft_1": "revolute",
        "shaft_2": "revolute",
        "teeth": "gear_pair",
    }
    joints = {j["name"]: j for j in data["joints"]}
    assert joints["lub"]["lubrication"] == {"length": 0.02, "viscosity": 0.04, "film": "short_pi"}
    assert joints["slide"]["clearance"]["guide_width"] == pytest.approx(0.03, rel=1e-15)
    assert joints["pin"]["play"]["play"] == pytest.approx(math.radians(1.0), rel=1e-15)
    assert joints["rail"]["play"]["centre"] == pytest.approx(5e-4, rel=1e-15)
    teeth = joints["teeth"]["gear"]
    assert teeth["mesh_stiffness"]["angle"][1] == pytest.approx(math.radians(10.0), rel=1e-15)
    assert "pressure_angle" not in teeth  # the engine's default
    m.save(tmp_path / "kinds.toml")
    assert jointgap.load(tmp_path / "kinds.toml").to_dict() == data
    m.check()  # the engine takes every kind as built


# (kind, what the file says, what the broken file says instead, key, words of the message)
BAD = [
    (
        "revolute_with_play",
        'play = "2 deg"',
        'play = "-2 deg"',
        "play.play",
        "must not be negative",
    ),
    (
        "lubricated_revolute",
        'viscosity = "40 cP"',
        'viscosity = "0 cP"',
        "lubrication.viscosity",
        "must be positive",
    ),
    ("gear_pair", "ratio = 2\n", "ratio = 0\n", "gear.ratio", "must be positive"),
    (
        "clearance_translational",
        'clearance = "0.2 mm"',
        'guide_width = "49 mm"',
        "block_height",
        "does not fit the guide",
    ),
    ("lubricated_revolute", 'film = "long"', 'film = "medium"', "lubrication.film", "one of"),
    (
        "gear_pair",
        '"2e8 N/m"',
        '"-2e8 N/m"',
        "gear.mesh_stiffness",
        "mesh_stiffness.value[1] must be positive",
    ),
]


@pytest.mark.parametrize(("kind", "given", "broken", "key", "words"), BAD, ids=[b[3] for b in BAD])
def test_a_bad_value_names_the_file_line_joint_and_key(
    write_model, kind: str, given: str, broken: str, key: str, words: str
) -> None:
    text, joint = KINDS[kind]
    assert text.count(given) == 1, given
    path = write_model(text.replace(given, broken))
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    e = err.value
    assert (e.kind, e.name, e.key) == ("joint", joint, key), str(e)
    lines = path.read_text(encoding="utf-8").splitlines()
    leaf = key.split(".")[-1]
    assert e.line is not None and f"{leaf} =" in lines[e.line - 1], (e.line, str(e))
    assert str(e).startswith(f"{path}:{e.line}: joint '{joint}': ")
    assert words in str(e)


def test_the_gears_must_mesh_at_the_placement(write_model) -> None:
    """The engine's check of the centres' distance reaches the user naming the joint."""
    path = write_model(GEARS.replace("ratio = 2\n", "ratio = 3\n"))
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    assert err.value.name == "mesh"
    assert "pitch radii" in str(err.value) and "0.200000 m" in str(err.value)


SWITCHES = [
    ("lubricated_revolute", "revolute", ["clearance", "lubrication"]),
    ("lubricated_revolute", "clearance_revolute", ["lubrication"]),
    ("clearance_translational", "prismatic", ["clearance"]),
    ("revolute_with_play", "revolute", ["play"]),
    ("prismatic_with_play", "prismatic", ["play"]),
]


@pytest.mark.parametrize(
    ("kind", "new", "kept"), SWITCHES, ids=[f"{k}-to-{n}" for k, n, _ in SWITCHES]
)
def test_a_joint_switches_kind_by_its_type_line(
    write_model, tmp_path, kind: str, new: str, kept: list[str]
) -> None:
    """A joint made dry or ideal by its type line alone: the tables the new type does
    not use stay in the model as they were read and the engine warns, naming the joint
    and each table, that it ignores them; the model writes back as it is."""
    text, name = KINDS[kind]
    before = _joint(jointgap.load(write_model(text, "before.toml")), name)
    switched = text.replace(f'type = "{kind}"', f'type = "{new}"')
    assert switched != text
    model = jointgap.load(write_model(switched))
    joint = _joint(model, name)
    assert joint["type"] == new
    for table in kept:
        assert joint[table] == before[table]
    result = model.simulate(0.002)
    assert result.status == "finished", result.message
    for table in kept:
        assert any(f"'{name}'" in w and f"'{table}'" in w for w in result.warnings), (
            table,
            result.warnings,
        )
    model.save(tmp_path / "switched.toml")
    assert jointgap.load(tmp_path / "switched.toml").to_dict() == model.to_dict()


def test_a_block_refuses_a_journals_keys_saying_why(write_model) -> None:
    path = write_model(
        TRANSLATIONAL.replace(
            'stiffness = "1e9 N/m^1.5"', 'stiffness = "1e9 N/m^1.5"\nbearing_material = "steel"'
        )
    )
    with pytest.raises(ModelError) as err:
        jointgap.load(path)
    assert (err.value.name, err.value.key) == ("slider_guide", "bearing_material")
    assert "no Hertz closed form" in str(err.value)
    assert path.read_text().splitlines()[err.value.line - 1].startswith("bearing_material")


def test_the_new_channels_have_their_units(write_model) -> None:
    models = {k: jointgap.load(write_model(t, f"{k}.toml")) for k, (t, _) in KINDS.items()}
    expected = {
        "lubricated_revolute": {
            "rod_slider.eccentricity_ratio": "",
            "rod_slider.attitude": "rad",
            "rod_slider.film_thickness": "m",
            "rod_slider.film_fx": "N",
            "rod_slider.peak_pressure": "Pa",
            "rod_slider.film_mode": "",
            "rod_slider.friction_torque": "N*m",
        },
        "clearance_translational": {
            "slider_guide.tilt": "rad",
            "slider_guide.offset": "m",
            "slider_guide.p3.fn": "N",
            "slider_guide.p3.penetration": "m",
        },
        "revolute_with_play": {
            "pivot.play_angle": "rad",
            "pivot.torque": "N*m",
            "pivot.penetration": "rad",
            "pivot.penetration_rate": "rad/s",
        },
        "prismatic_with_play": {
            "guide.play_travel": "m",
            "guide.force": "N",
            "guide.penetration": "m",
        },
        "gear_pair": {
            "mesh.mesh": "m",
            "mesh.fn": "N",
            "mesh.torque_1": "N*m",
            "mesh.torque_2": "N*m",
            "mesh.stiffness": "N/m",
        },
    }
    for kind, units in expected.items():
        data = models[kind].to_dict()
        channels = jointgap.results.model_channels(data)
        for channel, unit in units.items():
            assert channel in channels, (kind, channel)
            assert channel_unit(channel, data) == unit, (kind, channel)
    pendulum = models["revolute_with_play"].to_dict()
    assert impact_units(pendulum, "pivot") == {
        "onset_speed": "rad/s",
        "peak_force": "N*m",
        "max_penetration": "rad",
    }
    assert impact_units(models["gear_pair"].to_dict(), "mesh")["peak_force"] == "N"


@pytest.mark.parametrize("kind", list(KINDS))
def test_a_report_of_each_kind(write_model, tmp_path, kind: str) -> None:
    text, joint = KINDS[kind]
    model = jointgap.load(write_model(text))
    result = model.simulate(0.03, rate=20_000)
    assert result.status == "finished", result.message
    run = run_report_data(result, source=f"{kind}.toml")["run"]
    plotted = {p["id"] for p in run["plots"]}
    wanted = {
        "lubricated_revolute": ["eccentricity_ratio", "film_thickness", "film_fx", "film_mode"],
        "clearance_translational": ["p1.fn", "p4.fn", "tilt", "offset"],
        "revolute_with_play": ["play_angle", "torque"],
        "prismatic_with_play": ["play_travel", "force"],
        "gear_pair": ["mesh", "fn", "torque_2"],
    }[kind]
    assert {f"{joint}.{q}" for q in wanted} <= plotted, plotted
    orbits = [o["joint"] for o in run["orbits"]]
    assert orbits == (["rod_slider"] if kind == "lubricated_revolute" else [])
    tables = {t["id"]: t for t in run["tables"]}
    assert any(r[0] == joint for r in tables["model"]["rows"])
    if result.impacts and any(result.impacts.values()):
        impacts = tables["impacts"]
        assert ("units" in impacts["columns"]) == (kind == "revolute_with_play")
    page = write_run_report(result, tmp_path / f"{kind}.html")
    assert page.stat().st_size > 0


def test_each_kinds_report_opens_in_a_browser_without_an_error(write_model, tmp_path) -> None:
    """The page of each kind draws itself and moves its animation with no script error
    (headless Chromium, as tests/test_report_browser.py; skipped without it unless
    JOINTGAP_REQUIRE_BROWSER=1)."""
    from browser import pages_draw_without_errors

    pages = {}
    for kind, (text, _) in KINDS.items():
        result = jointgap.load(write_model(text, f"{kind}.toml")).simulate(0.01, rate=10_000)
        pages[kind] = write_run_report(result, tmp_path / f"{kind}.html")
    pages_draw_without_errors(pages)


def test_the_run_summary_gives_a_plays_stop_in_its_units(write_model) -> None:
    from jointgap.statistics import contact_statistics, format_statistics

    result = jointgap.load(write_model(PENDULUM)).simulate(0.06)
    assert result.impacts["pivot"], "the arm reaches its stop"
    line = format_statistics(contact_statistics(result), model=result.model)
    assert "N*m" in line and "µrad" in line and "rad/s" in line, line
    assert " N;" not in line and "µm" not in line and "m/s" not in line.replace("rad/s", ""), line


def test_kept_clearance_keys_need_their_law(write_model) -> None:
    """A joint keeping a clearance's keys for another type keeps them whole: without
    their normal law the error names the joint and the first key, not the engine's JSON."""
    text = PENDULUM.replace(
        'type = "revolute_with_play"', 'type = "revolute"\nclearance = "0.5 mm"'
    )
    with pytest.raises(ModelError) as err:
        jointgap.load(write_model(text))
    assert (err.value.name, err.value.key) == ("pivot", "clearance")
    assert "missing field 'normal_law'" in str(err.value)
