"""jointgap: planar multibody mechanisms with ideal (and, later, clearance) joints.

A Rust engine integrates the constrained equations of motion; this package describes
mechanisms (model files or the :class:`Model` builder), runs them and handles results.

>>> import jointgap
>>> model = jointgap.load("examples/slider_crank_ideal.toml")      # doctest: +SKIP
>>> result = model.simulate(t_end=0.5, rate=10_000)                 # doctest: +SKIP
>>> result["slider.ax"].max()                                       # doctest: +SKIP

Quantities are SI numbers or strings with units (``"300 rpm"``, ``"15 mm"``); see
:mod:`jointgap.units`. Output channels are named ``<element>.<quantity>``.
"""

from . import laws, profiles, units
from .io import load, loads
from .model import Model
from .profiles import constant_speed, linear_ramp, smooth_ramp, table_angle, table_speed
from .results import Result, channel_unit
from .schema import GROUND, ModelError

__version__ = "0.1.0"

__all__ = [
    "GROUND",
    "Model",
    "ModelError",
    "Result",
    "channel_unit",
    "constant_speed",
    "laws",
    "linear_ramp",
    "load",
    "loads",
    "profiles",
    "smooth_ramp",
    "table_angle",
    "table_speed",
    "units",
    "__version__",
]
