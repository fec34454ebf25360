"""Build a mechanism in Python: bodies, joints, drivers and forces, in SI or with units.

>>> import jointgap
>>> m = (
...     jointgap.Model("pendulum", gravity=(0, "-9.81 m/s^2"))
...     .add_body("bob", mass="1 kg", inertia="1e-3 kg*m^2", position=(1, 0),
...               points={"pivot": (-1, 0)})
...     .add_ground_point("O", (0, 0))
...     .add_revolute("hinge", "ground", "bob", point_i="O", point_j="pivot")
... )
>>> m.degrees_of_freedom()
1

Every quantity is a number in SI (kg, m, s, N, rad) or a string with a unit
(``"300 rpm"``, ``"15 mm"``). Each ``add_*`` method checks its own values and returns
the model, so calls chain; a bad value, a unit of the wrong dimension or a name used
twice raises :class:`jointgap.ModelError` at once. References between elements (a joint
naming a body) are checked by :meth:`Model.check` and before every run.
"""

from __future__ import annotations

import copy
import json
import math
import re
from collections.abc import Callable, Mapping, Sequence
from os import PathLike
from typing import TYPE_CHECKING, Any, Protocol

from ._schema import (
    DRIVEN_MOTION,
    GROUND,
    JOINT_EQUATIONS,
    SPATIAL_DRIVEN_MOTION,
    SPATIAL_JOINT_EQUATIONS,
    SPHERE_KEYS,
    convert_element,
)
from ._spatial_frames import at_centres_of_mass
from .errors import ModelError
from .laws import Law
from .profiles import Profile

if TYPE_CHECKING:
    from .results import Result

__all__ = ["Model"]

Quantity = float | str
Vector = Sequence[Quantity]
PointRef = str | Vector
Orientation = Mapping[str, Any]
"""A spatial body's orientation: ``{"axis": (x, y, z), "angle": "30 deg"}``,
``{"euler": ("30 deg", 0, 0), "convention": "ZYX"}`` or ``{"quaternion": (e0, e1, e2,
e3)}`` (scalar first)."""
Inertia = Quantity | Sequence[Quantity] | Sequence[Sequence[Quantity]]
"""A moment of inertia (planar), principal moments ``(J1, J2, J3)`` or a 3x3 tensor
(spatial), about the centre of mass."""

_KINDS = ("body", "joint", "driver", "force", "marker")
_SECTIONS = (
    ("bodies", "body"),
    ("joints", "joint"),
    ("drivers", "driver"),
    ("forces", "force"),
    ("markers", "marker"),
)
_RESERVED = (GROUND, "system")
_MOTION_UNITS = {"rotation": "angular units (rad, deg, rpm)", "translation": "linear units (m)"}


class Locator(Protocol):
    """Adds a file and line to an error about an element (see :mod:`jointgap._model_reader`)."""

    path: str

    def locate(self, error: ModelError) -> ModelError: ...


