"""The Radau IIA method (``method="radau5"``) on the founding clearance case against a
tight explicit run.

The founding case (examples/slider_crank_clearance.toml, 0.5 s: ramp to 300 rpm, then
one and a half turns, 21 impacts and five sustained contacts with sticking friction) is
integrated by DOPRI5 at rtol 1e-12, atol 1e-15, the reference of the speed benchmark
(benchmarks/run.py), and by Radau IIA at rtol 1e-6 and 1e-8 (atol = 1e-3 rtol). The
measure is the benchmark's: NRMSE of slider.ax on the 10 kHz grid, RMS of the difference
over the reference's max - min.

Measured: NRMSE 1.1e-4 at rtol 1e-6 and 2.3e-7 at rtol 1e-8; both runs find the
reference's 21 impacts, onset times within 8e-7 s and 5e-9 s. The bounds leave about 10x
for the run-to-run scatter of this chaotic contact sequence (benchmarks/README.md: a
change of atol in its 12th digit moves one run's NRMSE by up to 10x); a wrong coefficient
or a broken error estimate would miss impacts or the NRMSE by orders of magnitude.
"""

from __future__ import annotations

from pathlib import Path

import jointgap
import numpy as np
import pytest

FOUNDING = Path(__file__).resolve().parent.parent / "examples" / "slider_crank_clearance.toml"
T_END = 0.5  # [s]
RATE = 10_000  # [Hz]


def run(
    model: jointgap.Model, method: str, rtol: float, atol: float, exact_jacobian: bool = True
) -> jointgap.Result:
    result = model.simulate(
        T_END,
        rate=RATE,
        rtol=rtol,
        atol=atol,
        method=method,
        channels=["slider.ax"],
        exact_jacobian=exact_jacobian,
    )
    assert result.status == "finished", result.message
    return result


@pytest.fixture(scope="module")
def founding() -> jointgap.Model:
    return jointgap.load(FOUNDING)


@pytest.fixture(scope="module")
def reference(founding: jointgap.Model) -> jointgap.Result:
    return run(founding, "dopri5", 1e-12, 1e-15)


def nrmse(result: jointgap.Result, reference: jointgap.Result) -> float:
    ax, ref = np.asarray(result["slider.ax"]), np.asarray(reference["slider.ax"])
    assert ax.shape == ref.shape
    return float(np.sqrt(np.mean((ax - ref) ** 2)) / (ref.max() - ref.min()))


@pytest.mark.parametrize(("rtol", "bound", "onset_tol"), [(1e-6, 1e-3, 1e-5), (1e-8, 3e-6, 1e-7)])
@pytest.mark.parametrize("exact", [True, False])
def test_founding_case_matches_tight_dopri5(
    founding: jointgap.Model,
    reference: jointgap.Result,
    rtol: float,
    bound: float,
    onset_tol: float,
    exact: bool,
) -> None:
    """Exact Jacobians (the default) and the applied forces' approximation converge to
    the same reference; the run's account says which it took."""
    result = run(founding, "radau5", rtol, 1e-3 * rtol, exact_jacobian=exact)
    assert result.stats["method"] == "radau5"
    jacobians = result.stats["jacobian_evaluations"]
    assert jacobians > 0 and result.stats["newton_iterations"] > result.stats["accepted_steps"]
    taken = f"{jacobians} exact, 0 of the applied forces only" if exact else ""
    assert result.stats["compiled"].endswith(taken)
    if not exact:
        assert "Jacobians" not in result.stats["compiled"]
    error = nrmse(result, reference)
    assert error < bound, f"NRMSE {error:.2e} at rtol {rtol:g}"
    onsets = [i.onset_time for i in result.impacts["rod_slider"]]
    expected = [i.onset_time for i in reference.impacts["rod_slider"]]
    assert len(expected) == 21
    assert len(onsets) == len(expected)
    assert np.max(np.abs(np.subtract(onsets, expected))) < onset_tol
