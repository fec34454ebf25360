"""Independent cross-check of the founding case against a minimal-coordinate model.

The founding case is the slider-crank of Haroun & Megahed with a clearance in the joint
between the connecting rod and the slider (docs/physics.md section 5,
examples/slider_crank_clearance.toml). The engine solves it in Cartesian coordinates:
three bodies, nine coordinates, Lagrange multipliers for the ideal joints and the crank
driver, and the clearance joint as a force element. This file writes the same mechanism
again, from the physics, with the fewest unknowns, and solves it with SciPy's stiff Radau
IIA integrator at tight tolerance.

Reference model
---------------
The crank angle is prescribed (0 to 300 rpm in 0.2 s, then constant), so the crank pin
``A(t) = r (cos th, sin th)`` and its velocity and acceleration are known functions of
time. The only unknowns are the rod angle ``phi`` and the slider position ``x`` (the
prismatic guide keeps the slider on ``y = 0`` without rotating):

- rod (mass ``m_r``, ``J_r`` about its centre of mass ``G = A + a u``, ``u = (cos phi,
  sin phi)``, ``a = L/2``) pinned at the kinematically driven point ``A``: Newton-Euler
  with the pin reaction ``R_A = m_r a_G - m_r g - F`` eliminated gives, about ``A``,

      (J_r + m_r a^2) phi'' = -m_r a (u x A'') + m_r a (u x g) + (Q_J - A) x F

  with ``F = -F_N n + F_T t`` the contact force on the journal, applied at ``Q_J``;
- slider (mass ``m_s``): ``m_s x'' = -F_x``, the opposite force on the bearing (its
  ``y`` component and its moment go into the guide);
- contact (docs/physics.md sections 2-4): journal centre ``r_J = A + L u``, bearing centre
  ``r_B = (x, 0)``, ``e = r_J - r_B``, ``delta = |e| - c``, ``n = e/|e|``, ``t`` = ``n``
  turned by +90 degrees; ``Q_J = r_J + R_J n``, ``Q_B = r_B + R_B n``; the relative
  velocity of the contact points ``v = (A' + phi' k x (Q_J - A)) - (x', 0)`` gives
  ``delta' = v . n`` and the slip ``v_t = v . t``. ADAMS IMPACT normal force
  ``F_N = max(0, K delta^1.5 + STEP(delta, 0, 0, d_max, C_max) delta')`` with ``K`` from
  the materials (journal radius positive, bearing radius negative), ADAMS Coulomb friction
  ``F_T = -mu(v_t) F_N``;
- motor torque, from the crank's Euler equation about the fixed pivot ``O``
  (``J_O = J_c + m_c (r/2)^2``), the rod pushing on the crank with ``-R_A`` at ``A``:

      torque = J_O th'' - (r/2 e_th) x (m_c g) + A x R_A

  the torque the motor applies to the crank, counter-clockwise positive: the engine's
  ``motor.torque`` convention (docs/drivers.md).

The corner of the driver at 0.2 s is integrated as a boundary between two solves, and
contact onsets and separations are located as SciPy events.

What it proves
--------------
Two formulations that share no code (Cartesian coordinates with multipliers, projection,
DOPRI5 then SDIRK4, against two minimal coordinates with Radau IIA) agree over 0 to 0.5 s
of the founding case, ramp and one and a half turns at full speed, about twenty impacts
and several continuous contacts, with spells of sticking (slip below v_s): the same
impacts (number and onset times), the same peak slider acceleration and peak contact
force (within 0.5 %), and the same slider acceleration, contact force and motor torque
histories (NRMSE below 1e-3). This checks the engine's contact geometry (normal, contact
points, relative velocity including rotation), its normal and friction laws and their
signs, the application of the contact forces at the contact points, the driver's
reaction, and the integration through impacts and sticking.

Measured (engine rtol 1e-10, reference rtol 1e-9): 21 impacts on both sides, onset times
within 1e-9 s, peaks within 1e-5 relative, NRMSEs about 5e-8. The bounds are far from
loose for this motion: changing K or the friction coefficients by 1 % in the reference
alone raises the NRMSEs to about 1e-2; dropping the friction or flipping its sign, to
3e-2 and more, with twice the impacts.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

import jointgap
import numpy as np
import pytest
from numpy.typing import NDArray
from scipy.integrate import OdeSolution, solve_ivp
from scipy.optimize import minimize_scalar

EXAMPLE = Path(__file__).resolve().parent.parent / "examples" / "slider_crank_clearance.toml"

# --- the founding case (docs/physics.md section 5), SI units ---------------------------

G = 9.81  # gravity, along -y [m/s^2]
OMEGA = 300 * 2 * math.pi / 60  # final crank speed, 300 rpm [rad/s]
RAMP = 0.2  # time to reach it from rest [s]
T_END = 0.5  # [s]
RATE = 10_000  # output samples per second [Hz]

R_CRANK = 0.08  # crank length [m]
M_CRANK = 2.37  # [kg]
J_CRANK = 0.01201  # about its centre of mass, at mid-length [kg m^2]
L_ROD = 0.32  # rod length, pin A to journal centre B [m]
M_ROD = 0.72  # [kg]
J_ROD = 0.0006926  # about its centre of mass, at mid-length [kg m^2]
M_SLIDER = 2.28  # [kg]
X_SLIDER_0 = R_CRANK + L_ROD  # fully extended at t = 0 [m]

R_BEARING = 7.5e-3  # [m]
CLEARANCE = 0.5e-3  # radial [m]
R_JOURNAL = R_BEARING - CLEARANCE  # 7.0 mm
E_BEARING, NU_BEARING = 97e9, 0.3  # brass [Pa]
E_JOURNAL, NU_JOURNAL = 207e9, 0.3  # steel [Pa]
C_MAX = 27960.0  # ADAMS IMPACT full damping [N s/m]
D_MAX = 1e-5  # penetration of full damping [m]
EXPONENT = 1.5
MU_S, MU_D = 0.08, 0.05  # static and dynamic friction coefficients
V_S, V_D = 1e-4, 0.01016  # friction transition speeds [m/s]


def contact_stiffness() -> float:
    """K = 4 / (3 (sigma_J + sigma_B)) sqrt(R_J R_B / (R_J + R_B)), sigma = (1 - nu^2)/E,
    with the journal radius positive and the bearing radius negative [N/m^1.5]."""
    sigma_j = (1 - NU_JOURNAL**2) / E_JOURNAL
    sigma_b = (1 - NU_BEARING**2) / E_BEARING
    r_i, r_j = R_JOURNAL, -R_BEARING
    return 4 / (3 * (sigma_j + sigma_b)) * math.sqrt(r_i * r_j / (r_i + r_j))


K = contact_stiffness()
HALF_ROD = L_ROD / 2
J_ROD_PIN = J_ROD + M_ROD * HALF_ROD**2  # rod about its pin A
J_CRANK_PIVOT = J_CRANK + M_CRANK * (R_CRANK / 2) ** 2  # crank about its pivot O

# Tolerances. The difference between the two (NRMSE about 5e-8 with these, 1e-7 with the
# reference at rtol 1e-8) is four orders below the bounds asserted here.
ENGINE_RTOL, ENGINE_ATOL = 1e-10, 1e-13
REF_RTOL, REF_ATOL = 1e-9, 1e-12

PEAK_TOLERANCE = 0.005  # the 0.5 %
NRMSE_BOUND = 1e-3


# --- the minimal-coordinate model --------------------------------------------------------


def step(x: float, x0: float, h0: float, x1: float, h1: float) -> float:
    """ADAMS cubic STEP from (x0, h0) to (x1, h1), constant outside [x0, x1]."""
    s = (x - x0) / (x1 - x0)
    s = 0.0 if s < 0.0 else 1.0 if s > 1.0 else s
    return h0 + (h1 - h0) * s * s * (3.0 - 2.0 * s)


def friction_coefficient(v_t: float) -> float:
    """ADAMS Coulomb mu(v_t): odd in the slip, mu_s at v_s, mu_d beyond v_d."""
    speed = abs(v_t)
    if speed <= V_S:
        return step(v_t, -V_S, -MU_S, V_S, MU_S)
    sign = 1.0 if v_t > 0.0 else -1.0
    if speed <= V_D:
        return sign * step(speed, V_S, MU_S, V_D, MU_D)
    return sign * MU_D


def crank_motion(t: float) -> tuple[float, float, float]:
    """Crank angle, speed and acceleration of the linear ramp; at the corners (t = 0 and
    t = RAMP) the acceleration after the corner, as the engine samples it."""
    if t < RAMP:
        return 0.5 * OMEGA * t * t / RAMP, OMEGA * t / RAMP, OMEGA / RAMP
    return 0.5 * OMEGA * RAMP + OMEGA * (t - RAMP), OMEGA, 0.0


@dataclass(frozen=True)
class Dynamics:
    """Everything the equations of motion give at one state."""

    phi_dd: float  # rod angular acceleration [rad/s^2]
    x_dd: float  # slider acceleration [m/s^2]
    fx: float  # contact force on the journal (rod), global x [N]
    fy: float  # ... and y [N]
    fn: float  # normal contact force, compressive positive [N]
    ft: float  # friction force along t [N]
    delta: float  # penetration [m]
    theta: float  # crank angle [rad]
    theta_dd: float  # crank angular acceleration [rad/s^2]
    pin_acc: tuple[float, float]  # acceleration of the crank pin A [m/s^2]


def dynamics(t: float, phi: float, x: float, phi_d: float, x_d: float) -> Dynamics:
    """Rod and slider accelerations and the contact force at time t (plain floats: this
    is the integrator's right-hand side)."""
    th, th_d, th_dd = crank_motion(t)
    c, s = math.cos(th), math.sin(th)
    ax, ay = R_CRANK * c, R_CRANK * s  # crank pin A
    vax, vay = -R_CRANK * s * th_d, R_CRANK * c * th_d
    aax = -R_CRANK * s * th_dd - R_CRANK * c * th_d * th_d
    aay = R_CRANK * c * th_dd - R_CRANK * s * th_d * th_d
    cp, sp = math.cos(phi), math.sin(phi)
    jx, jy = ax + L_ROD * cp, ay + L_ROD * sp  # journal centre
    ex, ey = jx - x, jy  # eccentricity: journal centre minus bearing centre (x, 0)
    ecc = math.hypot(ex, ey)
    delta = ecc - CLEARANCE
    fx = fy = fn = ft = moment_a = 0.0
    if delta > 0.0:
        nx, ny = ex / ecc, ey / ecc
        tx, ty = -ny, nx
        qx, qy = jx + R_JOURNAL * nx, jy + R_JOURNAL * ny  # contact point on the journal
        # vel(Q_J) on the rod (pinned at A, turning at phi_d) minus vel(Q_B) on the
        # slider, which translates at (x_d, 0) without turning.
        vx = vax - phi_d * (qy - ay) - x_d
        vy = vay + phi_d * (qx - ax)
        delta_d = vx * nx + vy * ny
        slip = vx * tx + vy * ty
        fn = K * delta**EXPONENT + step(delta, 0.0, 0.0, D_MAX, C_MAX) * delta_d
        if fn > 0.0:
            ft = -friction_coefficient(slip) * fn
        else:
            fn = 0.0
        fx = -fn * nx + ft * tx
        fy = -fn * ny + ft * ty
        moment_a = (qx - ax) * fy - (qy - ay) * fx  # about the pin A
    u_cross_pin_acc = cp * aay - sp * aax
    u_cross_g = cp * -G
    phi_dd = (
        -M_ROD * HALF_ROD * u_cross_pin_acc + M_ROD * HALF_ROD * u_cross_g + moment_a
    ) / J_ROD_PIN
    return Dynamics(phi_dd, -fx / M_SLIDER, fx, fy, fn, ft, delta, th, th_dd, (aax, aay))


def rhs(t: float, y: NDArray[np.float64]) -> list[float]:
    """y = (phi, x, phi', x')."""
    phi, x, phi_d, x_d = y.tolist()
    d = dynamics(t, phi, x, phi_d, x_d)
    return [phi_d, x_d, d.phi_dd, d.x_dd]


def outputs(t: float, y: NDArray[np.float64]) -> tuple[float, float, float]:
    """Slider acceleration [m/s^2], normal contact force [N] and motor torque [N m]."""
    phi, x, phi_d, x_d = (float(v) for v in y)
    d = dynamics(t, phi, x, phi_d, x_d)
    cp, sp = math.cos(phi), math.sin(phi)
    aax, aay = d.pin_acc
    # Rod centre of mass acceleration, then the force of the crank on the rod at A from
    # m_r a_G = R_A + m_r g + F.
    agx = aax - HALF_ROD * (d.phi_dd * sp + phi_d * phi_d * cp)
    agy = aay + HALF_ROD * (d.phi_dd * cp - phi_d * phi_d * sp)
    rax = M_ROD * agx - d.fx
    ray = M_ROD * agy + M_ROD * G - d.fy
    c, s = math.cos(d.theta), math.sin(d.theta)
    # Crank about O: J_O th'' = torque + (r/2 e_th) x (m_c g) + A x (-R_A).
    torque = J_CRANK_PIVOT * d.theta_dd + M_CRANK * G * 0.5 * R_CRANK * c
    torque += R_CRANK * (c * ray - s * rax)
    return d.x_dd, d.fn, torque


def penetration_array(t: NDArray[np.float64], y: NDArray[np.float64]) -> NDArray[np.float64]:
    """Penetration at many times at once (y: 4 x n states)."""
    th = np.where(t < RAMP, 0.5 * OMEGA * t**2 / RAMP, OMEGA * (t - 0.5 * RAMP))
    jx = R_CRANK * np.cos(th) + L_ROD * np.cos(y[0])
    jy = R_CRANK * np.sin(th) + L_ROD * np.sin(y[0])
    result: NDArray[np.float64] = np.hypot(jx - y[1], jy) - CLEARANCE
    return result


def penetration_event(t: float, y: NDArray[np.float64]) -> float:
    return dynamics(t, *y.tolist()).delta


def onset_event(t: float, y: NDArray[np.float64]) -> float:
    """Contact onset: the penetration crosses zero upwards."""
    return penetration_event(t, y)


def separation_event(t: float, y: NDArray[np.float64]) -> float:
    """Separation: the penetration crosses zero downwards."""
    return penetration_event(t, y)


onset_event.direction = 1  # type: ignore[attr-defined]
separation_event.direction = -1  # type: ignore[attr-defined]


@dataclass
class Reference:
    """The minimal-coordinate solution: one dense solution per side of the ramp's end."""

    pieces: list[tuple[float, float, OdeSolution, NDArray[np.float64]]]  # t0, t1, sol, steps
    onsets: list[float]
    separations: list[float]
    wall_time: float
    steps: int

    def states(self, t: NDArray[np.float64]) -> NDArray[np.float64]:
        """States (4 x n) at the times t, from each piece's dense output; a time on the
        ramp's corner takes the piece after it."""
        y = np.empty((4, len(t)))
        for k, (t0, t1, sol, _) in enumerate(self.pieces):
            last = k == len(self.pieces) - 1
            inside = (t >= t0) & ((t <= t1) if last else (t < t1))
            y[:, inside] = sol(t[inside])
        return y

    def sample(self, t: NDArray[np.float64]) -> NDArray[np.float64]:
        """slider.ax, rod_slider.fn and motor.torque (3 x n) at the times t."""
        y = self.states(t)
        return np.array([outputs(float(ti), y[:, i]) for i, ti in enumerate(t)]).T

    def peak_contact_force(self) -> float:
        """Largest normal force over the run: the largest at the integrator's steps,
        refined on the dense output between the neighbouring steps."""
        best = 0.0
        for _, _, sol, ts in self.pieces:
            ys = sol(ts)
            forces = [outputs(float(t), ys[:, i])[1] for i, t in enumerate(ts)]
            k = int(np.argmax(forces))
            lo, hi = ts[max(k - 1, 0)], ts[min(k + 1, len(ts) - 1)]
            found = minimize_scalar(
                lambda t, sol=sol: -outputs(t, sol(t))[1],
                bounds=(lo, hi),
                method="bounded",
                options={"xatol": 1e-13},
            )
            best = max(best, forces[k], -float(found.fun))
        return best


def solve_reference() -> Reference:
    """Radau IIA from rest, fully extended and concentric, to T_END, stopping at the end of
    the ramp (where the crank's acceleration jumps)."""
    start = time.perf_counter()
    y0 = np.array([0.0, X_SLIDER_0, 0.0, 0.0])
    pieces = []
    onsets: list[float] = []
    separations: list[float] = []
    steps = 0
    for t0, t1 in ((0.0, RAMP), (RAMP, T_END)):
        sol = solve_ivp(
            rhs,
            (t0, t1),
            y0,
            method="Radau",
            rtol=REF_RTOL,
            atol=REF_ATOL,
            dense_output=True,
            events=(onset_event, separation_event),
        )
        assert sol.status == 0, sol.message
        pieces.append((t0, t1, sol.sol, sol.t))
        onsets += [float(t) for t in sol.t_events[0]]
        separations += [float(t) for t in sol.t_events[1]]
        steps += len(sol.t) - 1
        y0 = sol.y[:, -1]
    return Reference(pieces, onsets, separations, time.perf_counter() - start, steps)


def nrmse(actual: NDArray[np.float64], reference: NDArray[np.float64]) -> float:
    """Normalised root-mean-square error over the common 10 kHz grid:

        NRMSE = sqrt(mean((actual - reference)^2)) / (max(reference) - min(reference))

    the RMS difference as a fraction of the reference's range."""
    return float(np.sqrt(np.mean((actual - reference) ** 2)) / np.ptp(reference))


# --- both runs, once per module ----------------------------------------------------------


@dataclass
class CrossCheck:
    """The engine's run and the reference, sampled on the same grid."""

    time: NDArray[np.float64]
    engine: jointgap.Result
    engine_wall_time: float
    reference: Reference
    ref_samples: dict[str, NDArray[np.float64]]


CHANNELS = ("slider.ax", "rod_slider.fn", "motor.torque")


@pytest.fixture(scope="module")
def crosscheck() -> CrossCheck:
    pytest.importorskip("jointgap._jointgap", reason="the engine is not built: run make install")
    start = time.perf_counter()
    result = jointgap.load(EXAMPLE).simulate(
        t_end=T_END, rate=RATE, rtol=ENGINE_RTOL, atol=ENGINE_ATOL
    )
    engine_wall_time = time.perf_counter() - start
    assert result.status == "finished", result.message
    t = np.arange(int(round(T_END * RATE)) + 1) / RATE
    assert np.allclose(result.time, t, rtol=0, atol=1e-12)
    reference = solve_reference()
    samples = reference.sample(t)
    return CrossCheck(
        t, result, engine_wall_time, reference, dict(zip(CHANNELS, samples, strict=True))
    )


# --- the model file is the modelled mechanism --------------------------------------------


def test_example_file_is_the_modelled_mechanism() -> None:
    """The reference's data are those of examples/slider_crank_clearance.toml, and K from
    the materials is the founding paper's 3.136e10 N/m^1.5."""
    d = jointgap.load(EXAMPLE).to_dict()
    assert d["gravity"] == [0.0, -G]
    bodies = {b["name"]: b for b in d["bodies"]}
    crank, rod, slider = bodies["crank"], bodies["rod"], bodies["slider"]
    assert (crank["mass"], crank["inertia"]) == (M_CRANK, J_CRANK)
    assert (rod["mass"], rod["inertia"]) == (M_ROD, J_ROD)
    assert slider["mass"] == M_SLIDER
    # Bars with the centre of mass at mid-length, all along +x at rest at t = 0.
    assert crank["position"] == pytest.approx([R_CRANK / 2, 0.0])
    assert crank["points"] == {"O": [-R_CRANK / 2, 0.0], "A": [R_CRANK / 2, 0.0]}
    assert rod["position"] == pytest.approx([R_CRANK + HALF_ROD, 0.0])
    assert rod["points"] == {"A": [-HALF_ROD, 0.0], "B": [HALF_ROD, 0.0]}
    assert slider["position"] == pytest.approx([X_SLIDER_0, 0.0])
    assert slider["points"] == {"B": [0.0, 0.0]}
    for b in (crank, rod, slider):
        assert b["angle"] == 0.0 and b["omega"] == 0.0 and b["velocity"] == [0.0, 0.0]
    joints = {j["name"]: j for j in d["joints"]}
    assert joints["slider_guide"]["axis"] == [1.0, 0.0]
    gap = joints["rod_slider"]
    assert (gap["body_i"], gap["body_j"]) == ("slider", "rod")  # bearing, journal
    cl = gap["clearance"]
    assert (cl["bearing_radius"], cl["clearance"]) == (R_BEARING, CLEARANCE)
    assert cl["bearing_material"] == {"youngs_modulus": E_BEARING, "poisson_ratio": NU_BEARING}
    assert cl["journal_material"] == {"youngs_modulus": E_JOURNAL, "poisson_ratio": NU_JOURNAL}
    assert cl["normal_law"] == {
        "type": "adams_impact",
        "exponent": EXPONENT,
        "c_max": C_MAX,
        "d_max": D_MAX,
        "clip": True,
    }
    assert cl["friction"] == {"type": "coulomb", "mu_s": MU_S, "mu_d": MU_D, "v_s": V_S, "v_d": V_D}
    (driver,) = d["drivers"]
    assert driver["joint"] == "ground_crank"
    assert driver["profile"] == {"type": "linear_ramp", "speed": OMEGA, "ramp_time": RAMP}
    assert K == pytest.approx(3.136e10, rel=5e-4)


# --- the cross-check ---------------------------------------------------------------------


def test_same_impacts(engine: None, crosscheck: CrossCheck) -> None:
    """The same number of impacts, at the same onset times."""
    ref = crosscheck.reference
    impacts = crosscheck.engine.impacts["rod_slider"]
    engine_onsets = np.array([i.onset_time for i in impacts])
    ref_onsets = np.array(ref.onsets)
    print(
        f"\nimpacts: engine {len(impacts)}, reference {len(ref_onsets)}; wall time: engine "
        f"{crosscheck.engine_wall_time:.2f} s, reference {ref.wall_time:.2f} s "
        f"({ref.steps} Radau steps)"
    )
    # The reference's event location sees every contact: probing the penetration on the
    # dense output at 1 MHz finds the same onsets.
    t_fine = np.arange(int(round(T_END * 1e6)) + 1) / 1e6
    touching = penetration_array(t_fine, ref.states(t_fine)) > 0.0
    assert np.count_nonzero(touching[1:] & ~touching[:-1]) == len(ref_onsets)
    assert len(ref.separations) in (len(ref_onsets), len(ref_onsets) - 1)

    assert len(impacts) == len(ref_onsets), (
        f"engine onsets {engine_onsets}\nreference onsets {ref_onsets}"
    )
    assert len(impacts) >= 15  # the mechanism does impact: a train after every free flight
    gap = np.max(np.abs(engine_onsets - ref_onsets))
    print(f"largest onset time difference {gap:.2e} s")
    assert gap < 1e-6, f"onset times differ by up to {gap:.3e} s"


def test_same_peaks(engine: None, crosscheck: CrossCheck) -> None:
    """Peak |slider.ax| and peak contact force within 0.5 %.

    The slider acceleration's peak is taken over the common 10 kHz samples on both sides
    (the recorded signal, as an accelerometer sees it). The contact force's peak is taken
    two ways: the engine's impact list (largest force at its steps and samples) against the
    reference's largest force (at its steps, refined on its dense output), and the
    largest of the 10 kHz samples on both sides."""
    eng, ref = crosscheck.engine, crosscheck.ref_samples
    peak_ax = np.max(np.abs(eng["slider.ax"])), np.max(np.abs(ref["slider.ax"]))
    peak_fn_list = (
        max(i.peak_force for i in eng.impacts["rod_slider"]),
        crosscheck.reference.peak_contact_force(),
    )
    peak_fn_samples = np.max(eng["rod_slider.fn"]), np.max(ref["rod_slider.fn"])
    for name, (e, r) in {
        "|slider.ax| (10 kHz)": peak_ax,
        "contact force (impact list)": peak_fn_list,
        "contact force (10 kHz)": peak_fn_samples,
    }.items():
        print(f"\npeak {name}: engine {e:.6g}, reference {r:.6g}, rel. diff {e / r - 1:.2e}")
        assert abs(e / r - 1) < PEAK_TOLERANCE, f"peak {name}: engine {e}, reference {r}"
    # Sizes (docs/physics.md section 5): the impacts dominate, far above the ideal
    # mechanism's 98.7 m/s^2 peak slider acceleration.
    assert peak_ax[1] > 5 * 98.7
    assert peak_fn_list[1] > 1000.0


@pytest.mark.parametrize("channel", CHANNELS)
def test_histories_agree(engine: None, crosscheck: CrossCheck, channel: str) -> None:
    """NRMSE (see nrmse) of slider.ax, rod_slider.fn and motor.torque below 1e-3."""
    actual, reference = crosscheck.engine[channel], crosscheck.ref_samples[channel]
    error = nrmse(actual, reference)
    worst = int(np.argmax(np.abs(actual - reference)))
    print(
        f"\n{channel}: NRMSE {error:.2e}; largest difference "
        f"{actual[worst] - reference[worst]:.3g} at t = {crosscheck.time[worst]:.4f} s "
        f"(range {np.ptp(reference):.4g})"
    )
    assert error < NRMSE_BOUND, f"{channel}: NRMSE {error:.3e}"
