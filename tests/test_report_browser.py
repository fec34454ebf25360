"""The HTML report in a real browser (headless Chromium over the DevTools protocol,
tests/browser.py): it opens offline with no console error and no network request, the
animation moves when played, the time slider moves the plots' cursor, a click on a
plot or an impact moves the animation; screenshots go to test-artifacts/.

Chromium is Debian's ``chromium`` package, which ``make test`` installs when missing;
these tests are skipped without it, unless JOINTGAP_REQUIRE_BROWSER=1 (``make test``
sets it), when they fail."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np
import pytest
from browser import Browser, BrowserError, Page, find_chromium
from jointgap.report import write_folder_report, write_run_report
from report_folders import compare_folder, study_folder
from spatial_reports import spatial_run

pytestmark = pytest.mark.usefixtures("engine")

ROOT = Path(__file__).resolve().parent.parent
ARTIFACTS = ROOT / "test-artifacts"


@pytest.fixture(scope="module")
def browser():
    if find_chromium() is None:
        message = "no Chromium: apt-get install chromium (make test does)"
        if os.environ.get("JOINTGAP_REQUIRE_BROWSER") == "1":
            pytest.fail(message)
        pytest.skip(message)
    with Browser() as b:
        yield b


@pytest.fixture(scope="module")
def reports(tmp_path_factory):
    """Reports of the founding case (against its ideal twin, 0.5 s at 10 kHz, as make
    demo draws it) and of the two-clearance slider-crank, with their results."""
    import jointgap

    folder = tmp_path_factory.mktemp("reports")
    examples = ROOT / "examples"
    founding = jointgap.load(examples / "slider_crank_clearance.toml").simulate(0.5, rate=10_000)
    ideal = jointgap.load(examples / "slider_crank_ideal.toml").simulate(0.5, rate=10_000)
    two = jointgap.load(examples / "slider_crank_two_clearances.toml").simulate(0.2, rate=5000)
    return {
        "founding": (write_run_report(founding, folder / "founding.html", ideal=ideal), founding),
        "two": (write_run_report(two, folder / "two.html"), two),
    }


@pytest.fixture(scope="module")
def spatial_report(tmp_path_factory):
    """The 3D report of a spatial run (tests/spatial_reports.py), with its result."""
    result = spatial_run()
    return write_run_report(result, tmp_path_factory.mktemp("spatial") / "spatial.html"), result


def open_clean(browser: Browser, path: Path) -> Page:
    """Opens a report, waits until it has drawn itself, and checks that it logged no
    error and asked the network for nothing but its own file."""
    page = browser.open(path.resolve().as_uri())
    page.wait_for("document.body.dataset.ready === 'true'")
    assert page.console_errors == []
    requests = [u for u in page.requests if not u.startswith("data:")]
    assert requests == [path.resolve().as_uri()]
    return page


def js(page: Page, expression: str):
    return page.evaluate(expression)


def set_slider(page: Page, frame: int) -> None:
    js(
        page,
        f"(() => {{ const s = document.getElementById('time-slider'); s.value = '{frame}';"
        " s.dispatchEvent(new Event('input')); })()",
    )


CURSOR = "document.querySelector('[data-plot=\"slider.ax\"] .jg-cursor')"


def test_founding_report_opens_offline_and_shows_everything(browser, reports) -> None:
    path, result = reports["founding"]
    page = open_clean(browser, path)  # asks the network for nothing: opens offline
    n = len(result.impacts["rod_slider"])
    assert js(page, "document.querySelectorAll('#impacts tbody tr').length") == n
    assert js(page, "document.querySelectorAll('#impacts tbody tr[data-time]').length") == n
    assert js(page, "!!document.getElementById('orbit-rod_slider')")
    assert js(page, "!!document.getElementById('orbit-marker-rod_slider')")
    assert js(page, "!!document.querySelector('[data-plot=\"slider.ax\"] canvas')")
    assert js(page, "!!document.getElementById('journal-rod_slider')")
    for body in ("crank", "rod", "slider"):
        assert js(page, f"!!document.getElementById('body-{body}')"), body
        assert js(page, f"!!document.getElementById('ghost-{body}')"), body
    assert js(page, "document.getElementById('contact-statistics').textContent").count("rod_slider")
    set_slider(page, 4000)  # t = 0.4 s: the slider at the inner dead centre
    shot = page.screenshot(ARTIFACTS / "report_founding_case.png")
    assert shot.stat().st_size > 50_000
    page.close()


def test_animation_advances_when_played(browser, reports) -> None:
    path, _ = reports["founding"]
    page = open_clean(browser, path)
    read = (
        "[document.getElementById('body-rod').getAttribute('transform'),"
        " document.getElementById('journal-rod_slider').getAttribute('cx'),"
        " document.getElementById('orbit-marker-rod_slider').getAttribute('cy'),"
        " Number(document.getElementById('time-slider').value)]"
    )
    before = js(page, read)
    assert before[3] == 0
    js(page, "document.getElementById('play').click()")
    page.wait_for("Number(document.getElementById('time-slider').value) > 50")
    after = js(page, read)
    js(page, "document.getElementById('play').click()")  # pause
    assert after[0] != before[0]  # the rod moved
    assert after[1] != before[1]  # and its journal with it
    assert after[3] > before[3]
    assert js(page, "document.getElementById('play').textContent") == "▶ play"
    paused = js(page, "document.getElementById('time-slider').value")
    page.animation_frames(30)  # playing, these would move the slider
    assert js(page, "document.getElementById('time-slider').value") == paused
    page.close()


def test_time_slider_moves_the_plot_cursor(browser, reports) -> None:
    path, result = reports["founding"]
    page = open_clean(browser, path)
    start = js(page, f"parseFloat({CURSOR}.style.left)")
    set_slider(page, 2500)
    moved = js(page, f"parseFloat({CURSOR}.style.left)")
    t = float(result.time[2500])
    assert moved > start
    # The cursor sits at t = 0.25 s on the plot's time axis (every plot alike).
    expected = js(
        page,
        f"(() => {{ const r = document.querySelector('[data-plot=\"slider.ax\"] canvas')"
        f".getBoundingClientRect(); return (r.width - 66 - 14) * ({t} - 0) / 0.5 + 66; }})()",
    )
    assert moved == pytest.approx(expected, abs=1.0)
    lefts = js(page, "[...document.querySelectorAll('.jg-cursor')].map(c => c.style.left)")
    assert len(lefts) == 6 and len(set(lefts)) == 1
    assert js(page, "document.getElementById('time-readout').textContent").startswith(
        "t = 0.25000 s"
    )
    page.close()


def test_clicks_on_a_plot_and_an_impact_move_the_animation(browser, reports) -> None:
    path, result = reports["founding"]
    page = open_clean(browser, path)
    box = js(
        page,
        "(() => { const a = document.querySelector('[data-plot=\"slider.ax\"] .jg-plot-area');"
        " a.scrollIntoView(); const r = a.getBoundingClientRect();"
        " return [r.left, r.top, r.width, r.height]; })()",
    )
    x = box[0] + 66 + 0.6 * (box[2] - 80)  # 60 % along the time axis: t = 0.3 s
    y = box[1] + box[3] / 2
    for kind in ("mousePressed", "mouseReleased"):
        page.send(
            "Input.dispatchMouseEvent",
            {"type": kind, "x": x, "y": y, "button": "left", "clickCount": 1},
        )
    frame = js(page, "Number(document.getElementById('time-slider').value)")
    assert frame == pytest.approx(3000, abs=3)
    # A row of the impact list: the animation goes to that impact's onset.
    onset = result.impacts["rod_slider"][12].onset_time
    js(page, "document.querySelectorAll('#impacts tbody tr')[12].click()")
    frame = js(page, "Number(document.getElementById('time-slider').value)")
    assert result.time[frame] == pytest.approx(onset, abs=0.5 / 10_000)
    page.close()


def test_two_clearance_joints_are_both_shown(browser, reports) -> None:
    path, result = reports["two"]
    page = open_clean(browser, path)
    for joint in ("crank_rod", "rod_slider"):
        assert js(page, f"!!document.getElementById('journal-{joint}')"), joint
        assert js(page, f"!!document.getElementById('orbit-{joint}')"), joint
        rows = js(
            page,
            "[...document.querySelectorAll('#impacts tbody tr')]"
            f".filter(r => r.cells[0].textContent === '{joint}').length",
        )
        assert rows == len(result.impacts[joint])
    set_slider(page, 600)
    page.screenshot(ARTIFACTS / "report_two_clearances.png")
    page.close()


def test_comparison_and_study_reports_open_cleanly(browser, examples, tmp_path) -> None:
    compared = compare_folder(examples, tmp_path)
    page = open_clean(browser, compared / "report.html")
    for plot in ("comparison-signals", "comparison-difference", "comparison-spectra"):
        assert js(page, f"!!document.querySelector('[data-plot=\"{plot}\"]')"), plot
    assert js(page, "document.getElementById('comparison-measures').rows.length") == 7
    set_slider(page, 1200)
    cursor = "document.querySelector('[data-plot=\"comparison-signals\"] .jg-cursor')"
    assert js(page, f"{cursor}.style.display") == "block"
    page.screenshot(ARTIFACTS / "report_comparison.png")
    page.close()

    folder = study_folder(tmp_path)
    report = write_folder_report(folder)
    page = open_clean(browser, report)
    assert js(page, "document.querySelectorAll('#cases tbody tr').length") == 6
    assert js(page, "document.querySelectorAll('#cases tbody tr.failed').length") == 1
    assert js(page, "document.querySelectorAll('.jg-plot canvas').length") == 4
    assert js(page, "document.querySelectorAll('.jg-figure img').length") == 1
    # Sorting by a metric: finished cases in order, the failed one (null) last.
    js(page, "document.querySelectorAll('#cases th')[3].click()")
    column = js(
        page, "[...document.querySelectorAll('#cases tbody tr')].map(r => r.cells[3].textContent)"
    )
    values = [float(v) for v in column[:5]]
    assert values == sorted(values) and column[5] == "-"
    page.screenshot(ARTIFACTS / "report_study.png")
    page.close()
    info = json.loads((folder / "study.json").read_text())
    assert info["n_cases"] == 6


MECHANISM_3D = "document.getElementById('mechanism-3d')"


def drawn(page: Page, frame: int) -> None:
    """Waits until every 3D view shows ``frame`` (each says so once plotly has drawn it)."""
    page.wait_for(
        "[...document.querySelectorAll('#mechanism-3d, .jg-orbit-3d')]"
        f".every(v => v.dataset.frame === '{frame}')"
    )


def test_spatial_report_draws_in_3d_and_animates(browser, spatial_report) -> None:
    path, result = spatial_report
    page = open_clean(browser, path)  # plotly inlined: nothing fetched, nothing logged
    # plotly's WebGL scenes: the mechanism and one orbit per clearance joint.
    assert js(page, f"{MECHANISM_3D}.querySelectorAll('canvas').length") > 0
    names = js(page, f"{MECHANISM_3D}.data.map(t => t.name)")
    assert names[:2] == ["arm", "tip"] and "end path" in names and "joints" in names
    for joint in ("ball", "elbow"):
        orbit = f"document.getElementById('orbit-{joint}')"
        assert js(page, f"{orbit}.querySelectorAll('canvas').length") > 0, joint
        assert js(page, f"{orbit}.data.map(t => t.type)") == ["surface", "scatter3d", "scatter3d"]
    drawn(page, 0)
    read = (
        f"[{MECHANISM_3D}.data[1].x.slice(), {MECHANISM_3D}.data[1].z.slice(),"
        " document.getElementById('orbit-elbow').data[2].x[0],"
        " Number(document.getElementById('time-slider').value)]"
    )
    before = js(page, read)
    assert before[3] == 0
    js(page, "document.getElementById('play').click()")
    page.wait_for("Number(document.getElementById('time-slider').value) > 100")
    js(page, "document.getElementById('play').click()")  # pause
    frame = js(page, "Number(document.getElementById('time-slider').value)")
    drawn(page, frame)  # the views catch up with the last frame asked for
    after = js(page, read)
    assert after[3] == frame > before[3]
    assert after[0] != before[0] and after[1] != before[1]  # the tip swung
    assert after[2] != before[2]  # and the journal moved in its bearing
    # The tip's sticks as drawn: its pose (model frame) applied to its points.
    tip = result.model["bodies"][1]
    k = frame
    x = np.array(after[0]), np.array(after[1])
    assert x[0][-1] == pytest.approx(float(result["end.x"][k]), abs=1e-6)
    assert x[1][-1] == pytest.approx(float(result["end.z"][k]), abs=1e-6)
    assert len(x[0]) == len(tip["points"])
    page.screenshot(ARTIFACTS / "report_spatial.png")
    page.close()


def test_spatial_impact_row_moves_the_3d_views(browser, spatial_report) -> None:
    path, result = spatial_report
    page = open_clean(browser, path)
    onset = result.impacts["elbow.p1"][5].onset_time
    row = js(
        page,
        "[...document.querySelectorAll('#impacts tbody tr')]"
        ".findIndex(r => r.cells[0].textContent === 'elbow.p1' && r.cells[1].textContent === '6')",
    )
    js(page, f"document.querySelectorAll('#impacts tbody tr')[{row}].click()")
    frame = js(page, "Number(document.getElementById('time-slider').value)")
    assert result.time[frame] == pytest.approx(onset, abs=0.5 / 5000)
    drawn(page, frame)
    page.close()


def test_browser_reports_script_errors(browser, tmp_path) -> None:
    """The check itself: a page that throws is caught."""
    bad = tmp_path / "bad.html"
    bad.write_text("<html><body><script>undefinedFunction();</script></body></html>")
    page = browser.open(bad.resolve().as_uri())
    assert any("undefinedFunction" in e for e in page.wait_for_console_error())
    with pytest.raises(BrowserError, match="nope"):
        page.evaluate("(() => { throw new Error('nope'); })()")
    page.close()
