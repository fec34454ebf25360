"""Speed of the spatial engine: the spatial four-bar (RSSR), ideal and with a spherical
clearance joint, against the planar founding case (issue 23, "Speed").

The mechanism: a crank turning about the ground's z axis at the origin (revolute), a
coupler joined to it by a spherical joint, a rocker turning about an axis parallel to y
through D0 = (0.2, 0, 0.1) m (revolute), the coupler joined to the rocker by a spherical
joint: two skew revolute axes, so the mechanism is spatial. Crank 50 mm, coupler 220 mm,
rocker 120 mm: the crank turns fully (the coupler's length stays at least 70 mm inside
the range of distances the rocker's tip can reach). All three links are solid round steel
bars of 20 mm diameter (density 7850 kg/m^3): mass rho pi d^2 / 4 L, moment of inertia
m (L^2 / 12 + d^2 / 16) across the bar and m d^2 / 8 along it. Gravity -9.81 m/s^2 along
z. The crank is driven at a constant 300 rpm from t = 0, every body starting with the
loop's velocities at that speed (the ball centred in its socket). The coupler's spin about
its own axis (between the two ball joints) is a free coordinate of the RSSR, as in every
real one.

With clearance, the coupler-rocker spherical joint becomes a ``clearance_spherical``
joint: a 10 mm socket in the rocker, the coupler's ball 0.2 mm smaller (radial clearance
0.2 mm), steel on steel (E = 207 GPa, nu = 0.3: stiffness from the materials, ball in a
concave seat), Lankarani-Nikravesh law with restitution 0.9, frictionless.

For each model and rtol 1e-6 and 1e-8 (atol = 1e-3 x rtol, method ``auto``, 0.2 s: one
crank turn, the rocker's angular speed at 10 kHz): accepted and rejected steps, force
evaluations, impacts, and the engine's wall time per simulated second (median of REPEATS
runs, the model given to ``jointgap._jointgap.simulate`` as JSON); then the cost of one
evaluation (wall time over evaluations) against the planar founding case
(examples/slider_crank_clearance.toml, 0.5 s, ``slider.ax`` at 10 kHz, the same rtols),
measured in the same run.

    .venv/bin/python benchmarks/spatial.py          # about 20 s here

Writes benchmarks/output/spatial.md and benchmarks/results/spatial.json.
"""

from __future__ import annotations

import json
import math
import statistics
import time
from pathlib import Path
from typing import Any

import jointgap
import numpy as np
from jointgap import _jointgap
from jointgap._engine import run_options
from recording import machine, write_results

ROOT = Path(__file__).resolve().parents[1]
OUTPUT = ROOT / "benchmarks" / "output"
PLANAR = ROOT / "examples" / "slider_crank_clearance.toml"
PLANAR_T_END, PLANAR_CHANNEL = 0.5, "slider.ax"  # as benchmarks/run.py's clearance table

T_END = 0.2  # simulated time of each spatial run [s]: one crank turn
RATE = 10_000.0  # output rate of every run [Hz]
CHANNEL = "ground_rocker.omega"  # the one channel a spatial run records: the rocker's speed
RTOLS = (1e-6, 1e-8)
REPEATS = 3

STEEL = {"youngs_modulus": 207e9, "poisson_ratio": 0.3}
DENSITY = 7850.0  # [kg/m^3]
DIAMETER = 0.02  # of every link [m]
CRANK_SPEED = 300.0 * 2.0 * math.pi / 60.0  # [rad/s]
PIVOT = np.array([0.0, 0.0, 0.0])  # crank axis: z through the origin
ROCKER_PIVOT = np.array([0.2, 0.0, 0.1])  # rocker axis: y through this point
CRANK, COUPLER, ROCKER = 0.05, 0.22, 0.12  # link lengths [m]
SOCKET_RADIUS = 0.010  # [m]
CLEARANCE = 0.2e-3  # radial clearance of the ball in its socket [m]


