"""Small study files shared by the study tests (tests/test_study_*.py): short runs, few
cases, every metric family, a sampled parameter and failing cases."""

from __future__ import annotations

import textwrap
from pathlib import Path

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
CLEARANCE = EXAMPLES / "slider_crank_clearance.toml"

METRICS = """
[metrics]
peak_contact_force = "peak_contact_force"
impacts = "impacts"
peak_slider_acceleration = { stat = "peak", channel = "slider.ax" }
rms_slider_acceleration = { stat = "rms", channel = "slider.ax", window = ["0.02 s", "end"] }
max_torque = { stat = "max", channel = "motor.torque" }
min_torque = { stat = "min", channel = "motor.torque" }
mean_slider_x = { stat = "mean", channel = "slider.x", window = ["0.01 s", "0.03 s"] }
deviation_rms = { stat = "deviation_rms", channel = "slider.ax" }
deviation_peak = { stat = "deviation_peak", channel = "slider.ax" }
free_flight = { stat = "free_flight_fraction", joint = "rod_slider" }
contact = "contact_fraction"
"""

# 3 clearances (8 mm is more than the 7.5 mm bearing radius: the engine refuses those
# cases) x 2 speeds x 2 Monte Carlo draws of the friction = 12 cases, 4 of them failing.
SMALL = f"""
[study]
name = "small"
model = "{CLEARANCE}"
t_end = "0.05 s"
rate = "2 kHz"
sampling = "monte_carlo"
samples = 2
seed = 7

[parameters]
"rod_slider.clearance" = ["0.2 mm", "0.5 mm", "8 mm"]
"motor.speed" = ["200 rpm", "600 rpm"]
"rod_slider.mu_d" = {{ distribution = "uniform", low = 0.03, high = 0.07 }}
{METRICS}
"""


def tiny(parameters: str, head: str = "") -> str:
    """A study of 0.02 s runs keeping two metrics, with these [parameters] lines."""
    return f"""
[study]
model = "{CLEARANCE}"
t_end = "0.02 s"
rate = "2 kHz"
{head}
[parameters]
{parameters}
[metrics]
peak_contact_force = "peak_contact_force"
rms_slider_acceleration = {{ stat = "rms", channel = "slider.ax" }}
"""


def write_study(folder: Path, text: str, name: str = "study.toml") -> Path:
    """Writes study text (dedented) into ``folder`` and returns its path."""
    path = folder / name
    path.write_text(textwrap.dedent(text).lstrip("\n"), encoding="utf-8")
    return path


def grid_study(cases: int, t_end: str = "0.05 s", extra: str = "") -> str:
    """A grid over the clearance with ``cases`` values, all finishing."""
    return f"""
[study]
name = "grid"
model = "{CLEARANCE}"
t_end = "{t_end}"
rate = "2 kHz"
{extra}
[parameters]
"rod_slider.clearance" = {{ from = "0.1 mm", to = "0.6 mm", steps = {cases} }}
{METRICS}
"""
