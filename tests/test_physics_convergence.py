"""The founding case's peaks are converged at the default settings: a tenfold tighter
tolerance moves the peak slider acceleration by less than 1 % (issue 3, "defaults that
work"), and the impact count and the peak contact force hardly change."""

from __future__ import annotations

import jointgap
import numpy as np


def test_founding_case_peaks_converge_at_default_tolerance(examples, engine) -> None:
    model = jointgap.load(examples / "slider_crank_clearance.toml")
    default = model.simulate(0.5, rate=10_000)
    tighter = model.simulate(0.5, rate=10_000, rtol=1e-7, atol=1e-10)
    assert default.ok and tighter.ok
    peak = [np.max(np.abs(r["slider.ax"])) for r in (default, tighter)]
    assert abs(peak[0] / peak[1] - 1.0) < 0.01, peak
    # A real clearance response: many impacts and peaks ten times the ideal's 99 m/s^2.
    impacts = [r.impacts["rod_slider"] for r in (default, tighter)]
    assert len(impacts[0]) > 10 and peak[1] > 500.0
    assert abs(len(impacts[0]) - len(impacts[1])) <= 1
    force = [max(i.peak_force for i in imp) for imp in impacts]
    assert abs(force[0] / force[1] - 1.0) < 0.01, force
