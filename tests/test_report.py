"""The HTML report's data and file, without a browser: what it holds for the founding
case and the two-clearance model, that it is one self-contained file, the command
line (report, run --report, compare's folder), a study folder, the progress line.
The page in a real browser: tests/test_report_browser.py."""

from __future__ import annotations

import io
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from jointgap.cli import EXIT_INVALID, main
from jointgap.cli.progress import ProgressLine, progress_line
from jointgap.report import (
    DEFAULT_MAX_FRAMES,
    ReportError,
    auto_magnify,
    folder_kind,
    folder_report_data,
    frame_indices,
    render,
    run_report_data,
    write,
)
from jointgap.report.encode import minmax_indices, rounded
from jointgap.statistics import contact_statistics
from report_folders import compare_folder, embedded, study_folder
from terminal import in_terminal

pytestmark = pytest.mark.usefixtures("engine")

T_END = 0.5
RATE = 10_000


@pytest.fixture(scope="module")
def founding():
    """The founding case and its ideal twin, 0.5 s at 10 kHz (as make demo runs them)."""
    import jointgap

    root = Path(__file__).resolve().parent.parent / "examples"
    clearance = jointgap.load(root / "slider_crank_clearance.toml").simulate(T_END, rate=RATE)
    ideal = jointgap.load(root / "slider_crank_ideal.toml").simulate(T_END, rate=RATE)
    return clearance, ideal


def table(data: dict, id: str) -> dict:
    return next(t for t in data["run"]["tables"] if t["id"] == id)


# ---------------------------------------------------------------- founding case


def test_founding_report_holds_orbit_acceleration_and_every_impact(founding) -> None:
    result, ideal = founding
    data = run_report_data(result, ideal=ideal, source="examples/slider_crank_clearance.toml")
    run = data["run"]
    n = len(result.impacts["rod_slider"])
    assert n == 21  # the founding case at the default tolerances (README, tutorial)
    impacts = table(data, "impacts")
    assert len(impacts["rows"]) == n
    assert [row[2] for row in impacts["rows"]] == [
        pytest.approx(i.onset_time, rel=1e-6) for i in result.impacts["rod_slider"]
    ]
    assert run["impact_counts"] == {"rod_slider": n}
    assert len(run["impacts"]) == n
    # The acceleration plot: clearance and ideal, every sample (5001 < the point limit).
    ax = next(p for p in run["plots"] if p["id"] == "slider.ax")
    assert [s["label"] for s in ax["series"]] == ["clearance", "ideal"]
    assert ax["markers"] and ax["time"]
    assert ax["series"][0]["x"] == "run" and len(run["times"]["run"]) == len(result.time)
    assert max(ax["series"][0]["y"]) == pytest.approx(float(result["slider.ax"].max()), rel=1e-6)
    assert min(ax["series"][0]["y"]) == pytest.approx(float(result["slider.ax"].min()), rel=1e-6)
    # The orbit: the journal centre in the 0.5 mm clearance circle.
    (orbit,) = run["orbits"]
    assert orbit["joint"] == "rod_slider"
    assert orbit["clearance"] == pytest.approx(0.5e-3)
    assert len(orbit["ex"]) == len(result.time)
    assert max(math.hypot(x, y) for x, y in zip(orbit["ex"], orbit["ey"], strict=True)) == (
        pytest.approx(float(np.hypot(result["rod_slider.ex"], result["rod_slider.ey"]).max()))
    )
    # Contact statistics as jointgap.statistics computes them.
    (stats,) = contact_statistics(result)
    (row,) = table(data, "contact-statistics")["rows"]
    assert row[:2] == ["rod_slider", n]
    assert row[5] == pytest.approx(stats.peak_force)
    assert row[6] == pytest.approx(1e6 * stats.max_penetration)
    assert {t["id"] for t in run["tables"]} == {
        "model",
        "options",
        "run-statistics",
        "contact-statistics",
        "impacts",
        "deviation",
    }


