"""The paper's figures (jointgap.plots): files, axes, labels and series, checked on the
matplotlib objects, not on pixels."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import matplotlib as mpl
import numpy as np
import pytest
from jointgap import plots
from jointgap.results import Result
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from matplotlib.patches import Circle
from matplotlib.text import Text

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
T_END = 0.3  # [s]: two slider strokes with impacts, after the 0.2 s speed ramp
RATE = 10_000  # [Hz]
JOINT = "rod_slider"
SLIDER_FIGURES = {
    "slider_displacement": ("slider.x", "slider displacement [mm]", 1000.0),
    "slider_velocity": ("slider.vx", "slider velocity [m/s]", 1.0),
    "slider_acceleration": ("slider.ax", "slider acceleration [m/s$^2$]", 1.0),
    "motor_torque": ("motor.torque", "motor torque [N m]", 1.0),
}
STEMS = {*SLIDER_FIGURES, "figure", f"contact_force_{JOINT}", f"orbit_{JOINT}"}


def _simulate(name: str, t_end: float = T_END, rate: float = RATE, **options: object) -> Result:
    pytest.importorskip("jointgap._jointgap", reason="the engine is not built: run make install")
    import jointgap

    return jointgap.load(EXAMPLES / name).simulate(t_end=t_end, rate=rate, **options)


@pytest.fixture(scope="module")
def clearance() -> Result:
    return _simulate("slider_crank_clearance.toml")


@pytest.fixture(scope="module")
def ideal() -> Result:
    return _simulate("slider_crank_ideal.toml")


@pytest.fixture(scope="module")
def pendulum() -> Result:
    return _simulate("pendulum.toml", t_end=0.5, rate=200)


@pytest.fixture(scope="module")
def figures(clearance: Result, ideal: Result) -> dict[str, Figure]:
    return plots.figure_set(clearance, ideal)


@pytest.fixture(scope="module")
def written(figures: dict[str, Figure], tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    """The figure set as PNG and SVG (this also draws every figure)."""
    return plots.save_figures(figures, tmp_path_factory.mktemp("figures"))


def _line(fig: Figure, label: str) -> Line2D:
    (line,) = [x for x in fig.axes[0].lines if x.get_label() == label]
    return line


def test_figure_set_writes_every_figure_as_png_and_svg(written: list[Path], engine) -> None:
    assert {p.name for p in written} == {f"{s}.{f}" for s in STEMS for f in ("png", "svg")}
    for path in written:
        head = path.read_bytes()[:100]
        if path.suffix == ".png":
            assert head.startswith(b"\x89PNG")
            assert path.stat().st_size > 10_000
        else:
            assert head.lstrip().startswith(b"<?xml")


def test_svg_files_carry_no_date(written: list[Path], engine) -> None:
    svg = next(p for p in written if p.name == "figure.svg").read_text()
    assert "<dc:date>" not in svg


def test_save_figure_writes_the_overview(pendulum: Result, tmp_path: Path, engine) -> None:
    paths = plots.save_figure(pendulum, tmp_path)
    assert paths == [tmp_path / "figure.png", tmp_path / "figure.svg"]
    assert all(p.stat().st_size > 0 for p in paths)
    paths = plots.save_figure(pendulum, tmp_path, "overview", formats=("pdf",))
    assert paths == [tmp_path / "overview.pdf"]
    assert paths[0].read_bytes().startswith(b"%PDF")
    with pytest.raises(ValueError, match="unknown figure format 'jpg'"):
        plots.save_figure(pendulum, tmp_path, formats=("png", "jpg"))


@pytest.mark.parametrize("stem", sorted(SLIDER_FIGURES))
def test_time_series_overlay_ideal_and_clearance(
    figures: dict[str, Figure], clearance: Result, ideal: Result, stem: str, engine
) -> None:
    channel, ylabel, scale = SLIDER_FIGURES[stem]
    fig = figures[stem]
    (ax,) = fig.axes
    assert ax.get_xlabel() == "time [s]"
    assert ax.get_ylabel() == ylabel
    assert [line.get_label() for line in ax.lines] == ["clearance", "ideal"]
    for label, result in (("clearance", clearance), ("ideal", ideal)):
        line = _line(fig, label)
        np.testing.assert_array_equal(line.get_xdata(), result.time)
        np.testing.assert_allclose(line.get_ydata(), scale * result[channel], rtol=1e-15)
    assert _line(fig, "ideal").get_linestyle() == "--"  # the ideal run dashed, on top
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == ["clearance", "ideal"]


def test_contact_force_figure(
    figures: dict[str, Figure], clearance: Result, ideal: Result, engine
) -> None:
    fig = figures[f"contact_force_{JOINT}"]
    (ax,) = fig.axes
    assert (ax.get_xlabel(), ax.get_ylabel(), ax.get_title()) == (
        "time [s]",
        "contact force [N]",
        JOINT,
    )
    np.testing.assert_array_equal(_line(fig, "clearance").get_ydata(), clearance[f"{JOINT}.fn"])
    reaction = np.hypot(ideal[f"{JOINT}.fx"], ideal[f"{JOINT}.fy"])
    np.testing.assert_allclose(_line(fig, "ideal").get_ydata(), reaction, rtol=1e-15)
    with_friction = plots.contact_force_figure(clearance, JOINT, friction=True)
    (ax,) = with_friction.axes
    assert [line.get_label() for line in ax.lines] == ["normal", "friction"]
    np.testing.assert_array_equal(ax.lines[1].get_ydata(), clearance[f"{JOINT}.ft"])


def test_orbit_draws_the_clearance_circle_and_the_journal_centre(
    figures: dict[str, Figure], clearance: Result, engine
) -> None:
    fig = figures[f"orbit_{JOINT}"]
    (ax,) = fig.axes
    assert plots.radial_clearance(clearance, JOINT) == pytest.approx(0.5e-3)
    (circle,) = [p for p in ax.patches if isinstance(p, Circle)]
    assert circle.get_gid() == "clearance-circle"
    assert circle.get_radius() == pytest.approx(0.5)  # [mm]
    assert circle.center == (0.0, 0.0)
    assert ax.get_aspect() == 1.0
    assert ax.get_xlabel() == "$e_x$ [mm]" and ax.get_ylabel() == "$e_y$ [mm]"
    (path,) = [line for line in ax.lines if line.get_gid() == "journal-centre"]
    np.testing.assert_allclose(path.get_xdata(), 1000.0 * clearance[f"{JOINT}.ex"], rtol=1e-15)
    np.testing.assert_allclose(path.get_ydata(), 1000.0 * clearance[f"{JOINT}.ey"], rtol=1e-15)
    # The circle and the whole path are in view.
    reach = max(0.5, float(np.max(np.hypot(path.get_xdata(), path.get_ydata()))))
    for lo, hi in (ax.get_xlim(), ax.get_ylim()):
        assert lo < -reach and hi > reach
    # The samples of each contact mode, in their own colours, listed in the legend.
    modes = {line.get_label() for line in ax.lines if str(line.get_gid()).startswith("mode-")}
    assert modes == {"free flight", "impact", "continuous contact"}
    (legend,) = fig.legends
    texts = [t.get_text() for t in legend.get_texts()]
    assert texts[0] == "clearance c = 0.5 mm"
    assert set(texts[1:]) == modes


def test_radial_clearance_from_the_two_radii(clearance: Result, engine) -> None:
    model = dict(clearance.model)
    joints = []
    for joint in model["joints"]:
        if joint.get("type") == "clearance_revolute":
            spec = {k: v for k, v in joint["clearance"].items() if k != "clearance"}
            joint = {**joint, "clearance": {**spec, "journal_radius": 0.007}}
        joints.append(joint)
    derived = dataclasses.replace(clearance, model={**model, "joints": joints})
    assert plots.radial_clearance(derived, JOINT) == pytest.approx(0.5e-3)
    (circle,) = plots.orbit_figure(derived, JOINT, by_mode=False).axes[0].patches
    assert isinstance(circle, Circle) and circle.get_radius() == pytest.approx(0.5)
    with pytest.raises(ValueError, match="no clearance joint 'crank_rod'"):
        plots.radial_clearance(derived, "crank_rod")


def test_overview_overlays_every_quantity(figures: dict[str, Figure], engine) -> None:
    fig = figures["figure"]
    assert [ax.get_ylabel() for ax in fig.axes] == [
        "slider displacement [mm]",
        "slider velocity [m/s]",
        "slider acceleration [m/s$^2$]",
        "motor torque [N m]",
        f"{JOINT} contact force [N]",
    ]
    assert fig.axes[-1].get_xlabel() == "time [s]"
    for ax in fig.axes:
        assert [line.get_label() for line in ax.lines] == ["clearance", "ideal"]
    (legend,) = fig.legends
    assert [t.get_text() for t in legend.get_texts()] == ["clearance", "ideal"]


def test_every_text_is_readable_in_a_paper(
    figures: dict[str, Figure], written: list[Path], engine
) -> None:
    """At least 9 pt at the saved size, single figures one paper column wide."""
    for name, fig in figures.items():
        sizes = [t.get_fontsize() for t in fig.findobj(Text) if t.get_text()]
        assert sizes and min(sizes) >= 9, name
        width = fig.get_figwidth()
        assert width == (7.0 if name == "figure" else 3.5), name


def test_labels_and_styles_of_several_runs(clearance: Result, ideal: Result, engine) -> None:
    fig = plots.time_series_figure(
        [clearance, ideal], "slider.vx", labels=["c = 0.5 mm", "ideal joints"]
    )
    assert [line.get_label() for line in fig.axes[0].lines] == ["c = 0.5 mm", "ideal joints"]
    assert fig.axes[0].get_ylabel() == "slider.vx [m/s]"
    with pytest.raises(ValueError, match="1 labels for 2 results"):
        plots.time_series_figure([clearance, ideal], "slider.vx", labels=["one"])
    # Two clearance runs: told apart by their model names, then by their order.
    fig = plots.time_series_figure([clearance, clearance], "slider.ax")
    labels = [line.get_label() for line in fig.axes[0].lines]
    assert labels == ["slider_crank_clearance #1", "slider_crank_clearance #2"]
    assert fig.axes[0].lines[0].get_color() != fig.axes[0].lines[1].get_color()
    with pytest.raises(ValueError, match="no result holds"):
        plots.time_series_figure(ideal, f"{JOINT}.fn")


def test_building_figures_leaves_matplotlib_settings_alone(clearance: Result, engine) -> None:
    before = dict(mpl.rcParams)
    plots.orbit_figure(clearance, JOINT)
    assert dict(mpl.rcParams) == before


def test_a_failed_run_is_marked_where_it_stopped(ideal: Result, engine) -> None:
    failed = _simulate("slider_crank_clearance.toml", max_steps=300)
    assert not failed.ok
    stop = float(failed.time[-1])
    fig = plots.figure_set(failed, ideal)["slider_acceleration"]
    (mark,) = [line for line in fig.axes[0].lines if "failed" in str(line.get_label())]
    assert mark.get_label() == f"clearance failed, t = {stop:.4g} s"
    assert list(mark.get_xdata()) == [stop, stop]
    assert "run failed" in plots.figure(failed).texts[0].get_text()
    orbit = plots.orbit_figure(failed, JOINT)
    (cross,) = [line for line in orbit.axes[0].lines if line.get_marker() == "x"]
    assert cross.get_xdata()[0] == pytest.approx(1000.0 * failed[f"{JOINT}.ex"][-1])


def test_a_pendulum_still_plots(pendulum: Result, tmp_path: Path, engine) -> None:
    assert plots.clearance_joints(pendulum) == []
    figures = plots.figure_set(pendulum)
    assert list(figures) == ["figure"]
    assert [ax.get_ylabel() for ax in figures["figure"].axes] == ["x [m]", "y [m]", "angle [deg]"]
    paths = plots.save_figure_set(pendulum, tmp_path, formats=("svg",))
    assert paths == [tmp_path / "figure.svg"]


def test_two_clearance_joints_get_a_figure_each(engine) -> None:
    two = _simulate("slider_crank_two_clearances.toml", t_end=0.05, rate=2000)
    names = list(plots.figure_set(two))
    for joint in ("crank_rod", "rod_slider"):
        assert f"contact_force_{joint}" in names and f"orbit_{joint}" in names