def rocker_tip(psi: float) -> np.ndarray:
    """The rocker's tip C at rocker angle psi (about +y, from +x)."""
    return ROCKER_PIVOT + ROCKER * np.array([math.cos(psi), 0.0, -math.sin(psi)])


def closing_angle(crank_pin: np.ndarray) -> float:
    """The rocker angle that closes the loop (|C - B| = coupler) on the branch with the tip
    below the pivot's height and nearest +x (bisection on the bracket found by a scan)."""
    psis = np.linspace(-0.5 * math.pi, 0.5 * math.pi, 721)
    gap = [np.linalg.norm(rocker_tip(p) - crank_pin) - COUPLER for p in psis]
    k = next(i for i in range(len(gap) - 1) if gap[i] * gap[i + 1] <= 0.0)
    lo, hi = psis[k], psis[k + 1]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if (np.linalg.norm(rocker_tip(lo) - crank_pin) - COUPLER) * (
            np.linalg.norm(rocker_tip(mid) - crank_pin) - COUPLER
        ) <= 0.0:
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def loop_velocities(b: np.ndarray, c: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """Each body's velocity and angular velocity (global) at t = 0, the crank at
    CRANK_SPEED: the rocker's tip moves as psi' y x (C - D0) = v_B + w x (C - B), with the
    coupler's w normal to C - B (its free spin zero); three equations in psi' and w."""
    z, y = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0])
    w_crank = CRANK_SPEED * z
    v_b = np.cross(w_crank, b - PIVOT)
    u = (c - b) / np.linalg.norm(c - b)
    e1 = np.cross(u, z) / np.linalg.norm(np.cross(u, z))
    e2 = np.cross(u, e1)
    lhs = np.column_stack(
        [np.cross(y, c - ROCKER_PIVOT), -np.cross(e1, c - b), -np.cross(e2, c - b)]
    )
    psi_dot, w1, w2 = np.linalg.solve(lhs, v_b)
    w_coupler, w_rocker = w1 * e1 + w2 * e2, psi_dot * y
    return {
        "crank": (np.cross(w_crank, 0.5 * (PIVOT + b) - PIVOT), w_crank),
        "coupler": (v_b + np.cross(w_coupler, 0.5 * (b + c) - b), w_coupler),
        "rocker": (np.cross(w_rocker, 0.5 * (ROCKER_PIVOT + c) - ROCKER_PIVOT), w_rocker),
    }


def bar(name: str, start: np.ndarray, end: np.ndarray, points: dict[str, np.ndarray]) -> dict:
    """A solid round steel bar from ``start`` to ``end``: its centre of mass at mid-length,
    its frame parallel to the ground's, its inertia tensor in that frame; ``points`` are
    global positions, given in the body frame."""
    length = float(np.linalg.norm(end - start))
    mass = DENSITY * math.pi * DIAMETER**2 / 4.0 * length
    across = mass * (length**2 / 12.0 + DIAMETER**2 / 16.0)
    along = mass * DIAMETER**2 / 8.0
    u = (end - start) / length
    tensor = across * (np.eye(3) - np.outer(u, u)) + along * np.outer(u, u)
    centre = 0.5 * (start + end)
    return {
        "name": name,
        "mass": mass,
        "inertia": {"tensor": tensor.tolist()},
        "position": centre.tolist(),
        "points": {k: (p - centre).tolist() for k, p in points.items()},
    }


def moving(body: dict[str, Any], velocities: dict[str, tuple[np.ndarray, np.ndarray]]) -> dict:
    """``body`` with its velocity and angular velocity at t = 0."""
    v, w = velocities[body["name"]]
    return {**body, "velocity": v.tolist(), "angular_velocity": w.tolist()}


LANKARANI_NIKRAVESH = {"type": "lankarani_nikravesh", "exponent": 1.5, "restitution": 0.9}