def test_animation_frames_and_magnified_clearance(founding) -> None:
    result, ideal = founding
    run = run_report_data(result, ideal=ideal)["run"]
    frames = run["frames"]
    assert len(frames["time"]) == min(len(result.time), DEFAULT_MAX_FRAMES) == 5001
    assert set(frames["bodies"]) == {"crank", "rod", "slider"}
    assert frames["bodies"]["slider"]["x"][100] == pytest.approx(result["slider.x"][100])
    assert set(frames["ideal"]) == {"crank", "rod", "slider"}
    scene = run["scene"]
    # Drawing about 0.53 m wide: 2 % is 10.6 mm, so a 0.5 mm clearance drawn 20 times.
    assert scene["magnify"] == 20.0
    (c,) = scene["clearances"]
    assert (c["bearing_body"], c["journal_body"], c["point"]) == ("slider", "rod", [0.0, 0.0])
    assert c["drawn_bearing_radius"] - c["drawn_journal_radius"] == pytest.approx(20 * 0.5e-3)
    shapes = {b["name"]: b["shapes"][0]["type"] for b in scene["bodies"]}
    assert shapes == {"crank": "bar", "rod": "bar", "slider": "block"}
    rod = next(b for b in scene["bodies"] if b["name"] == "rod")
    assert rod["shapes"][0]["from"] == [-0.16, 0.0] and rod["shapes"][0]["width"] == 0.015
    assert run_report_data(result, magnify=50)["run"]["scene"]["magnify"] == 50.0


def test_page_is_one_self_contained_file(founding, tmp_path) -> None:
    result, ideal = founding
    path = write(run_report_data(result, ideal=ideal), tmp_path / "report.html")
    page = path.read_text(encoding="utf-8")
    size = path.stat().st_size
    assert 0.5e6 < size < 4e6, f"{size / 1e6:.2f} MB"
    # Nothing to fetch: no external script, style sheet, image or font, and a policy
    # that forbids any request anyway.
    assert "default-src 'none'" in page
    assert not re.search(r"<(link|iframe|object|embed)\b", page)
    assert not re.search(r"""\bsrc\s*=\s*["'](?!data:)""", page)
    assert not re.search(r"\b(fetch|XMLHttpRequest|WebSocket|importScripts)\s*\(", page)
    assert "@import" not in page and "url(" not in page
    assert page.count("<script") == 3  # data, plots, report
    data = embedded(page)
    assert data["title"] == "slider_crank_clearance: clearance against ideal"
    assert len(table(data, "impacts")["rows"]) == len(result.impacts["rod_slider"])


def test_text_cannot_end_the_script_early(founding) -> None:
    result, _ = founding
    data = run_report_data(result)
    data["title"] = "a </script><script>alert(1)</script> & more"
    page = render(data)
    assert page.count("</script>") == 3
    assert embedded(page)["title"] == data["title"]
    assert "<title>a &lt;/script&gt;" in page


def test_two_clearance_joints_are_both_drawn(tmp_path) -> None:
    import jointgap

    root = Path(__file__).resolve().parent.parent / "examples"
    result = jointgap.load(root / "slider_crank_two_clearances.toml").simulate(0.15, rate=5000)
    run = run_report_data(result)["run"]
    joints = ["crank_rod", "rod_slider"]
    assert [c["joint"] for c in run["scene"]["clearances"]] == joints
    assert [o["joint"] for o in run["orbits"]] == joints
    assert sorted(run["frames"]["joints"]) == joints
    counts = {j: len(result.impacts[j]) for j in joints}
    assert run["impact_counts"] == counts and min(counts.values()) > 0
    rows = next(t for t in run["tables"] if t["id"] == "impacts")["rows"]
    assert {j: sum(r[0] == j for r in rows) for j in joints} == counts
    assert [p["id"] for p in run["plots"] if p["id"].endswith(".fn")] == [
        "crank_rod.fn",
        "rod_slider.fn",
    ]


def test_result_without_pose_channels_names_them(founding) -> None:
    import jointgap

    root = Path(__file__).resolve().parent.parent / "examples"
    model = jointgap.load(root / "slider_crank_clearance.toml")
    result = model.simulate(0.05, rate=1000, channels=["slider.*", "rod_slider.*"])
    with pytest.raises(ReportError, match=r"crank\.x, crank\.y, crank\.angle"):
        run_report_data(result)


# ---------------------------------------------------------------- helpers


