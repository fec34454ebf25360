"""jointgap: planar multibody mechanisms with ideal joints and joints with clearance.

A Rust engine integrates the constrained equations of motion; this package describes
mechanisms (model files or the :class:`Model` builder), runs them and handles results.

>>> import jointgap
>>> model = jointgap.load("examples/slider_crank_ideal.toml")      # doctest: +SKIP
>>> result = model.simulate(t_end=0.5, rate=10_000)                 # doctest: +SKIP
>>> result["slider.ax"].max()                                       # doctest: +SKIP

Quantities are SI numbers or strings with units (``"300 rpm"``, ``"15 mm"``); see
:mod:`jointgap.units`. Output channels are named ``<element>.<quantity>``.

The names below are grouped by what they are for: building a model, running it, its
results, analysing them against ideal runs, measurements and tolerances, studies of many
variants, and the errors. The modules whose names start with ``_`` are the package's
own workings, not its interface.
"""

from typing import TYPE_CHECKING

from . import laws, profiles, units, variants
from ._batch import simulate_batch
from ._model_reader import load, loads
from ._schema import GROUND
from ._version import __version__
from .calibration import calibrate_damping, damping_from_restitution, restitution_from_damping
from .convergence import check_convergence
from .errors import (
    BatchInterrupted,
    CalibrationError,
    ComparisonWarning,
    MeasuredDataError,
    ModelError,
    OutputTooLarge,
    ReportError,
    RunStopped,
    RunWarning,
    StudyError,
    UnitError,
)
from .identify import Parameter, identify
from .model import Model
from .profiles import constant_speed, linear_ramp, smooth_ramp, table_angle, table_speed
from .results import Impact, Result, RunStats, RunStatus, StageTimes, channel_unit
from .statistics import contact_statistics, deviation_from_ideal

if TYPE_CHECKING:  # loaded on first use (below); type checkers see the real signatures
    from .comparison import compare
    from .measured import read_measured, synthetic_record
    from .study import load_results, load_study, run_study
    from .wear import predict_wear, wear_pairs

__all__ = [
    # model building
    "GROUND",
    "Model",
    "load",
    "loads",
    "laws",
    "profiles",
    "constant_speed",
    "linear_ramp",
    "smooth_ramp",
    "table_angle",
    "table_speed",
    "units",
    # running
    "simulate_batch",
    "variants",
    # results
    "Impact",
    "Result",
    "RunStats",
    "RunStatus",
    "StageTimes",
    "channel_unit",
    # analysis: against the ideal run, a measurement, tighter tolerances
    "Parameter",
    "calibrate_damping",
    "check_convergence",
    "compare",
    "contact_statistics",
    "damping_from_restitution",
    "deviation_from_ideal",
    "identify",
    "read_measured",
    "restitution_from_damping",
    "synthetic_record",
    # studies: many variants of a mechanism, one table
    "load_results",
    "load_study",
    "run_study",
    # wear over life
    "predict_wear",
    "wear_pairs",
    # errors and warnings (also in jointgap.errors)
    "BatchInterrupted",
    "CalibrationError",
    "ComparisonWarning",
    "MeasuredDataError",
    "ModelError",
    "OutputTooLarge",
    "ReportError",
    "RunStopped",
    "RunWarning",
    "StudyError",
    "UnitError",
    "__version__",
]

# Signal comparison pulls in SciPy's signal tools: it, measured data and studies are
# loaded on first use, so that `import jointgap` and the CLI start fast.
_LAZY = {
    "compare": "comparison",
    "read_measured": "measured",
    "synthetic_record": "measured",
    "load_results": "study",
    "load_study": "study",
    "run_study": "study",
    "predict_wear": "wear",
    "wear_pairs": "wear",
}


def __getattr__(name: str) -> object:
    if name in _LAZY:
        import importlib

        value = getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
        globals()[name] = value  # later look-ups skip this function
        return value
    raise AttributeError(f"module 'jointgap' has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_LAZY})
