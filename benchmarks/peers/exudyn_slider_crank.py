"""Peer benchmark: the founding clearance slider-crank written in Exudyn, against jointgap.

The case is examples/slider_crank_clearance.toml (docs/physics.md section 5), 0 to 0.5 s:
crank 0.08 m, rod 0.32 m, vertical plane, the crank driven from rest to 300 rpm in 0.2 s, and
a 0.5 mm radial clearance between rod and slider with the ADAMS IMPACT contact law and ADAMS
Coulomb friction. Here it is written the way an Exudyn user would write it, in two
formulations, because Exudyn's explicit solvers take no constraints:

- "bodies" (for the implicit solvers GeneralizedAlpha and TrapezoidalIndex2): three
  ObjectRigidBody2D, ObjectJointRevolute2D for ground-crank and crank-rod,
  ObjectJointPrismatic2D for the slider guide, the crank driven by an ObjectConnectorCoordinate
  whose offset user function is the ramp's angle, gravity as LoadMassProportional.
- "tree" (for the explicit solvers DOPRI5 and ODE23): one ObjectKinematicTree in minimal
  coordinates (crank and rod revolute, slider prismatic). A prescribed coordinate cannot be
  imposed on an explicit solver (a CoordinateConstraint is eliminated only as a fixed
  coordinate), so the crank is a flywheel of 1e9 kg m^2 driven by the torque that gives it
  the ramp's acceleration (jointForceVector), and the solve is split at the end of the
  ramp, where that torque drops to zero. The crank then follows the ramp to within the
  integration error (reported).

In both, the clearance joint is an ObjectConnectorRigidBodySpringDamper between a rigid
marker at the bearing centre (slider) and one at the journal centre (rod) whose
springForceTorqueUserFunction computes jointgap's contact force (Python user function;
exudyn.symbolic user functions measured alongside): the force on the journal at its
contact point, applied as the same force at the journal centre plus the moment R_J x F_t.

The Exudyn part runs in its own environment (benchmarks/peers/.venv, ``pip install
exudyn``) as a subprocess of this script: the main .venv runs jointgap (the reference, and
the timed jointgap runs), the peer .venv runs Exudyn; nothing of Exudyn enters the
package's dependencies.

Accuracy: NRMSE of slider.ax on the 10 kHz grid against the converged jointgap run
(benchmarks/peers/common.py, as in the SciPy peer). Exudyn records every step (sensors,
writePeriod 0) and the slider acceleration is interpolated linearly onto the grid (the
fixed steps land on it). Speed: process CPU time (and wall time), best of 2 for runs under
5 s, of model building, the solve and the interpolation; jointgap's ``simulate`` at rtol
1e-4 ... 1e-10 in the same ``make bench-peers`` run.

Run from the repository root after ``make install`` and ``make bench-peers`` (which makes
the peer venv):

    .venv/bin/python benchmarks/peers/exudyn_slider_crank.py [--quick] [--cap SECONDS]

Writes benchmarks/output/peers_exudyn.md and benchmarks/results/peers_exudyn.json.
About 3-4 minutes on 2 shared cores.
"""

from __future__ import annotations

import argparse
import json
import math
import signal
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

HERE = Path(__file__).resolve().parent
PEER_PYTHON = HERE / ".venv" / "bin" / "python"
JBIG = 1e9  # flywheel inertia of the crank in the "tree" formulation [kg m^2]
H_MAX = 1e-4  # largest step of the explicit solvers [s]: the output period
IMPLICIT = ("GeneralizedAlpha", "TrapezoidalIndex2")
STEPS = [1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2.5e-6]  # fixed steps of the implicit solvers [s]
RTOLS = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11]  # atol = 1e-3 x rtol
ORDER = {"DOPRI5": 5, "ODE23": 3}


def sweeps(quick: bool) -> list[tuple[str, str, str, list[float], str]]:
    """(method, formulation, setting, values, user function) per sweep, cheapest first."""
    if quick:
        return [
            ("GeneralizedAlpha", "bodies", "h", [5e-5, 1e-5], "python"),
            ("TrapezoidalIndex2", "bodies", "h", [5e-5], "python"),
            ("DOPRI5", "tree", "rtol", [1e-6, 1e-10], "python"),
        ]
    return [
        ("GeneralizedAlpha", "bodies", "h", STEPS, "python"),
        ("TrapezoidalIndex2", "bodies", "h", STEPS, "python"),
        ("DOPRI5", "tree", "rtol", RTOLS, "python"),
        ("ODE23", "tree", "rtol", RTOLS[:5], "python"),
        ("GeneralizedAlpha", "bodies", "h", [1e-5], "symbolic"),
        ("DOPRI5", "tree", "rtol", [1e-8], "symbolic"),
    ]


# ==== the Exudyn side (runs in benchmarks/peers/.venv) ===================================