def test_minmax_decimation_keeps_every_peak() -> None:
    rng = np.random.default_rng(1)
    values = rng.normal(size=200_000)
    values[123_457] = 50.0
    values[7] = -60.0
    keep = minmax_indices(values, 2000)
    assert len(keep) <= 2002
    assert np.all(np.diff(keep) > 0)
    assert 123_457 in keep and 7 in keep and keep[0] == 0 and keep[-1] == len(values) - 1
    assert np.array_equal(minmax_indices(values[:100], 2000), np.arange(100))


def test_frame_indices_are_even_in_time() -> None:
    time = np.linspace(0.0, 1.0, 100_001)
    k = frame_indices(time, 1001)
    assert len(k) == 1001 and k[0] == 0 and k[-1] == 100_000
    assert np.allclose(np.diff(time[k]), 0.001)
    assert np.array_equal(frame_indices(time[:50], 1001), np.arange(50))
    with pytest.raises(ReportError, match="at least 2"):
        frame_indices(time, 1)


def test_auto_magnify_is_a_round_factor() -> None:
    assert auto_magnify(0.5e-3, 0.53) == 20.0  # 21.2 -> 20
    assert auto_magnify(1e-4, 1.0) == 200.0
    assert auto_magnify(0.1, 1.0) == 1.0  # never shrinks
    assert auto_magnify(0.0, 1.0) == 1.0


def test_rounded_keeps_seven_digits_and_nulls() -> None:
    assert rounded([1.23456789, math.nan, -math.inf, 0.0]) == [1.234568, None, None, 0.0]


# ---------------------------------------------------------------- command line


def test_run_with_report(examples, tmp_path, capsys) -> None:
    out = tmp_path / "run"
    status = main(
        [
            "run",
            str(examples / "slider_crank_clearance.toml"),
            "--t-end",
            "0.1",
            "--rate",
            "2000",
            "--out",
            str(out),
            "--ideal",
            str(examples / "slider_crank_ideal.toml"),
            "--report",
        ]
    )
    assert status == 0
    assert str(out / "report.html") in capsys.readouterr().out
    data = embedded((out / "report.html").read_text(encoding="utf-8"))
    assert data["kind"] == "comparison" and data["run"]["frames"]["ideal"]
    model = table(data, "model")
    assert ["file", str(examples / "slider_crank_clearance.toml")] in model["rows"]
    # The folder gives the same report again, ideal/ included.
    assert main(["report", str(out), "--out", str(tmp_path / "again.html")]) == 0
    again = embedded((tmp_path / "again.html").read_text(encoding="utf-8"))
    assert again["run"]["impact_counts"] == data["run"]["impact_counts"]
    assert len(again["run"]["frames"]["time"]) == len(data["run"]["frames"]["time"]) == 201
    # --report FILE puts it elsewhere.
    elsewhere = tmp_path / "elsewhere" / "r.html"
    args = ["run", str(examples / "pendulum.toml"), "--t-end", "0.1", "--rate", "1000"]
    assert main([*args, "--out", str(tmp_path / "p"), "--report", str(elsewhere)]) == 0
    assert elsewhere.exists() and not (tmp_path / "p" / "report.html").exists()


def test_report_of_a_model_file(examples, tmp_path, capsys) -> None:
    out = tmp_path / "m.html"
    model = str(examples / "slider_crank_clearance.toml")
    args = ["report", model, "--t-end", "0.05", "--rate", "1000", "--out", str(out)]
    assert main([*args, "--magnify", "10", "--max-frames", "11"]) == 0
    assert re.search(r"written +.*m\.html \(\d+\.\d\d MB\)", capsys.readouterr().out)
    data = embedded(out.read_text(encoding="utf-8"))
    assert data["run"]["scene"]["magnify"] == 10.0
    assert len(data["run"]["frames"]["time"]) == 11
    assert main(["report", model, "--out", str(out)]) == EXIT_INVALID
    assert "--t-end is needed" in capsys.readouterr().err


def test_report_of_a_folder_that_holds_no_results(tmp_path, capsys) -> None:
    (tmp_path / "notes.txt").write_text("nothing\n")
    assert main(["report", str(tmp_path)]) == EXIT_INVALID
    err = capsys.readouterr().err
    assert str(tmp_path) in err and "not a results folder" in err
    with pytest.raises(ReportError, match="no such folder"):
        folder_kind(tmp_path / "missing")