def four_bar(clearance: bool, normal_law: dict[str, Any] | None = None) -> dict[str, Any]:
    """The spatial four-bar's engine JSON (SI units), crank at angle 0 at t = 0; with
    ``clearance``, the ball's normal law is ``normal_law`` (Lankarani-Nikravesh, restitution
    0.9, by default)."""
    b = PIVOT + np.array([CRANK, 0.0, 0.0])
    c = rocker_tip(closing_angle(b))
    start = loop_velocities(b, c)
    ball: dict[str, Any] = {
        "name": "coupler_rocker",
        "type": "spherical",
        "body_i": "rocker",
        "point_i": "C",
        "body_j": "coupler",
        "point_j": "C",
    }
    if clearance:
        ball["type"] = "clearance_spherical"
        ball["clearance"] = {
            "bearing_radius": SOCKET_RADIUS,
            "clearance": CLEARANCE,
            "bearing_material": STEEL,
            "journal_material": STEEL,
            "normal_law": normal_law or LANKARANI_NIKRAVESH,
        }
    return {
        "dimension": 3,
        "name": "spatial_four_bar" + ("_clearance" if clearance else ""),
        "gravity": [0.0, 0.0, -9.81],
        "ground_points": {"O": PIVOT.tolist(), "D": ROCKER_PIVOT.tolist()},
        "bodies": [
            moving(bar("crank", PIVOT, b, {"O": PIVOT, "B": b}), start),
            moving(bar("coupler", b, c, {"B": b, "C": c}), start),
            moving(bar("rocker", ROCKER_PIVOT, c, {"D": ROCKER_PIVOT, "C": c}), start),
        ],
        "joints": [
            {
                "name": "ground_crank",
                "type": "revolute",
                "body_i": "ground",
                "point_i": "O",
                "body_j": "crank",
                "point_j": "O",
                "axis": [0.0, 0.0, 1.0],
            },
            {
                "name": "crank_coupler",
                "type": "spherical",
                "body_i": "crank",
                "point_i": "B",
                "body_j": "coupler",
                "point_j": "B",
            },
            ball,
            {
                "name": "ground_rocker",
                "type": "revolute",
                "body_i": "ground",
                "point_i": "D",
                "body_j": "rocker",
                "point_j": "D",
                "axis": [0.0, 1.0, 0.0],
            },
        ],
        "drivers": [
            {
                "name": "motor",
                "joint": "ground_crank",
                "profile": {"type": "constant_speed", "speed": CRANK_SPEED},
            }
        ],
    }


def timed(model_json: str, t_end: float, rtol: float, channel: str) -> dict[str, Any]:
    """One engine run through the binding (method ``auto``, atol = 1e-3 x rtol, one
    channel at RATE): its wall time [s] and the engine's counters."""
    options = json.dumps(
        run_options(
            t_end, rate=RATE, rtol=rtol, atol=1e-3 * rtol, method="auto", channels=[channel]
        )
    )
    start = time.perf_counter()
    _, _, _, summary_json = _jointgap.simulate(model_json, options)
    wall = time.perf_counter() - start
    summary = json.loads(summary_json)
    status = summary["status"]
    if status.get("status") != "finished":
        raise RuntimeError(f"run at rtol {rtol:g} did not finish: {status}")
    stats = summary["stats"]
    return {
        "wall": wall,
        "accepted_steps": stats["accepted_steps"],
        "rejected_steps": stats["rejected_steps"],
        "evaluations": stats["rhs_evaluations"],
        "impacts": sum(len(j["impacts"]) for j in summary.get("impacts", [])),
    }


def measure(name: str, model_json: str, t_end: float, rtol: float, channel: str) -> dict:
    """REPEATS runs of one case: the counters (the same in every run: the engine is
    deterministic) and the median wall time, per simulated second and per evaluation."""
    runs = [timed(model_json, t_end, rtol, channel) for _ in range(REPEATS)]
    wall = statistics.median(r["wall"] for r in runs)
    row = {"case": name, "rtol": rtol, "t_end": t_end, **runs[0], "wall": wall}
    row["walls"] = [r["wall"] for r in runs]
    row["wall_per_simulated_s"] = wall / t_end
    row["us_per_evaluation"] = 1e6 * wall / runs[0]["evaluations"]
    print(
        f"{name:28s} rtol {rtol:.0e}: {row['accepted_steps']:7d} + {row['rejected_steps']:5d} "
        f"steps, {row['evaluations']:8d} evaluations, {row['impacts']:4d} impacts, "
        f"{row['wall_per_simulated_s']:8.3f} s/s, {row['us_per_evaluation']:6.2f} us/eval",
        flush=True,
    )
    return row