class Case:
    """The founding case's data, in SI units, from jointgap's ``Model.to_dict()``."""

    def __init__(self, d: dict[str, Any]) -> None:
        self.bodies = {b["name"]: b for b in d["bodies"]}
        self.joints = d["joints"]
        self.ground_points = d["ground_points"]
        self.gravity = d["gravity"]
        clear = next(j for j in d["joints"] if j["type"] == "clearance_revolute")
        guide = next(j for j in d["joints"] if j["type"] == "prismatic")
        (driver,) = d["drivers"]
        motor = next(j for j in d["joints"] if j["name"] == driver["joint"])
        profile = driver["profile"]
        assert profile["type"] == "linear_ramp", profile
        assert motor["body_i"] == "ground" and motor["type"] == "revolute", motor
        self.omega, self.ramp = profile["speed"], profile["ramp_time"]
        self.clear, self.guide, self.motor = clear, guide, motor
        self.crank = motor["body_j"]
        self.bearing_body, self.journal_body = clear["body_i"], clear["body_j"]
        c = clear["clearance"]
        self.c = c["clearance"]
        self.r_bearing = c.get("bearing_radius") or c["journal_radius"] + self.c
        self.r_journal = self.r_bearing - self.c

        def sigma(m: dict[str, float]) -> float:
            return (1 - m["poisson_ratio"] ** 2) / m["youngs_modulus"]

        # Journal in a bearing (bearing radius negative): materials.rs.
        rj, rb = self.r_journal, -self.r_bearing
        sig = sigma(c["journal_material"]) + sigma(c["bearing_material"])
        self.k = 4.0 / (3.0 * sig) * math.sqrt(rj * rb / (rj + rb))
        law, fr = c["normal_law"], c["friction"]
        assert law["type"] == "adams_impact" and fr["type"] == "coulomb", (law, fr)
        self.n, self.c_max, self.d_max = law["exponent"], law["c_max"], law["d_max"]
        self.mu_s, self.mu_d, self.v_s, self.v_d = fr["mu_s"], fr["mu_d"], fr["v_s"], fr["v_d"]

    def point(self, body: str, name: str) -> list[float]:
        """A named point, local to its body (or global on the ground), as 3D."""
        p = self.ground_points[name] if body == "ground" else self.bodies[body]["points"][name]
        return [p[0], p[1], 0.0]

    def angle(self, t: float) -> float:
        """The ramp: crank angle [rad] at t."""
        if t < self.ramp:
            return 0.5 * self.omega * t * t / self.ramp
        return self.omega * (t - 0.5 * self.ramp)

    def speed(self, t: float) -> float:
        return self.omega * t / self.ramp if t < self.ramp else self.omega


def contact_python(case: Case):  # noqa: ANN201  (an Exudyn user function)
    """jointgap's contact force as an Exudyn springForceTorqueUserFunction (plain Python).

    Marker 0 is the bearing centre (slider), marker 1 the journal centre (rod); Exudyn
    gives their relative position, velocity and angular velocity in marker 0's frame (the
    slider's, which the guide keeps from rotating) and applies the returned force-torque
    +f on marker 0 and -f on marker 1. jointgap (mechanics/contact/mod.rs): n = e / |e|, penetration
    |e| - c, contact points on both circles along n, relative velocity of the journal's
    contact point against the bearing's: normal rate v.n, slip v.t with t = (-n_y, n_x);
    F_n = K delta^n + STEP(delta, 0, 0, d_max, c_max) delta' (clipped at 0), F_t = -mu(slip)
    F_n (ADAMS Coulomb), force on the journal -n F_n + t F_t at its contact point.
    """
    c, rj, k, n, c_max, d_max = case.c, case.r_journal, case.k, case.n, case.c_max, case.d_max
    mu_s, mu_d, v_s, v_d = case.mu_s, case.mu_d, case.v_s, case.v_d
    zero = [0.0] * 6

    def step(x: float, x0: float, h0: float, x1: float, h1: float) -> float:
        s = min(max((x - x0) / (x1 - x0), 0.0), 1.0)
        return h0 + (h1 - h0) * s * s * (3.0 - 2.0 * s)

    def contact(
        mbs, t, itemNumber, displacement, rotation, velocity, angularVelocity,
        stiffness, damping, rotJ0, rotJ1, offset,
    ):  # fmt: skip
        ex, ey = displacement[0], displacement[1]
        ecc = math.sqrt(ex * ex + ey * ey)
        delta = ecc - c
        if delta <= 0.0:
            return zero
        nx, ny = ex / ecc, ey / ecc
        vx, vy = velocity[0], velocity[1]
        rate = vx * nx + vy * ny
        # The journal's contact point turns with the rod; the slider does not rotate.
        slip = -vx * ny + vy * nx + angularVelocity[2] * rj
        fn = k * delta**n + step(delta, 0.0, 0.0, d_max, c_max) * rate
        if fn <= 0.0:
            return zero
        speed = abs(slip)
        if speed <= v_s:
            mu = step(slip, -v_s, -mu_s, v_s, mu_s)
        else:
            mu = math.copysign(step(speed, v_s, mu_s, v_d, mu_d), slip)
        ft = -mu * fn
        # The force on the journal is (-n fn + t ft); Exudyn applies -f to marker 1.
        return [nx * fn + ny * ft, ny * fn - nx * ft, 0.0, 0.0, 0.0, -rj * ft]

    return contact


def contact_symbolic(case: Case, mbs):  # noqa: ANN001, ANN201
    """The same law as an exudyn.symbolic user function (an expression tree evaluated in
    C++, no Python call per evaluation): branches become IfThenElse, min and max."""
    import exudyn as exu
    from exudyn.advancedUtilities import CreateSymbolicUserFunction

    es = exu.symbolic
    c, rj, k, n, c_max, d_max = case.c, case.r_journal, case.k, case.n, case.c_max, case.d_max
    mu_s, mu_d, v_s, v_d = case.mu_s, case.mu_d, case.v_s, case.v_d

    def smooth(s):  # noqa: ANN001, ANN202
        return s * s * (3.0 - 2.0 * s)

    def clamp01(s):  # noqa: ANN001, ANN202
        return es.min(es.max(s, 0.0), 1.0)

    def contact(
        mbs, t, itemNumber, displacement, rotation, velocity, angularVelocity,
        stiffness, damping, rotJ0, rotJ1, offset,
    ):  # fmt: skip
        ex, ey = displacement[0], displacement[1]
        ecc = es.sqrt(ex * ex + ey * ey)
        delta = es.max(ecc - c, 0.0)
        inv = 1.0 / es.max(ecc, 1e-15)
        nx, ny = ex * inv, ey * inv
        vx, vy = velocity[0], velocity[1]
        rate = vx * nx + vy * ny
        slip = -vx * ny + vy * nx + angularVelocity[2] * rj
        fn = es.max(k * es.pow(delta, n) + c_max * smooth(clamp01(delta / d_max)) * rate, 0.0)
        speed = es.abs(slip)
        stick = -mu_s + 2.0 * mu_s * smooth(clamp01((slip + v_s) / (2.0 * v_s)))
        slide = es.sign(slip) * (
            mu_s + (mu_d - mu_s) * smooth(clamp01((speed - v_s) / (v_d - v_s)))
        )
        ft = -es.IfThenElse(speed <= v_s, stick, slide) * fn
        return [nx * fn + ny * ft, ny * fn - nx * ft, 0.0, 0.0, 0.0, -rj * ft]

    return CreateSymbolicUserFunction(
        mbs, contact, "springForceTorqueUserFunction",
        itemTypeName="ObjectConnectorRigidBodySpringDamper",
    )  # fmt: skip