def test_run_report_without_pose_channels_is_a_warning(examples, tmp_path, capsys) -> None:
    args = ["run", str(examples / "slider_crank_clearance.toml"), "--t-end", "0.02"]
    status = main([*args, "--out", str(tmp_path), "--channel", "slider.*", "--report"])
    assert status == 0
    assert "warning    no report: the animation needs the channels crank.x" in (
        capsys.readouterr().out
    )
    assert (tmp_path / "results.csv").exists() and not (tmp_path / "report.html").exists()


def test_report_of_a_comparison_with_a_measurement(examples, tmp_path, capsys) -> None:
    out = compare_folder(examples, tmp_path)
    for name in ("comparison.json", "measured.csv", "simulation/summary.json", "report.html"):
        assert (out / name).exists(), name
    assert folder_kind(out) == "comparison"
    saved = json.loads((out / "comparison.json").read_text())
    data = folder_report_data(out)
    assert data["title"] == "slider_crank_clearance: simulation against measurement"
    cmp = data["comparison"]
    # The comparison drawn again from simulation/ and measured.csv is the one compare made.
    for key, value in saved["measures"].items():
        assert cmp["measures"][key] == pytest.approx(value, rel=1e-9), key
    assert [p["id"] for p in cmp["plots"]] == [
        "comparison-signals",
        "comparison-difference",
        "comparison-spectra",
    ]
    assert [s["label"] for s in cmp["plots"][0]["series"]] == ["simulated", "measured"]
    assert data["run"]["impact_counts"]["rod_slider"] > 0
    written = embedded((out / "report.html").read_text(encoding="utf-8"))
    assert written["comparison"]["measures"] == pytest.approx(cmp["measures"])
    # Without the run beside it (an older compare folder), the message says what to do.
    (out / "measured.csv").unlink()
    with pytest.raises(ReportError, match="without measured.csv: run 'jointgap compare' again"):
        folder_report_data(out)


def test_report_of_a_study_folder(tmp_path) -> None:
    folder = study_folder(tmp_path)
    assert folder_kind(folder) == "study"
    assert main(["report", str(folder)]) == 0
    data = embedded((folder / "report.html").read_text(encoding="utf-8"))
    assert data["kind"] == "study" and data["run"] is None
    study = data["study"]
    assert study["n_cases"] == 6 and study["n_failed"] == 1
    cases = study["cases"]
    assert len(cases["rows"]) == 6 and cases["sortable"]
    assert cases["columns"][:5] == [
        "case",
        "rod_slider.clearance",
        "motor.speed",
        "slider.ax.max_abs",
        "impacts",
    ]
    assert cases["row_classes"] == ["", "", "", "", "failed", ""]
    assert cases["rows"][4][3] is None  # a failed case's metric: null, not NaN
    # 2 metrics x 2 parameters, each over the 5 finished cases.
    assert len(study["plots"]) == 4
    assert all(len(p["series"][0]["x"]) == 5 for p in study["plots"])
    (figure,) = study["figures"]
    assert figure["src"].startswith("data:image/png;base64,")


def test_report_of_a_study_run_by_jointgap_study(examples, tmp_path) -> None:
    study_file = tmp_path / "tiny.toml"
    study_file.write_text(
        f"""
[study]
name = "tiny"
model = "{(examples / "slider_crank_clearance.toml").as_posix()}"
t_end = "0.05 s"
rate = "2 kHz"

[parameters]
"rod_slider.clearance" = {{ from = "0.25 mm", to = "0.5 mm", steps = 2 }}
"motor.speed" = {{ from = "200 rpm", to = "300 rpm", step = "100 rpm" }}

[metrics]
impacts = "impacts"
peak_slider_acceleration = {{ stat = "peak", channel = "slider.ax" }}
"""
    )
    out = tmp_path / "study"
    assert main(["study", str(study_file), "--out", str(out), "--workers", "1"]) == 0
    assert main(["study-plot", str(out)]) == 0
    assert main(["report", str(out), "--out", str(tmp_path / "study.html")]) == 0
    study = embedded((tmp_path / "study.html").read_text(encoding="utf-8"))["study"]
    import pandas as pd

    cases = pd.read_csv(out / "cases.csv")
    assert study["n_cases"] == len(cases) == 4 and study["n_failed"] == 0
    table = study["cases"]
    assert table["columns"][:3] == ["case", "rod_slider.clearance [m]", "motor.speed [rad/s]"]
    k = table["columns"].index("impacts")
    assert [row[k] for row in table["rows"]] == cases["impacts"].tolist()
    assert len(study["plots"]) == 4  # 2 metrics x 2 parameters
    assert len(study["figures"]) == len(list((out / "figures").glob("*.png"))) > 0


