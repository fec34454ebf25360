"""The size-scaling benchmark mechanisms (benchmarks/benchmark_models.py) move as they must.

The chain of N four-bar loops (IFToMM benchmark A02) is a chain of parallelograms: every
coupler translates and every rocker keeps the same angle phi, so the whole chain is one
degree of freedom with (per unit mass and length, bars of inertia m L^2 / 12)

    kinetic   (N + 1) (1/6) phi'^2 + N (1/2) phi'^2 = (4N + 1)/6 phi'^2
    potential g ((N + 1)/2 + N) sin(phi)             = g (3N + 1)/2 sin(phi)

that is I phi'' = -g k cos(phi), I = (4N + 1)/3, k = (3N + 1)/2, from phi = pi/2 with
phi' = -1 rad/s. That equation, integrated here by SciPy, is the reference. The N-link
chain is checked by its energy, its joints and the compound pendulum (N = 1).
"""

from __future__ import annotations

import math

import jointgap
import numpy as np
import pytest
from benchmark_models import G, four_bar_chain, four_bar_chain_energy, n_link_chain
from scipy.integrate import solve_ivp

TIGHT = {"method": "dopri5", "rtol": 1e-10, "atol": 1e-12}


def one_dof_angle(n_loops: int, t: np.ndarray) -> np.ndarray:
    """Rocker angle of the chain of n_loops parallelograms (1 m, 1 kg bars, B_0 at 1 m/s)
    from its one-degree-of-freedom equation of motion."""
    inertia, k = (4 * n_loops + 1) / 3, (3 * n_loops + 1) / 2
    sol = solve_ivp(
        lambda _, y: [y[1], -G * k / inertia * math.cos(y[0])],
        (0.0, float(t[-1])),
        [math.pi / 2, -1.0],
        rtol=1e-12,
        atol=1e-12,
        dense_output=True,
    )
    return np.asarray(sol.sol(t)[0])


def total_energy(r: jointgap.Result) -> np.ndarray:
    return np.asarray(r["system.kinetic_energy"] + r["system.potential_energy"])


def rocker_angles(r: jointgap.Result, n_loops: int) -> np.ndarray:
    return np.array([r[f"rocker_{i}.angle"] for i in range(n_loops + 1)])


@pytest.mark.parametrize("n", [1, 2, 4])
def test_four_bar_chain_structure(n):
    """2N + 1 bars, one degree of freedom, no redundant constraint: in the plane the
    6N + 2 pin equations of the chain are independent (each coupler is its own body), so
    the engine removes no row. B_0 starts at 1 m/s along +x with every rocker at -1 rad/s
    and every coupler translating at 1 m/s: a consistent velocity, kept by the assembly."""
    m = four_bar_chain(n)
    assert len(m.bodies) == 2 * n + 1
    assert len(m.joints) == 3 * n + 1
    assert m.degrees_of_freedom() == 1
    assert m.check() == []
    r = m.simulate(1e-9, rate=1e9, **TIGHT)
    assert r.status == "finished", r.message
    assert r.warnings == []
    kinetic, potential = four_bar_chain_energy(n)
    assert r["system.kinetic_energy"][0] == pytest.approx(kinetic, rel=1e-12)
    assert r["system.potential_energy"][0] == pytest.approx(potential, rel=1e-12)
    for i in range(n + 1):
        assert r[f"rocker_{i}.omega"][0] == pytest.approx(-1.0, rel=1e-12)
    for i in range(1, n + 1):
        assert r[f"coupler_{i}.vx"][0] == pytest.approx(1.0, rel=1e-12)
        assert r[f"coupler_{i}.vy"][0] == pytest.approx(0.0, abs=1e-12)