def drive_functions(case: Case, uf: str, mbs):  # noqa: ANN001, ANN201
    """Offset user functions of the crank's coordinate constraint: angle and speed."""
    if uf == "python":

        def angle(mbs, t, itemNumber, lOffset):  # noqa: ANN001, ANN202, N803
            return case.angle(t)

        def speed(mbs, t, itemNumber, lOffset):  # noqa: ANN001, ANN202, N803
            return case.speed(t)

        return angle, speed
    import exudyn as exu
    from exudyn.advancedUtilities import CreateSymbolicUserFunction

    es = exu.symbolic
    w, tr = case.omega, case.ramp

    def angle_s(mbs, t, itemNumber, lOffset):  # noqa: ANN001, ANN202, N803
        return es.IfThenElse(t < tr, 0.5 * w * t * t / tr, w * (t - 0.5 * tr))

    def speed_s(mbs, t, itemNumber, lOffset):  # noqa: ANN001, ANN202, N803
        return es.IfThenElse(t < tr, w * t / tr, es.Real(w))

    kind = "ObjectConnectorCoordinate"
    return (
        CreateSymbolicUserFunction(mbs, angle_s, "offsetUserFunction", itemTypeName=kind),
        CreateSymbolicUserFunction(mbs, speed_s, "offsetUserFunction_t", itemTypeName=kind),
    )


class Built:
    """An assembled Exudyn model and what the run reads back."""

    def __init__(self, mbs, sensors: dict[str, Any], keep: list[Any], tree=None) -> None:  # noqa: ANN001
        self.mbs, self.sensors, self.keep, self.tree = mbs, sensors, keep, tree


def build_bodies(case: Case, uf: str) -> Built:
    """Three rigid bodies, Exudyn's joints, the crank driven through a coordinate
    constraint, the clearance joint as a user-function connector."""
    import exudyn as exu
    from exudyn import itemInterface as ii

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ii.ObjectGround())
    node, body = {}, {}
    for name, b in case.bodies.items():
        node[name] = mbs.AddNode(
            ii.NodeRigidBody2D(referenceCoordinates=[*b["position"], b["angle"]])
        )
        body[name] = mbs.AddObject(
            ii.ObjectRigidBody2D(mass=b["mass"], inertia=b["inertia"], nodeNumber=node[name])
        )
        mbs.AddLoad(
            ii.LoadMassProportional(
                markerNumber=mbs.AddMarker(ii.MarkerBodyMass(bodyNumber=body[name])),
                loadVector=[*case.gravity, 0.0],
            )
        )

    def marker(name: str, point: str, rigid: bool = False):  # noqa: ANN202
        kind = ii.MarkerBodyRigid if rigid else ii.MarkerBodyPosition
        b = ground if name == "ground" else body[name]
        return mbs.AddMarker(kind(bodyNumber=b, localPosition=case.point(name, point)))

    for j in case.joints:
        pair = (j["body_i"], j["point_i"]), (j["body_j"], j["point_j"])
        if j["type"] == "revolute":
            mbs.AddObject(ii.ObjectJointRevolute2D(markerNumbers=[marker(*p) for p in pair]))
        elif j["type"] == "prismatic":
            ax = j["axis"]
            mbs.AddObject(
                ii.ObjectJointPrismatic2D(
                    markerNumbers=[marker(*p, rigid=True) for p in pair],
                    axisMarker0=[ax[0], ax[1], 0.0],
                    normalMarker1=[-ax[1], ax[0], 0.0],
                    constrainRotation=True,
                )
            )
    keep: list[Any] = []
    angle, speed = drive_functions(case, uf, mbs)
    keep += [angle, speed]
    fixed = mbs.AddNode(ii.NodePointGround())
    mbs.AddObject(
        ii.ObjectConnectorCoordinate(
            markerNumbers=[
                mbs.AddMarker(ii.MarkerNodeCoordinate(nodeNumber=fixed, coordinate=0)),
                mbs.AddMarker(ii.MarkerNodeCoordinate(nodeNumber=node[case.crank], coordinate=2)),
            ],
            offsetUserFunction=angle,
            offsetUserFunction_t=speed,
        )
    )
    cl = case.clear
    law = contact_python(case) if uf == "python" else contact_symbolic(case, mbs)
    keep.append(law)
    mbs.AddObject(
        ii.ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[
                marker(cl["body_i"], cl["point_i"], rigid=True),
                marker(cl["body_j"], cl["point_j"], rigid=True),
            ],
            stiffness=np.zeros((6, 6)),
            damping=np.zeros((6, 6)),
            springForceTorqueUserFunction=law,
        )
    )
    out = exu.OutputVariableType

    def sensor(name: str, what) -> Any:  # noqa: ANN001
        return mbs.AddSensor(
            ii.SensorNode(
                nodeNumber=node[name],
                outputVariableType=what,
                storeInternal=True,
                writeToFile=False,
            )
        )

    sensors = {
        "ax": sensor(case.bearing_body, out.Acceleration),
        "journal": sensor(case.journal_body, out.Coordinates),
        "bearing": sensor(case.bearing_body, out.Coordinates),
    }
    mbs.Assemble()
    return Built(mbs, sensors, keep)


