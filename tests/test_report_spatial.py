"""The 3D report of a spatial run, without a browser: the drawing's data (bodies, joints,
poses of the model frames, orbits in the bearing frames, marker paths), the tables per
contact point, and the one self-contained file with plotly inlined. The page in a real
browser: tests/test_report_browser.py."""

from __future__ import annotations

import re

import numpy as np
import pytest
from jointgap.report import ReportError, render, run_report_data, write_run_report
from jointgap.report.spatial import orientation_matrix, principal_frame, spatial_section
from jointgap.results import Result
from spatial_reports import ball_and_hinge_pendulum, ideal_run, spatial_run

pytestmark = pytest.mark.usefixtures("engine")


@pytest.fixture(scope="module")
def run() -> Result:
    return spatial_run()


def attitude(e: np.ndarray) -> np.ndarray:
    """The rotation matrix of Euler parameters (scalar first), written as Nikravesh's
    A = (2 e0^2 - 1) I + 2 (e e^T + e0 e~) (Computer-Aided Analysis of Mechanical
    Systems, eq. 6.19): independent of the report's scipy conversion."""
    e0, v = e[0], np.asarray(e[1:])
    tilde = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return (2 * e0 * e0 - 1) * np.eye(3) + 2 * (np.outer(v, v) + e0 * tilde)


def test_the_page_data_of_a_spatial_run(run) -> None:
    data = run_report_data(run, source="pendulum.json")
    section = data["run"]
    assert section["spatial"] is True
    scene = section["scene"]
    assert [b["name"] for b in scene["bodies"]] == ["arm", "tip"]
    # Sticks through the named points, then the joint and marker points not among them.
    assert scene["bodies"][0]["sticks"] == [[0.0, 0.0, -0.15], [0.0, 0.0, 0.15]]
    assert [(j["name"], j["type"], j["body"]) for j in scene["joints"]] == [
        ("ball", "clearance_spherical", None),
        ("elbow", "clearance_cylindrical", "arm"),
    ]
    assert scene["markers"] == [{"name": "end", "body": "tip", "point": [0.0, 0.0, 0.05]}]
    frames = section["frames"]
    assert len(frames["time"]) == len(run.time) == 1501
    assert set(frames["bodies"]) == {"arm", "tip"}
    assert set(frames["joints"]) == {"ball", "elbow"}
    (path,) = scene["paths"]
    assert path["marker"] == "end" and path["x"][-1] == pytest.approx(run["end.x"][-1])
    # Orbits: a sphere for the ball, a cylinder about the bearing's axis for the journal.
    ball, elbow = section["orbits"]
    assert (ball["type"], ball["axis"], ball["clearance"]) == (
        "clearance_spherical",
        None,
        pytest.approx(2e-4),
    )
    assert (elbow["type"], elbow["axis"], elbow["bearing_body"]) == (
        "clearance_cylindrical",
        [0.0, 1.0, 0.0],
        "arm",
    )
    assert elbow["clearance"] == pytest.approx(1e-4)
    # The ball's socket is the ground: its eccentricity is global, as recorded.
    assert ball["ex"] == pytest.approx(list(run["ball.ex"]), rel=1e-6, abs=1e-15)
    # Plots: each contact point's normal force, the marker's position, the constraint error.
    assert [p["id"] for p in section["plots"]] == [
        "ball.fn",
        "elbow.p1.fn",
        "elbow.p2.fn",
        "elbow.p3.fn",
        "elbow.p4.fn",
        "end.x",
        "end.y",
        "end.z",
        "system.constraint_error",
    ]


def test_tables_count_impacts_per_contact_point(run) -> None:
    section = run_report_data(run)["run"]
    tables = {t["id"]: t for t in section["tables"]}
    assert set(tables) == {"model", "options", "run-statistics", "contact-statistics", "impacts"}
    contacts = ["ball", "elbow.p1", "elbow.p2", "elbow.p3", "elbow.p4"]
    assert [r[0] for r in tables["contact-statistics"]["rows"]] == contacts
    assert [r[1] for r in tables["contact-statistics"]["rows"]] == [
        len(run.impacts[c]) for c in contacts
    ]
    total = sum(len(v) for v in run.impacts.values())
    assert total > 20  # the run shows impacts at both joints
    assert len(tables["impacts"]["rows"]) == total == len(section["impacts"])
    model = dict(map(tuple, tables["model"]["rows"]))
    assert model["gravity [m/s^2]"] == "(0, 0, -9.81)"
    assert model["elbow"].startswith("clearance 0.1 mm")