def main() -> None:
    begun = time.perf_counter()
    planar = jointgap.load(PLANAR).to_json()
    cases = [
        ("spatial four-bar, ideal", json.dumps(four_bar(False)), T_END, CHANNEL),
        ("spatial four-bar, clearance", json.dumps(four_bar(True)), T_END, CHANNEL),
        ("planar founding case", planar, PLANAR_T_END, PLANAR_CHANNEL),
    ]
    rows = [measure(*case[:2], case[2], rtol, case[3]) for case in cases for rtol in RTOLS]
    planar_cost = {r["rtol"]: r["us_per_evaluation"] for r in rows if r["case"] == cases[2][0]}
    for r in rows:
        r["cost_vs_planar"] = r["us_per_evaluation"] / planar_cost[r["rtol"]]
    total = time.perf_counter() - begun
    lines = [
        "## The spatial four-bar (RSSR): speed, and cost per evaluation against the planar case",
        "",
        f"`benchmarks/spatial.py`. {machine()} The whole run took {total:.0f} s.",
        "",
        "Spatial four-bar: crank 50 mm about z (300 rpm from t = 0), coupler 220 mm between "
        "two spherical joints, rocker 120 mm about an axis parallel to y through "
        "(0.2, 0, 0.1) m, solid steel bars of 20 mm diameter, gravity -z; 'clearance': the "
        f"coupler-rocker ball in a {1e3 * SOCKET_RADIUS:g} mm socket with "
        f"{1e3 * CLEARANCE:g} mm radial clearance, steel on steel, Lankarani-Nikravesh "
        f"(restitution 0.9), frictionless; {T_END} s (one crank turn), `{CHANNEL}` at "
        f"{RATE / 1e3:g} kHz. Planar: examples/slider_crank_clearance.toml, {PLANAR_T_END} s, "
        f"`{PLANAR_CHANNEL}` at {RATE / 1e3:g} kHz. Every run: `jointgap._jointgap.simulate` "
        "on the model's JSON, method `auto`, atol = 1e-3 x rtol; wall time the median of "
        f"{REPEATS} runs; steps accepted + rejected; evaluations: the engine's "
        "`rhs_evaluations`; cost per evaluation: wall time / evaluations (recording included).",
        "The ideal runs take a few hundred evaluations: their time is mostly the run's fixed "
        "cost (compiling the model, assembly, the recorded samples), so their cost per "
        "evaluation is not an evaluation's.",
        "",
        "| case | rtol | steps | evaluations | impacts | wall per simulated s [s] | "
        "us per evaluation | x planar |",
        "|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['rtol']:.0e} | {r['accepted_steps']} + {r['rejected_steps']} "
            f"| {r['evaluations']} | {r['impacts']} | {r['wall_per_simulated_s']:.3f} | "
            f"{r['us_per_evaluation']:.2f} | {r['cost_vs_planar']:.2f} |"
        )
    OUTPUT.mkdir(parents=True, exist_ok=True)
    out = OUTPUT / "spatial.md"
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    path = write_results(
        "spatial",
        {
            "case": "spatial four-bar (RSSR), ideal and with one clearance_spherical joint, "
            "against examples/slider_crank_clearance.toml",
            "models": {"ideal": four_bar(False), "clearance": four_bar(True)},
            "repeats": REPEATS,
            "rows": rows,
            "total_s": total,
        },
    )
    print(f"wrote {out.relative_to(ROOT)} and {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
