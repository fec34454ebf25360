"""Mechanisms of any size for benchmarks: the chain of N four-bar loops and the N-link chain.

Both are built with the public :class:`jointgap.Model` builder, so they run through the
same path as any user model; ``benchmarks/scaling.py`` uses them to measure how the cost
of a step grows with the size of the mechanism.

>>> import benchmark_models as bm
>>> model = bm.four_bar_chain(3)
>>> len(model.bodies), model.degrees_of_freedom()
(7, 1)
>>> bm.n_link_chain(5).degrees_of_freedom()
5

**The chain of N four-bar loops** (:func:`four_bar_chain`) is problem A02, "N four-bar
mechanism", of the multibody benchmark library of the IFToMM Technical Committee for
Multibody Dynamics (M. Gonzalez, D. Dopico, U. Lugris, J. Cuadrado, A benchmarking
system for MBS simulation software: problem standardization and performance
measurement, *Multibody System Dynamics* 16 (2006) 179-190; specification
``http://lim.ii.udc.es/mbsbenchmark/dist/A02/A02_specification.xml``), an extension of
the two four-bar mechanism of E. Bayo and A. Avello, Singularity-free augmented
Lagrangian algorithms for constrained multibody dynamics, *Nonlinear Dynamics* 5 (1994)
209-231. Its data:

- 2N + 1 links, each 1 m long with a uniformly distributed mass of 1 kg (a slender bar:
  moment of inertia m L^2 / 12 about its centre);
- ground pivots A_0 ... A_N every 1 m along x; N + 1 vertical rockers A_i B_i (B_i at
  y = 1 m) and N horizontal couplers B_(i-1) B_i: N parallelogram windows in a row;
- gravity 9.81 N/kg along -y;
- at t = 0 the mechanism is in that position and point B_0 moves at 1 m/s along +x;
  the benchmark runs 20 s with N = 40 (reference: x and y of B_0).

The mechanism has one degree of freedom: 3 (2N + 1) coordinates less 2 (3N + 1) pin
equations. In the plane none of its pin equations is redundant at the initial position
(each coupler is its own body), so the engine's assembly removes no row; every window
is a parallelogram, the couplers translate and all rockers keep the same angle. When the
rockers pass the horizontal all bars are collinear (a change point): the Jacobian loses
N ranks there and the mechanism instantaneously has N + 1 degrees of freedom, the
singular position the benchmark is about. The rockers start at the top and turn through
the horizontal 0.71-0.72 s later (0.717 s for N = 3); benchmarks of cost per step stop before it.

**The N-link chain** (:func:`n_link_chain`) is a planar pendulum of N uniform bars pinned
end to end, the first one to the ground at the origin, released from rest lying along
+x under gravity: N degrees of freedom, 2N constraint rows, no loops.
"""

from __future__ import annotations

import math

from jointgap import Model

__all__ = [
    "G",
    "four_bar_chain",
    "four_bar_chain_energy",
    "n_link_chain",
]

G = 9.81
"""Gravity of both benchmark mechanisms [m/s^2] (the benchmark's 9.81 N/kg)."""


def _bar(
    model: Model,
    name: str,
    length: float,
    mass: float,
    position: tuple[float, float],
    angle: float,
    velocity: tuple[float, float] = (0.0, 0.0),
    omega: float = 0.0,
) -> None:
    """A uniform slender bar along its body x axis, end points ``A`` (at -L/2) and ``B``."""
    half = 0.5 * length
    model.add_body(
        name,
        mass=mass,
        inertia=mass * length**2 / 12.0,
        position=position,
        angle=angle,
        velocity=velocity,
        omega=omega,
        points={"A": (-half, 0.0), "B": (half, 0.0)},
        shape={"type": "bar", "from": "A", "to": "B", "width": 0.04 * length},
    )