class Model:
    """A mechanism: moving rigid bodies, ideal joints, drivers and force elements.

    Planar by default; ``dimension=3`` makes a spatial mechanism (3-vectors, orientations,
    spatial joints; a model file says ``dimension = 3`` in ``[model]``). The ground (the
    fixed frame) is implicit and named ``ground``; its named points are added with
    :meth:`add_ground_point`. ``gravity`` defaults to (0, -9.81) m/s^2 in a planar model
    (a vertical plane with y up) and to the engine's (0, 0, -9.81) in a spatial one.
    """

    def __init__(self, name: str = "", gravity: Vector | None = None, dimension: int = 2) -> None:
        if dimension not in (2, 3):
            raise ModelError(
                f"dimension = {dimension!r}: 2 (planar) or 3 (spatial)",
                kind="model",
                key="dimension",
            )
        self._dimension = dimension
        raw = {"name": name, "gravity": gravity}
        fields, _ = convert_element("model", raw, dimension=dimension)
        self._name: str = fields["name"]
        self._gravity: list[float] | None = fields.get("gravity")
        self._elements: dict[str, list[dict[str, Any]]] = {k: [] for k in _KINDS}
        self._motions: list[str | None] = []  # per driver: units it was given in
        self._owner: dict[str, tuple[str, int]] = {}  # element name -> (kind, index)
        self._ground_points: dict[str, list[float]] = {}
        self._source: Locator | None = None

    # ------------------------------------------------------------------ read access

    @property
    def name(self) -> str:
        """Model name, for reports."""
        return self._name

    @property
    def dimension(self) -> int:
        """2 for a planar model, 3 for a spatial one."""
        return self._dimension

    @property
    def spatial(self) -> bool:
        """True for a spatial model (``dimension == 3``)."""
        return self._dimension == 3

    @property
    def gravity(self) -> tuple[float, ...] | None:
        """Gravity vector [m/s^2]; None in a spatial model that leaves it to the engine's
        default, (0, 0, -9.81)."""
        return None if self._gravity is None else tuple(self._gravity)

    @property
    def bodies(self) -> dict[str, dict[str, Any]]:
        """Bodies by name, in model order (copies, SI units)."""
        return self._view("body")

    @property
    def joints(self) -> dict[str, dict[str, Any]]:
        """Joints by name, in model order (copies, SI units)."""
        return self._view("joint")

    @property
    def drivers(self) -> dict[str, dict[str, Any]]:
        """Drivers by name, in model order (copies, SI units and radians)."""
        return self._view("driver")

    @property
    def forces(self) -> dict[str, dict[str, Any]]:
        """Force elements by name, in model order (copies, SI units)."""
        return self._view("force")

    @property
    def markers(self) -> dict[str, dict[str, Any]]:
        """Markers by name, in model order (copies, SI units)."""
        return self._view("marker")

    @property
    def ground_points(self) -> dict[str, tuple[float, ...]]:
        """Named points of the ground [m], global coordinates."""
        return {k: tuple(v) for k, v in self._ground_points.items()}

    @property
    def source(self) -> str | None:
        """The file the model was loaded from, if any."""
        return None if self._source is None else self._source.path

    def _view(self, kind: str) -> dict[str, dict[str, Any]]:
        return {e["name"]: copy.deepcopy(e) for e in self._elements[kind]}

    def degrees_of_freedom(self, with_drivers: bool = False) -> int:
        """Nominal degrees of freedom (Gruebler): 3 per body (6 in a spatial model) less
        the joint equations, less one per driver if ``with_drivers``. Redundant
        constraints, which the engine reports as warnings of :meth:`check`, add to the
        true count."""
        n = (6 if self.spatial else 3) * len(self._elements["body"])
        n -= self.joint_equations()
        if with_drivers:
            n -= len(self._elements["driver"])
        return n

    def joint_equations(self) -> int:
        """The number of constraint equations of the joints (none for a clearance joint)."""
        table = SPATIAL_JOINT_EQUATIONS if self.spatial else JOINT_EQUATIONS
        return sum(table[j["type"]] for j in self._elements["joint"])

    def __repr__(self) -> str:
        shown = [k for k in _KINDS if k != "marker" or self._elements[k]]
        counts = ", ".join(_count(len(self._elements[k]), k) for k in shown)
        kind = " (spatial)" if self.spatial else ""
        return f"<Model {self._name!r}{kind}: {counts}>"

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Model) and self.to_dict() == other.to_dict()

    __hash__ = None  # type: ignore[assignment]

    # ------------------------------------------------------------------ building

    def add_body(
        self,
        name: str,
        mass: Quantity,
        inertia: Inertia,
        position: Vector | None = None,
        angle: Quantity | None = None,
        velocity: Vector | None = None,
        omega: Quantity | None = None,
        points: Mapping[str, Vector] | None = None,
        shape: Mapping[str, Any] | None = None,
        com: Vector | None = None,
        *,
        orientation: Orientation | None = None,
        angular_velocity: Vector | None = None,
        inertia_frame: Orientation | None = None,
    ) -> Model:
        """Adds a rigid body, described in its own frame.

        The frame's origin is the centre of mass unless ``com`` places the centre of mass
        elsewhere in it (as URDF's inertial origin or an ADAMS part's cm marker): the
        position, velocity, points and shape are then those of the frame, and the engine
        works at the centre of mass (:meth:`to_dict`).

        Args:
            name: unique name (letters, digits, ``_``, ``-``).
            mass: mass [kg], > 0.
            inertia: moment of inertia about the centre of mass [kg m^2], >= 0 (0 for a
                point mass whose joints fix its rotation).
            position: approximate initial position of the frame's origin [m], default
                (0, 0); the engine assembles the mechanism from it.
            angle: approximate initial angle [rad], default 0.
            velocity: initial velocity of the frame's origin [m/s], default (0, 0).
            omega: initial angular velocity [rad/s], default 0.
            points: named points in the body frame [m].
            shape: drawing shape, e.g. ``{"type": "bar", "from": "O", "to": "A",
                "width": "20 mm"}``, ``{"type": "block", "width": .., "height": ..}`` or
                ``{"type": "disk", "radius": ..}`` (block and disk centred on the centre
                of mass); the engine ignores it.
            com: the centre of mass in the body frame [m]; by default the origin.

        A spatial body (``Model(..., dimension=3)``) has its frame at its centre of mass
        and takes 3-vectors; instead of ``angle``, ``omega``, ``shape`` and ``com``:

        Args:
            inertia: principal moments ``(J1, J2, J3)`` [kg m^2] about the body axes (or
                those of ``inertia_frame``), or the full symmetric 3x3 tensor in the body
                frame.
            orientation: approximate initial orientation (:data:`Orientation`).
            angular_velocity: initial angular velocity [rad/s], global axes.
            inertia_frame: the principal axes' orientation in the body frame.
        """
        raw = {
            "name": name,
            "mass": mass,
            "inertia": inertia,
            "position": position,
            "angle": angle,
            "velocity": velocity,
            "omega": omega,
            "points": points,
            "shape": shape,
            "com": com,
            "orientation": orientation,
            "angular_velocity": angular_velocity,
            "inertia_frame": inertia_frame,
        }
        return self._add("body", raw)

    def add_ground_point(self, name: str, xy: Vector) -> Model:
        """Names a point fixed in the ground, global coordinates [m]."""
        if name in self._ground_points:
            raise ModelError(f"duplicate point '{name}'", kind="ground", key=f"points.{name}")
        fields, _ = convert_element("ground", {"points": {name: xy}}, dimension=self._dimension)
        self._ground_points.update(fields["points"])
        return self

    def add_revolute(
        self,
        name: str,
        body_i: str,
        body_j: str,
        point_i: PointRef,
        point_j: PointRef,
        *,
        initial: Quantity | None = None,
        initial_rate: Quantity | None = None,
        axis: Vector | None = None,
        axis_j: Vector | None = None,
    ) -> Model:
        """Adds a pin joint: ``point_i`` of ``body_i`` and ``point_j`` of ``body_j``
        coincide. Points are point names or vectors [m] in the body frame (for the
        ground: global coordinates); both are required.

        ``initial`` and ``initial_rate`` set the joint's relative angle ``phi_j - phi_i``
        [rad] and its rate [rad/s] at t = 0; assembly solves the other coordinates.

        In a spatial model ``axis`` (in the frame of ``body_i``) is the pin's axis, and
        ``axis_j`` (in the frame of ``body_j``) the same line on body j, by default the
        one at the initial placement."""
        return self._add_joint(
            "revolute", name, body_i, body_j, point_i, point_j, axis, initial, initial_rate, axis_j
        )

    def add_prismatic(
        self,
        name: str,
        body_i: str,
        body_j: str,
        axis: Vector,
        point_i: PointRef,
        point_j: PointRef,
        *,
        initial: Quantity | None = None,
        initial_rate: Quantity | None = None,
        axis_j: Vector | None = None,
    ) -> Model:
        """Adds a slider: ``point_j`` stays on the line through ``point_i`` along ``axis``
        (a direction in the frame of ``body_i``), and the relative angle is fixed.

        ``initial`` and ``initial_rate`` set the travel of ``point_j`` from ``point_i``
        along the axis [m] and its rate [m/s] at t = 0; assembly solves the rest. In a
        spatial model, ``axis_j`` is the axis in the frame of ``body_j``."""
        return self._add_joint(
            "prismatic", name, body_i, body_j, point_i, point_j, axis, initial, initial_rate, axis_j
        )

    def add_fixed(
        self,
        name: str,
        body_i: str,
        body_j: str,
        point_i: PointRef,
        point_j: PointRef,
    ) -> Model:
        """Welds two bodies: the points coincide and the relative angle is fixed."""
        return self._add_joint("fixed", name, body_i, body_j, point_i, point_j)

    def add_spherical(
        self, name: str, body_i: str, body_j: str, point_i: PointRef, point_j: PointRef
    ) -> Model:
        """Spatial: a ball joint; ``point_i`` of ``body_i`` and ``point_j`` of ``body_j``
        coincide (3 equations)."""
        return self._add_joint("spherical", name, body_i, body_j, point_i, point_j)

    def add_cylindrical(
        self,
        name: str,
        body_i: str,
        body_j: str,
        axis: Vector,
        point_i: PointRef,
        point_j: PointRef,
        *,
        axis_j: Vector | None = None,
        initial: Quantity | None = None,
        initial_rate: Quantity | None = None,
    ) -> Model:
        """Spatial: the joint's axes (``axis`` in the frame of ``body_i`` through
        ``point_i``, ``axis_j`` in that of ``body_j``, by default the same line at the
        placement) stay on one line; turning about it and sliding along it are free (4
        equations). ``initial`` and ``initial_rate``: the angle about the axis [rad] and
        its rate at t = 0. A driver on it turns it."""
        return self._add_joint(
            "cylindrical",
            name,
            body_i,
            body_j,
            point_i,
            point_j,
            axis,
            initial,
            initial_rate,
            axis_j,
        )

    def add_universal(
        self,
        name: str,
        body_i: str,
        body_j: str,
        axis: Vector,
        axis_j: Vector,
        point_i: PointRef,
        point_j: PointRef,
    ) -> Model:
        """Spatial: Hooke's joint; the points coincide and the cross axes (``axis`` in the
        frame of ``body_i``, ``axis_j`` in that of ``body_j``) stay perpendicular (4
        equations)."""
        return self._add_joint(
            "universal", name, body_i, body_j, point_i, point_j, axis, None, None, axis_j
        )

    def add_planar(
        self,
        name: str,
        body_i: str,
        body_j: str,
        axis: Vector,
        point_i: PointRef,
        point_j: PointRef,
    ) -> Model:
        """Spatial: ``point_j`` stays in the plane of ``body_i`` through ``point_i`` with
        normal ``axis`` (frame of ``body_i``), and the two normals stay parallel (3
        equations)."""
        return self._add_joint("planar", name, body_i, body_j, point_i, point_j, axis)

    def _add_joint(
        self,
        type_: str,
        name: str,
        body_i: str,
        body_j: str,
        point_i: PointRef,
        point_j: PointRef,
        axis: Vector | None = None,
        initial: Quantity | None = None,
        initial_rate: Quantity | None = None,
        axis_j: Vector | None = None,
    ) -> Model:
        raw = {
            "name": name,
            "type": type_,
            "body_i": body_i,
            "point_i": point_i,
            "body_j": body_j,
            "point_j": point_j,
            "axis": axis,
            "axis_j": axis_j,
            "initial": initial,
            "initial_rate": initial_rate,
        }
        return self._add("joint", raw)

    def add_clearance_revolute(
        self,
        name: str,
        bearing_body: str,
        journal_body: str,
        point_bearing: PointRef,
        point_journal: PointRef,
        *,
        bearing_radius: Quantity | None = None,
        journal_radius: Quantity | None = None,
        clearance: Quantity | None = None,
        stiffness: Quantity | None = None,
        bearing_material: str | Mapping[str, Any] | None = None,
        journal_material: str | Mapping[str, Any] | None = None,
        normal_law: Law | Mapping[str, Any],
        friction: Law | Mapping[str, Any] | None = None,
    ) -> Model:
        """Adds a revolute joint with radial clearance: no constraint, a contact force
        between the bearing (a hole in ``bearing_body`` centred at ``point_bearing``) and
        the journal (a pin on ``journal_body`` centred at ``point_journal``). In a model
        file the bearing is ``body_i``/``point_i`` and the journal ``body_j``/``point_j``.

        Args:
            name: unique name; channels ``<name>.fx fy fn ft penetration
                penetration_rate ex ey slip mode`` and the impact list of the result.
            bearing_body, journal_body: the two bodies (either may be ``ground``).
            point_bearing, point_journal: point names or vectors [m] in the body frame.
            bearing_radius, journal_radius, clearance: two of the three [m].
            stiffness: contact stiffness K [N/m^n], n the normal law's exponent; by
                default computed from the two materials and the radii.
            bearing_material, journal_material: a library name (``"steel"``,
                ``"brass"``, ...) or ``{"youngs_modulus": .., "poisson_ratio": ..}``
                (:func:`jointgap.laws.material`).
            normal_law: e.g. ``laws.adams_impact("27960 N*s/m", "0.01 mm")`` or the
                same as a dict with a ``type``.
            friction: e.g. ``laws.coulomb(0.08, 0.05, "0.1 mm/s", "10.16 mm/s")``;
                frictionless by default.
        """
        raw = {
            "name": name,
            "type": "clearance_revolute",
            "body_i": bearing_body,
            "point_i": point_bearing,
            "body_j": journal_body,
            "point_j": point_journal,
            "bearing_radius": bearing_radius,
            "journal_radius": journal_radius,
            "clearance": clearance,
            "stiffness": stiffness,
            "bearing_material": bearing_material,
            "journal_material": journal_material,
            "normal_law": normal_law,
            "friction": friction,
        }
        return self._add("joint", raw)

    def add_lubricated_revolute(
        self,
        name: str,
        bearing_body: str,
        journal_body: str,
        point_bearing: PointRef,
        point_journal: PointRef,
        *,
        length: Quantity,
        viscosity: Quantity,
        film: str | None = None,
        roughness: Quantity | None = None,
        bearing_radius: Quantity | None = None,
        journal_radius: Quantity | None = None,
        clearance: Quantity | None = None,
        stiffness: Quantity | None = None,
        bearing_material: str | Mapping[str, Any] | None = None,
        journal_material: str | Mapping[str, Any] | None = None,
        normal_law: Law | Mapping[str, Any],
        friction: Law | Mapping[str, Any] | None = None,
    ) -> Model:
        """Adds a lubricated revolute joint: a clearance revolute joint (see
        :meth:`add_clearance_revolute`, whose arguments these are too) whose journal an oil
        film carries; where the film gets thinner than three times the roughness, the
        contact laws act as well (docs/lubrication.md).

        Args:
            name: unique name; channels ``<name>.fx fy`` (film and contact together),
                ``fn ft penetration penetration_rate ex ey slip mode`` (the contact's),
                ``eccentricity_ratio attitude film_thickness film_fx film_fy
                peak_pressure film_mode friction_torque`` (the film's; ``film_mode`` 0
                film, 1 mixed, 2 dry) and the impact list of the result.
            length: bearing length [m].
            viscosity: the oil's dynamic viscosity [Pa*s], e.g. ``"40 cP"``.
            film: ``"short"`` (the engine's default: Ocvirk, positive pressure),
                ``"long"`` (Sommerfeld), ``"short_pi"`` or ``"long_pi"`` (pi-film forms).
            roughness: composite RMS roughness of journal and bearing [m]; by default the
                engine's.
        """
        raw = {
            "name": name,
            "type": "lubricated_revolute",
            "body_i": bearing_body,
            "point_i": point_bearing,
            "body_j": journal_body,
            "point_j": point_journal,
            "bearing_radius": bearing_radius,
            "journal_radius": journal_radius,
            "clearance": clearance,
            "stiffness": stiffness,
            "bearing_material": bearing_material,
            "journal_material": journal_material,
            "normal_law": normal_law,
            "friction": friction,
            "lubrication": {
                "length": length,
                "viscosity": viscosity,
                "film": film,
                "roughness": roughness,
            },
        }
        return self._add("joint", raw)

    def add_clearance_translational(
        self,
        name: str,
        guide_body: str,
        block_body: str,
        axis: Vector,
        point_guide: PointRef,
        point_block: PointRef,
        *,
        block_length: Quantity,
        block_height: Quantity | None = None,
        guide_width: Quantity | None = None,
        clearance: Quantity | None = None,
        stiffness: Quantity,
        normal_law: Law | Mapping[str, Any],
        friction: Law | Mapping[str, Any] | None = None,
        height_axis: Vector | None = None,
        block_depth: Quantity | None = None,
        guide_depth: Quantity | None = None,
        depth_clearance: Quantity | None = None,
    ) -> Model:
        """Adds a slider with clearance in its guide: no constraint, a block (on
        ``block_body``, centred at ``point_block``) between the two surfaces of a guide (on
        ``guide_body``, its centreline through ``point_guide`` along ``axis``, a direction
        in the guide body's frame), touching them at its four corners. In a model file the
        guide is ``body_i``/``point_i`` and the block ``body_j``/``point_j``.

        Args:
            name: unique name; channels ``<name>.fx fy`` (the resultant on the block),
                ``tilt`` [rad] and ``offset`` [m] (the block in its guide), per corner
                ``<name>.p<i>.fn ft penetration penetration_rate slip mode`` (p1 front
                upper, p2 rear upper, p3 rear lower, p4 front lower) and each corner's
                impact list (``<name>.p<i>``).
            block_length: the block's length along the guide [m].
            block_height, guide_width, clearance: two of the block's height, the distance
                between the guide's surfaces and the total gap between them [m].
            stiffness: contact stiffness K [N/m^n] of a corner on a surface, n the normal
                law's exponent.
            normal_law, friction: as for :meth:`add_clearance_revolute`.
            height_axis, block_depth, guide_depth, depth_clearance: spatial only. The
                block is a box in a channel of rectangular section: ``height_axis`` (in
                the guide body's frame, perpendicular to ``axis``) is the direction of
                ``block_height`` and ``guide_width``; two of the block's depth, the
                channel's and their difference size it across both. Its eight corners
                each touch the height wall and the depth wall on their side: points
                ``p<2k-1>`` and ``p<2k>`` of corner ``k``; channels ``<name>.fx fy fz``,
                ``travel speed offset_height offset_depth tilt_along tilt_height
                tilt_depth`` and per point as in the plane.
        """
        raw = {
            "name": name,
            "type": "clearance_translational",
            "body_i": guide_body,
            "point_i": point_guide,
            "body_j": block_body,
            "point_j": point_block,
            "axis": axis,
            "height_axis": height_axis,
            "block_length": block_length,
            "block_height": block_height,
            "guide_width": guide_width,
            "block_depth": block_depth,
            "guide_depth": guide_depth,
            "depth_clearance": depth_clearance,
            "clearance": clearance,
            "stiffness": stiffness,
            "normal_law": normal_law,
            "friction": friction,
        }
        return self._add("joint", raw)

    def add_revolute_with_play(
        self,
        name: str,
        body_i: str,
        body_j: str,
        point_i: PointRef,
        point_j: PointRef,
        *,
        play: Quantity,
        stiffness: Quantity,
        normal_law: Law | Mapping[str, Any],
        centre: Quantity | None = None,
        initial: Quantity | None = None,
        initial_rate: Quantity | None = None,
    ) -> Model:
        """Adds a pin joint with play (backlash): the points coincide as in
        :meth:`add_revolute`, the relative angle ``phi_j - phi_i`` turns freely within
        ``centre +- play/2``, then a stop's torque acts by the contact law.

        Args:
            name: unique name; channels ``<name>.fx fy`` (the pin's reaction), ``angle
                omega``, ``play_angle`` [rad] (the angle less the centre), ``torque``
                [N*m] (the stop's torque on body_j), ``penetration`` [rad],
                ``penetration_rate`` [rad/s], ``mode`` and the impact list (onset speed in
                rad/s, peak in N*m).
            play: total free rotation [rad], e.g. ``"0.5 deg"`` or ``"20 arcmin"``.
            stiffness: the stop's stiffness K [N*m/rad^n], n the normal law's exponent.
            normal_law: the stop's law, its penetration the angle beyond the play.
            centre: the angle at the middle of the play [rad]; by default that of the
                model's placement.
            initial, initial_rate: as for :meth:`add_revolute`.
        """
        raw = {
            "name": name,
            "type": "revolute_with_play",
            "body_i": body_i,
            "point_i": point_i,
            "body_j": body_j,
            "point_j": point_j,
            "initial": initial,
            "initial_rate": initial_rate,
            "play": {
                "play": play,
                "centre": centre,
                "stiffness": stiffness,
                "normal_law": normal_law,
            },
        }
        return self._add("joint", raw)

    def add_prismatic_with_play(
        self,
        name: str,
        body_i: str,
        body_j: str,
        axis: Vector,
        point_i: PointRef,
        point_j: PointRef,
        *,
        play: Quantity,
        stiffness: Quantity,
        normal_law: Law | Mapping[str, Any],
        centre: Quantity | None = None,
        initial: Quantity | None = None,
        initial_rate: Quantity | None = None,
    ) -> Model:
        """Adds a slider with play along its axis: ``point_j`` stays on the line as in
        :meth:`add_prismatic`, its travel is free within ``centre +- play/2``, then a
        stop's force acts by the contact law.

        Args:
            name: unique name; channels ``<name>.fx fy moment`` (the slider's reaction),
                ``travel speed``, ``play_travel`` [m] (the travel less the centre),
                ``force`` [N] (the stop's force on body_j), ``penetration
                penetration_rate mode`` and the impact list.
            play: total free travel [m].
            stiffness: the stop's stiffness K [N/m^n], n the normal law's exponent.
            normal_law: the stop's law, its penetration the travel beyond the play.
            centre: the travel at the middle of the play [m]; by default that of the
                model's placement.
            initial, initial_rate: as for :meth:`add_prismatic`.
        """
        raw = {
            "name": name,
            "type": "prismatic_with_play",
            "body_i": body_i,
            "point_i": point_i,
            "body_j": body_j,
            "point_j": point_j,
            "axis": axis,
            "initial": initial,
            "initial_rate": initial_rate,
            "play": {
                "play": play,
                "centre": centre,
                "stiffness": stiffness,
                "normal_law": normal_law,
            },
        }
        return self._add("joint", raw)

    def add_gear_pair(
        self,
        name: str,
        gear_1: str,
        gear_2: str,
        centre_1: PointRef,
        centre_2: PointRef,
        *,
        ratio: Quantity,
        pitch_radius: Quantity,
        mesh_stiffness: Quantity | Mapping[str, Any],
        normal_law: Law | Mapping[str, Any],
        backlash: Quantity | None = None,
        pressure_angle: Quantity | None = None,
    ) -> Model:
        """Adds a pair of external spur gears in mesh with backlash: no constraint (each
        gear turns on its own revolute joint), a tooth force along the line of action
        once the mesh has taken up the backlash. In a model file gear 1 is
        ``body_i``/``point_i`` (its centre) and gear 2 ``body_j``/``point_j``; the
        centres must be ``pitch_radius * (1 + ratio)`` apart at the placement.

        Args:
            name: unique name; channels ``<name>.fx fy`` (the tooth force on gear 2),
                ``mesh`` [m] (along the line of action), ``fn`` [N], ``torque_1
                torque_2`` [N*m] (the teeth's torque on each gear about its centre),
                ``penetration penetration_rate mode``, ``stiffness`` (the mesh's there)
                and the impact list.
            ratio: gear 2's pitch radius over gear 1's (tooth counts z2/z1), > 0.
            pitch_radius: gear 1's pitch radius [m].
            mesh_stiffness: [N/m^n], n the normal law's exponent: a number, or
                ``{"angle": [...], "value": [...]}`` against gear 1's angle to the line
                of centres (periodic with the table's span, linear between points).
            normal_law: the teeth's contact law, its penetration along the line of action.
            backlash: circumferential backlash on the pitch circle [m]; none by default.
            pressure_angle: by default the engine's (20 deg).
        """
        raw = {
            "name": name,
            "type": "gear_pair",
            "body_i": gear_1,
            "point_i": centre_1,
            "body_j": gear_2,
            "point_j": centre_2,
            "gear": {
                "ratio": ratio,
                "pitch_radius": pitch_radius,
                "backlash": backlash,
                "pressure_angle": pressure_angle,
                "mesh_stiffness": mesh_stiffness,
                "normal_law": normal_law,
            },
        }
        return self._add("joint", raw)

    def add_clearance_spherical(
        self,
        name: str,
        socket_body: str,
        ball_body: str,
        point_socket: PointRef,
        point_ball: PointRef,
        *,
        socket_radius: Quantity | None = None,
        ball_radius: Quantity | None = None,
        clearance: Quantity | None = None,
        stiffness: Quantity | None = None,
        socket_material: str | Mapping[str, Any] | None = None,
        ball_material: str | Mapping[str, Any] | None = None,
        normal_law: Law | Mapping[str, Any],
        friction: Law | Mapping[str, Any] | None = None,
    ) -> Model:
        """Spatial: a ball joint with clearance, a contact force between the socket (on
        ``socket_body`` centred at ``point_socket``; ``body_i`` in a model file) and the
        ball (on ``ball_body`` at ``point_ball``; ``body_j``). Two of ``socket_radius``,
        ``ball_radius``, ``clearance`` [m]; ``stiffness`` or the two materials; the laws
        as for :meth:`add_clearance_revolute`. Channels ``<name>.fx fy fz ex ey ez`` and
        ``fn ft penetration ...`` of its contact point, and its impact list."""
        raw = {
            "name": name,
            "type": "clearance_spherical",
            "body_i": socket_body,
            "point_i": point_socket,
            "body_j": ball_body,
            "point_j": point_ball,
            "socket_radius": socket_radius,
            "ball_radius": ball_radius,
            "clearance": clearance,
            "stiffness": stiffness,
            "socket_material": socket_material,
            "ball_material": ball_material,
            "normal_law": normal_law,
            "friction": friction,
        }
        return self._add("joint", raw)

    def add_clearance_cylindrical(
        self,
        name: str,
        bearing_body: str,
        journal_body: str,
        axis: Vector,
        point_bearing: PointRef,
        point_journal: PointRef,
        *,
        length: Quantity,
        axis_j: Vector | None = None,
        axial_clearance: Quantity | None = None,
        bearing_radius: Quantity | None = None,
        journal_radius: Quantity | None = None,
        clearance: Quantity | None = None,
        stiffness: Quantity | None = None,
        bearing_material: str | Mapping[str, Any] | None = None,
        journal_material: str | Mapping[str, Any] | None = None,
        normal_law: Law | Mapping[str, Any],
        friction: Law | Mapping[str, Any] | None = None,
    ) -> Model:
        """Spatial: a revolute joint with radial clearance whose journal may tilt: a
        bearing on ``bearing_body`` (centre ``point_bearing``, ``axis`` in its frame) and
        a journal of ``length`` [m] on ``journal_body`` (centre ``point_journal``,
        ``axis_j`` in its frame, by default the same line at the placement), touching at
        either end. ``axial_clearance`` [m] adds thrust faces. The contact data as for
        :meth:`add_clearance_revolute`. Channels ``<name>.fx fy fz ex ey ez`` and, per
        contact point ``p<i>``, ``<name>.p<i>.fn ...``; an impact list per point."""
        raw = {
            "name": name,
            "type": "clearance_cylindrical",
            "body_i": bearing_body,
            "point_i": point_bearing,
            "body_j": journal_body,
            "point_j": point_journal,
            "axis": axis,
            "axis_j": axis_j,
            "bearing_radius": bearing_radius,
            "journal_radius": journal_radius,
            "clearance": clearance,
            "stiffness": stiffness,
            "bearing_material": bearing_material,
            "journal_material": journal_material,
            "normal_law": normal_law,
            "friction": friction,
            "length": length,
            "axial_clearance": axial_clearance,
        }
        return self._add("joint", raw)

    def add_lubricated_cylindrical(
        self,
        name: str,
        bearing_body: str,
        journal_body: str,
        axis: Vector,
        point_bearing: PointRef,
        point_journal: PointRef,
        *,
        length: Quantity,
        viscosity: Quantity,
        normal_law: Law | Mapping[str, Any],
        film: str | None = None,
        roughness: Quantity | None = None,
        **contact: Any,
    ) -> Model:
        """Spatial: a cylindrical clearance joint whose journal an oil film over its
        ``length`` carries, the film taken in two halves at their mid-planes so that a
        tilted journal feels a restoring moment; the contact laws act where the film gets
        thinner than three times the roughness (docs/lubrication.md, "In space").

        ``contact`` takes the other arguments of :meth:`add_clearance_cylindrical`
        (``axis_j``, ``axial_clearance``, the radii, ``stiffness`` or the materials,
        ``friction``); ``viscosity``, ``film`` and ``roughness`` are those of
        :meth:`add_lubricated_revolute`. Channels as the dry joint's, then
        ``<name>.film_fx fy fz`` (the film's force on the journal) and per half
        (``<name>.p1``, ``<name>.p2``) ``eccentricity_ratio film_thickness film_force
        peak_pressure film_mode friction_torque``.
        """
        raw = {
            "name": name,
            "type": "lubricated_cylindrical",
            "body_i": bearing_body,
            "point_i": point_bearing,
            "body_j": journal_body,
            "point_j": point_journal,
            "axis": axis,
            "length": length,
            "normal_law": normal_law,
            **contact,
            "lubrication": {
                "length": length,
                "viscosity": viscosity,
                "film": film,
                "roughness": roughness,
            },
        }
        return self._add("joint", raw)

    def add_driver(
        self,
        name: str,
        joint: str,
        profile: Profile | Mapping[str, Any],
        initial: Quantity | None = None,
    ) -> Model:
        """Prescribes the motion of a revolute or prismatic joint.

        Args:
            name: unique name; its output channel is ``<name>.torque`` (revolute) or
                ``<name>.force`` (prismatic), as applied by the motor to ``body_j``.
            joint: the driven joint.
            profile: a profile from :mod:`jointgap.profiles`, e.g.
                ``profiles.linear_ramp("300 rpm", "0.2 s")``, or the same as a dict with
                a ``type``.
            initial: joint coordinate at t = 0 [rad or m]; by default the one of the
                initial placement.
        """
        return self._add(
            "driver", {"name": name, "joint": joint, "profile": profile, "initial": initial}
        )

    def add_spring_damper(
        self,
        name: str,
        body_i: str,
        body_j: str,
        stiffness: Quantity | None = None,
        damping: Quantity | None = None,
        free_length: Quantity | None = None,
        point_i: PointRef | None = None,
        point_j: PointRef | None = None,
    ) -> Model:
        """Adds a point-to-point spring-damper: tension ``k (l - l0) + c dl/dt``.

        ``stiffness`` [N/m], ``damping`` [N s/m] and ``free_length`` [m] default to 0;
        the attachments ``point_i`` and ``point_j`` (point names or vectors in the body
        frames) are required."""
        raw = {
            "name": name,
            "type": "spring_damper",
            "body_i": body_i,
            "point_i": point_i,
            "body_j": body_j,
            "point_j": point_j,
            "stiffness": stiffness,
            "damping": damping,
            "free_length": free_length,
        }
        return self._add("force", raw)

    def add_rotational_spring_damper(
        self,
        name: str,
        body_i: str,
        body_j: str,
        stiffness: Quantity | None = None,
        damping: Quantity | None = None,
        free_angle: Quantity | None = None,
    ) -> Model:
        """Adds a torsion spring-damper: torque on ``body_j`` of
        ``-k (phi_j - phi_i - free_angle) - c (omega_j - omega_i)``, opposite on ``body_i``.

        ``stiffness`` [N m/rad], ``damping`` [N m s/rad], ``free_angle`` [rad], default 0."""
        raw = {
            "name": name,
            "type": "rotational_spring_damper",
            "body_i": body_i,
            "body_j": body_j,
            "stiffness": stiffness,
            "damping": damping,
            "free_angle": free_angle,
        }
        return self._add("force", raw)

    def add_force(
        self,
        name: str,
        body: str,
        force: Any,
        point: PointRef | None = None,
        *,
        frame: str | None = None,
    ) -> Model:
        """Applies a force [N] in global axes at a point of a body (by default its centre
        of mass).

        ``force`` is a constant ``(fx, fy)`` or a table against time:
        ``(times, [(fx, fy), ...])`` or ``{"time": [...], "value": [...]}`` (linear
        between points, held outside). In a spatial model it is ``(fx, fy, fz)``, in the
        axes of ``frame``: ``"ground"`` (global, the default) or ``"body"`` (turning with
        the body)."""
        raw = {
            "name": name,
            "type": "applied_force",
            "body": body,
            "point": point,
            "force": _signal(force),
            "frame": frame,
        }
        return self._add("force", raw)

    def add_torque(self, name: str, body: str, torque: Any, *, frame: str | None = None) -> Model:
        """Applies a torque [N m], counter-clockwise positive: a constant, or a table
        ``(times, values)`` / ``{"time": [...], "value": [...]}``. In a spatial model a
        vector ``(mx, my, mz)`` in the axes of ``frame``, ``"ground"`` (default) or
        ``"body"``."""
        raw = {
            "name": name,
            "type": "applied_torque",
            "body": body,
            "torque": _signal(torque),
            "frame": frame,
        }
        return self._add("force", raw)

    def add_marker(self, name: str, body: str, point: PointRef, frame: str | None = None) -> Model:
        """Adds a marker: a point whose motion the run reports as channels
        ``<name>.x .y`` [m], ``.vx .vy`` [m/s] and ``.ax .ay`` [m/s^2].

        Args:
            name: unique name.
            body: the body carrying the point (or ``ground``).
            point: a point name of the body or a vector in its frame [m].
            frame: a body in whose frame the motion is measured (its coordinates in
                that body's frame and their time derivatives as an observer riding the
                body sees them); the ground by default.
        """
        return self._add("marker", {"name": name, "body": body, "point": point, "frame": frame})

    def _add(self, kind: str, raw: Mapping[str, Any]) -> Model:
        index = len(self._elements[kind])
        fields, motion = convert_element(kind, raw, index=index, dimension=self._dimension)
        name = fields["name"]
        if name in _RESERVED:
            raise ModelError(f"the name '{name}' is reserved", kind=kind, index=index, key="name")
        if name in self._owner:
            other_kind, other_index = self._owner[name]
            raise ModelError(
                f"duplicate name '{name}', already used by a {other_kind}",
                kind=kind,
                name=name,
                index=index,
                key="name",
                related=(other_kind, other_index),
            )
        if kind == "driver":
            self._check_motion(fields, motion, index)
            self._motions.append(motion)
        self._elements[kind].append(fields)
        self._owner[name] = (kind, index)
        return self

    def _check_motion(self, driver: Mapping[str, Any], motion: str | None, index: int) -> None:
        """A driver given in angular units must drive a revolute joint, and so on."""
        owner = self._owner.get(driver["joint"])
        if motion is None or owner is None or owner[0] != "joint":
            return  # plain numbers, or a missing joint: the engine reports the latter
        joint = self._elements["joint"][owner[1]]
        expected = (SPATIAL_DRIVEN_MOTION if self.spatial else DRIVEN_MOTION).get(joint["type"])
        if expected is not None and expected != motion:
            raise ModelError(
                f"profile is given in {_MOTION_UNITS[motion]} but joint '{joint['name']}' is "
                f"{joint['type']}: use {_MOTION_UNITS[expected]}",
                kind="driver",
                name=driver["name"],
                index=index,
                key="profile",
            )

    # ------------------------------------------------------------------ conversion

    def to_dict(self) -> dict[str, Any]:
        """The model as the engine reads it: plain data, SI units and radians, every body
        in its centre-of-mass frame (:func:`_at_centres_of_mass`). A spatial model's
        starts with ``"dimension": 3`` and leaves out what its elements leave to the
        engine's defaults."""
        if self.spatial:
            model: dict[str, Any] = {"dimension": 3, "name": self._name}
            if self._gravity is not None:
                model["gravity"] = list(self._gravity)
            for key, kind in _SECTIONS:
                model[key] = copy.deepcopy(self._elements[kind])
            model["ground_points"] = copy.deepcopy(self._ground_points)
            return at_centres_of_mass(model)
        return _at_centres_of_mass(
            {
                "name": self._name,
                "gravity": list(self._gravity or ()),
                "bodies": copy.deepcopy(self._elements["body"]),
                "joints": copy.deepcopy(self._elements["joint"]),
                "drivers": copy.deepcopy(self._elements["driver"]),
                "forces": copy.deepcopy(self._elements["force"]),
                "ground_points": copy.deepcopy(self._ground_points),
                "markers": copy.deepcopy(self._elements["marker"]),
            }
        )

    def to_json(self, indent: int | None = None) -> str:
        """:meth:`to_dict` as JSON, the engine's input."""
        return json.dumps(self.to_dict(), indent=indent)

    @classmethod
    def from_dict(cls, data: Mapping[str, Any]) -> Model:
        """Rebuilds a model from :meth:`to_dict` output (e.g. a run's ``summary.json``)."""
        known = {
            "dimension",
            "name",
            "gravity",
            "bodies",
            "joints",
            "drivers",
            "forces",
            "ground_points",
            "markers",
        }
        unknown = sorted(set(data) - known)
        if unknown:
            raise ModelError(f"unknown key '{unknown[0]}' (allowed: {', '.join(sorted(known))})")
        model = cls(data.get("name", ""), data.get("gravity"), data.get("dimension", 2))
        for name, xy in (data.get("ground_points") or {}).items():
            model.add_ground_point(name, xy)
        for kind, key in (("body", "bodies"), ("joint", "joints"), ("driver", "drivers")):
            for element in data.get(key) or []:
                model._add(kind, element)
        for element in data.get("forces") or []:
            model._add("force", element)
        for element in data.get("markers") or []:
            model._add("marker", element)
        return model

    def save(self, path: str | PathLike[str]) -> None:
        """Writes the model as a TOML model file (SI numbers) that :func:`jointgap.load`
        reads back to the same model."""
        from ._model_writer import save

        save(self.to_dict(), path)

    # ------------------------------------------------------------------ checks and runs

    def check(self) -> list[str]:
        """Checks the whole model with the engine (references, assembly data); returns
        its warnings (e.g. redundant constraints) or raises :class:`ModelError`."""
        self._check_drivers()
        from ._jointgap import check_model

        try:
            return list(check_model(self.to_json()))
        except ValueError as exc:
            raise self.engine_error(exc) from None

    def clearance_data(self) -> dict[str, dict[str, Any]]:
        """Each clearance joint as the engine resolves it, without a run, keyed by joint:
        ``bearing_radius``, ``journal_radius``, ``clearance`` [m] (from the two given),
        ``stiffness`` K [N/m^n] (from the materials unless given), ``exponent`` n,
        ``d_max`` [m] (of an adams_impact law, given or the bearing material's; None for
        the other laws) and the laws in force, ``normal_law`` and ``friction`` (SI, every
        default filled in). What Python needs of these it reads here, never guessing the
        engine's defaults."""
        from ._jointgap import clearance_data

        try:
            data = json.loads(clearance_data(self.to_json()))
        except ValueError as exc:
            raise self.engine_error(exc) from None
        return {d.pop("joint"): d for d in data}

    def _check_drivers(self) -> None:
        for index, (driver, motion) in enumerate(
            zip(self._elements["driver"], self._motions, strict=True)
        ):
            try:
                self._check_motion(driver, motion, index)
            except ModelError as exc:
                raise self._located(exc) from None

    def engine_error(self, exc: ValueError) -> Exception:
        """Turns an engine error (the binding's ``EngineError``, which carries the
        category, element kind and name, key and problem as attributes) into a ModelError
        naming the element, and its file and line for a loaded model. Errors about run
        options, and any other ValueError, are returned as they are."""
        from ._jointgap import EngineError

        if not isinstance(exc, EngineError) or exc.category == "options":
            return exc
        kind, name, key, problem = exc.kind, exc.element, exc.key, exc.problem
        if kind is None or name is None:
            return self._located(ModelError(problem))
        owner = self._owner.get(name)
        index = owner[1] if owner is not None and owner[0] == kind else None
        if index is not None and self._elements[kind][index].get("type") == "clearance_spherical":
            key = None if key is None else _sphere_words(key)
            problem = _sphere_words(problem)
        return self._located(ModelError(problem, kind=kind, name=name, index=index, key=key))

    def _located(self, error: ModelError) -> ModelError:
        return error if self._source is None else self._source.locate(error)

    def simulate(
        self,
        t_end: Quantity,
        rate: Quantity | None = None,
        rtol: float | None = None,
        atol: float | None = None,
        method: str | None = None,
        every_step: bool = False,
        max_step: Quantity | None = None,
        channels: Sequence[str] | None = None,
        max_steps: int | None = None,
        decimate: int | None = None,
        stream: str | PathLike[str] | None = None,
        progress: Callable[[float, int, int], object] | None = None,
        profile: bool = False,
        step_peaks: bool = False,
        energy: bool = False,
        wear_cells: int | None = None,
        wear_start: Quantity | None = None,
        compiled: bool = True,
        exact_jacobian: bool = True,
    ) -> Result:
        """Runs the mechanism from t = 0 to ``t_end`` and returns its :class:`Result`.

        Args:
            t_end: end time [s] (or e.g. ``"0.5 s"``).
            rate: output sampling rate [Hz] (e.g. ``"10 kHz"``); ``None`` records every
                accepted step.
            rtol, atol: tolerances of the local error test (atol in m, rad, m/s, rad/s);
                by default the engine's (:data:`jointgap._engine.DEFAULT_OPTIONS`).
            method: ``"auto"`` (the default; explicit Dormand-Prince, handing the steps to the
                implicit Radau IIA while sticking friction is stiff and to SDIRK4 when the
                problem turns stiff otherwise), ``"dopri5"``, ``"sdirk4"`` or ``"radau5"``
                (implicit Radau IIA of order 5, for stiff contact at tight tolerances).
            every_step: also record every accepted step.
            max_step: largest step [s]; unbounded by default.
            channels: channels to record (exact names or ``"element.*"``); all by default.
            max_steps: step budget (default 1e7 steps, or 1e6 per simulated second when
                that is more); the run fails when it is spent.
            decimate: keep every ``decimate``-th output record (e.g. of ``every_step``).
            stream: a Parquet file to write the samples to in chunks as the run goes,
                for long runs: memory then holds one chunk, and the result reads its
                channels back from the file.
            progress: ``progress(t, steps, impacts)``, called about every 0.2 s of wall
                time (simulated time, steps taken, impacts so far), e.g. for a display;
                an exception it raises stops the run and propagates (a
                KeyboardInterrupt interrupts it, as Ctrl-C does).
            profile: measure where the time goes: ``stats["profile"]`` then holds the
                seconds spent in force evaluation, linear solves, Jacobians, output,
                event location and projection, and the integration's total.
            step_peaks: evaluate the channels at every accepted step for their peaks
                (``Result.peaks``) while keeping only the samples.
            energy: keep the energy accounts: channels ``system.driver_work``,
                ``load_work``, ``damper_dissipation``, ``contact_dissipation``,
                ``friction_dissipation`` [J] (time integrals of their powers over the
                steps) and ``system.energy_balance``, kinetic + potential - work in +
                dissipated, which stays at its initial value. Costs about three more
                evaluations of the equations of motion per step and per sample.
            wear_cells: accumulate the Archard wear of the clearance_revolute joints
                (each needs its ``length``) and dry clearance_cylindrical joints on
                angular grids of this many cells (at least 8) into :attr:`Result.wear`
                (docs/wear.md).
            wear_start: the time from which the wear counts [s] (by default from the
                start): the steady cycles after a start-up.
            compiled: evaluate the equations of motion by native code compiled from the
                model where the compiler covers it (the default; docs/compiled.md), or
                always interpreted (``False``). The results are the same to the bit;
                ``stats["compiled"]`` says which ran and why.
            exact_jacobian: the implicit methods (``radau5``, ``sdirk4``, and ``auto``
                when it hands them the steps) take the exact derivatives of the
                accelerations, differentiated from the recorded evaluation where the
                compiler covers the model (the default), or the applied forces' part by
                forward differences (``False``, as where it does not cover the model).

        A run that stops early is returned with ``status == "failed"``, one stopped by
        Ctrl-C with ``status == "interrupted"``, each with everything computed up to
        then. Raises :class:`ModelError` for an invalid model and
        ValueError for invalid options.
        """
        from ._engine import run_options, simulate

        self._check_drivers()
        options = run_options(
            t_end,
            rate=rate,
            rtol=rtol,
            atol=atol,
            method=method,
            every_step=every_step,
            max_step=max_step,
            channels=channels,
            max_steps=max_steps,
            decimate=decimate,
            energy=energy,
            profile=profile,
            step_peaks=step_peaks,
            wear_cells=wear_cells,
            wear_start=wear_start,
            compiled=compiled,
            exact_jacobian=exact_jacobian,
        )
        try:
            return simulate(self.to_dict(), options, progress=progress, stream=stream)
        except ValueError as exc:
            raise self.engine_error(exc) from None


