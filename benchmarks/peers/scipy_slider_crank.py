"""Peer benchmark: the founding clearance slider-crank written with SciPy, against jointgap.

The case is examples/slider_crank_clearance.toml (docs/physics.md section 5): the Haroun &
Megahed slider-crank in a vertical plane, crank 0.08 m, rod 0.32 m, the crank driven from
rest to 300 rpm in 0.2 s, and a 0.5 mm radial clearance in the rod-slider joint with an
ADAMS IMPACT contact law and ADAMS Coulomb friction; 0 to 0.5 s.

Here it is written the way a researcher would write it with SciPy: the crank angle is
prescribed, so the only unknowns are the rod angle ``phi`` and the slider position ``x``
(minimal coordinates), the equations of motion are derived by hand, and ``solve_ivp``
integrates them. Every method of ``solve_ivp`` (RK45, DOP853, Radau, BDF, LSODA) runs at
rtol 1e-4 ... 1e-9 (atol = 1e-3 x rtol), finite-difference Jacobians for the implicit
ones (as a researcher would leave them). The solve is split at the end of the crank's
ramp (t = 0.2 s), where the crank's acceleration jumps. The slider acceleration is then
evaluated on a 10 kHz grid from the dense output.

Accuracy: NRMSE of the slider acceleration on that grid against a converged jointgap run
(rtol 1e-11, itself checked against rtol 1e-12), NRMSE = RMS(difference) / (max - min of
the reference). Speed: wall time, best of 2, of the solve plus the evaluation on the grid
(jointgap's ``simulate`` also records at 10 kHz). jointgap's own ``simulate`` (model
loaded once, methods auto and radau5) runs at the same tolerances on the same grid; the
fastest of each side at equal accuracy is compared.

Run from the repository root after ``make install``:

    .venv/bin/python benchmarks/peers/scipy_slider_crank.py [--cap SECONDS] [--quick]

Writes benchmarks/output/peers_scipy.md and benchmarks/results/peers_scipy.json. About
3-4 minutes on 2 shared cores.
"""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import dataclass

import jointgap
import numpy as np
import scipy
from common import (
    JOINTGAP_METHODS,
    MODEL,
    OUTPUT,
    PAIRED_ROUNDS,
    ROOT,
    T_END,
    TARGETS,
    Row,
    fastest,
    fmt,
    grid,
    load_text,
    machine,
    nrmse,
    paired_ratio,
    paired_text,
    reference,
    reference_summary,
    row_dict,
    run_jointgap,
    write_json,
)
from scipy.integrate import solve_ivp

OUT = OUTPUT / "peers_scipy.md"

# --- the founding clearance case, SI units -----------------------------------------------

G = 9.81  # gravity, along -y [m/s^2]
OMEGA = 300 * 2 * math.pi / 60  # final crank speed, 300 rpm [rad/s]
RAMP = 0.2  # time to reach it from rest [s]

R_CRANK = 0.08  # crank length [m]
L_ROD = 0.32  # rod length, crank pin A to journal centre B [m]
M_ROD = 0.72  # [kg]
J_ROD = 0.0006926  # about its centre of mass, at mid-length [kg m^2]
M_SLIDER = 2.28  # [kg]

R_BEARING = 7.5e-3  # bearing (hole in the slider) radius [m]
CLEARANCE = 0.5e-3  # radial clearance [m]
R_JOURNAL = R_BEARING - CLEARANCE  # journal (pin on the rod) radius [m]
E_BEARING, E_JOURNAL, NU = 97e9, 207e9, 0.3  # Young's moduli [Pa], Poisson's ratio
C_MAX = 27960.0  # ADAMS IMPACT full damping [N s/m]
D_MAX = 1e-5  # penetration at which the damping is full [m]
EXPONENT = 1.5
MU_S, MU_D = 0.08, 0.05  # static and dynamic friction coefficients
V_S, V_D = 1e-4, 0.01016  # friction transition speeds [m/s]