def test_poses_put_each_pin_centre_at_its_bearing_centre_plus_the_eccentricity(run) -> None:
    """The frames' poses are those of the model frames (the engine records the principal
    frames; the arm's is turned by its inertia's frame, the tip's is its tensor's
    eigenvectors): the journal centre on body j, placed by its pose, lies at the bearing
    centre on body i plus the recorded eccentricity turned from body i's frame. A pose
    left in the principal frame misplaces them by centimetres (the arm's principal
    frame is turned by 0.3 rad about x, its bearing 0.15 m from its centre)."""
    section = run_report_data(run)["run"]
    frames, scene = section["frames"], section["scene"]

    def turn(body: str | None, v: np.ndarray, k: int) -> np.ndarray:
        if body is None:
            return v
        return attitude(np.array([q[k] for q in frames["bodies"][body]["q"]])) @ v

    def place(body: str | None, p: list[float], k: int) -> np.ndarray:
        if body is None:
            return np.asarray(p)
        b = frames["bodies"][body]
        return np.array([b["x"][k], b["y"][k], b["z"][k]]) + turn(body, np.asarray(p), k)

    model = ball_and_hinge_pendulum()
    points = {b["name"]: b["points"] for b in model["bodies"]}
    worst = 0.0
    for c in scene["clearances"]:
        joint = next(j for j in model["joints"] if j["name"] == c["joint"])
        journal = points[joint["body_j"]][joint["point_j"]]
        for k in range(0, len(frames["time"]), 25):
            e = frames["joints"][c["joint"]]
            e_k = np.array([e["ex"][k], e["ey"][k], e["ez"][k]])
            bearing = place(c["bearing_body"], c["point"], k)
            turned = turn(c["bearing_body"], e_k, k)
            gap = np.linalg.norm(bearing + turned - place(joint["body_j"], journal, k))
            worst = max(worst, float(gap))
    # Rounding to 7 digits of positions of 0.4 m: a few 1e-8 m.
    assert worst < 2e-7


def test_principal_frames_as_the_engine_finds_them() -> None:
    # A tensor's frame diagonalises it into right-handed axes near the model axes.
    tensor = np.array([[1e-3, 0.0, 0.0], [0.0, 1e-3, 2e-4], [0.0, 2e-4, 5e-4]])
    axes = principal_frame({"inertia": {"tensor": tensor.tolist()}})
    inner = axes.T @ tensor @ axes
    assert np.abs(inner - np.diag(np.diag(inner))).max() < 1e-15
    assert np.linalg.det(axes) == pytest.approx(1.0)
    assert np.all(np.diag(axes) > 0)
    # A principal frame as given: intrinsic ZYX of (a, 0, 0) is a turn a about z.
    euler = {"euler": {"convention": "ZYX", "angles": [0.4, 0.0, 0.0]}}
    turn = {"axis_angle": {"axis": [0.0, 0.0, 2.0], "angle": 0.4}}
    c, s = np.cos(0.4), np.sin(0.4)
    about_z = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
    assert orientation_matrix(euler) == pytest.approx(about_z)
    assert orientation_matrix(turn) == pytest.approx(about_z)
    half = np.cos(0.2), 0.0, 0.0, np.sin(0.2)
    assert orientation_matrix({"quaternion": list(half)}) == pytest.approx(about_z)
    assert principal_frame({"inertia": {"principal": {"moments": [1, 1, 1]}}}) == (
        pytest.approx(np.eye(3))
    )
    # Intrinsic ZYX (yaw, pitch, roll): R = Rz(yaw) Ry(pitch) Rx(roll).
    y, p, r = 0.2, -0.5, 0.3
    rz = np.array([[np.cos(y), -np.sin(y), 0], [np.sin(y), np.cos(y), 0], [0, 0, 1]])
    ry = np.array([[np.cos(p), 0, np.sin(p)], [0, 1, 0], [-np.sin(p), 0, np.cos(p)]])
    rx = np.array([[1, 0, 0], [0, np.cos(r), -np.sin(r)], [0, np.sin(r), np.cos(r)]])
    zyx = {"euler": {"convention": "ZYX", "angles": [y, p, r]}}
    assert orientation_matrix(zyx) == pytest.approx(rz @ ry @ rx)