def _at_centres_of_mass(model: dict[str, Any]) -> dict[str, Any]:
    """Moves every body given in its own frame (``com`` = the centre of mass in that
    frame) to its centre-of-mass frame, the engine's, in place: the one place where
    frames are converted.

    With ``c`` the centre of mass in the body frame and ``R`` the frame's rotation, a
    point ``s`` of the frame becomes ``s - c``; the frame origin's position ``r`` and
    velocity ``v`` become the centre of mass's ``r + R c`` and ``v + omega k x (R c)``.
    Joint and force points given as vectors move with their body's points; the ground
    has no centre of mass, and the angle is the same in both frames.
    """
    offsets: dict[str, tuple[float, float]] = {}
    for body in model["bodies"]:
        cx, cy = body.pop("com", None) or (0.0, 0.0)
        if cx == 0.0 and cy == 0.0:
            continue
        offsets[body["name"]] = (cx, cy)
        body["points"] = {k: [x - cx, y - cy] for k, (x, y) in body["points"].items()}
        shape = body.get("shape") or {}
        for end in ("from", "to"):
            if isinstance(shape.get(end), list):
                shape[end] = [shape[end][0] - cx, shape[end][1] - cy]
        c, s = math.cos(body["angle"]), math.sin(body["angle"])
        rc = (c * cx - s * cy, s * cx + c * cy)  # R c, global axes
        body["position"] = [body["position"][0] + rc[0], body["position"][1] + rc[1]]
        w = body["omega"]
        body["velocity"] = [body["velocity"][0] - w * rc[1], body["velocity"][1] + w * rc[0]]

    def move(element: dict[str, Any], body_key: str, point_key: str) -> None:
        offset = offsets.get(element.get(body_key, ""))
        point = element.get(point_key)
        if offset is not None and isinstance(point, list):
            element[point_key] = [point[0] - offset[0], point[1] - offset[1]]

    for joint in model["joints"]:
        move(joint, "body_i", "point_i")
        move(joint, "body_j", "point_j")
    for force in model["forces"]:
        move(force, "body_i", "point_i")
        move(force, "body_j", "point_j")
        move(force, "body", "point")
    for marker in model["markers"]:
        move(marker, "body", "point")
    return model


def _sphere_words(text: str) -> str:
    """An engine message or key about a clearance_spherical joint in the words of its
    file: ``journal_radius`` is its ``ball_radius`` (:data:`SPHERE_KEYS`)."""
    for own, engine in SPHERE_KEYS.items():
        text = re.sub(rf"\b(clearance\.)?{engine}\b", own, text)
    return text


def _count(n: int, kind: str) -> str:
    plural = {"body": "bodies"}.get(kind, kind + "s")
    return f"{n} {kind if n == 1 else plural}"


def _signal(value: Any) -> Any:
    """A builder's table ``(times, values)`` as the file's ``{time, value}``."""
    if (
        isinstance(value, Sequence)
        and not isinstance(value, str)
        and len(value) == 2
        and isinstance(value[0], Sequence)
        and not isinstance(value[0], str)
    ):
        return {"time": list(value[0]), "value": list(value[1])}
    return value