def test_study_folder_missing_a_column(tmp_path) -> None:
    folder = study_folder(tmp_path)
    info = json.loads((folder / "study.json").read_text())
    info["metrics"].append("torque.max")
    (folder / "study.json").write_text(json.dumps(info))
    with pytest.raises(ReportError, match=r"cases\.csv: no column 'torque\.max'"):
        folder_report_data(folder)


# ---------------------------------------------------------------- progress line


class Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_line_on_a_terminal_only() -> None:
    screen = Terminal()
    with progress_line("0.5 s", stream=screen) as progress:
        assert isinstance(progress, ProgressLine)
        progress(0.125, 1200, 3)
        progress(0.25, 2400, 1)
    text = screen.getvalue()
    assert "\rt = 0.125 / 0.5 s ( 25.0 %), 1200 steps, 3 impacts" in text
    assert "\rt = 0.25 / 0.5 s ( 50.0 %), 2400 steps, 1 impact" in text
    assert text.endswith("\r")  # erased at the end: the summary stands alone
    with progress_line("0.5 s", stream=io.StringIO()) as progress:
        assert progress is None


def test_progress_line_follows_a_run(examples, monkeypatch) -> None:
    import jointgap

    monkeypatch.setenv("JOINTGAP_PROGRESS_INTERVAL", "0")  # a report every 16 steps
    model = jointgap.load(examples / "slider_crank_clearance.toml")
    screen = Terminal()
    line = ProgressLine(0.5, screen)
    seen: list[tuple[float, int, int]] = []

    def progress(t: float, steps: int, impacts: int) -> None:
        seen.append((t, steps, impacts))
        line(t, steps, impacts)

    result = model.simulate(0.5, rate=1000, progress=progress)
    assert result.ok
    assert len(seen) == result.stats["accepted_steps"] // 16
    for (t0, s0, i0), (t1, s1, i1) in zip(seen, seen[1:], strict=False):
        assert t1 >= t0 and s1 >= s0 and i1 >= i0
    assert 0 < seen[-1][2] <= len(result.impacts["rod_slider"])
    assert "steps" in screen.getvalue()


def test_cli_progress_line_in_a_terminal_and_not_in_a_pipe(examples, tmp_path) -> None:
    # A report every 16 steps, however fast the machine: several progress lines.
    model = str(examples / "slider_crank_two_clearances.toml")
    done = in_terminal("run", model, "--t-end", "1", "--rate", "1000", "--out", str(tmp_path))
    assert done.returncode == 0
    lines = re.findall(
        r"\rt = ([0-9.e-]+) / 1 s \( *[0-9.]+ %\), (\d+) steps, (\d+) impacts?", done.screen
    )
    assert len(lines) > 2, done.screen
    times = [float(t) for t, _, _ in lines]
    assert times == sorted(times) and 0 < times[-1] <= 1.0
    assert done.screen.endswith("\r")  # erased before the summary
    assert "\r" not in done.stdout and "model      slider_crank_two_clearances" in done.stdout


def test_a_body_whose_shape_misses_its_joint_is_linked_to_it(examples) -> None:
    """The pendulum's bob is a disk at the end of an undrawn rod: a line from its centre
    to the hinge shows what holds it, and the drawing's extent takes in the pivot."""
    import jointgap

    result = jointgap.load(examples / "pendulum.toml").simulate(0.5, rate=100)
    scene = run_report_data(result)["run"]["scene"]
    (bob,) = scene["bodies"]
    assert bob["shapes"][0]["type"] == "disk"
    assert bob["links"] == [[-1.0, 0.0]]  # the point 'pivot', 1 m behind the centre
    (pivot,) = scene["ground"]["pins"]
    x0, y0, x1, y1 = scene["bounds"]
    assert x0 <= pivot[0] <= x1 and y0 <= pivot[1] <= y1