def build_tree(case: Case, uf: str) -> Built:
    """The mechanism as one kinematic tree in minimal coordinates q = (crank angle, rod
    angle relative to the crank, slider position), for the explicit solvers."""
    import exudyn as exu
    from exudyn import itemInterface as ii

    crank, rod, slider = (
        case.bodies[n] for n in (case.crank, case.journal_body, case.bearing_body)
    )
    for b in (crank, rod, slider):
        assert b["angle"] == 0.0 and b["velocity"] == [0.0, 0.0] and b["omega"] == 0.0, b
    assert case.guide["axis"] == [1.0, 0.0] and case.guide["body_j"] == case.bearing_body
    crank_rod = next(
        j
        for j in case.joints
        if j["type"] == "revolute" and {j["body_i"], j["body_j"]} == {case.crank, case.journal_body}
    )
    pivot = np.array(case.point("ground", case.motor["point_i"]))
    o_crank = np.array(crank["position"] + [0.0]) + np.array(
        case.point(case.crank, case.motor["point_j"])
    )
    assert np.allclose(pivot, o_crank), "crank pivot"
    p_crank = case.point(
        case.crank, crank_rod["point_i" if crank_rod["body_i"] == case.crank else "point_j"]
    )
    p_rod = case.point(
        case.journal_body,
        crank_rod["point_j" if crank_rod["body_j"] == case.journal_body else "point_i"],
    )
    p_motor = case.point(case.crank, case.motor["point_j"])
    journal = np.subtract(case.point(case.journal_body, case.clear["point_j"]), p_rod)
    bearing = case.point(case.bearing_body, case.clear["point_i"])
    # Link frames: crank at its pivot, rod at the crank pin, slider at its initial position.
    offsets = [list(pivot), list(np.subtract(p_crank, p_motor)), [*slider["position"], 0.0]]
    coms = [list(-np.array(p_motor)), list(-np.array(p_rod)), [0.0, 0.0, 0.0]]
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    zeros = [0.0] * 3
    node = mbs.AddNode(
        ii.NodeGenericODE2(
            referenceCoordinates=zeros,
            initialCoordinates=zeros,
            initialCoordinates_t=zeros,
            numberOfODE2Coordinates=3,
        )
    )
    eye = np.eye(3)
    tree = mbs.AddObject(
        ii.ObjectKinematicTree(
            nodeNumber=node,
            jointTypes=[exu.JointType.RevoluteZ, exu.JointType.RevoluteZ, exu.JointType.PrismaticX],
            linkParents=[-1, 0, -1],
            jointTransformations=exu.Matrix3DList([eye, eye, eye]),
            jointOffsets=exu.Vector3DList(offsets),
            linkInertiasCOM=exu.Matrix3DList(
                [np.diag([0.0, 0.0, j]) for j in (JBIG, rod["inertia"], slider["inertia"])]
            ),
            linkCOMs=exu.Vector3DList(coms),
            linkMasses=[crank["mass"], rod["mass"], slider["mass"]],
            gravity=[*case.gravity, 0.0],
            jointForceVector=[JBIG * case.omega / case.ramp, 0.0, 0.0],
        )
    )
    law = contact_python(case) if uf == "python" else contact_symbolic(case, mbs)

    def marker(link: int, p) -> Any:  # noqa: ANN001
        return mbs.AddMarker(
            ii.MarkerKinematicTreeRigid(objectNumber=tree, linkNumber=link, localPosition=list(p))
        )

    mbs.AddObject(
        ii.ObjectConnectorRigidBodySpringDamper(
            markerNumbers=[marker(2, bearing), marker(1, journal)],
            stiffness=np.zeros((6, 6)),
            damping=np.zeros((6, 6)),
            springForceTorqueUserFunction=law,
        )
    )
    out = exu.OutputVariableType
    sensors = {
        name: mbs.AddSensor(
            ii.SensorNode(
                nodeNumber=node, outputVariableType=what, storeInternal=True, writeToFile=False
            )
        )
        for name, what in (("q_tt", out.Coordinates_tt), ("q", out.Coordinates))
    }
    mbs.Assemble()
    built = Built(mbs, sensors, [law], tree)
    built.geometry = (offsets, journal, bearing)  # type: ignore[attr-defined]
    return built


def simulate(
    case: Case,
    method: str,
    formulation: str,
    value: float,
    uf: str,
    t_end: float,
    cap: float | None = None,
) -> dict[str, Any]:
    """One Exudyn run; CPU and wall time of building, solving and reading back. A run
    past ``cap`` seconds of CPU time is stopped and reported as over budget: a profiling
    timer raises OverBudget in the next Python user function call. (A pre-step user
    function does not do: at Exudyn's minimum step size the explicit solvers can reject
    the same step again and again without starting a new one.)"""
    import exudyn as exu

    cpu0, wall0 = time.process_time(), time.perf_counter()
    if cap is not None:
        signal.signal(signal.SIGPROF, _over_budget)
        signal.setitimer(signal.ITIMER_PROF, cap)
    try:
        return _simulate(exu, case, method, formulation, value, uf, t_end, cpu0, wall0)
    except OverBudget:
        return {"ok": False, "message": f"over budget (> {cap:g} s CPU)", "ax": None,
                "impacts": None, "crank_error": None, "cpu": time.process_time() - cpu0,
                "wall": time.perf_counter() - wall0}  # fmt: skip
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)