def test_one_offline_file_with_plotly_inlined(run, tmp_path) -> None:
    path = write_run_report(run, tmp_path / "spatial.html")
    text = path.read_text(encoding="utf-8")
    assert "plotly.js v" in text  # the script itself, from plotly's wheel
    assert "Content-Security-Policy" in text and "default-src 'none'" in text
    # Nothing is fetched: no element names an address outside the file.
    assert not re.search(r"""<(script|link|img|iframe)[^>]*\s(src|href)\s*=""", text, re.I)
    assert "renderSpatialRun" in text
    # The planar report stays without it.
    planar = dict(run_report_data(run))
    planar["run"] = dict(planar["run"], spatial=False)
    assert "plotly.js v" not in render(planar)


def test_missing_pose_channels_are_named(run) -> None:
    kept = [c for c in run.channels if c != "tip.e2"]
    partial = Result(
        time=run.time,
        channels=kept,
        data=np.vstack([run[c] for c in kept]),
        model=run.model,
        impacts=run.impacts,
        clearances=run.clearances,
    )
    with pytest.raises(ReportError, match=r"tip\.e2"):
        spatial_section(partial)
    with pytest.raises(ReportError, match="dimension"):
        spatial_section(Result(time=run.time, channels=[], data=np.zeros((0, len(run.time)))))


def test_a_saved_spatial_run_reports_in_3d(run, tmp_path) -> None:
    """``jointgap report FOLDER`` on what ``jointgap run`` writes: the same 3D page."""
    from jointgap.report import folder_report_data

    run.save(tmp_path / "run")
    data = folder_report_data(tmp_path / "run")
    assert data["run"]["spatial"] is True
    assert data["run"]["impact_counts"] == {c: len(v) for c, v in run.impacts.items()}
    assert (
        data["run"]["frames"]["bodies"]["tip"]["q"][0]
        == (run_report_data(run)["run"]["frames"]["bodies"]["tip"]["q"][0])
    )


def test_against_the_ideal_run(run) -> None:
    """With the ideal twin: its marker path dashed beside the run's, the plots overlaid,
    and the marker's deviation from its ideal path in the deviation table."""
    ideal = ideal_run()
    section = run_report_data(run, ideal=ideal)["run"]
    paths = [(p["marker"], p["ideal"]) for p in section["scene"]["paths"]]
    assert paths == [("end", False), ("end", True)]
    end_x = next(p for p in section["plots"] if p["id"] == "end.x")
    assert [s["label"] for s in end_x["series"]] == ["clearance", "ideal"]
    deviation = next(t for t in section["tables"] if t["id"] == "deviation")
    rows = {r[0]: r for r in deviation["rows"]}
    assert list(rows) == ["end.x", "end.y", "end.z"]
    for q in "xyz":
        gap = np.abs(run[f"end.{q}"] - ideal[f"end.{q}"])
        assert rows[f"end.{q}"][4] == pytest.approx(float(gap.max()), rel=1e-12)
    # The clearances let the end wander by more than they are wide (a lever), not by
    # the arm's length.
    assert 2e-4 < rows["end.z"][4] < 0.05


def test_a_tensor_with_two_equal_moments_is_flagged() -> None:
    """Its principal axes in the plane of the equal moments are not unique: the page
    says the body may be drawn turned about its symmetry axis."""
    c, s = np.cos(0.3), np.sin(0.3)
    about_x = np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])
    symmetric = about_x @ np.diag([2e-3, 2e-3, 1e-3]) @ about_x.T
    model = ball_and_hinge_pendulum()
    model["bodies"][1]["inertia"] = {"tensor": symmetric.tolist()}
    model["joints"], model["markers"] = [], []  # the bodies alone: poses are all it needs
    names = [f"{b}.{q}" for b in ("arm", "tip") for q in ("x", "y", "z", "e0", "e1", "e2", "e3")]
    data = np.zeros((len(names), 2))
    data[[names.index("arm.e0"), names.index("tip.e0")]] = 1.0
    result = Result(time=[0.0, 0.1], channels=names, data=data, model=model)
    (note,) = spatial_section(result)["scene"]["notes"]
    assert note.startswith("body 'tip': its inertia tensor has two equal principal moments")
    # The test model's tip (three distinct moments) draws without a note.
    model["bodies"][1]["inertia"] = ball_and_hinge_pendulum()["bodies"][1]["inertia"]
    assert spatial_section(result)["scene"]["notes"] == []
