"""Friction in a clearance joint, felt through the motor and through a spring.

1. A journal held against the bottom of its bearing (load N, guided vertically so it
   can neither turn nor move sideways) while the bearing, a ring on a motor, is turned
   through a slow speed sweep. The slip is v_t = -omega R_B, set by the motor; the
   torque the motor needs is J alpha - R_B mu(v_t) N by the ring's moment balance. The
   test writes each friction law (docs/physics.md section 4) itself and checks the motor
   torque the engine computes (a Lagrange multiplier, not the contact channel) across
   the sweep: the stick peak mu_s at v_s and the fall to mu_d at v_d of the ADAMS law.
2. Stick-slip: the journal may turn, held by a torsion spring, while the ring turns at
   constant speed. It sticks (winding the spring) until the spring torque reaches the
   static friction moment R_J mu_s N, then slips back harmonically under kinetic friction
   and re-sticks at the mirror image about R_J mu_d N: the spring torque cycles between
   R_J mu_s N and R_J (2 mu_d - mu_s) N.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import jointgap
import numpy as np
import pytest
from jointgap import laws

G = 9.81
R_B, C = 7.5e-3, 0.5e-3
R_J = R_B - C
LOAD = 100.0  # normal force: gravity on the carrier and pin plus a downward push [N]
M_CARRIER, M_PIN, J_PIN = 1.0, 0.05, 2e-6
J_RING = 1e-4
MU_S, MU_D, V_S, V_D = 0.08, 0.05, 1e-4, 0.01016


def step(x: float, x0: float, h0: float, x1: float, h1: float) -> float:
    """The cubic STEP of ADAMS, written out."""
    s = min(max((x - x0) / (x1 - x0), 0.0), 1.0)
    return h0 + (h1 - h0) * s * s * (3.0 - 2.0 * s)


def mu_adams(v: float) -> float:
    a = abs(v)
    if a <= V_S:
        return step(v, -V_S, -MU_S, V_S, MU_S)
    if a <= V_D:
        return math.copysign(step(a, V_S, MU_S, V_D, MU_D), v)
    return math.copysign(MU_D, v)


def mu_ambrosio(v: float, mu: float = 0.06, v0: float = 1e-4, v1: float = 1e-2) -> float:
    c_d = min(max((abs(v) - v0) / (v1 - v0), 0.0), 1.0)
    return math.copysign(mu * c_d, v)


def ring_and_journal(friction: laws.Law, ring_motion: jointgap.profiles.Profile, pin_turns: bool):
    """A ring (bearing, radius R_B) on a motor about the origin; the journal below its
    centre on a carrier that slides vertically and is pushed down so that the contact
    force is LOAD. With ``pin_turns`` the journal is a separate pin on a revolute of the
    carrier, held by a torsion spring; otherwise the journal is the carrier itself."""
    m = jointgap.Model("friction_rig", gravity=(0.0, -G))
    m.add_ground_point("O", (0.0, 0.0))
    m.add_body("ring", 0.5, J_RING)
    m.add_revolute("ring_bearing", "ground", "ring", point_i="O", point_j=(0.0, 0.0))
    m.add_driver("motor", "ring_bearing", ring_motion)
    y0 = -C  # journal touching the bottom of the bearing
    m.add_body("carrier", M_CARRIER, 1e-3, position=(0.0, y0))
    m.add_prismatic("guide", "ground", "carrier", axis=(0.0, 1.0), point_i="O", point_j=(0.0, 0.0))
    weight = (M_CARRIER + (M_PIN if pin_turns else 0.0)) * G
    m.add_force("push", "carrier", (0.0, -(LOAD - weight)))
    journal = "carrier"
    if pin_turns:
        m.add_body("pin", M_PIN, J_PIN, position=(0.0, y0))
        m.add_revolute("pin_axle", "carrier", "pin", point_i=(0.0, 0.0), point_j=(0.0, 0.0))
        m.add_rotational_spring_damper("spring", "carrier", "pin", stiffness=SPRING)
        journal = "pin"
    m.add_clearance_revolute(
        "gap",
        "ring",
        journal,
        point_bearing=(0.0, 0.0),
        point_journal=(0.0, 0.0),
        bearing_radius=R_B,
        clearance=C,
        stiffness=1e10,
        normal_law=laws.adams_impact("2000 N*s/m", "1e-5 m"),
        friction=friction,
    )
    return m


SWEEP_SPEED = 0.03 / R_B  # ring speed at the ends of the sweep: 30 mm/s at the wall
SWEEP = jointgap.table_speed(
    [0.0, 0.05, 2.05, 2.1], [-SWEEP_SPEED, -SWEEP_SPEED, SWEEP_SPEED, SWEEP_SPEED]
)


@pytest.mark.parametrize(
    ("friction", "mu"),
    [
        (laws.coulomb(MU_S, MU_D, V_S, V_D), mu_adams),
        (laws.modified_coulomb(0.06, 1e-4, 1e-2), mu_ambrosio),
        (laws.viscous_coulomb(0.06, 1e-3, 0.5), None),
    ],
    ids=["coulomb", "modified_coulomb", "viscous_coulomb"],
)
def test_motor_feels_the_friction_law(
    engine, friction: laws.Law, mu: Callable[[float], float] | None
) -> None:
    r = ring_and_journal(friction, SWEEP, pin_turns=False).simulate(
        2.1, rate=20_000, rtol=1e-8, atol=1e-12
    )
    assert r.ok, r.message
    after = r.time > 0.06  # the journal has settled on the wall
    omega, alpha = r["ring.omega"][after], r["ring.alpha"][after]
    slip = -omega * R_B
    np.testing.assert_allclose(r["gap.slip"][after], slip, atol=1e-9)
    np.testing.assert_allclose(r["gap.fn"][after], LOAD, rtol=1e-6)
    if mu is None:  # viscous-Coulomb: mu N tanh(v / v_s) + c v
        f_t = -(0.06 * LOAD * np.tanh(slip / 1e-3) + 0.5 * slip)
    else:
        f_t = -LOAD * np.array([mu(v) for v in slip])
    expected = J_RING * alpha + R_B * f_t
    torque = r["motor.torque"][after]
    scale = R_B * 0.08 * LOAD
    assert np.max(np.abs(torque - expected)) < 1e-6 * scale
    # The guide holds the journal against the drag: its reaction is -F_T.
    np.testing.assert_allclose(r["guide.fx"][after], -f_t, atol=1e-6 * LOAD)
    if mu is mu_adams:
        # The sweep really crosses the stick peak and the fall to kinetic friction.
        peak = np.max(torque - J_RING * alpha)
        assert peak == pytest.approx(R_B * MU_S * LOAD, rel=2e-3)
        fast = np.abs(slip) > V_D
        assert np.all(np.abs(np.abs(torque - J_RING * alpha)[fast] / (R_B * LOAD) - MU_D) < 1e-6)


SPRING = 0.05  # torsion spring of the pin [N m/rad]
RING_SPEED = 0.02 / R_B  # 20 mm/s at the bearing wall


def test_stick_slip_cycles_between_static_and_kinetic_friction(engine) -> None:
    m = ring_and_journal(
        laws.coulomb(MU_S, MU_D, V_S, V_D), jointgap.constant_speed(RING_SPEED), True
    )
    r = m.simulate(1.2, rate=20_000, rtol=1e-8, atol=1e-12)
    assert r.ok, r.message
    spring_torque = SPRING * (r["pin.angle"] - r["carrier.angle"])
    static, kinetic = R_J * MU_S * LOAD, R_J * MU_D * LOAD
    slip = r["gap.slip"]
    sticking = np.abs(slip) < V_S
    # Stick: the journal's wall moves with the ring's (slip below v_s) most of the time.
    assert np.mean(sticking) > 0.7
    # Breakaway at the static friction moment, every cycle.
    breakaways = np.flatnonzero(sticking[:-1] & ~sticking[1:])
    assert len(breakaways) >= 3
    for i in breakaways:
        assert spring_torque[i] == pytest.approx(static, rel=5e-3)
    # Slip: harmonic about the kinetic friction moment, so the spring unloads to its
    # mirror image 2 kinetic - static before the journal sticks again.
    first = breakaways[0]
    low = np.min(spring_torque[first:])
    assert low == pytest.approx(2 * kinetic - static, abs=0.03 * (static - kinetic))
