"""The spatial joints with contact that carry the planar kinds into space, from model files
with units and from the builder: a block in its guide channel (``clearance_translational``
with a ``height_axis`` and a depth) and the lubricated cylindrical joint; their channels,
impact lists, errors and reports (the physics is proven in
crates/jointgap-core/tests/spatial_joint_kinds.rs)."""

from __future__ import annotations

import jointgap
import pytest
from jointgap import ModelError
from jointgap.report import run_report_data, write_run_report

BLOCK = """
[model]
name = "block_in_channel"
dimension = 3
gravity = [0, 0, 0]

[[body]]
name = "block"
mass = "500 g"
inertia = { principal = { moments = [2e-5, 7e-5, 7e-5] } }
velocity = [0.5, 0.2, 0.15]
angular_velocity = [1.0, 1.5, -0.8]

[[joint]]
name = "guide"
type = "clearance_translational"
body_i = "ground"
point_i = [0, 0, 0]
body_j = "block"
point_j = [0, 0, 0]
axis = [1, 0, 0]
height_axis = [0, 1, 0]
block_length = "40 mm"
block_height = "10 mm"
guide_width = "10.5 mm"
block_depth = "20 mm"
depth_clearance = "0.4 mm"
stiffness = 2e9
normal_law = { type = "hertz" }
"""

JOURNAL = """
[model]
name = "lubricated_journal"
dimension = 3
gravity = [0, 0, 0]

[[body]]
name = "journal"
mass = 1.0
inertia = { principal = { moments = [25, 25, 50] } }
angular_velocity = ["0 rad/s", "0 rad/s", "955 rpm"]

[[joint]]
name = "bearing"
type = "lubricated_cylindrical"
body_i = "ground"
point_i = [0, 0, 0]
body_j = "journal"
point_j = [0, 0, 0]
axis = [0, 0, 1]
length = "10 mm"
journal_radius = "20 mm"
clearance = "50 um"
stiffness = 1e10
normal_law = { type = "hunt_crossley", restitution = 0.5 }

[joint.lubrication]
length = "10 mm"
viscosity = "50 cP"

[[force]]
name = "load"
type = "applied_force"
body = "journal"
force = [0, -300, 0]
"""


def test_a_block_in_its_channel_from_a_file(write_model) -> None:
    model = jointgap.load(write_model(BLOCK))
    joint = model.to_dict()["joints"][0]
    assert joint["clearance"]["depth_clearance"] == pytest.approx(4e-4)
    assert joint["clearance"]["guide_width"] == pytest.approx(0.0105)
    result = model.simulate(0.02, rate=20_000)
    assert result.status == "finished", result.message
    # Sixteen points, each with its channels and impact list.
    assert {f"guide.p{i}.fn" for i in range(1, 17)} <= set(result.channels)
    for q in ("travel", "speed", "offset_height", "offset_depth", "tilt_along", "tilt_depth"):
        assert f"guide.{q}" in result.channels
    assert sorted(result.impacts) == sorted(f"guide.p{i}" for i in range(1, 17))
    assert sum(len(v) for v in result.impacts.values()) > 5
    # Frictionless: the slide along the channel keeps its speed.
    assert result["guide.speed"] == pytest.approx(0.5, abs=1e-9)


def test_a_lubricated_journal_from_a_file(write_model) -> None:
    result = jointgap.load(write_model(JOURNAL)).simulate(0.2, rate=1_000)
    assert result.status == "finished", result.message
    # The film carries the load alone, both halves alike (an aligned journal).
    assert result["bearing.film_fy"][-1] == pytest.approx(300.0, rel=1e-6)
    assert result["bearing.p1.eccentricity_ratio"][-1] == pytest.approx(
        result["bearing.p2.eccentricity_ratio"][-1], rel=1e-9
    )
    assert (result["bearing.p1.film_mode"] == 0).all()
    assert not any(result.impacts.values())


def test_the_builder_makes_both_and_the_writer_reads_back(tmp_path) -> None:
    model = jointgap.Model("both", dimension=3, gravity=[0, 0, 0])
    model.add_body("block", mass=0.5, inertia={"principal": {"moments": [2e-5, 7e-5, 7e-5]}})
    model.add_clearance_translational(
        "guide",
        "ground",
        "block",
        [1, 0, 0],
        [0, 0, 0],
        [0, 0, 0],
        height_axis=[0, 1, 0],
        block_length="40 mm",
        block_height="10 mm",
        clearance="0.5 mm",
        block_depth="20 mm",
        guide_depth="20.4 mm",
        stiffness=2e9,
        normal_law={"type": "hertz"},
    )
    model.add_body(
        "journal", mass=1.0, inertia={"principal": {"moments": [25, 25, 50]}}, position=[0, 1, 0]
    )
    model.add_lubricated_cylindrical(
        "bearing",
        "ground",
        "journal",
        [0, 0, 1],
        [0, 1, 0],
        [0, 0, 0],
        length="10 mm",
        viscosity="50 cP",
        film="long",
        journal_radius="20 mm",
        clearance="50 um",
        stiffness=1e10,
        normal_law={"type": "hunt_crossley", "restitution": 0.5},
    )
    joints = {j["name"]: j for j in model.to_dict()["joints"]}
    film = joints["bearing"]["lubrication"]
    assert (film["length"], film["viscosity"], film["film"]) == (
        pytest.approx(0.01),
        pytest.approx(0.05),
        "long",
    )
    path = tmp_path / "both.toml"
    model.save(path)
    again = jointgap.load(path)
    assert again.to_dict()["joints"] == model.to_dict()["joints"]
    assert again.simulate(0.002, rate=10_000).status == "finished"


@pytest.mark.parametrize(
    ("edit", "key", "words"),
    [
        (("height_axis = [0, 1, 0]\n", ""), "height_axis", "height_axis"),
        (("height_axis = [0, 1, 0]", "height_axis = [0.1, 1, 0]"), "height_axis", "perpendicular"),
        (('depth_clearance = "0.4 mm"\n', ""), None, "block_depth, guide_depth"),
        (('block_depth = "20 mm"', 'block_depth = "-20 mm"'), "block_depth", "positive"),
    ],
)
def test_bad_block_data_names_the_joint_and_key(write_model, edit, key, words) -> None:
    text = BLOCK.replace(*edit)
    with pytest.raises(ModelError) as caught:
        jointgap.load(write_model(text)).simulate(0.001)
    message = str(caught.value)
    assert "guide" in message and words in message, message


def test_reports_of_both_open_in_a_browser(write_model, tmp_path) -> None:
    """The lubricated journal's orbit is drawn, the block's contact forces plotted; each
    page draws itself and moves its animation with no script error (headless Chromium;
    skipped without it unless JOINTGAP_REQUIRE_BROWSER=1)."""
    results = {
        "block": jointgap.load(write_model(BLOCK, "block.toml")).simulate(0.01, rate=10_000),
        "journal": jointgap.load(write_model(JOURNAL, "journal.toml")).simulate(0.01, rate=10_000),
    }
    orbits = {
        kind: [o["joint"] for o in run_report_data(r, source=f"{kind}.toml")["run"]["orbits"]]
        for kind, r in results.items()
    }
    assert orbits == {"block": [], "journal": ["bearing"]}
    pages = {kind: write_run_report(r, tmp_path / f"{kind}.html") for kind, r in results.items()}
    from browser import pages_draw_without_errors

    pages_draw_without_errors(pages)
