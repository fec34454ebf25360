"""jointgap: planar multibody mechanisms with ideal joints and joints with clearance.

A Rust engine integrates the constrained equations of motion; this package describes
mechanisms (model files or the :class:`Model` builder), runs them and handles results.

>>> import jointgap
>>> model = jointgap.load("examples/slider_crank_ideal.toml")      # doctest: +SKIP
>>> result = model.simulate(t_end=0.5, rate=10_000)                 # doctest: +SKIP
>>> result["slider.ax"].max()                                       # doctest: +SKIP

Quantities are SI numbers or strings with units (``"300 rpm"``, ``"15 mm"``); see
:mod:`jointgap.units`. Output channels are named ``<element>.<quantity>``.
"""

from typing import TYPE_CHECKING

from . import laws, profiles, units, variants
from .batch import simulate_batch
from .calibration import calibrate_damping, damping_from_restitution, restitution_from_damping
from .convergence import check_convergence
from .identify import Parameter, identify
from .io import load, loads
from .model import Model
from .profiles import constant_speed, linear_ramp, smooth_ramp, table_angle, table_speed
from .results import Result, channel_unit
from .schema import GROUND, ModelError
from .statistics import contact_statistics, deviation_from_ideal

if TYPE_CHECKING:  # loaded on first use (below); type checkers see the real signatures
    from .comparison import compare
    from .measured import read_measured, synthetic_record

__version__ = "0.1.0"

__all__ = [
    "GROUND",
    "Model",
    "ModelError",
    "Parameter",
    "Result",
    "calibrate_damping",
    "channel_unit",
    "check_convergence",
    "compare",
    "contact_statistics",
    "damping_from_restitution",
    "deviation_from_ideal",
    "identify",
    "constant_speed",
    "laws",
    "linear_ramp",
    "load",
    "loads",
    "profiles",
    "read_measured",
    "restitution_from_damping",
    "simulate_batch",
    "smooth_ramp",
    "synthetic_record",
    "table_angle",
    "table_speed",
    "units",
    "variants",
    "__version__",
]

# Signal comparison and measured data pull in SciPy's signal tools and matplotlib:
# loaded on first use, so that `import jointgap` and the CLI start fast.
_LAZY = {
    "compare": "comparison",
    "read_measured": "measured",
    "synthetic_record": "measured",
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