def test_four_bar_chain_moves_as_one_parallelogram():
    """N = 3 for 0.6 s (the rockers fall from vertical toward the horizontal, reached at
    0.717 s): every rocker has the same angle to 1e-12 rad, couplers stay horizontal, the
    angle follows the one-degree-of-freedom equation to 1e-9 rad and phi'^2 its energy
    integral, and the total energy (51.2 J) holds to 1e-8 J (measured 2.7e-9 J)."""
    n = 3
    r = four_bar_chain(n).simulate(0.6, rate=200, **TIGHT)
    assert r.status == "finished", r.message
    phi = rocker_angles(r, n)
    assert np.max(np.abs(phi - phi[0])) < 1e-12
    for i in range(1, n + 1):
        assert np.max(np.abs(r[f"coupler_{i}.angle"])) < 1e-12
    t = np.asarray(r.time)
    assert phi[0][-1] < 0.5  # it really fell, from pi/2
    assert np.max(np.abs(phi[0] - one_dof_angle(n, t))) < 1e-9
    inertia, k = (4 * n + 1) / 3, (3 * n + 1) / 2
    omega_ref = -np.sqrt(1.0 + 2 * G * k / inertia * (1.0 - np.sin(phi[0])))
    assert np.max(np.abs(r["rocker_0.omega"] - omega_ref)) < 1e-9
    e = total_energy(r)
    assert e[0] == pytest.approx(sum(four_bar_chain_energy(n)), rel=1e-12)
    assert np.max(np.abs(e - e[0])) < 1e-8
    assert np.max(r["system.constraint_error"]) < 1e-10


@pytest.mark.parametrize("n", [2, 3])
def test_four_bar_chain_passes_the_change_points(n):
    """Through the singular position (all bars horizontal, N + 1 degrees of freedom for
    an instant) the chain stays one parallelogram chain: over 3 s the rockers turn more
    than a full turn, passing the horizontal four times, and still share one angle, which
    follows the one-degree-of-freedom equation to 1e-5 rad; energy holds to 3e-4 J of
    51 J (rtol 1e-7: measured 1.8e-6 rad and 6e-5 J). At tight tolerances
    tests/test_singular_positions.py checks the passage against the same equation."""
    r = four_bar_chain(n).simulate(3.0, rate=200, method="dopri5", rtol=1e-7, atol=1e-9)
    assert r.status == "finished", r.message
    phi = rocker_angles(r, n)
    assert phi[0][-1] < math.pi / 2 - 2 * math.pi  # more than one turn
    assert np.max(np.abs(phi - phi[0])) < 1e-9
    assert np.max(np.abs(phi[0] - one_dof_angle(n, np.asarray(r.time)))) < 1e-5
    e = total_energy(r)
    assert np.max(np.abs(e - e[0])) < 3e-4


def test_n_link_chain_conserves_energy_and_holds_together():
    """Four bars released from horizontal (chaotic motion) for 2 s: the total energy
    (zero at release) stays within 1e-8 of the largest kinetic energy reached (about
    77 J), and each bar's end B meets the next bar's end A to 1e-10 m."""
    n = 4
    m = n_link_chain(n)
    assert m.degrees_of_freedom() == n
    assert m.check() == []
    r = m.simulate(2.0, rate=200, **TIGHT)
    assert r.status == "finished", r.message
    e = total_energy(r)
    scale = np.max(r["system.kinetic_energy"])
    assert scale > 50.0
    assert abs(e[0]) < 1e-12
    assert np.max(np.abs(e - e[0])) < 1e-8 * scale

    def end(i: int, sign: float) -> np.ndarray:
        a = r[f"link_{i}.angle"]
        return np.array(
            [r[f"link_{i}.x"] + sign * 0.5 * np.cos(a), r[f"link_{i}.y"] + sign * 0.5 * np.sin(a)]
        )

    assert np.max(np.abs(end(1, -1.0))) < 1e-10  # pinned at the origin
    for i in range(1, n):
        assert np.max(np.abs(end(i, 1.0) - end(i + 1, -1.0))) < 1e-10


def test_one_link_is_the_compound_pendulum():
    """N = 1: a bar pinned at one end, released horizontal, starts with the angular
    acceleration -3 g / (2 L)."""
    r = n_link_chain(1, link_length=0.5, link_mass=2.0).simulate(1e-9, rate=1e9, **TIGHT)
    assert r["link_1.alpha"][0] == pytest.approx(-3 * G / (2 * 0.5), rel=1e-10)


def test_sizes_below_one_are_refused():
    with pytest.raises(ValueError, match="n_loops"):
        four_bar_chain(0)
    with pytest.raises(ValueError, match="n_links"):
        n_link_chain(0)