# Hertz-type stiffness of a journal in a bearing (bearing radius negative) [N/m^1.5].
SIGMA = (1 - NU**2) / E_JOURNAL + (1 - NU**2) / E_BEARING
K = 4 / (3 * SIGMA) * math.sqrt(R_JOURNAL * R_BEARING / (R_BEARING - R_JOURNAL))
HALF_ROD = L_ROD / 2
J_ROD_PIN = J_ROD + M_ROD * HALF_ROD**2  # rod about the crank pin A


# --- the model: y = (phi, x, phi', x') ---------------------------------------------------


def step(x: float, x0: float, h0: float, x1: float, h1: float) -> float:
    """ADAMS cubic STEP from (x0, h0) to (x1, h1), constant outside [x0, x1]."""
    s = min(max((x - x0) / (x1 - x0), 0.0), 1.0)
    return h0 + (h1 - h0) * s * s * (3.0 - 2.0 * s)


def friction_coefficient(v: float) -> float:
    """ADAMS Coulomb: mu_s at the slip speed v_s, mu_d beyond v_d, odd in the slip."""
    speed = abs(v)
    if speed <= V_S:
        return step(v, -V_S, -MU_S, V_S, MU_S)
    mu = step(speed, V_S, MU_S, V_D, MU_D) if speed <= V_D else MU_D
    return mu if v > 0.0 else -mu


def crank(t: float) -> tuple[float, float, float]:
    """Prescribed crank angle, speed and acceleration (linear speed ramp, then constant)."""
    if t < RAMP:
        return 0.5 * OMEGA * t * t / RAMP, OMEGA * t / RAMP, OMEGA / RAMP
    return 0.5 * OMEGA * RAMP + OMEGA * (t - RAMP), OMEGA, 0.0


def rhs(t: float, y: np.ndarray) -> list[float]:
    """Rod and slider equations of motion.

    Rod pinned at the driven crank pin A, moments about A:
        (J_rod + m_rod a^2) phi'' = -m_rod a u x A'' + m_rod a u x g + (Q - A) x F
    Slider on its guide: m_slider x'' = -F_x. F is the contact force on the journal,
    applied at the contact point Q, the slider gets -F.
    """
    phi, x, phi_d, x_d = y
    th, th_d, th_dd = crank(t)
    c, s = math.cos(th), math.sin(th)
    ax, ay = R_CRANK * c, R_CRANK * s  # crank pin A, its velocity and acceleration
    vax, vay = -ay * th_d, ax * th_d
    aax = -ay * th_dd - ax * th_d * th_d
    aay = ax * th_dd - ay * th_d * th_d
    cp, sp = math.cos(phi), math.sin(phi)
    jx, jy = ax + L_ROD * cp, ay + L_ROD * sp  # journal centre; the bearing's is (x, 0)
    ex, ey = jx - x, jy
    ecc = math.hypot(ex, ey)
    fx = fy = moment = 0.0
    if ecc > CLEARANCE:  # in contact
        delta = ecc - CLEARANCE
        nx, ny = ex / ecc, ey / ecc
        qx, qy = jx + R_JOURNAL * nx, jy + R_JOURNAL * ny  # contact point on the journal
        vx = vax - phi_d * (qy - ay) - x_d  # its velocity relative to the slider
        vy = vay + phi_d * (qx - ax)
        delta_d = vx * nx + vy * ny
        slip = -vx * ny + vy * nx
        fn = K * delta**EXPONENT + step(delta, 0.0, 0.0, D_MAX, C_MAX) * delta_d
        if fn > 0.0:
            ft = -friction_coefficient(slip) * fn
            fx = -fn * nx - ft * ny
            fy = -fn * ny + ft * nx
            moment = (qx - ax) * fy - (qy - ay) * fx
    phi_dd = (M_ROD * HALF_ROD * (sp * aax - cp * aay - cp * G) + moment) / J_ROD_PIN
    return [phi_d, x_d, phi_dd, -fx / M_SLIDER]


