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
from benchmark_models import G, four_bar_chain
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


def unequal_parallelogram(
    phi0: float = math.pi / 2, omega: float = -2.0
) -> tuple[jointgap.Model, float, float]:
    """A parallelogram four-bar (Grashof equality: ground = coupler = 1.2 m, both rockers
    0.7 m) with unequal rockers (2 kg and 0.5 kg, centres of mass at their middles) and a
    3 kg coupler, released with the rockers at ``phi0`` (upright by default) turning at
    ``omega``; returns the model and its I and k."""
    ground, rocker = 1.2, 0.7
    masses = (2.0, 0.5)
    coupler_mass = 3.0
    m = jointgap.Model("unequal_parallelogram", gravity=(0.0, -G))
    m.add_ground_point("O0", (0.0, 0.0))
    m.add_ground_point("O1", (ground, 0.0))
    half = 0.5 * rocker
    c, s = math.cos(phi0), math.sin(phi0)
    for k, mass in enumerate(masses):
        m.add_body(
            f"rocker_{k}",
            mass=mass,
            inertia=mass * rocker**2 / 12,
            position=(k * ground + half * c, half * s),
            angle=phi0,
            velocity=(-omega * half * s, omega * half * c),
            omega=omega,
            points={"A": (-half, 0.0), "B": (half, 0.0)},
        )
        m.add_revolute(f"pivot_{k}", "ground", f"rocker_{k}", point_i=f"O{k}", point_j="A")
    m.add_body(
        "coupler",
        mass=coupler_mass,
        inertia=coupler_mass * ground**2 / 12,
        position=(0.5 * ground + rocker * c, rocker * s),
        angle=0.0,
        velocity=(-omega * rocker * s, omega * rocker * c),
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


def chain_at(n: int, phi0: float, omega: float, driven: bool = False) -> jointgap.Model:
    """The chain of ``n`` parallelogram loops of :func:`four_bar_chain` (1 m, 1 kg bars)
    with its rockers at ``phi0`` turning at ``omega`` and its couplers translating; with
    ``driven``, its first pivot turned at ``omega`` by a driver named ``motor``."""
    m = jointgap.Model(f"four_bar_chain_{n}_at_{phi0}", gravity=(0.0, -G))
    c, s = math.cos(phi0), math.sin(phi0)

    def bar(name: str, x: float, y: float, angle: float, vx: float, vy: float, w: float) -> None:
        m.add_body(
            name,
            mass=1.0,
            inertia=1.0 / 12,
            position=(x, y),
            angle=angle,
            velocity=(vx, vy),
            omega=w,
            points={"A": (-0.5, 0.0), "B": (0.5, 0.0)},
        )

    for i in range(n + 1):
        m.add_ground_point(f"A{i}", (float(i), 0.0))
        bar(f"rocker_{i}", i + 0.5 * c, 0.5 * s, phi0, -0.5 * omega * s, 0.5 * omega * c, omega)
        m.add_revolute(f"pivot_{i}", "ground", f"rocker_{i}", point_i=f"A{i}", point_j="A")
    for i in range(1, n + 1):
        bar(f"coupler_{i}", i - 0.5 + c, s, 0.0, -omega * s, omega * c, 0.0)
        m.add_revolute(f"left_{i}", f"rocker_{i - 1}", f"coupler_{i}", point_i="B", point_j="A")
        m.add_revolute(f"right_{i}", f"coupler_{i}", f"rocker_{i}", point_i="B", point_j="B")
    if driven:
        m.add_driver("motor", "pivot_0", {"type": "constant_speed", "speed": omega})
    return m


def tip_error(r: jointgap.Result, phi: np.ndarray, pivots: list[float], half: float) -> float:
    """Largest distance of each rocker's tip B from its closed-form place on a circle of
    radius ``2 half`` about its pivot at (x0, 0), the rocker at angle ``phi``."""
    worst = 0.0
    for i, x0 in enumerate(pivots):
        exact = np.array([x0 + 2 * half * np.cos(phi), 2 * half * np.sin(phi)])
        worst = max(worst, float(np.max(np.hypot(*(tip(r, f"rocker_{i}", half) - exact)))))
    return worst


def redundant(r: jointgap.Result) -> list[str]:
    return [w for w in r.warnings if "redundant" in w]


def test_four_bar_started_at_its_change_point():
    """The parallelogram four-bar placed exactly at its change point (all four links on
    the ground line, rockers at 0 rad, turning at -4 rad/s). Before, the assembly
    decided there that one pin row repeated the others, dropped it for the whole run,
    and the rockers came 3 rad apart. Now no row is dropped and, every step of 5 s
    (through the change point at each half turn), the rockers stay parallel and their
    tips follow the one-degree-of-freedom motion to 1e-8 m, as does the same model
    started 1e-3 rad before the change point; the energy holds to 1e-8 of itself
    (measured: 10 passes, 1.05e-9 m and 1.03e-9 m, rockers 2.5e-10 rad apart, energy
    4.6e-10)."""
    _, inertia, k = unequal_parallelogram()
    for phi0 in (0.0, 1e-3):
        model, _, _ = unequal_parallelogram(phi0, -4.0)
        r = model.simulate(5.0, every_step=True, **RUN)
        assert r.status == "finished", r.message
        assert redundant(r) == []
        t = np.asarray(r.time)
        phi = reference_angle(inertia, k, phi0, -4.0, t)
        assert horizontal_passes(phi) >= 6
        a0, a1 = np.asarray(r["rocker_0.angle"]), np.asarray(r["rocker_1.angle"])
        assert np.max(np.abs(a0 - a1)) < 1e-9
        error = tip_error(r, phi, [0.0, 1.2], 0.35)
        assert error < 1e-8, f"phi0 = {phi0}: {error:.3e} m"
        e = total_energy(r)
        assert np.max(np.abs(e - e[0])) < 1e-8 * np.max(np.abs(e))


def test_driven_parallelogram_started_at_its_change_point_follows_its_closed_form():
    """Driven at -2 rad/s from its change point, the parallelogram moves as its closed
    form says: every rocker angle equals the driven one, the coupler translates. Every
    step of 2 s, the rocker tips are on their circles at the driven angle to 1e-8 m and
    the coupler keeps its angle to 1e-8 rad (measured: 8.0e-10 m, 6.7e-10 rad)."""
    model, _, _ = unequal_parallelogram(0.0, -2.0)
    model.add_driver("motor", "pivot_0", {"type": "constant_speed", "speed": -2.0})
    r = model.simulate(2.0, every_step=True, **RUN)
    assert r.status == "finished", r.message
    assert redundant(r) == []
    t = np.asarray(r.time)
    assert tip_error(r, -2.0 * t, [0.0, 1.2], 0.35) < 1e-8
    assert np.max(np.abs(np.asarray(r["coupler.angle"]))) < 1e-8


def test_two_loop_chain_started_with_all_bars_horizontal():
    """The two-loop chain of benchmark A02 placed at its singular position (all bars
    horizontal, rank 12 of 14), moving at the speed the benchmark has there (its energy
    of 35.8 J at the top all kinetic): no row is dropped, and every step of 10 s, through
    11 singular positions, the rocker tips follow the one-degree-of-freedom motion to
    1e-8 m, and the energy holds to 1e-8 of itself (measured with dopri5: 3.6e-9 m,
    3.0e-11; radau5 8.4e-9 m, sdirk4 1.07e-8 m)."""
    n = 2
    inertia, k = (4 * n + 1) / 3, (3 * n + 1) / 2
    top = (n + 1) / 6 + n / 2 + G * ((n + 1) * 0.5 + n)
    omega = -math.sqrt(2 * top / inertia)
    r = chain_at(n, 0.0, omega).simulate(10.0, every_step=True, **RUN)
    assert r.status == "finished", r.message
    assert redundant(r) == []
    t = np.asarray(r.time)
    phi = reference_angle(inertia, k, 0.0, omega, t)
    assert horizontal_passes(phi) == 11
    error = tip_error(r, phi, [0.0, 1.0, 2.0], 0.5)
    assert error < 1e-8, f"{error:.3e} m"
    e = total_energy(r)
    assert np.max(np.abs(e - e[0])) < 1e-8 * abs(e[0])


def test_forty_loop_chain_driven_through_its_singular_position():
    """The chain of 40 loops (243 rows: faer's sparse factor) driven at -1 rad/s, every
    step checked against its closed form (every rocker at the driven angle, the couplers
    translating), placed exactly at its singular position (rank 202 of 243: it keeps
    every row) and started 0.05 rad before it. Both pass it in fewer than 1000 steps
    (183 from before it; 4736 steps and 3212 rejections before the sparse factor read
    the rank loss from its pivots), and the rocker tips are on their circles to 1e-8 m
    away from the position; within 2e-3 rad of it, where the lost rank is released, to
    1e-5 m (measured: 4.8e-7 m from the position, 3.9e-6 m through it, 1e-12 m after
    it; docs/formulation.md, "How wide the release is")."""
    n = 40
    for phi0, t_end in ((0.0, 0.1), (0.05, 0.1)):
        r = chain_at(n, phi0, -1.0, driven=True).simulate(t_end, every_step=True, **RUN)
        assert r.status == "finished", r.message
        assert redundant(r) == []
        assert r.stats["accepted_steps"] + r.stats["rejected_steps"] < 1000
        phi = phi0 - np.asarray(r.time)
        errors = np.zeros_like(phi)
        for i in range(n + 1):
            exact = np.array([i + np.cos(phi), np.sin(phi)])
            errors = np.maximum(errors, np.hypot(*(tip(r, f"rocker_{i}", 0.5) - exact)))
        near = np.abs(phi) < 2e-3
        assert near.any() and (~near).any()
        assert np.max(errors[~near]) < 1e-8, f"phi0 = {phi0}: {np.max(errors[~near]):.3e} m"
        assert np.max(errors[near]) < 1e-5, f"phi0 = {phi0}: {np.max(errors[near]):.3e} m"
