"""Mechanisms that pass singular positions at tight tolerance.

A parallelogram linkage loses rank when all its bars are collinear: its loop equations
become dependent for an instant and the Schur complement of the augmented system is
singular there (docs/formulation.md, "Singular positions"). Both mechanisms below have
one degree of freedom along their motion: every rocker turns by the same angle phi about
its ground pivot and every coupler translates, so with the kinetic energy
``I phi'^2 / 2`` and the potential energy ``g k sin(phi)`` (zero at the pivots' height)
the motion is

    I phi'' = -g k cos(phi)

integrated here by SciPy's DOP853 at rtol 1e-13, apart from the engine. The engine runs
in Cartesian coordinates with every pin equation, through the singular position at each
half turn.
"""

from __future__ import annotations

import math

import jointgap
import numpy as np
from jointgap.benchmark_models import G, four_bar_chain
from scipy.integrate import solve_ivp

RUN = {"method": "dopri5", "rtol": 1e-10, "atol": 1e-12}


def reference_angle(
    inertia: float, k: float, phi0: float, omega0: float, t: np.ndarray
) -> np.ndarray:
    """phi(t) of I phi'' = -g k cos(phi) from (phi0, omega0)."""
    sol = solve_ivp(
        lambda _, y: [y[1], -G * k / inertia * math.cos(y[0])],
        (0.0, float(t[-1])),
        [phi0, omega0],
        method="DOP853",
        rtol=1e-13,
        atol=1e-13,
        dense_output=True,
    )
    return np.asarray(sol.sol(t)[0])


def tip(r: jointgap.Result, body: str, half: float) -> np.ndarray:
    """Point B (at +half along the body's x axis) of a bar, from its recorded pose."""
    a = np.asarray(r[f"{body}.angle"])
    return np.array([r[f"{body}.x"] + half * np.cos(a), r[f"{body}.y"] + half * np.sin(a)])


def horizontal_passes(phi: np.ndarray) -> int:
    """How often phi crosses a multiple of pi (all bars collinear)."""
    return int(np.count_nonzero(np.diff(np.floor(phi / math.pi))))


def total_energy(r: jointgap.Result) -> np.ndarray:
    return np.asarray(r["system.kinetic_energy"] + r["system.potential_energy"])


def test_two_loop_chain_runs_ten_seconds_through_its_singular_positions():
    """Benchmark A02 with N = 2 (stopped at t = 0.714 s, the first singular position,
    at rtol 1e-12 before the engine released the lost rank): over 10 s it passes the
    collinear position 10 times, and the top of each rocker follows the one-degree-of-
    freedom motion (I = (4N + 1)/3, k = (3N + 1)/2 for 1 m, 1 kg bars) to 1e-8 m; the
    total energy (35.8 J) holds to 1e-8 of itself. Measured: 1.1e-9 m and 6.7e-10
    (radau5 and sdirk4 at rtol 1e-10: 7e-9 m; every method at 1e-12: below 1e-9 m)."""
    n = 2
    r = four_bar_chain(n).simulate(10.0, rate=100, **RUN)
    assert r.status == "finished", r.message
    t = np.asarray(r.time)
    assert t[-1] == 10.0
    phi = reference_angle((4 * n + 1) / 3, (3 * n + 1) / 2, math.pi / 2, -1.0, t)
    assert horizontal_passes(phi) == 10
    for i in range(n + 1):
        exact = np.array([i + np.cos(phi), np.sin(phi)])
        error = np.max(np.hypot(*(tip(r, f"rocker_{i}", 0.5) - exact)))
        assert error < 1e-8, f"rocker_{i}: {error:.3e} m"
    e = total_energy(r)
    assert np.max(np.abs(e - e[0])) < 1e-8 * abs(e[0])


def unequal_parallelogram() -> tuple[jointgap.Model, float, float]:
    """A parallelogram four-bar (Grashof equality: ground = coupler = 1.2 m, both rockers
    0.7 m) with unequal rockers (2 kg and 0.5 kg, centres of mass at their middles) and a
    3 kg coupler, released from the rockers upright at -2 rad/s; returns the model and
    its I and k."""
    ground, rocker = 1.2, 0.7
    masses = (2.0, 0.5)
    coupler_mass = 3.0
    m = jointgap.Model("unequal_parallelogram", gravity=(0.0, -G))
    m.add_ground_point("O0", (0.0, 0.0))
    m.add_ground_point("O1", (ground, 0.0))
    omega = -2.0
    half = 0.5 * rocker
    for k, mass in enumerate(masses):
        m.add_body(
            f"rocker_{k}",
            mass=mass,
            inertia=mass * rocker**2 / 12,
            position=(k * ground, half),
            angle=math.pi / 2,
            velocity=(-omega * half, 0.0),
            omega=omega,
            points={"A": (-half, 0.0), "B": (half, 0.0)},
        )
        m.add_revolute(f"pivot_{k}", "ground", f"rocker_{k}", point_i=f"O{k}", point_j="A")
    m.add_body(
        "coupler",
        mass=coupler_mass,
        inertia=coupler_mass * ground**2 / 12,
        position=(0.5 * ground, rocker),
        angle=0.0,
        velocity=(-omega * rocker, 0.0),
        omega=0.0,
        points={"A": (-0.5 * ground, 0.0), "B": (0.5 * ground, 0.0)},
    )
    m.add_revolute("left", "rocker_0", "coupler", point_i="B", point_j="A")
    m.add_revolute("right", "coupler", "rocker_1", point_i="B", point_j="B")
    inertia = sum(mass * rocker**2 / 3 for mass in masses) + coupler_mass * rocker**2
    k = sum(mass * half for mass in masses) + coupler_mass * rocker
    return m, inertia, k


def test_four_bar_through_its_change_point():
    """A parallelogram four-bar with unequal rockers, so that nothing but the pin
    equations keeps its rockers parallel through the change point (all four links
    collinear, two degrees of freedom for an instant): over 5 s it passes the change
    point at least 6 times, the rockers stay parallel to 1e-9 rad, their tips follow the
    one-degree-of-freedom motion to 1e-8 m and the energy holds to 1e-8 of itself
    (measured: 7 passes, 4e-14 rad, 4.8e-10 m, 5.5e-10)."""
    model, inertia, k = unequal_parallelogram()
    assert model.degrees_of_freedom() == 1
    r = model.simulate(5.0, rate=200, **RUN)
    assert r.status == "finished", r.message
    t = np.asarray(r.time)
    phi = reference_angle(inertia, k, math.pi / 2, -2.0, t)
    assert horizontal_passes(phi) >= 6
    a0, a1 = np.asarray(r["rocker_0.angle"]), np.asarray(r["rocker_1.angle"])
    assert np.max(np.abs(a0 - a1)) < 1e-9
    for i, x0 in enumerate((0.0, 1.2)):
        exact = np.array([x0 + 0.7 * np.cos(phi), 0.7 * np.sin(phi)])
        error = np.max(np.hypot(*(tip(r, f"rocker_{i}", 0.35) - exact)))
        assert error < 1e-8, f"rocker_{i}: {error:.3e} m"
    e = total_energy(r)
    assert np.max(np.abs(e - e[0])) < 1e-8 * abs(e[0])