class OverBudget(Exception):  # noqa: N818
    """A run went past its CPU time cap."""


def _over_budget(signum: int, frame: object) -> None:
    raise OverBudget


def _simulate(
    exu,  # noqa: ANN001
    case: Case,
    method: str,
    formulation: str,
    value: float,
    uf: str,
    t_end: float,
    cpu0: float,
    wall0: float,
) -> dict[str, Any]:
    built = (build_bodies if formulation == "bodies" else build_tree)(case, uf)
    mbs = built.mbs
    counters = {"steps": 0, "rejected": 0, "newton": 0, "jacobians": 0}
    records: dict[str, list[np.ndarray]] = {k: [] for k in built.sensors}
    phases = [(0.0, t_end)]
    if formulation == "tree" and t_end > case.ramp:
        phases = [(0.0, case.ramp), (case.ramp, t_end)]
    ok, message = True, ""
    for k, (t0, t1) in enumerate(phases):
        s = exu.SimulationSettings()
        ti = s.timeIntegration
        ti.startTime, ti.endTime = t0, t1
        ti.verboseMode = 0
        s.solution.file.write = False
        s.solution.sensors.writePeriod = 0.0  # every step
        if method not in ORDER:  # fixed step
            ti.numberOfSteps = int(round((t1 - t0) / value))
            ti.automaticStepSize = False
        else:
            ti.numberOfSteps = int(round((t1 - t0) / H_MAX))
            ti.automaticStepSize = True
            ti.relativeTolerance, ti.absoluteTolerance = value, 1e-3 * value
            # DOPRI5 and ODE23 are FSAL: their last stage is the end of the step, so the
            # end-of-step accelerations need no extra evaluation (same results, checked).
            ti.explicit.computeEndOfStepAccelerations = False
        if k == 1:  # the ramp is over: no more driving torque
            mbs.SetObjectParameter(built.tree, "jointForceVector", [0.0, 0.0, 0.0])
        try:
            done = mbs.SolveDynamic(
                s, solverType=getattr(exu.DynamicSolverType, method), updateInitialValues=True
            )
        except Exception as err:  # noqa: BLE001  (a failed solve is a row, not a crash)
            if "OverBudget" in str(err):  # raised in a user function
                raise OverBudget from err
            done, message = False, f"{type(err).__name__}: {err}"
        it = mbs.sys["dynamicSolver"].it
        counters["steps"] += it.currentStepIndex
        counters["rejected"] += it.rejectedAutomaticStepSizeSteps
        counters["newton"] += it.newtonStepsCount
        counters["jacobians"] += it.newtonJacobiCount
        for name, sensor in built.sensors.items():
            data = np.asarray(mbs.GetSensorStoredData(sensor))
            records[name].append(data if k == 0 else data[1:])
        if not done:
            ok, message = False, message or f"solver failed at t = {it.currentTime:.6g} s"
            break
        if it.currentTime < t1 - 1e-9:
            ok, message = False, f"stopped at t = {it.currentTime:.6g} s"
            break
    result: dict[str, Any] = {"ok": ok, "message": message, "ax": None, "impacts": None, **counters}
    result["crank_error"] = None
    if not ok:
        result["cpu"], result["wall"] = time.process_time() - cpu0, time.perf_counter() - wall0
        return result
    rec = {name: np.concatenate(parts) for name, parts in records.items()}
    t = np.arange(int(round(t_end * 10_000)) + 1) / 10_000
    if formulation == "bodies":
        times, ax = rec["ax"][:, 0], rec["ax"][:, 1]
        rod, sl = rec["journal"], rec["bearing"]
        jx, jy = case.point(case.journal_body, case.clear["point_j"])[:2]
        bx, by = case.point(case.bearing_body, case.clear["point_i"])[:2]
        ref_rod, ref_sl = case.bodies[case.journal_body], case.bodies[case.bearing_body]
        phi, psi = rod[:, 3] + ref_rod["angle"], sl[:, 3] + ref_sl["angle"]
        ex = (ref_rod["position"][0] + rod[:, 1] + np.cos(phi) * jx - np.sin(phi) * jy) - (
            ref_sl["position"][0] + sl[:, 1] + np.cos(psi) * bx - np.sin(psi) * by
        )
        ey = (ref_rod["position"][1] + rod[:, 2] + np.sin(phi) * jx + np.cos(phi) * jy) - (
            ref_sl["position"][1] + sl[:, 2] + np.sin(psi) * bx + np.cos(psi) * by
        )
        crank_error = None
    else:
        times, ax = rec["q_tt"][:, 0], rec["q_tt"][:, 3]
        q = rec["q"]
        offsets, journal, bearing = built.geometry  # type: ignore[attr-defined]
        a1, a2 = q[:, 1], q[:, 1] + q[:, 2]
        jxy = np.array(offsets[0][:2])[:, None] + np.array(
            [
                np.cos(a1) * offsets[1][0] + np.cos(a2) * journal[0] - np.sin(a2) * journal[1],
                np.sin(a1) * offsets[1][0] + np.sin(a2) * journal[0] + np.cos(a2) * journal[1],
            ]
        )
        ex = jxy[0] - (offsets[2][0] + q[:, 3] + bearing[0])
        ey = jxy[1] - (offsets[2][1] + bearing[1])
        crank_error = float(np.max(np.abs(q[:, 1] - np.vectorize(case.angle)(q[:, 0]))))
    result["ax"] = np.interp(t, times, ax)
    result["cpu"], result["wall"] = time.process_time() - cpu0, time.perf_counter() - wall0
    inside = np.hypot(ex, ey) - case.c > 0.0
    result["impacts"] = int(np.count_nonzero(inside[1:] & ~inside[:-1]))
    result["crank_error"], result["records"] = crank_error, len(times)
    return result