def slider_acceleration(t: np.ndarray, y: np.ndarray) -> np.ndarray:
    """x'' at many times at once (y: 4 x n states), the contact force of rhs in numpy."""
    phi, x, phi_d, x_d = y
    ramp = t < RAMP
    th = np.where(ramp, 0.5 * OMEGA * t * t / RAMP, OMEGA * (t - 0.5 * RAMP))
    th_d = np.where(ramp, OMEGA * t / RAMP, OMEGA)
    ax, ay = R_CRANK * np.cos(th), R_CRANK * np.sin(th)
    vax, vay = -ay * th_d, ax * th_d
    jx, jy = ax + L_ROD * np.cos(phi), ay + L_ROD * np.sin(phi)
    ex, ey = jx - x, jy
    ecc = np.hypot(ex, ey)
    delta = np.maximum(ecc - CLEARANCE, 0.0)
    ecc = np.where(ecc > 0.0, ecc, 1.0)  # concentric at t = 0: no contact, any normal
    nx, ny = ex / ecc, ey / ecc
    qx, qy = jx + R_JOURNAL * nx, jy + R_JOURNAL * ny
    vx = vax - phi_d * (qy - ay) - x_d
    vy = vay + phi_d * (qx - ax)
    delta_d = vx * nx + vy * ny
    slip = -vx * ny + vy * nx
    s = np.clip(delta / D_MAX, 0.0, 1.0)
    fn = np.maximum(K * delta**EXPONENT + C_MAX * s * s * (3 - 2 * s) * delta_d, 0.0)
    speed = np.abs(slip)
    s_low = np.clip((slip + V_S) / (2 * V_S), 0.0, 1.0)
    s_mid = np.clip((speed - V_S) / (V_D - V_S), 0.0, 1.0)
    mu = np.where(
        speed <= V_S,
        -MU_S + 2 * MU_S * s_low * s_low * (3 - 2 * s_low),
        np.sign(slip) * (MU_S + (MU_D - MU_S) * s_mid * s_mid * (3 - 2 * s_mid)),
    )
    fx = -fn * nx + mu * fn * ny
    return -fx / M_SLIDER


class OverBudget(Exception):
    """A solve ran past its time cap."""


@dataclass
class Solution:
    pieces: list  # (t0, t1, OdeSolution) per side of the ramp's end
    nfev: int
    njev: int
    steps: int

    def slider_ax(self, t: np.ndarray) -> np.ndarray:
        y = np.empty((4, len(t)))
        for k, (t0, t1, sol) in enumerate(self.pieces):
            last = k == len(self.pieces) - 1
            inside = (t >= t0) & ((t <= t1) if last else (t < t1))
            y[:, inside] = sol(t[inside])
        return slider_acceleration(t, y)


def solve(method: str, rtol: float, cap: float) -> Solution:
    """From rest, fully extended (rod along +x, journal centred), to T_END; raises
    OverBudget once the solve has run for cap seconds."""
    deadline = time.perf_counter() + cap

    def f(t: float, y: np.ndarray) -> list[float]:
        if time.perf_counter() > deadline:
            raise OverBudget
        return rhs(t, y)

    y0 = np.array([0.0, R_CRANK + L_ROD, 0.0, 0.0])
    pieces, nfev, njev, steps = [], 0, 0, 0
    for t0, t1 in ((0.0, RAMP), (RAMP, T_END)):
        sol = solve_ivp(
            f, (t0, t1), y0, method=method, rtol=rtol, atol=1e-3 * rtol, dense_output=True
        )
        if sol.status != 0:
            raise RuntimeError(f"{method} rtol {rtol}: {sol.message}")
        pieces.append((t0, t1, sol.sol))
        nfev, njev, steps = nfev + sol.nfev, njev + sol.njev, steps + len(sol.t) - 1
        y0 = sol.y[:, -1]
    return Solution(pieces, nfev, njev, steps)


# --- the benchmark -----------------------------------------------------------------------