def four_bar_chain(
    n_loops: int,
    *,
    link_length: float = 1.0,
    link_mass: float = 1.0,
    speed: float = 1.0,
    gravity: float = G,
) -> Model:
    """The chain of ``n_loops`` four-bar (parallelogram) loops, benchmark problem A02.

    Bodies ``rocker_0`` ... ``rocker_N`` (vertical at t = 0, point ``A`` at the ground
    pivot ``A<i>`` = (i L, 0), point ``B`` on top, body angle pi/2) and ``coupler_1`` ...
    ``coupler_N`` (horizontal at y = L, from ``B`` of ``rocker_<i-1>`` to ``B`` of
    ``rocker_<i>``). Joints: ``pivot_<i>`` (ground - rocker i), ``left_<i>`` (rocker i-1
    - coupler i) and ``right_<i>`` (coupler i - rocker i), all revolute.

    Args:
        n_loops: number of loops N >= 1 (2N + 1 bodies, 6N + 3 coordinates, 6N + 2
            constraint rows).
        link_length: length of every bar [m] (benchmark: 1 m).
        link_mass: mass of every bar [kg] (benchmark: 1 kg).
        speed: initial speed of point B_0, the top of ``rocker_0``, along +x [m/s]
            (benchmark: 1 m/s); every rocker then turns at -speed / L and every coupler
            translates at ``speed``, a consistent initial velocity.
        gravity: gravity along -y [m/s^2].

    Returns:
        The model; :func:`four_bar_chain_energy` gives its total energy at t = 0.
    """
    if n_loops < 1:
        raise ValueError(f"n_loops = {n_loops}: must be at least 1")
    length = float(link_length)
    half = 0.5 * length
    omega = -float(speed) / length
    model = Model(f"four_bar_chain_{n_loops}", gravity=(0.0, -float(gravity)))
    for i in range(n_loops + 1):
        model.add_ground_point(f"A{i}", (i * length, 0.0))
        _bar(
            model,
            f"rocker_{i}",
            length,
            link_mass,
            position=(i * length, half),
            angle=0.5 * math.pi,
            velocity=(-omega * half, 0.0),
            omega=omega,
        )
        model.add_revolute(f"pivot_{i}", "ground", f"rocker_{i}", point_i=f"A{i}", point_j="A")
    for i in range(1, n_loops + 1):
        _bar(
            model,
            f"coupler_{i}",
            length,
            link_mass,
            position=((i - 0.5) * length, length),
            angle=0.0,
            velocity=(-omega * length, 0.0),
            omega=0.0,
        )
        model.add_revolute(f"left_{i}", f"rocker_{i - 1}", f"coupler_{i}", point_i="B", point_j="A")
        model.add_revolute(f"right_{i}", f"coupler_{i}", f"rocker_{i}", point_i="B", point_j="B")
    return model


def four_bar_chain_energy(
    n_loops: int,
    *,
    link_length: float = 1.0,
    link_mass: float = 1.0,
    speed: float = 1.0,
    gravity: float = G,
) -> tuple[float, float]:
    """Kinetic and potential energy [J] of :func:`four_bar_chain` at t = 0 (potential
    ``sum m g y`` of the centres of mass, zero at y = 0, as the engine reports it).

    Each rocker turns about its pivot, ``J_pivot omega^2 / 2`` with ``J_pivot = m L^2 /
    3``; each coupler translates at ``speed``."""
    n = n_loops
    omega = speed / link_length
    kinetic = (n + 1) * link_mass * link_length**2 / 6.0 * omega**2 + n * link_mass * speed**2 / 2
    potential = gravity * link_mass * link_length * ((n + 1) * 0.5 + n)
    return kinetic, potential


def n_link_chain(
    n_links: int,
    *,
    link_length: float = 1.0,
    link_mass: float = 1.0,
    gravity: float = G,
) -> Model:
    """A planar chain of ``n_links`` uniform bars, pinned end to end and to the ground at
    the origin, released from rest lying along +x.

    Bodies ``link_1`` ... ``link_N`` (link i from x = (i-1) L to i L, angle 0), joints
    ``pin_1`` (ground - link 1) ... ``pin_N`` (link i-1 - link i), all revolute: N
    degrees of freedom, 3N coordinates, 2N constraint rows.

    Args:
        n_links: number of bars N >= 1.
        link_length: length of every bar [m].
        link_mass: mass of every bar [kg].
        gravity: gravity along -y [m/s^2].
    """
    if n_links < 1:
        raise ValueError(f"n_links = {n_links}: must be at least 1")
    length = float(link_length)
    model = Model(f"n_link_chain_{n_links}", gravity=(0.0, -float(gravity)))
    model.add_ground_point("O", (0.0, 0.0))
    for i in range(1, n_links + 1):
        _bar(model, f"link_{i}", length, link_mass, position=((i - 0.5) * length, 0.0), angle=0.0)
        if i == 1:
            model.add_revolute("pin_1", "ground", "link_1", point_i="O", point_j="A")
        else:
            model.add_revolute(f"pin_{i}", f"link_{i - 1}", f"link_{i}", point_i="B", point_j="A")
    return model