def worker(case_path: Path, out_path: Path, quick: bool, cap: float) -> None:
    """Every sweep; writes out_path (JSON) and out_path.npz (the slider acceleration)."""
    import exudyn as exu

    payload = json.loads(case_path.read_text())
    case = Case(payload["model"])
    t_end = payload["t_end"]
    runs, arrays = [], {}
    print(f"Exudyn {exu.__version__}, K = {case.k:.4e} N/m^1.5", flush=True)
    for method, formulation, setting, values, uf in sweeps(quick):
        previous: tuple[float, float] | None = None  # (value, CPU time) of the last run
        for value in values:
            row: dict[str, Any] = dict(
                method=method, formulation=formulation, setting=setting, value=value, uf=uf
            )
            if previous is not None:
                factor = (
                    previous[0] / value
                    if setting == "h"
                    else (previous[0] / value) ** (1 / ORDER[method])
                )
                if previous[1] * factor > cap:
                    row["note"] = f"over budget (> {cap:.0f} s predicted)"
                    runs.append(row)
                    print(
                        f"{method:18s} {uf:8s} {setting} {num(value)}: skipped, {row['note']}",
                        flush=True,
                    )
                    continue
            best: dict[str, Any] | None = None
            for _ in range(2):
                r = simulate(case, method, formulation, value, uf, t_end, cap)
                if best is None or r["cpu"] < best["cpu"]:
                    best, best_wall = r, r["wall"]
                best_wall = min(best_wall, r["wall"])
                row["runs"] = row.get("runs", 0) + 1
                if r["cpu"] > 5.0 or not r["ok"]:
                    break
            assert best is not None
            best["wall"] = best_wall
            key = f"run{len(runs)}"
            if best["ax"] is not None:
                arrays[key] = best.pop("ax")
            else:
                best.pop("ax")
            row.update(best, key=key)
            runs.append(row)
            previous = (value, best["cpu"])
            print(
                f"{method:18s} {uf:8s} {setting} {num(value)}: CPU {best['cpu']:.3f} s, "
                f"steps {best['steps']}, "
                f"Newton {best['newton']}, impacts {best['impacts']} {best['message']}",
                flush=True,
            )
    np.savez(out_path.with_suffix(".npz"), **arrays)
    out_path.write_text(
        json.dumps({"exudyn": exu.__version__, "K": case.k, "runs": runs}, indent=1) + "\n"
    )


def time_one(case_path: Path, spec: str) -> None:
    """One run of one configuration (``spec``: JSON of method, formulation, value, uf);
    prints its CPU time as JSON (the paired timing of the main side)."""
    payload = json.loads(case_path.read_text())
    run = json.loads(spec)
    r = simulate(
        Case(payload["model"]), run["method"], run["formulation"], run["value"], run["uf"],
        payload["t_end"],
    )  # fmt: skip
    print(json.dumps({"cpu": r["cpu"], "ok": r["ok"]}))


