"""The clearance slider-crank tends to the ideal one as the gap closes.

How the gap closes: the founding case's rod-slider clearance is c_k with a linear
Kelvin-Voigt contact of stiffness k_k, critically damped for the slider's mass
(d = 2 sqrt(k m_slider)), no friction, along the path

    k_k = 1e7, 1e8, 1e9 N/m,    c_k = 0.1 mm * (k_k / 1e7)^(-3/2).

Why c must shrink faster than 1/k: at each reversal of the joint force the journal
crosses the gap, reaching a speed of order sqrt(a c), and the contact turns that into an
acceleration transient of order sqrt(a c) sqrt(k / m); it vanishes only if c k -> 0.
Along this path c k falls as k^(-1/2).

Measured against the ideal run (examples/slider_crank_ideal.toml): the slider position
differs by about the clearance, and every error (position, velocity, NRMSE of the slider
acceleration and of the motor torque) falls by at least a factor of 5 per step, down to
below 1e-3 of the ideal range at the last one.
"""

from __future__ import annotations

import math

import jointgap
import numpy as np
from test_clearance_api import founding_builder

SLIDER_MASS = 2.28
STIFFNESS = (1e7, 1e8, 1e9)


def gap(stiffness: float) -> float:
    return 1e-4 * (stiffness / 1e7) ** -1.5


def nrmse(actual: np.ndarray, reference: np.ndarray) -> float:
    """RMS difference over the reference's range."""
    return float(np.sqrt(np.mean((actual - reference) ** 2)) / np.ptp(reference))


def test_clearance_slider_crank_tends_to_the_ideal_one(examples, engine) -> None:
    ideal = jointgap.load(examples / "slider_crank_ideal.toml").simulate(0.5, rate=10_000)
    errors = []
    for k in STIFFNESS:
        c = gap(k)
        law = jointgap.laws.kelvin_voigt(2.0 * math.sqrt(k * SLIDER_MASS), exponent=1.0)
        model = founding_builder(clearance=c, stiffness=k, normal_law=law, friction=None)
        # Tight tolerances: the stiff contact's tolerance-level ripple, amplified by
        # k / m in the accelerations, must stay below the difference being measured.
        r = model.simulate(0.5, rate=10_000, rtol=1e-8, atol=1e-12)
        assert r.ok, r.message
        x_err = np.max(np.abs(r["slider.x"] - ideal["slider.x"]))
        # The slider can be off by the gap plus the contact's deflection, no more.
        peak_force = np.max(r["rod_slider.fn"])
        assert x_err <= 1.1 * (c + peak_force / k), (k, x_err)
        errors.append(
            (
                x_err,
                np.max(np.abs(r["slider.vx"] - ideal["slider.vx"])),
                nrmse(r["slider.ax"], ideal["slider.ax"]),
                nrmse(r["motor.torque"], ideal["motor.torque"]),
            )
        )
    errors_ = np.array(errors)
    assert np.all(errors_[1:] < errors_[:-1] / 5.0), errors_
    assert errors_[-1, 2] < 1e-3 and errors_[-1, 3] < 1e-3, errors_[-1]
