"""Energy: conserved by passive mechanisms without damping (double pendulum, four-bar,
spring oscillator), dissipated by a damper exactly as the closed-form damped oscillation
says. system.potential_energy holds gravity and spring potential."""

from __future__ import annotations

import math

import jointgap
import numpy as np
import pytest
from reference import FourBar, add_bar, add_four_bar, damped_free_vibration, simulate_ok

G = 9.81
TIGHT = {"rtol": 1e-11, "atol": 1e-13, "method": "dopri5"}


def total_energy(r):
    return r["system.kinetic_energy"] + r["system.potential_energy"]


def test_double_pendulum_conserves_energy():
    """Two bars released from rest at -30 and +45 degrees (chaotic motion). Over 10 s the
    total energy stays within 1e-8 of the energy exchanged (the largest kinetic energy
    reached, about 20 J here) and the constraints hold to 1e-10."""
    m = jointgap.Model(name="double_pendulum", gravity=(0.0, -G))
    elbow = add_bar(m, "upper", 1.0, 1.0, (0.0, 0.0), -math.pi / 6)
    add_bar(m, "lower", 0.6, 0.8, elbow, math.pi / 4)
    m.add_revolute("shoulder", "ground", "upper", point_i=(0.0, 0.0), point_j="a")
    m.add_revolute("elbow", "upper", "lower", point_i="b", point_j="a")
    r = simulate_ok(m, 10.0, rate=100, **TIGHT)
    e = total_energy(r)
    scale = np.max(r["system.kinetic_energy"])
    assert scale > 5.0  # the pendulum really swings
    drift = np.max(np.abs(e - e[0]))
    assert drift < 1e-8 * scale, f"energy drift {drift:.3e} J of {scale:.3f} J"
    cerr = np.max(np.abs(r["system.constraint_error"]))
    assert cerr < 1e-10, f"constraint error {cerr:.3e}"
    # At rest at t = 0; the potential energy is -sum m g . r_cm = sum m g y_cm (datum y = 0).
    y_upper = 0.5 * math.sin(-math.pi / 6)
    y_lower = math.sin(-math.pi / 6) + 0.4 * math.sin(math.pi / 4)
    pe0 = G * (1.0 * y_upper + 0.6 * y_lower)
    assert r["system.kinetic_energy"][0] == pytest.approx(0.0, abs=1e-14)
    assert r["system.potential_energy"][0] == pytest.approx(pe0, rel=1e-12)


FOUR_BAR = FourBar(ground=0.4, a=0.12, b=0.35, c=0.3)


def test_passive_four_bar_conserves_energy():
    """A Grashof crank-rocker without a driver, released from rest under gravity."""
    assert FOUR_BAR.is_grashof()
    m = jointgap.Model(name="passive_four_bar", gravity=(0.0, -G))
    add_four_bar(m, FOUR_BAR, 0.5)
    r = simulate_ok(m, 10.0, rate=100, **TIGHT)
    e = total_energy(r)
    scale = np.max(r["system.kinetic_energy"])
    assert scale > 0.1
    drift = np.max(np.abs(e - e[0]))
    assert drift < 1e-8 * scale, f"energy drift {drift:.3e} J of {scale:.3f} J"
    assert np.max(np.abs(r["system.constraint_error"])) < 1e-10
    # The linkage stays closed on its branch: rocker pin where the closed form puts it.
    (_, _), (bx, by), _, _ = FOUR_BAR.positions(r["crank.angle"])
    phi = r["rocker.angle"]
    assert np.max(np.abs(r["rocker.x"] + 0.5 * FOUR_BAR.c * np.cos(phi) - bx)) < 1e-9
    assert np.max(np.abs(r["rocker.y"] + 0.5 * FOUR_BAR.c * np.sin(phi) - by)) < 1e-9


# Mass hanging on a spring along a vertical prismatic guide. The anchor sits at
# h = l0 + m g / k so that the static equilibrium is y = 0.
MASS, K, L0 = 2.0, 800.0, 0.5
H = L0 + MASS * G / K
U0 = 0.05  # initial stretch below equilibrium [m]


def hanging_mass(damping: float) -> jointgap.Model:
    m = jointgap.Model(name="spring_mass", gravity=(0.0, -G))
    m.add_ground_point("anchor", (0.0, H))
    m.add_body("mass", MASS, 0.01, position=(0.0, -U0))
    m.add_prismatic(
        "guide", "ground", "mass", axis=(0.0, 1.0), point_i=(0.0, 0.0), point_j=(0.0, 0.0)
    )
    m.add_spring_damper(
        "spring",
        "ground",
        "mass",
        point_i="anchor",
        point_j=(0.0, 0.0),
        stiffness=K,
        damping=damping,
        free_length=L0,
    )
    return m


def test_spring_mass_without_damping_conserves_energy():
    """y(t) = -u0 cos(w t), w = sqrt(k/m); kinetic + gravity + spring energy constant."""
    r = simulate_ok(hanging_mass(0.0), 3.0, rate=1000, **TIGHT)
    w = math.sqrt(K / MASS)
    t = r.time
    assert np.max(np.abs(r["mass.y"] + U0 * np.cos(w * t))) < 1e-9 * U0
    e = total_energy(r)
    oscillation = 0.5 * K * U0**2  # 1 J
    assert np.max(np.abs(e - e[0])) < 1e-8 * oscillation
    # Potential at t = 0: gravity m g y0 plus spring k (l - l0)^2 / 2, l = h + u0.
    pe0 = MASS * G * (-U0) + 0.5 * K * (H + U0 - L0) ** 2
    assert r["system.potential_energy"][0] == pytest.approx(pe0, rel=1e-12)


def test_damped_spring_mass_matches_closed_form():
    """Damping ratio 0.05: y(t) = -u(t) with u the underdamped free vibration from u0 at
    rest; energy decreases monotonically and equals the closed form
    E(t) - E(0) = m v^2/2 + k u^2/2 - k u0^2/2 (gravity and the static spring force
    cancel about the equilibrium)."""
    zeta = 0.05
    c = 2 * zeta * math.sqrt(K * MASS)
    r = simulate_ok(hanging_mass(c), 3.0, rate=1000, **TIGHT)
    t = r.time
    u, v = damped_free_vibration(t, MASS, K, c, U0)
    assert np.max(np.abs(r["mass.y"] + u)) < 1e-9 * U0
    assert np.max(np.abs(r["mass.vy"] + v)) < 1e-9 * U0 * math.sqrt(K / MASS)
    e = total_energy(r)
    oscillation = 0.5 * K * U0**2
    expected = 0.5 * MASS * v**2 + 0.5 * K * u**2 - oscillation
    assert np.max(np.abs((e - e[0]) - expected)) < 1e-8 * oscillation
    # Monotonic decay (dE/dt = -c v^2 <= 0); a wrong damper sign would raise it by
    # ~c v^2 dt ~ 1e-3 J per sample.
    assert np.max(np.diff(e)) < 1e-12 * oscillation
    # After 3 s (about 9.5 periods) the amplitude has decayed by exp(-zeta w t).
    assert e[0] - e[-1] == pytest.approx(
        oscillation - (0.5 * MASS * v[-1] ** 2 + 0.5 * K * u[-1] ** 2), rel=1e-8
    )
    assert e[0] - e[-1] > 0.9 * oscillation