# ==== the main side (runs in the main .venv, with jointgap) ==============================


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="a few configurations only")
    parser.add_argument("--cap", type=float, default=30.0, help="CPU time cap per run [s]")
    parser.add_argument(
        "--worker", nargs=2, type=Path, metavar=("CASE", "OUT"), help=argparse.SUPPRESS
    )
    parser.add_argument("--time", nargs=2, metavar=("CASE", "SPEC"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.worker:
        worker(*args.worker, quick=args.quick, cap=args.cap)
        return
    if args.time:
        time_one(Path(args.time[0]), args.time[1])
        return

    import common
    import jointgap

    if not PEER_PYTHON.exists():
        sys.exit(f"{PEER_PYTHON} is missing: `make bench-peers` creates it (pip install exudyn)")
    load_start, begun = common.load_text(), time.perf_counter()
    model = jointgap.load(common.MODEL)
    ref = common.reference(model)
    print(
        f"reference: {ref.wall:.2f} s, {ref.impacts} impacts; "
        f"rtol 1e-12 differs by NRMSE {ref.error:.1e}"
    )
    work = common.OUTPUT / "peers_exudyn"
    work.mkdir(parents=True, exist_ok=True)
    case_path, out_path = work / "case.json", work / "runs.json"
    case_path.write_text(json.dumps({"model": model.to_dict(), "t_end": common.T_END}))
    command = [
        str(PEER_PYTHON),
        str(Path(__file__).resolve()),
        "--worker",
        str(case_path),
        str(out_path),
    ]
    command += ["--cap", str(args.cap)] + (["--quick"] if args.quick else [])
    subprocess.run(command, check=True, cwd=work)  # cwd: Exudyn's stray files stay there
    raw = json.loads(out_path.read_text())
    arrays = np.load(out_path.with_suffix(".npz"))
    for run in raw["runs"]:
        run["error"] = (
            common.nrmse(arrays[run["key"]], ref.ax) if run.get("key") in arrays else None
        )
    (k_jointgap,) = (c["stiffness"] for c in model.clearance_data().values())
    assert abs(raw["K"] / k_jointgap - 1) < 1e-12, (raw["K"], k_jointgap)

    rtols = [1e-4, 1e-6, 1e-8] if args.quick else [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10]
    jg = []
    for method in common.JOINTGAP_METHODS:
        for rtol in rtols:
            row = common.run_jointgap(model, rtol, ref.ax, repeats=3, method=method)
            jg.append(row)
            print(
                f"jointgap {method} rtol {rtol:.0e}: CPU {common.fmt(row.cpu, '.3f')} s "
                f"NRMSE {common.fmt(row.error, '.1e')}"
            )

    def exudyn_cpu(run: dict[str, Any]) -> float:
        """CPU time of one more run of an Exudyn configuration, in its own venv."""
        spec = json.dumps({k: run[k] for k in ("method", "formulation", "value", "uf")})
        command = [str(PEER_PYTHON), str(Path(__file__).resolve()), "--time", str(case_path), spec]
        done = subprocess.run(command, check=True, cwd=work, capture_output=True, text=True)
        timing = json.loads(done.stdout.strip().splitlines()[-1])
        assert timing["ok"], (run, timing)
        return timing["cpu"]

    def pair(run: dict[str, Any], j: common.Row) -> dict[str, Any]:
        return common.paired_ratio(lambda: exudyn_cpu(run), model, j.rtol, j.method)

    write(raw, jg, ref, load_start, time.perf_counter() - begun, args.cap, model, pair)


def brief(row: Any) -> dict[str, Any]:  # noqa: ANN401
    return {
        "method": row.method,
        row.setting: row.rtol,
        "cpu": row.cpu,
        "wall": row.wall,
        "nrmse": row.error,
    }


def label(run: dict[str, Any]) -> str:
    uf = "" if run["uf"] == "python" else ", symbolic UF"
    return f"{run['method']} ({run['formulation']}{uf})"


def num(x: float) -> str:
    """1e-05, 2.5e-06: a setting in scientific notation, no trailing .0."""
    return f"{x:.1e}".replace(".0e", "e")


def setting_text(run: dict[str, Any]) -> str:
    return f"{run['setting']} {num(run['value'])}"


def write(raw, jg, ref, load_start: str, total: float, cap: float, model, pair) -> None:  # noqa: ANN001
    """The tables and the JSON; ``pair(run, jointgap_row)`` times the matched pair of each
    target again in alternation (``common.paired_ratio``)."""
    import common

    runs = raw["runs"]
    ex_rows = []
    raw_of = {}  # id() of an Exudyn row -> its run
    for run in runs:
        if run.get("error") is None:
            continue
        ex_rows.append(
            common.Row(
                "Exudyn",
                label(run),
                run["value"],
                wall=run["wall"],
                cpu=run["cpu"],
                error=run["error"],
                steps=run["steps"],
                runs=run.get("runs", 0),
                setting=run["setting"],
            )
        )
        raw_of[id(ex_rows[-1])] = run
    # Correctness: the tightest run of each formulation.
    checks = []
    for method in ("GeneralizedAlpha", "TrapezoidalIndex2", "DOPRI5"):
        done = [
            r
            for r in runs
            if r["method"] == method and r["uf"] == "python" and r.get("error") is not None
        ]
        if done:
            tight = min(done, key=lambda r: r["value"])
            checks.append(tight)
    lines = [
        "## Peer: the founding clearance case in Exudyn",
        "",
        f"`benchmarks/peers/exudyn_slider_crank.py`. {common.machine()} Exudyn {raw['exudyn']} "
        f"(its own venv, benchmarks/peers/.venv). Load average (1, 5, 15 min) {load_start} at "
        f"the start, {common.load_text()} at the end; the whole run took {total:.0f} s.",
        "",
        "Exudyn: 'bodies' = three RigidBody2D with RevoluteJoint2D, PrismaticJoint2D and the "
        "crank driven by a CoordinateConstraint with an offset user function (implicit "
        "solvers, fixed step h); 'tree' = one ObjectKinematicTree in minimal coordinates, the "
        f"crank a flywheel of {JBIG:.0e} kg m^2 driven by the ramp's torque, the solve split "
        "at t = 0.2 s (explicit solvers, atol = 1e-3 x rtol, largest step 1e-4 s). The "
        "clearance joint: ObjectConnectorRigidBodySpringDamper with a Python "
        "springForceTorqueUserFunction (or the same law as an exudyn.symbolic user "
        "function). 'CPU': process CPU time of building, solving and reading back, best of 2 "
        "(one run when it took over 5 s). jointgap: `simulate(0.5, rate=10000, rtol, "
        "atol=1e-3 x rtol, method='auto' or 'radau5', channels=['slider.ax'])`, model loaded "
        "once, best "
        "of 3. NRMSE: RMS of the slider.ax difference on the 10 kHz grid over the "
        "reference's max - min (Exudyn's every-step record interpolated linearly onto it).",
        "",
        f"Reference: jointgap at rtol 1e-11, atol 1e-14 ({ref.wall:.2f} s, {ref.impacts} "
        f"impacts); jointgap at rtol 1e-12 differs from it by NRMSE **{ref.error:.1e}**. "
        f"Contact stiffness K = {raw['K']:.4e} N/m^1.5 in both (checked).",
        "",
        "**Is the Exudyn model right?** Its tightest run per solver against the reference:",
        "",
        "| Exudyn | setting | NRMSE ax | impacts (reference) | crank angle error [rad] |",
        "|---|---|---:|---:|---:|",
    ]
    for r in checks:
        lines.append(
            f"| {label(r)} | {setting_text(r)} | {r['error']:.1e} | "
            f"{r['impacts']} ({ref.impacts}) | "
            f"{common.fmt(r.get('crank_error'), '.1e') or 'exact (constraint)'} |"
        )
    lines += [
        "",
        "| peer | method | setting | CPU [s] | wall [s] | NRMSE ax | steps | rejected | "
        "Newton it. | Jacobians | impacts | note |",
        "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---|",
    ]
    for r in runs:
        lines.append(
            f"| Exudyn | {label(r)} | {setting_text(r)} | {common.fmt(r.get('cpu'), '.3f')} | "
            f"{common.fmt(r.get('wall'), '.3f')} | {common.fmt(r.get('error'), '.1e')} | "
            f"{common.fmt(r.get('steps'), 'd')} | {common.fmt(r.get('rejected'), 'd')} | "
            f"{common.fmt(r.get('newton'), 'd')} | {common.fmt(r.get('jacobians'), 'd')} | "
            f"{common.fmt(r.get('impacts'), 'd')} | {r.get('note', '') or r.get('message', '')} |"
        )
    for r in jg:
        lines.append(
            f"| jointgap | {r.method} | rtol {r.rtol:.0e} | {common.fmt(r.cpu, '.3f')} | "
            f"{common.fmt(r.wall, '.3f')} | {common.fmt(r.error, '.1e')} | "
            f"{common.fmt(r.steps, 'd')} | | | | | {r.note} |"
        )
    lines += [
        "",
        "**Speed ratio at matched accuracy**: per NRMSE target, the cheapest Exudyn "
        "configuration meeting it (by CPU time) against the cheapest jointgap one; ratio = "
        "Exudyn CPU / jointgap CPU (the project's target: at least 100). One row per Exudyn "
        "solver (its cheapest run meeting the target); the cheapest of all in bold.",
        "",
        "| target NRMSE | Exudyn (solver, setting) | Exudyn CPU [s] | jointgap rtol | "
        "jointgap CPU [s] | ratio | wall ratio |",
        "|---:|---|---:|---:|---:|---:|---:|",
    ]
    summary = []
    paired_lines: list[str] = []
    for target in common.TARGETS:
        j = common.fastest(jg, "jointgap", target, key="cpu")
        overall = common.fastest(ex_rows, "Exudyn", target, key="cpu")
        per = {"overall": overall}
        for method in sorted({r.method for r in ex_rows}):
            per[method] = common.fastest(
                [r for r in ex_rows if r.method == method], "Exudyn", target, key="cpu"
            )
        for name, e in per.items():
            ratio = e.cpu / j.cpu if e and j and e.cpu and j.cpu else None
            wall_ratio = e.wall / j.wall if e and j and e.wall and j.wall else None
            paired = pair(raw_of[id(e)], j) if name == "overall" and e and j else None
            if paired:
                paired_lines.append(
                    f"- NRMSE {target:.0e}: {e.method} {e.setting} {num(e.rtol)} against "
                    f"jointgap {j.method} rtol {j.rtol:.0e}: {common.paired_text(paired)}"
                )
            summary.append(
                {
                    "target": target,
                    "which": name,
                    "exudyn": None if e is None else brief(e),
                    "jointgap": None if j is None else brief(j),
                    "ratio_cpu": ratio,
                    "ratio_wall": wall_ratio,
                    "paired": paired,
                }
            )
        shown = sorted(
            (e for name, e in per.items() if name != "overall" and e is not None),
            key=lambda e: e.cpu,
        )
        for e in shown or [None]:
            ratio = e.cpu / j.cpu if e and j and e.cpu and j.cpu else None
            wall_ratio = e.wall / j.wall if e and j and e.wall and j.wall else None
            bold = "**" if e is overall and e is not None else ""
            what = "not met"
            if e is not None:
                what = f"{bold}{e.method}{bold} {e.setting} {num(e.rtol)} (NRMSE {e.error:.1e})"
            lines.append(
                f"| {target:.0e} | {what} | {common.fmt(e.cpu if e else None, '.3f')} | "
                + (f"{j.rtol:.0e} (NRMSE {j.error:.1e})" if j else "not met")
                + f" | {common.fmt(j.cpu if j else None, '.3f')} | "
                + (f"{bold}{ratio:.0f}x{bold}" if ratio else "")
                + f" | {common.fmt(wall_ratio, '.0f')} |"
            )
    lines += [
        "",
        f"**Paired**: the bold pair of each target timed again in {common.PAIRED_ROUNDS} "
        "alternating rounds (one Exudyn run in its venv, jointgap's best of 3; process CPU "
        "time), the median of the rounds' ratios (min-max in brackets): both sides of each "
        "ratio in the same few seconds of a machine whose speed drifts.",
        "",
        *paired_lines,
    ]
    out = common.OUTPUT / "peers_exudyn.md"
    out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    print(f"wrote {out.relative_to(common.ROOT)}")
    path = common.write_json(
        "peers_exudyn.json",
        {
            "case": "examples/slider_crank_clearance.toml, 0 to 0.5 s, slider.ax at 10 kHz",
            "exudyn": raw["exudyn"],
            "target_ratio": 100,
            "targets_nrmse": list(common.TARGETS),
            "timing": "process CPU time (and wall), best of 2 for Exudyn (one run when over 5 s), "
            "best of 3 for jointgap",
            "reference": common.reference_summary(ref.wall, ref.error, impacts=ref.impacts),
            "check": [
                {
                    "solver": label(r),
                    "setting": setting_text(r),
                    "nrmse": r["error"],
                    "impacts": r["impacts"],
                    "crank_error": r.get("crank_error"),
                }
                for r in checks
            ],
            "exudyn_runs": [{k: v for k, v in r.items() if k != "key"} for r in runs],
            "jointgap_runs": [common.row_dict(r) for r in jg],
            "matched_accuracy": summary,
            "cap_s": cap,
            "load_average_start": load_start,
            "total_s": total,
        },
    )
    print(f"wrote {path.relative_to(common.ROOT)}")


if __name__ == "__main__":
    main()