def run_scipy(method: str, rtol: float, t: np.ndarray, ref: np.ndarray, cap: float) -> Row:
    row = Row("SciPy", method, rtol)
    for _ in range(2):
        start, cpu_start = time.perf_counter(), time.process_time()
        try:
            sol = solve(method, rtol, cap)
        except OverBudget:
            row.note = f"over budget (> {cap:.0f} s)"
            return row
        solved = time.perf_counter()
        ax = sol.slider_ax(t)
        end, cpu = time.perf_counter(), time.process_time() - cpu_start
        row.runs += 1
        if row.wall is None or end - start < row.wall:
            row.wall, row.solve = end - start, solved - start
        row.cpu = cpu if row.cpu is None else min(row.cpu, cpu)
        row.error, row.nfev, row.njev, row.steps = nrmse(ax, ref), sol.nfev, sol.njev, sol.steps
        if end - start > cap / 4:  # long enough that a second run would change little
            break
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--cap", type=float, default=60.0, help="time cap per solve [s]")
    parser.add_argument("--quick", action="store_true", help="rtol 1e-4 and 1e-6 only")
    args = parser.parse_args()
    rtols = [1e-4, 1e-6] if args.quick else [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9]
    methods = ["RK45", "DOP853", "Radau", "BDF", "LSODA"]
    load_start, begun = load_text(), time.perf_counter()

    # The reference: jointgap at rtol 1e-11, checked against rtol 1e-12 (common.py).
    model = jointgap.load(MODEL)
    t = grid()
    converged = reference(model)
    ref, ref_wall, ref_error = converged.ax, converged.wall, converged.error
    print(f"reference: {ref_wall:.2f} s; rtol 1e-12 differs by NRMSE {ref_error:.1e}")

    # The vectorised slider acceleration is the same law as rhs's.
    sol = solve("LSODA", 1e-6, 600.0)
    y = np.concatenate([p[2](np.linspace(p[0], p[1], 50)) for p in sol.pieces], axis=1)
    tt = np.concatenate([np.linspace(p[0], p[1], 50) for p in sol.pieces])
    scalar = np.array([rhs(float(ti), y[:, i])[3] for i, ti in enumerate(tt)])
    assert np.allclose(slider_acceleration(tt, y), scalar, rtol=1e-9, atol=1e-6)

    rows: list[Row] = []
    for method in methods:
        over = False
        for rtol in rtols:
            if over:
                rows.append(Row("SciPy", method, rtol, note="over budget (looser rtol was)"))
                continue
            row = run_scipy(method, rtol, t, ref, args.cap)
            over = row.wall is None
            rows.append(row)
            print(
                f"SciPy {method:6s} rtol {rtol:.0e}: {fmt(row.wall, '.3f')} s "
                f"NRMSE {fmt(row.error, '.1e')} {row.note}",
                flush=True,
            )
    for method in JOINTGAP_METHODS:
        for rtol in rtols:
            row = run_jointgap(model, rtol, ref, method=method)
            rows.append(row)
            print(
                f"jointgap {method:6s} rtol {rtol:.0e}: {fmt(row.wall, '.3f')} s "
                f"NRMSE {fmt(row.error, '.1e')} {row.note}",
                flush=True,
            )
    paired = {}
    for target in TARGETS:
        s, j = fastest(rows, "SciPy", target), fastest(rows, "jointgap", target)
        if s and j:
            paired[target] = paired_ratio(
                lambda s=s: scipy_cpu(s.method, s.rtol, t), model, j.rtol, j.method
            )
            print(f"paired at {target:.0e}: {paired_text(paired[target])}", flush=True)
    write(rows, paired, ref_wall, ref_error, load_start, time.perf_counter() - begun, args.cap)


def scipy_cpu(method: str, rtol: float, t: np.ndarray) -> float:
    """Process CPU time of one solve plus the slider acceleration on the grid [s]."""
    start = time.process_time()
    solve(method, rtol, math.inf).slider_ax(t)
    return time.process_time() - start


def write(
    rows: list[Row],
    paired: dict[float, dict],
    ref_wall: float,
    ref_error: float,
    load_start: str,
    total: float,
    cap: float,
) -> None:
    lines = [
        "## Peer: the founding clearance case with SciPy `solve_ivp` (minimal coordinates)",
        "",
        f"`benchmarks/peers/scipy_slider_crank.py`. {machine()} NumPy {np.__version__}, "
        f"SciPy {scipy.__version__}. Load average (1, 5, 15 min) {load_start} at the start, "
        f"{load_text()} at the end; the whole run took {total:.0f} s.",
        "",
        "Case: `examples/slider_crank_clearance.toml`, 0 to 0.5 s. SciPy: rod angle and "
        "slider position as unknowns, crank prescribed, the solve split at t = 0.2 s (end "
        "of the ramp), finite-difference Jacobians, atol = 1e-3 x rtol, slider acceleration "
        "evaluated from the dense output on the 10 kHz grid (vectorised). jointgap: "
        "`simulate(0.5, rate=10000, rtol, atol=1e-3 x rtol, method='auto' or 'radau5', "
        "channels=['slider.ax'])`, model loaded once. 'wall': best of 2 runs (one when a "
        f"run took more than {cap / 4:.0f} s), solve plus 10 kHz output; 'solve': the "
        "SciPy solve alone. NRMSE: RMS of the slider.ax difference on the 10 kHz grid over "
        "the reference's max - min.",
        "",
        f"Reference: jointgap at rtol 1e-11, atol 1e-14 ({ref_wall:.2f} s); jointgap at "
        f"rtol 1e-12, atol 1e-15 differs from it by NRMSE **{ref_error:.1e}**: NRMSE values "
        "near or below that are not resolved.",
        "",
        "| peer | method | rtol | wall [s] | solve [s] | NRMSE ax | RHS | Jacobians | steps "
        "| note |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r.peer} | {r.method} | {r.rtol:.0e} | {fmt(r.wall, '.3f')} | "
            f"{fmt(r.solve, '.3f')} | {fmt(r.error, '.1e')} | {fmt(r.nfev, 'd')} | "
            f"{fmt(r.njev, 'd')} | {fmt(r.steps, 'd')} | {r.note} |"
        )
    lines += [
        "",
        "**Speed ratio at matched accuracy**: per NRMSE target, the fastest SciPy "
        "configuration meeting it against the fastest jointgap one; ratio = SciPy wall / "
        "jointgap wall from the sweep above (the project's target: at least 30). 'paired': "
        f"the same two configurations timed again in {PAIRED_ROUNDS} alternating rounds "
        "(one SciPy run, jointgap's best of 3; process CPU time), the median of the rounds' "
        "ratios (min-max in brackets): both sides of each ratio in the same few seconds of "
        "a machine whose speed drifts.",
        "",
        "| target NRMSE | SciPy (method, rtol) | SciPy wall [s] | jointgap rtol | "
        "jointgap wall [s] | ratio | paired |",
        "|---:|---|---:|---:|---:|---:|---:|",
    ]
    summary = []
    for target in TARGETS:
        s, j = fastest(rows, "SciPy", target), fastest(rows, "jointgap", target)
        ratio = f"{s.wall / j.wall:.1f}x" if s and j and s.wall and j.wall else ""
        summary.append(
            {
                "target": target,
                "scipy": None if s is None else row_dict(s),
                "jointgap": None if j is None else row_dict(j),
                "ratio_wall": s.wall / j.wall if s and j and s.wall and j.wall else None,
                "ratio_cpu": s.cpu / j.cpu if s and j and s.cpu and j.cpu else None,
                "paired": paired.get(target),
            }
        )
        lines.append(
            f"| {target:.0e} | "
            + (f"{s.method} {s.rtol:.0e} (NRMSE {s.error:.1e})" if s else "not met")
            + f" | {fmt(s.wall if s else None, '.3f')} | "
            + (f"{j.rtol:.0e} (NRMSE {j.error:.1e})" if j else "not met")
            + f" | {fmt(j.wall if j else None, '.3f')} | {ratio} "
            + f"| {paired_text(paired.get(target))} |"
        )
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("\n".join(lines) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}")
    path = write_json(
        "peers_scipy.json",
        {
            "case": "examples/slider_crank_clearance.toml, 0 to 0.5 s, slider.ax at 10 kHz",
            "scipy": scipy.__version__,
            "target_ratio": 30,
            "targets_nrmse": list(TARGETS),
            "timing": "wall time (and process CPU time), best of 2; solve + 10 kHz output",
            "reference": reference_summary(ref_wall, ref_error),
            "runs": [row_dict(r) for r in rows],
            "matched_accuracy": summary,
            "cap_s": cap,
            "load_average_start": load_start,
            "total_s": total,
        },
    )
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
