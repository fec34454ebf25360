"""The model's fields in one table: dimension, bound, default; and their conversion to SI.

Every field of every model element is declared once here. The file reader
(:mod:`jointgap._model_reader`), the builder (:mod:`jointgap.model`) and the reference tables of
``docs/model-file.md`` (:func:`reference_markdown`) all read this table, so a unit, a
bound or a default can change in one place only.

:func:`convert_element` turns the user's values (numbers in SI or quantity strings) into
the engine's plain-SI dictionaries, raising :class:`ModelError` naming the element, the
field and the problem. Cross-references (does body ``rod`` exist?) are not checked here:
the engine checks them (:meth:`jointgap.Model.check`).
"""

from __future__ import annotations

import json
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, replace
from fractions import Fraction
from typing import Any

from . import _jointgap
from . import units as u
from .errors import ModelError, UnitError
from .results import CLEARANCE_TYPES
from .units import Dimension

__all__ = [
    "Param",
    "ELEMENTS",
    "SPATIAL_ELEMENTS",
    "convert_element",
    "params_of",
    "types_of",
    "reference_markdown",
    "GROUND",
]

GROUND = "ground"
"""The name of the fixed frame, to which joints and forces may refer."""

_NAME = re.compile(r"^[A-Za-z0-9_\-]+$")

ENGINE_DEFAULTS: dict[str, Any] = json.loads(_jointgap.defaults())
"""What the engine takes for a value left out, asked of the core once: ``gravity``
[m/s^2], ``normal_law`` (``exponent``, ``clip``) and the run ``options`` (without
``t_end``). The table below and :data:`jointgap._engine.DEFAULT_OPTIONS` read them from here,
so that Python repeats none of the core's defaults."""


@dataclass(frozen=True)
class Param:
    """One field of a model element.

    ``kind`` says how a value is read: ``text``, ``name`` (this element's unique name),
    ``ref`` (another element's name), ``choice`` (the element's ``type``), ``scalar``,
    ``vector`` ([x, y]), ``point`` (a point name or a vector), ``points`` (name -> vector),
    ``list`` (numbers), ``scalar_signal`` / ``vector_signal`` (constant or a table
    ``{time, value}``), ``shape`` and ``profile`` (nested tables with a ``type``).
    ``dim`` is the expected dimension, or several for a driver's motion (angular for a
    revolute joint, linear for a prismatic one; ``motion`` is then true).
    """

    key: str
    kind: str
    dim: Dimension | tuple[Dimension, ...] | None = None
    required: bool = False
    default: Any = None
    bound: str | None = None  # ">0" or ">=0"
    doc: str = ""
    motion: bool = False
    choices: tuple[str, ...] = ()


def _name(doc: str = "unique name of the element") -> Param:
    return Param("name", "name", required=True, doc=doc)


_ROTATION_OR_TRANSLATION_SPEED = (u.ANGULAR_SPEED, u.SPEED)
_ROTATION_OR_TRANSLATION = (u.ANGLE, u.LENGTH)

_JOINT_COMMON = [
    _name(),
    Param(
        "type",
        "choice",
        required=True,
        doc="revolute, prismatic, fixed, clearance_revolute, lubricated_revolute, "
        "clearance_translational, revolute_with_play, prismatic_with_play or gear_pair",
    ),
    Param("body_i", "ref", required=True, doc="first body, or ground"),
    Param("point_i", "point", u.LENGTH, required=True, doc="joint point on body_i"),
    Param("body_j", "ref", required=True, doc="second body (reactions are forces on it)"),
    Param("point_j", "point", u.LENGTH, required=True, doc="joint point on body_j"),
]

_FORCE_HEAD = [_name(), Param("type", "choice", required=True, doc="force element kind")]

_SPEED = Param(
    "speed",
    "scalar",
    _ROTATION_OR_TRANSLATION_SPEED,
    required=True,
    motion=True,
    doc="final speed: rad/s for a revolute joint (counter-clockwise positive), m/s for a "
    "prismatic joint (along its axis)",
)
_RAMP = Param("ramp_time", "scalar", u.TIME, required=True, bound=">0", doc="ramp duration")
_TIMES = Param("time", "list", u.TIME, required=True, doc="strictly increasing times")

_EXPONENT = Param(
    "exponent",
    "scalar",
    u.DIMENSIONLESS,
    default=ENGINE_DEFAULTS["normal_law"]["exponent"],
    doc="exponent n of the penetration",
)
_CLIP = Param(
    "clip",
    "bool",
    default=ENGINE_DEFAULTS["normal_law"]["clip"],
    doc="set pulling (negative) forces to zero",
)
_RESTITUTION = Param(
    "restitution", "scalar", u.DIMENSIONLESS, required=True, doc="coefficient of restitution"
)


def _law(*params: Param) -> list[Param]:
    return [Param("type", "choice", required=True), *params]


CLEARANCE_KEYS = (
    "bearing_radius",
    "journal_radius",
    "clearance",
    "stiffness",
    "bearing_material",
    "journal_material",
    "normal_law",
    "friction",
)
"""The keys of a clearance joint that the engine reads nested in ``clearance`` (a
clearance_spherical joint's file names them as :data:`SPHERE_KEYS` says)."""

_CLEARANCE = [
    Param("bearing_radius", "scalar", u.LENGTH, doc="radius of the hole (on body_i)"),
    Param("journal_radius", "scalar", u.LENGTH, doc="radius of the pin (on body_j)"),
    Param(
        "clearance",
        "scalar",
        u.LENGTH,
        doc="radial clearance; give two of bearing_radius, journal_radius, clearance",
    ),
    Param(
        "stiffness",
        "contact_stiffness",
        doc="contact stiffness K [N/m^n], n the law's exponent; by default from the materials",
    ),
    Param(
        "bearing_material",
        "material",
        doc="library name (steel, brass, ...) or { youngs_modulus, poisson_ratio }",
    ),
    Param("journal_material", "material", doc="as bearing_material"),
    Param("normal_law", "normal_law", required=True, doc="normal force law, a table with a type"),
    Param("friction", "friction", doc="friction law, a table with a type; none by default"),
]

WEAR_TABLES = ("bearing_wear", "journal_wear")
"""A worn joint's profiles, keys of its ``clearance`` table (docs/wear.md)."""
WEAR_KEYS = ("length", *WEAR_TABLES)
"""A planar clearance_revolute joint's own keys of its ``clearance`` table for wear."""

_WEAR = [
    Param(
        "length",
        "scalar",
        u.LENGTH,
        bound=">0",
        doc="bearing length along the axis: the line contact's length, needed for wear",
    ),
    Param(
        "bearing_wear",
        "list",
        u.LENGTH,
        doc="wear depth of the bearing at N >= 8 equally spaced angles 2 pi k / N in body_i's "
        "frame (from its x axis): the hole's radius becomes bearing_radius + w(theta)",
    ),
    Param(
        "journal_wear",
        "list",
        u.LENGTH,
        doc="wear depth of the journal at N >= 8 equally spaced angles in body_j's frame: "
        "its radius becomes journal_radius - w(theta)",
    ),
]

BLOCK_KEYS = ("block_length", "block_height", "guide_width")
"""A clearance_translational joint's own keys of its ``clearance`` table (with
``clearance``, ``stiffness``, ``normal_law`` and ``friction``)."""
DEPTH_KEYS = ("block_depth", "guide_depth", "depth_clearance")
"""A spatial clearance_translational joint's keys of its ``clearance`` table for the
channel's depth, beside :data:`BLOCK_KEYS`."""

_AXIS = Param(
    "axis",
    "vector",
    u.DIMENSIONLESS,
    required=True,
    doc="sliding direction in the frame of body_i",
)
_REVOLUTE_INITIAL = [
    Param(
        "initial",
        "scalar",
        u.ANGLE,
        doc="relative angle phi_j - phi_i at t = 0; assembly solves the rest",
    ),
    Param(
        "initial_rate",
        "scalar",
        u.ANGULAR_SPEED,
        doc="relative angular velocity at t = 0; assembly solves the rest",
    ),
]
_PRISMATIC_INITIAL = [
    Param(
        "initial",
        "scalar",
        u.LENGTH,
        doc="travel of point_j from point_i along the axis at t = 0",
    ),
    Param("initial_rate", "scalar", u.SPEED, doc="sliding speed at t = 0"),
]

_BLOCK_CLEARANCE = [
    Param(
        "block_length",
        "scalar",
        u.LENGTH,
        required=True,
        bound=">0",
        doc="length of the block (on body_j) along the guide",
    ),
    Param(
        "block_height", "scalar", u.LENGTH, bound=">0", doc="height of the block across the guide"
    ),
    Param(
        "guide_width",
        "scalar",
        u.LENGTH,
        bound=">0",
        doc="distance between the guide's two surfaces (on body_i)",
    ),
    Param(
        "clearance",
        "scalar",
        u.LENGTH,
        bound=">0",
        doc="total lateral gap guide_width - block_height; give two of block_height, "
        "guide_width, clearance",
    ),
    Param(
        "stiffness",
        "contact_stiffness",
        required=True,
        doc="contact stiffness K [N/m^n] of a corner on a guide surface, n the law's exponent",
    ),
    _CLEARANCE[-2],  # normal_law
    _CLEARANCE[-1],  # friction
]

_LUBRICATION = Param(
    "lubrication",
    "lubrication",
    required=True,
    doc="the oil film, a table { length, viscosity, film, roughness }",
)
_GEAR = Param(
    "gear",
    "gear",
    required=True,
    doc="the teeth, a table { ratio, pitch_radius, backlash, mesh_stiffness, normal_law, ... }",
)


def _play(kind: str) -> Param:
    return Param(
        "play",
        kind,
        required=True,
        doc="the play, a table { play, centre, stiffness, normal_law }",
    )


def _play_table(dim: Dimension, what: str, stiffness: str) -> list[Param]:
    return [
        Param(
            "play",
            "scalar",
            dim,
            required=True,
            bound=">=0",
            doc=f"total free {what}: the joint is free within centre +- play/2",
        ),
        Param(
            "centre",
            "scalar",
            dim,
            doc=f"{what} at the middle of the play; by default that of the model's placement",
        ),
        Param(
            "stiffness",
            "contact_stiffness",
            dim,
            required=True,
            doc=f"contact stiffness K [{stiffness}], n the law's exponent",
        ),
        Param(
            "normal_law",
            "normal_law",
            required=True,
            doc="the stop's law, its penetration the coordinate beyond the play",
        ),
    ]


# Element kind -> fields, or -> {type: fields} for elements with a ``type``.
ELEMENTS: dict[str, list[Param] | dict[str, list[Param]]] = {
    "model": [
        Param("name", "text", default="", doc="model name, for reports"),
        Param(
            "gravity",
            "vector",
            u.ACCELERATION,
            default=tuple(ENGINE_DEFAULTS["gravity"]),
            doc="uniform gravity in the plane; [0, 0] for a horizontal mechanism",
        ),
    ],
    "ground": [
        Param("points", "points", u.LENGTH, default={}, doc="named points, global coordinates"),
    ],
    "body": [
        _name(),
        Param("mass", "scalar", u.MASS, required=True, bound=">0", doc="mass"),
        Param(
            "inertia",
            "scalar",
            u.INERTIA,
            required=True,
            bound=">=0",
            doc="moment of inertia about the centre of mass; 0 for a point mass whose "
            "joints fix its rotation",
        ),
        Param(
            "com",
            "vector",
            u.LENGTH,
            doc="centre of mass in the body frame; by default the frame's origin",
        ),
        Param(
            "position",
            "vector",
            u.LENGTH,
            default=(0.0, 0.0),
            doc="initial position of the frame's origin (approximate: assembly corrects it)",
        ),
        Param("angle", "scalar", u.ANGLE, default=0.0, doc="initial angle (approximate)"),
        Param(
            "velocity", "vector", u.SPEED, default=(0.0, 0.0), doc="initial velocity of the origin"
        ),
        Param("omega", "scalar", u.ANGULAR_SPEED, default=0.0, doc="initial angular velocity"),
        Param("points", "points", u.LENGTH, default={}, doc="named points in the body frame"),
        Param("shape", "shape", doc="drawing shape (bar, block or disk); ignored by the engine"),
    ],
    "joint": {
        "revolute": [*_JOINT_COMMON, *_REVOLUTE_INITIAL],
        "prismatic": [*_JOINT_COMMON, _AXIS, *_PRISMATIC_INITIAL],
        "fixed": _JOINT_COMMON,
        "clearance_revolute": [*_JOINT_COMMON, *_CLEARANCE, *_WEAR],
        "lubricated_revolute": [*_JOINT_COMMON, *_CLEARANCE, _LUBRICATION],
        "clearance_translational": [
            *_JOINT_COMMON,
            Param(
                "axis",
                "vector",
                u.DIMENSIONLESS,
                required=True,
                doc="the guide's direction in the frame of body_i; its centreline passes "
                "through point_i, the block is centred at point_j",
            ),
            *_BLOCK_CLEARANCE,
        ],
        "revolute_with_play": [*_JOINT_COMMON, *_REVOLUTE_INITIAL, _play("rotation_play")],
        "prismatic_with_play": [
            *_JOINT_COMMON,
            _AXIS,
            *_PRISMATIC_INITIAL,
            _play("travel_play"),
        ],
        "gear_pair": [
            Param("name", "name", required=True, doc="unique name of the element"),
            _JOINT_COMMON[1],
            Param("body_i", "ref", required=True, doc="gear 1"),
            Param("point_i", "point", u.LENGTH, required=True, doc="gear 1's centre on body_i"),
            Param("body_j", "ref", required=True, doc="gear 2 (the tooth force is on it)"),
            Param("point_j", "point", u.LENGTH, required=True, doc="gear 2's centre on body_j"),
            _GEAR,
        ],
    },
    "driver": [
        _name(),
        Param("joint", "ref", required=True, doc="driven joint (revolute or prismatic)"),
        Param("profile", "profile", required=True, doc="motion profile, a table with a type"),
        Param(
            "initial",
            "scalar",
            _ROTATION_OR_TRANSLATION,
            motion=True,
            doc="joint coordinate at t = 0; by default that of the initial placement",
        ),
    ],
    "profile": {
        "constant_speed": [Param("type", "choice", required=True), _SPEED],
        "linear_ramp": [Param("type", "choice", required=True), _SPEED, _RAMP],
        "smooth_ramp": [Param("type", "choice", required=True), _SPEED, _RAMP],
        "table_angle": [
            Param("type", "choice", required=True),
            _TIMES,
            Param(
                "value",
                "list",
                _ROTATION_OR_TRANSLATION,
                required=True,
                motion=True,
                doc="displacement from the initial coordinate (rad or m), spline",
            ),
        ],
        "table_speed": [
            Param("type", "choice", required=True),
            _TIMES,
            Param(
                "value",
                "list",
                _ROTATION_OR_TRANSLATION_SPEED,
                required=True,
                motion=True,
                doc="speed (rad/s or m/s), linear between points",
            ),
        ],
    },
    "force": {
        "spring_damper": [
            *_FORCE_HEAD,
            Param("body_i", "ref", required=True, doc="first body"),
            Param("point_i", "point", u.LENGTH, required=True, doc="attachment on body_i"),
            Param("body_j", "ref", required=True, doc="second body"),
            Param("point_j", "point", u.LENGTH, required=True, doc="attachment on body_j"),
            Param("stiffness", "scalar", u.STIFFNESS, default=0.0, bound=">=0", doc="stiffness"),
            Param("damping", "scalar", u.DAMPING, default=0.0, bound=">=0", doc="damping"),
            Param("free_length", "scalar", u.LENGTH, default=0.0, bound=">=0", doc="free length"),
        ],
        "rotational_spring_damper": [
            *_FORCE_HEAD,
            Param("body_i", "ref", required=True, doc="first body"),
            Param("body_j", "ref", required=True, doc="second body (torque acts on it)"),
            Param(
                "stiffness",
                "scalar",
                u.ROTATIONAL_STIFFNESS,
                default=0.0,
                bound=">=0",
                doc="rotational stiffness",
            ),
            Param(
                "damping",
                "scalar",
                u.ROTATIONAL_DAMPING,
                default=0.0,
                bound=">=0",
                doc="rotational damping",
            ),
            Param(
                "free_angle",
                "scalar",
                u.ANGLE,
                default=0.0,
                doc="relative angle phi_j - phi_i at which the spring is unloaded",
            ),
        ],
        "applied_force": [
            *_FORCE_HEAD,
            Param("body", "ref", required=True, doc="loaded body"),
            Param(
                "point",
                "point",
                u.LENGTH,
                doc="point of application; by default the centre of mass",
            ),
            Param(
                "force",
                "vector_signal",
                u.FORCE,
                required=True,
                doc="[fx, fy] in global axes, or a table {time = [...], value = [[fx, fy], ...]}",
            ),
        ],
        "applied_torque": [
            *_FORCE_HEAD,
            Param("body", "ref", required=True, doc="loaded body"),
            Param(
                "torque",
                "scalar_signal",
                u.TORQUE,
                required=True,
                doc="counter-clockwise positive; or a table {time = [...], value = [...]}",
            ),
        ],
    },
    "marker": [
        _name("unique name: the channels are name.x, .y, .vx, .vy, .ax, .ay"),
        Param("body", "ref", required=True, doc="the body carrying the point, or ground"),
        Param("point", "point", u.LENGTH, required=True, doc="the point, in the body's frame"),
        Param(
            "frame",
            "ref",
            doc="the body in whose frame the motion is measured; by default the ground",
        ),
    ],
    "material": [
        Param("youngs_modulus", "scalar", u.PRESSURE, required=True, doc="Young's modulus"),
        Param("poisson_ratio", "scalar", u.DIMENSIONLESS, required=True, doc="Poisson's ratio"),
    ],
    "normal_law": {
        "hertz": _law(_EXPONENT),
        "kelvin_voigt": _law(
            _EXPONENT,
            Param("damping", "scalar", u.DAMPING, required=True, doc="damping c"),
            _CLIP,
        ),
        "hunt_crossley": _law(_EXPONENT, _RESTITUTION, _CLIP),
        "lankarani_nikravesh": _law(_EXPONENT, _RESTITUTION, _CLIP),
        "gonthier": _law(_EXPONENT, _RESTITUTION, _CLIP),
        "flores": _law(_EXPONENT, _RESTITUTION, _CLIP),
        "adams_impact": _law(
            _EXPONENT,
            Param("c_max", "scalar", u.DAMPING, required=True, doc="full damping coefficient"),
            Param(
                "d_max",
                "scalar",
                u.LENGTH,
                doc="penetration of full damping; by default the bearing material's (library)",
            ),
            _CLIP,
        ),
    },
    "friction": {
        "none": _law(),
        "coulomb": _law(
            Param("mu_s", "scalar", u.DIMENSIONLESS, required=True, doc="static coefficient"),
            Param("mu_d", "scalar", u.DIMENSIONLESS, required=True, doc="dynamic coefficient"),
            Param("v_s", "scalar", u.SPEED, required=True, doc="stiction transition speed"),
            Param("v_d", "scalar", u.SPEED, required=True, doc="friction transition speed"),
        ),
        "modified_coulomb": _law(
            Param("mu", "scalar", u.DIMENSIONLESS, required=True, doc="friction coefficient"),
            Param("v_0", "scalar", u.SPEED, required=True, doc="no friction below this slip"),
            Param("v_1", "scalar", u.SPEED, required=True, doc="full friction from this slip"),
        ),
        "viscous_coulomb": _law(
            Param("mu", "scalar", u.DIMENSIONLESS, required=True, doc="friction coefficient"),
            Param("v_s", "scalar", u.SPEED, required=True, doc="regularisation speed of tanh"),
            Param("viscous", "scalar", u.DAMPING, required=True, doc="viscous coefficient"),
        ),
    },
    "lubrication": [
        Param("length", "scalar", u.LENGTH, required=True, bound=">0", doc="bearing length"),
        Param(
            "viscosity",
            "scalar",
            u.VISCOSITY,
            required=True,
            bound=">0",
            doc="dynamic viscosity of the oil (Pa*s, or cP)",
        ),
        Param(
            "film",
            "choice",
            choices=("short", "long", "short_pi", "long_pi"),
            doc="film model: short (Ocvirk, positive pressure; the engine's default), long "
            "(Sommerfeld), short_pi or long_pi (pi-film forms)",
        ),
        Param(
            "roughness",
            "scalar",
            u.LENGTH,
            bound=">0",
            doc="composite RMS roughness; the film threshold is three times it; by default "
            "the engine's",
        ),
    ],
    "rotation_play": _play_table(u.ANGLE, "rotation", "N*m/rad^n"),
    "travel_play": _play_table(u.LENGTH, "travel", "N/m^n"),
    "gear": [
        Param(
            "ratio",
            "scalar",
            u.DIMENSIONLESS,
            required=True,
            bound=">0",
            doc="gear 2's pitch radius over gear 1's (z2/z1), external gears",
        ),
        Param(
            "pitch_radius",
            "scalar",
            u.LENGTH,
            required=True,
            bound=">0",
            doc="gear 1's pitch radius r1 (gear 2's is ratio * r1)",
        ),
        Param(
            "backlash",
            "scalar",
            u.LENGTH,
            bound=">=0",
            doc="circumferential backlash on the pitch circle; none by default",
        ),
        Param(
            "pressure_angle",
            "scalar",
            u.ANGLE,
            bound=">=0",
            doc="pressure angle; by default the engine's (20 deg)",
        ),
        Param(
            "mesh_stiffness",
            "contact_stiffness",
            required=True,
            doc="mesh stiffness [N/m^n]: a number, or a table { angle = [...], value = [...] } "
            "against gear 1's angle to the line of centres (periodic, linear between points)",
        ),
        Param("normal_law", "normal_law", required=True, doc="the teeth's contact law"),
    ],
    "shape": {
        "bar": [
            Param("type", "choice", required=True),
            Param("from", "point", u.LENGTH, required=True, doc="one end"),
            Param("to", "point", u.LENGTH, required=True, doc="other end"),
            Param("width", "scalar", u.LENGTH, default=0.01, bound=">0", doc="drawn width"),
        ],
        "block": [
            Param("type", "choice", required=True),
            Param("width", "scalar", u.LENGTH, required=True, bound=">0", doc="size along x"),
            Param("height", "scalar", u.LENGTH, required=True, bound=">0", doc="size along y"),
        ],
        "disk": [
            Param("type", "choice", required=True),
            Param("radius", "scalar", u.LENGTH, required=True, bound=">0", doc="radius"),
        ],
    },
}

# Number of constraint equations of each joint type (for degree-of-freedom counts).
JOINT_EQUATIONS = {
    "revolute": 2,
    "prismatic": 2,
    "fixed": 3,
    "clearance_revolute": 0,
    "lubricated_revolute": 0,
    "clearance_translational": 0,
    "revolute_with_play": 2,
    "prismatic_with_play": 2,
    "gear_pair": 0,
}
# The joint coordinate a driver moves, per joint type.
DRIVEN_MOTION = {
    "revolute": "rotation",
    "prismatic": "translation",
    "revolute_with_play": "rotation",
    "prismatic_with_play": "translation",
}


def _table(kind: str, dimension: int) -> list[Param] | dict[str, list[Param]]:
    if dimension == 3 and kind in SPATIAL_ELEMENTS:
        return SPATIAL_ELEMENTS[kind]
    return ELEMENTS[kind]


def params_of(kind: str, type_: str | None = None, dimension: int = 2) -> list[Param]:
    """The fields of an element kind (and type, for joints, forces, profiles, shapes), of
    a planar model or (``dimension=3``) a spatial one."""
    entry = _table(kind, dimension)
    if isinstance(entry, dict):
        if type_ is None:
            raise KeyError(f"{kind} needs a type")
        return entry[type_]
    return entry


def types_of(kind: str, dimension: int = 2) -> list[str]:
    """The allowed ``type`` values of an element kind (empty when it has no type)."""
    entry = _table(kind, dimension)
    return list(entry) if isinstance(entry, dict) else []


# ---------------------------------------------------------------------- spatial models

_SPATIAL_JOINT_COMMON = [
    _name(),
    Param(
        "type",
        "choice",
        required=True,
        doc="spherical, revolute, cylindrical, prismatic, universal, fixed, planar, "
        "revolute_with_play, prismatic_with_play, clearance_spherical, clearance_cylindrical, "
        "lubricated_cylindrical or clearance_translational",
    ),
    Param("body_i", "ref", required=True, doc="first body, or ground"),
    Param("point_i", "point", u.LENGTH, required=True, doc="joint point on body_i"),
    Param("body_j", "ref", required=True, doc="second body (reactions are forces on it)"),
    Param("point_j", "point", u.LENGTH, required=True, doc="joint point on body_j"),
]


def _axis(doc: str) -> Param:
    return Param(
        "axis", "vector", u.DIMENSIONLESS, required=True, doc=f"{doc}, in the frame of body_i"
    )


_AXIS_J = Param(
    "axis_j",
    "vector",
    u.DIMENSIONLESS,
    doc="the axis in the frame of body_j; by default the same line as axis at the placement",
)
_ANGLE_INITIAL = [
    Param("initial", "scalar", u.ANGLE, doc="angle about the axis at t = 0"),
    Param("initial_rate", "scalar", u.ANGULAR_SPEED, doc="its rate at t = 0"),
]
_TRAVEL_INITIAL = [
    Param("initial", "scalar", u.LENGTH, doc="travel along the axis at t = 0"),
    Param("initial_rate", "scalar", u.SPEED, doc="its rate at t = 0"),
]
_LOAD_FRAME = Param(
    "frame",
    "choice",
    choices=("ground", "body"),
    doc="axes of the vector: ground (global) or body (turning with it); ground by default",
)

SPHERE_KEYS = {
    "socket_radius": "bearing_radius",
    "ball_radius": "journal_radius",
    "socket_material": "bearing_material",
    "ball_material": "journal_material",
}
"""A clearance_spherical joint's keys in a model file -> the engine's (those of a
clearance_revolute's ``clearance`` table; the others keep their names)."""

_SPHERE_CLEARANCE = [
    Param("socket_radius", "scalar", u.LENGTH, doc="radius of the socket (on body_i)"),
    Param("ball_radius", "scalar", u.LENGTH, doc="radius of the ball (on body_j)"),
    Param(
        "clearance",
        "scalar",
        u.LENGTH,
        doc="radial clearance; give two of socket_radius, ball_radius, clearance",
    ),
    Param(
        "stiffness",
        "contact_stiffness",
        doc="contact stiffness K [N/m^n], n the law's exponent; by default from the materials",
    ),
    Param(
        "socket_material",
        "material",
        doc="library name (steel, brass, ...) or { youngs_modulus, poisson_ratio }",
    ),
    Param("ball_material", "material", doc="as socket_material"),
    _CLEARANCE[-2],  # normal_law
    _CLEARANCE[-1],  # friction
]

_CYLINDER_CLEARANCE = [
    *_SPATIAL_JOINT_COMMON,
    _axis("the bearing's axis"),
    Param("axis_j", "vector", u.DIMENSIONLESS, doc="the journal's axis, in body_j's frame"),
    *_CLEARANCE,
    Param("length", "scalar", u.LENGTH, required=True, doc="length of the journal"),
    Param(
        "axial_clearance",
        "scalar",
        u.LENGTH,
        doc="gap on each side between the journal's ends and thrust faces; none by default",
    ),
]

_CYLINDER_WEAR = [
    Param(
        "bearing_wear",
        "list",
        u.LENGTH,
        doc="wear depth of the bearing, uniform along it, at N >= 8 equally spaced angles "
        "2 pi k / N about its axis (from body_i's x axis made normal to the axis, its y axis "
        "for an axis near x; docs/wear.md)",
    ),
    Param(
        "journal_wear",
        "list",
        u.LENGTH,
        doc="wear depth of the journal at N >= 8 equally spaced angles about its axis in "
        "body_j's frame, counted as bearing_wear's",
    ),
]

SPATIAL_ELEMENTS: dict[str, list[Param] | dict[str, list[Param]]] = {
    "model": [
        Param("name", "text", default="", doc="model name, for reports"),
        Param(
            "gravity",
            "vector",
            u.ACCELERATION,
            doc="uniform gravity, global axes; by default the engine's [0, 0, -9.81]",
        ),
    ],
    "ground": [
        Param("points", "points", u.LENGTH, default={}, doc="named points, global coordinates"),
    ],
    "body": [
        _name(),
        Param("mass", "scalar", u.MASS, required=True, bound=">0", doc="mass"),
        Param(
            "inertia",
            "inertia",
            u.INERTIA,
            required=True,
            doc="about the centre of mass: principal moments [J1, J2, J3] about the body "
            "axes (or those of inertia_frame), or the full symmetric 3x3 tensor in the body "
            "frame",
        ),
        Param(
            "inertia_frame",
            "orientation",
            doc="orientation of the principal axes in the body frame (with principal moments)",
        ),
        Param(
            "com",
            "vector",
            u.LENGTH,
            doc="centre of mass in the body frame; by default the frame's origin",
        ),
        Param(
            "position",
            "vector",
            u.LENGTH,
            doc="initial position of the frame's origin (approximate); [0, 0, 0] by default",
        ),
        Param(
            "orientation",
            "orientation",
            doc="initial orientation of the body frame (approximate); unturned by default",
        ),
        Param("velocity", "vector", u.SPEED, doc="initial velocity of the frame's origin"),
        Param(
            "angular_velocity",
            "vector",
            u.ANGULAR_SPEED,
            doc="initial angular velocity, global axes",
        ),
        Param("points", "points", u.LENGTH, default={}, doc="named points in the body frame"),
    ],
    "joint": {
        "spherical": _SPATIAL_JOINT_COMMON,
        "revolute": [
            *_SPATIAL_JOINT_COMMON,
            _axis("the pin's axis"),
            _AXIS_J,
            *_ANGLE_INITIAL,
        ],
        "cylindrical": [
            *_SPATIAL_JOINT_COMMON,
            _axis("the common axis"),
            _AXIS_J,
            *_ANGLE_INITIAL,
        ],
        "prismatic": [
            *_SPATIAL_JOINT_COMMON,
            _axis("the sliding direction"),
            _AXIS_J,
            *_TRAVEL_INITIAL,
        ],
        "universal": [
            *_SPATIAL_JOINT_COMMON,
            _axis("body_i's cross axis"),
            Param(
                "axis_j",
                "vector",
                u.DIMENSIONLESS,
                required=True,
                doc="body_j's cross axis, in its frame",
            ),
        ],
        "fixed": _SPATIAL_JOINT_COMMON,
        "planar": [*_SPATIAL_JOINT_COMMON, _axis("the plane's normal")],
        "revolute_with_play": [
            *_SPATIAL_JOINT_COMMON,
            _axis("the pin's axis"),
            _AXIS_J,
            *_ANGLE_INITIAL,
            _play("rotation_play"),
        ],
        "prismatic_with_play": [
            *_SPATIAL_JOINT_COMMON,
            _axis("the sliding direction"),
            _AXIS_J,
            *_TRAVEL_INITIAL,
            _play("travel_play"),
        ],
        "clearance_spherical": [*_SPATIAL_JOINT_COMMON, *_SPHERE_CLEARANCE],
        "clearance_cylindrical": [*_CYLINDER_CLEARANCE, *_CYLINDER_WEAR],
        "lubricated_cylindrical": [*_CYLINDER_CLEARANCE, _LUBRICATION],
        "clearance_translational": [
            *_SPATIAL_JOINT_COMMON,
            _axis(
                "the guide's direction (its centreline passes through point_i; the block is "
                "centred at point_j)"
            ),
            Param(
                "height_axis",
                "vector",
                u.DIMENSIONLESS,
                required=True,
                doc="the direction across which block_height and guide_width are measured, "
                "in the frame of body_i, perpendicular to axis",
            ),
            *_BLOCK_CLEARANCE[:4],
            Param("block_depth", "scalar", u.LENGTH, bound=">0", doc="depth of the block"),
            Param(
                "guide_depth",
                "scalar",
                u.LENGTH,
                bound=">0",
                doc="distance between the channel's side walls, across axis and height_axis",
            ),
            Param(
                "depth_clearance",
                "scalar",
                u.LENGTH,
                bound=">0",
                doc="guide_depth - block_depth; give two of block_depth, guide_depth, "
                "depth_clearance",
            ),
            *_BLOCK_CLEARANCE[4:],
        ],
    },
    "driver": [
        _name(),
        Param(
            "joint", "ref", required=True, doc="driven joint (revolute, cylindrical or prismatic)"
        ),
        *params_of("driver")[2:],
    ],
    "force": {
        "spring_damper": params_of("force", "spring_damper"),
        "applied_force": [
            *_FORCE_HEAD,
            Param("body", "ref", required=True, doc="loaded body"),
            Param(
                "point",
                "point",
                u.LENGTH,
                doc="point of application; by default the centre of mass",
            ),
            Param(
                "force",
                "vector_signal",
                u.FORCE,
                required=True,
                doc="[fx, fy, fz], or a table {time = [...], value = [[fx, fy, fz], ...]}",
            ),
            _LOAD_FRAME,
        ],
        "applied_torque": [
            *_FORCE_HEAD,
            Param("body", "ref", required=True, doc="loaded body"),
            Param(
                "torque",
                "vector_signal",
                u.TORQUE,
                required=True,
                doc="[mx, my, mz], or a table {time = [...], value = [[mx, my, mz], ...]}",
            ),
            _LOAD_FRAME,
        ],
    },
    "marker": [
        _name("unique name: the channels are name.x, .y, .z, .vx, ... .az"),
        Param("body", "ref", required=True, doc="the body carrying the point, or ground"),
        Param("point", "point", u.LENGTH, required=True, doc="the point, in the body's frame"),
    ],
}
"""The fields of a spatial model's elements (``dimension = 3``); the nested tables
(profile, material, normal_law, friction) are the planar ones of :data:`ELEMENTS`."""

# Number of constraint equations of each spatial joint type.
SPATIAL_JOINT_EQUATIONS = {
    "spherical": 3,
    "revolute": 5,
    "cylindrical": 4,
    "prismatic": 5,
    "universal": 4,
    "fixed": 6,
    "planar": 3,
    "revolute_with_play": 5,
    "prismatic_with_play": 5,
    "clearance_spherical": 0,
    "clearance_cylindrical": 0,
    "lubricated_cylindrical": 0,
    "clearance_translational": 0,
}
SPATIAL_DRIVEN_MOTION = {
    "revolute": "rotation",
    "cylindrical": "rotation",
    "prismatic": "translation",
}


class _Context:
    """Builds errors naming one element; ``prefix`` dots nested keys (``profile.``)."""

    def __init__(
        self,
        kind: str | None,
        name: str | None,
        index: int | None,
        prefix: str = "",
        dimension: int = 2,
    ):
        self.kind, self.name, self.index, self.prefix = kind, name, index, prefix
        self.dimension = dimension  # 3 in a spatial model: 3-vectors, its own tables

    def error(self, problem: str, key: str | None = None) -> ModelError:
        full = None if key is None else self.prefix + key
        return ModelError(problem, kind=self.kind, name=self.name, index=self.index, key=full)

    def nested(self, key: str) -> _Context:
        return _Context(self.kind, self.name, self.index, f"{self.prefix}{key}.", self.dimension)

    def label(self, key: str) -> str:
        return self.prefix + key


def convert_element(
    kind: str,
    raw: Mapping[str, Any],
    *,
    index: int | None = None,
    label: str | None = None,
    dimension: int = 2,
) -> tuple[dict[str, Any], str | None]:
    """Converts one element's user values to the engine's SI dictionary.

    Returns the dictionary (fields in table order, defaults filled in) and the motion it
    was given in, for a driver or a profile: ``"rotation"`` (angular units),
    ``"translation"`` (linear units) or ``None`` (plain SI numbers only). A key whose
    value is ``None`` takes its default. ``label`` replaces the element's name in
    messages (for a profile made on its own). ``dimension=3`` reads the element of a
    spatial model (:data:`SPATIAL_ELEMENTS`).
    """
    name = raw.get("name") if isinstance(raw.get("name"), str) else None
    ctx = _Context(kind if label is None else label, name, index, dimension=dimension)
    motions: set[str] = set()
    carried: dict[str, Any] = {}
    if kind == "joint" and isinstance(raw, Mapping):
        raw = _flatten_clearance(raw, ctx)
        if dimension == 2:
            _check_block_keys(raw, ctx)
            raw, carried = _split_carried(raw)
    out = _convert_table(kind, raw, ctx, motions)
    if carried:
        out.update(_convert_carried(carried, str(out["type"]), ctx))
    keys = PLANAR_CLEARANCE_KEYS if dimension == 2 else SPATIAL_CLEARANCE_KEYS
    if kind == "joint" and (out.get("type") in CLEARANCE_TYPES or any(k in out for k in keys)):
        nested = {k: out.pop(k) for k in keys if k in out}
        nested.update({SPHERE_KEYS[k]: out.pop(k) for k in SPHERE_KEYS if k in out})
        if nested:
            out["clearance"] = {k: nested[k] for k in keys if k in nested}
    if kind == "body" and dimension == 3:
        _merge_inertia_frame(out, ctx)
    if len(motions) > 1:
        raise ctx.error("mixes angular units (rad, deg, rpm) and linear units (m, m/s)")
    if kind == "body" and "shape" in out:
        _check_shape_points(out, ctx)
    return out, (motions.pop() if motions else None)


PLANAR_CLEARANCE_KEYS = (*CLEARANCE_KEYS, *BLOCK_KEYS, *WEAR_KEYS)
"""The keys of a planar joint's ``clearance`` table: a revolute clearance joint's (with
its wear data) and a translational one's."""
SPATIAL_CLEARANCE_KEYS = (*CLEARANCE_KEYS, *BLOCK_KEYS, *DEPTH_KEYS, *WEAR_TABLES)
"""The keys of a spatial joint's ``clearance`` table: the planar joints' contact keys,
a block's depth and a cylindrical joint's wear tables (a spatial joint's ``length`` is
its own, not the clearance's)."""

_DATA_TABLES = {
    "clearance": ("clearance_revolute", "clearance_translational"),
    "lubrication": ("lubricated_revolute",),
    "play": ("revolute_with_play", "prismatic_with_play"),
    "gear": ("gear_pair",),
}
"""A planar joint's data tables, by the joint types that use them (a file writes the
``clearance`` table's keys flat in the joint)."""


def _table_keys(table: str) -> tuple[str, ...]:
    return PLANAR_CLEARANCE_KEYS if table == "clearance" else (table,)


def _check_block_keys(raw: Mapping[str, Any], ctx: _Context) -> None:
    """A clearance_translational joint given a journal's radii or materials: an error
    that says what a block takes instead."""
    if raw.get("type") != "clearance_translational":
        return
    for key in ("bearing_radius", "journal_radius", "bearing_material", "journal_material"):
        if raw.get(key) is not None:
            raise ctx.error(
                f"{key} is not a key of a clearance_translational joint: its block takes "
                "block_length, two of block_height, guide_width and clearance, and a "
                "stiffness (a block's corner on a flat has no Hertz closed form to compute "
                "it from materials)",
                key,
            )


def _split_carried(raw: Mapping[str, Any]) -> tuple[dict[str, Any], dict[str, Any]]:
    """A planar joint's fields and the data tables it carries for another type (a
    ``revolute`` keeping its ``clearance`` keys, say): those the engine ignores with a
    warning, so that a joint switches kind by its ``type`` alone. A table whose keys
    the type has (a clearance_translational's ``clearance``) is its own, not carried."""
    type_ = raw.get("type")
    if type_ not in ELEMENTS["joint"]:
        return dict(raw), {}
    own = {p.key for p in params_of("joint", str(type_))}
    uses = {t for t, types in _DATA_TABLES.items() if type_ in types}
    if "clearance" in own:
        uses.add("clearance")
    carried_keys = {k for t in _DATA_TABLES if t not in uses for k in _table_keys(t)}
    kept = {k: v for k, v in raw.items() if k not in carried_keys or k in own}
    carried = {k: v for k, v in raw.items() if k in carried_keys and k not in own}
    return kept, carried


def _convert_carried(carried: Mapping[str, Any], type_: str, ctx: _Context) -> dict[str, Any]:
    """The carried data tables in SI, read as the type that uses them reads them: a
    ``play`` as a rotation on a joint of the revolute kinds, else as a travel."""
    rotation = type_ in ("revolute", "clearance_revolute", "lubricated_revolute", "fixed")
    play = "revolute_with_play" if rotation else "prismatic_with_play"
    owners = (
        "clearance_revolute",
        "clearance_translational",
        "lubricated_revolute",
        play,
        "gear_pair",
    )
    params: dict[str, Param] = {}
    for owner in owners:
        for p in params_of("joint", owner)[len(_JOINT_COMMON) :]:
            params.setdefault(p.key, p)
    clearance = [k for k in PLANAR_CLEARANCE_KEYS if carried.get(k) is not None]
    if clearance and carried.get("normal_law") is None:
        raise ctx.error(
            f"missing field 'normal_law': the clearance data kept by a {type_} joint "
            f"({', '.join(clearance)}) need their normal_law too",
            clearance[0],
        )
    optional = [replace(params[k], required=False) for k in params if k in carried]
    return _convert_params(optional, carried, "joint", ctx, set())


def _flatten_clearance(raw: Mapping[str, Any], ctx: _Context) -> Mapping[str, Any]:
    """A joint's nested ``clearance`` table (the engine's form, as in summary.json) as the
    flat keys of a model file."""
    nested = raw.get("clearance")
    if not isinstance(nested, Mapping):
        return raw  # absent, or the flat radial clearance
    flat = {k: v for k, v in raw.items() if k != "clearance"}
    sphere = raw.get("type") == "clearance_spherical"
    renamed = {engine: own for own, engine in SPHERE_KEYS.items()} if sphere else {}
    keys = PLANAR_CLEARANCE_KEYS if ctx.dimension == 2 else SPATIAL_CLEARANCE_KEYS
    for key, value in nested.items():
        if key not in keys:
            raise ctx.error(
                f"unknown key 'clearance.{key}' (allowed: {', '.join(keys)})",
                f"clearance.{key}",
            )
        own = renamed.get(str(key), str(key))
        if flat.get(own) is not None:
            raise ctx.error(f"{own} is given twice (flat and in clearance)", own)
        flat[own] = value
    return flat


def _check_shape_points(body: Mapping[str, Any], ctx: _Context) -> None:
    """A bar's ends, when named, must be points of the body itself."""
    for end in ("from", "to"):
        ref = body["shape"].get(end)
        if isinstance(ref, str) and ref not in body["points"]:
            known = ", ".join(body["points"]) or "none"
            raise ctx.error(
                f"shape.{end} '{ref}' is not a point of body '{body['name']}' (points: {known})",
                key=f"shape.{end}",
            )


def _convert_table(
    kind: str, raw: Mapping[str, Any], ctx: _Context, motions: set[str]
) -> dict[str, Any]:
    if not isinstance(raw, Mapping):
        raise ctx.error(f"expected a table of fields, got {raw!r}")
    types = types_of(kind, ctx.dimension)
    if types:
        type_ = raw.get("type")
        if type_ is None:
            raise ctx.error(f"missing field '{ctx.label('type')}' (one of: {', '.join(types)})")
        if type_ not in types:
            raise ctx.error(
                f"unknown {kind} type {type_!r} (allowed: {', '.join(types)})", key="type"
            )
        params = params_of(kind, type_, ctx.dimension)
    else:
        params = params_of(kind, dimension=ctx.dimension)
    allowed = [p.key for p in params]
    for key, value in raw.items():
        if key not in allowed and value is not None:
            what = f" for a {raw['type']} {kind}" if types else ""
            raise ctx.error(
                f"unknown key '{ctx.label(str(key))}'{what} (allowed: {', '.join(allowed)})",
                key=str(key),
            )
    return _convert_params(params, raw, kind, ctx, motions)


def _convert_params(
    params: Sequence[Param], raw: Mapping[str, Any], kind: str, ctx: _Context, motions: set[str]
) -> dict[str, Any]:
    """``raw``'s values of ``params`` in SI, in table order, defaults filled in."""
    out: dict[str, Any] = {}
    stiffnesses = []
    for p in params:
        value = raw.get(p.key)
        if value is None:
            if p.required:
                raise ctx.error(f"missing field '{ctx.label(p.key)}'", key=p.key)
            if p.default is None:
                continue
            value = p.default
        if p.kind == "contact_stiffness":
            stiffnesses.append((p.key, value))  # after the normal law: its exponent
            continue
        out[p.key] = _convert_value(p, value, ctx, motions)
    for key, value in stiffnesses:
        out[key] = _stiffness(key, value, out, kind, ctx)
    return out


def _stiffness(key: str, value: Any, out: Mapping[str, Any], kind: str, ctx: _Context) -> Any:
    """A contact stiffness in SI: [N/m^n], n the normal law's exponent, or for a rotation's
    play [N*m/rad^n]; a gear's mesh stiffness may be a table ``{angle, value}``."""
    law = out.get("normal_law", {})
    n = law.get("exponent", 1.5) if isinstance(law, Mapping) else 1.5
    try:
        power = Fraction(str(float(n))).limit_denominator(1000)
    except (ValueError, OverflowError):
        power = Fraction(3, 2)
    if kind == "rotation_play":
        dim = u.TORQUE / u.ANGLE**power
    else:
        dim = u.FORCE / u.LENGTH**power
    label = ctx.label(key)
    if key == "mesh_stiffness" and isinstance(value, Mapping):
        if set(value) != {"angle", "value"}:
            raise ctx.error(f"{label} must be a number or a table {{ angle, value }}", key)
        seqs = (value["angle"], value["value"])
        if any(isinstance(v, (str, Mapping)) or not isinstance(v, Sequence) for v in seqs):
            raise ctx.error(f"{label}.angle and {label}.value must be lists", key)
        angle = Param(key, "scalar", u.ANGLE)
        angles = [
            _scalar(angle, a, ctx, f"{label}.angle[{i}]", set()) for i, a in enumerate(seqs[0])
        ]
        k = Param(key, "scalar", dim, bound=">0")
        values = [_scalar(k, v, ctx, f"{label}.value[{i}]", set()) for i, v in enumerate(seqs[1])]
        return {"angle": angles, "value": values}
    try:
        return u.to_si(value, dim)
    except UnitError as exc:
        raise ctx.error(f"{label} {exc}", key) from None


def _convert_value(p: Param, value: Any, ctx: _Context, motions: set[str]) -> Any:
    key = ctx.label(p.key)
    if hasattr(value, "tolist") and getattr(value, "ndim", 0) > 0:
        value = value.tolist()  # NumPy arrays as lists
    if p.kind == "text":
        if not isinstance(value, str):
            raise ctx.error(f"{key} must be a string, got {value!r}", p.key)
        return value
    if p.kind in ("name", "ref", "choice"):
        if not isinstance(value, str) or not value:
            raise ctx.error(f"{key} must be a non-empty string, got {value!r}", p.key)
        if p.kind == "name":
            _check_name(value, key, ctx, p.key)
        if p.choices and value not in p.choices:
            raise ctx.error(f"{key} {value!r}: must be one of {', '.join(p.choices)}", p.key)
        return value
    if p.kind == "scalar":
        return _scalar(p, value, ctx, key, motions)
    if p.kind == "vector":
        return _vector(p, value, ctx, key)
    if p.kind == "point":
        if isinstance(value, str):
            _check_name(value, key, ctx, p.key)
            return value
        return _vector(p, value, ctx, key)
    if p.kind == "points":
        if not isinstance(value, Mapping):
            form = "[x, y]" if ctx.dimension == 2 else "[x, y, z]"
            raise ctx.error(f"{key} must be a table of name = {form}, got {value!r}", p.key)
        points = {}
        for pname, xy in value.items():
            _check_name(str(pname), f"{key} name", ctx, f"{p.key}.{pname}")
            points[str(pname)] = _vector(p, xy, ctx, f"{key}.{pname}", f"{p.key}.{pname}")
        return points
    if p.kind == "list":
        if isinstance(value, (str, Mapping)) or not isinstance(value, Sequence):
            raise ctx.error(f"{key} must be a list of numbers, got {value!r}", p.key)
        return [_scalar(p, v, ctx, f"{key}[{i}]", motions) for i, v in enumerate(value)]
    if p.kind in ("scalar_signal", "vector_signal"):
        return _signal(p, value, ctx, key, motions)
    if p.kind == "orientation":
        return _orientation(value, ctx, key, p.key)
    if p.kind == "inertia":
        return _inertia(p, value, ctx, key)
    if p.kind == "bool":
        if not isinstance(value, bool):
            raise ctx.error(f"{key} must be true or false, got {value!r}", p.key)
        return value
    if p.kind == "material" and isinstance(value, str):
        if not value:
            raise ctx.error(f"{key} must be a library name or a table, got {value!r}", p.key)
        return value
    if p.kind in _NESTED_TABLES:
        if hasattr(value, "to_dict"):
            value = value.to_dict()
        return _convert_table(p.kind, value, ctx.nested(p.key), motions)
    raise AssertionError(f"unknown parameter kind {p.kind}")  # pragma: no cover


_NESTED_TABLES = (
    "shape",
    "profile",
    "material",
    "normal_law",
    "friction",
    "lubrication",
    "rotation_play",
    "travel_play",
    "gear",
)
"""The parameter kinds that are tables of their own fields (:data:`ELEMENTS`)."""


def _check_name(value: str, key: str, ctx: _Context, param_key: str) -> None:
    if not _NAME.match(value):
        raise ctx.error(f"{key} {value!r} may only contain letters, digits, '_' and '-'", param_key)


def _scalar(p: Param, value: Any, ctx: _Context, key: str, motions: set[str]) -> float:
    assert p.dim is not None
    try:
        x, dim = u.to_si_with_dimension(value, p.dim)
    except UnitError as exc:
        raise ctx.error(f"{key} {exc}", p.key) from None
    if p.motion and dim is not None:
        motions.add("rotation" if dim.angle != 0 else "translation")
    if p.bound == ">0" and not x > 0:
        raise ctx.error(f"{key} must be positive, got {_shown(value, p.dim)}", p.key)
    if p.bound == ">=0" and not x >= 0:
        raise ctx.error(f"{key} must not be negative, got {_shown(value, p.dim)}", p.key)
    return x


def _shown(value: Any, dim: Dimension | tuple[Dimension, ...]) -> str:
    if isinstance(value, str):
        return value
    d = dim if isinstance(dim, Dimension) else dim[0]
    unit = d.si_unit()
    return f"{value:g}" if unit == "1" else f"{value:g} {unit}"


def _vector(
    p: Param, value: Any, ctx: _Context, key: str, param_key: str | None = None
) -> list[float]:
    if hasattr(value, "tolist") and getattr(value, "ndim", 0) > 0:
        value = value.tolist()
    n = ctx.dimension
    if isinstance(value, (str, Mapping)) or not isinstance(value, Sequence) or len(value) != n:
        form = "[x, y]" if n == 2 else "[x, y, z]"
        raise ctx.error(f"{key} must be a vector {form}, got {value!r}", param_key or p.key)
    assert p.dim is not None
    out = []
    for v in value:
        try:
            out.append(u.to_si(v, p.dim))
        except UnitError as exc:
            raise ctx.error(f"{key} {exc}", param_key or p.key) from None
    return out


def _signal(p: Param, value: Any, ctx: _Context, key: str, motions: set[str]) -> Any:
    vector = p.kind == "vector_signal"
    if not isinstance(value, Mapping):
        return _vector(p, value, ctx, key) if vector else _scalar(p, value, ctx, key, motions)
    extra = set(value) - {"time", "value"}
    if extra:
        raise ctx.error(f"unknown key '{key}.{sorted(extra)[0]}' (allowed: time, value)", p.key)
    for part in ("time", "value"):
        if part not in value:
            raise ctx.error(f"missing field '{key}.{part}'", p.key)
    seqs = (value["time"], value["value"])
    if any(isinstance(s, (str, Mapping)) or not isinstance(s, Sequence) for s in seqs):
        raise ctx.error(f"{key}.time and {key}.value must be lists", p.key)
    times = [_scalar(_TIMES, t, ctx, f"{key}.time[{i}]", motions) for i, t in enumerate(seqs[0])]
    if vector:
        vals: list[Any] = [_vector(p, v, ctx, f"{key}.value[{i}]") for i, v in enumerate(seqs[1])]
    else:
        vals = [_scalar(p, v, ctx, f"{key}.value[{i}]", motions) for i, v in enumerate(seqs[1])]
    return {"time": times, "value": vals}


_AXIS_VALUE = Param("axis", "vector", u.DIMENSIONLESS)
_ANGLE_VALUE = Param("angle", "scalar", u.ANGLE)
_NUMBER_VALUE = Param("value", "scalar", u.DIMENSIONLESS)
ORIENTATION_FORMS = (
    "{ axis = [x, y, z], angle = .. }",
    '{ euler = [a, b, c], convention = "ZYX" }',
    "{ quaternion = [e0, e1, e2, e3] }",
)
"""The three ways a model file writes an orientation (the engine's own forms,
``{axis_angle = {axis, angle}}`` and ``{euler = {convention, angles}}``, also load)."""


def _orientation(value: Any, ctx: _Context, key: str, param_key: str) -> dict[str, Any]:
    """An orientation as the engine reads it: ``{"quaternion": [..]}``, ``{"axis_angle":
    {"axis", "angle"}}`` or ``{"euler": {"convention", "angles"}}`` (SI, radians); the
    engine checks the quaternion's norm, the axis and the convention."""
    if hasattr(value, "to_dict"):
        value = value.to_dict()
    if not isinstance(value, Mapping):
        raise ctx.error(f"{key} must be one of {', '.join(ORIENTATION_FORMS)}", param_key)
    forms = {
        frozenset({"axis", "angle"}),
        frozenset({"axis_angle"}),
        frozenset({"euler", "convention"}),
        frozenset({"euler"}),
        frozenset({"quaternion"}),
    }
    if frozenset(value) not in forms:
        raise ctx.error(
            f"{key} = {dict(value)!r}: write one of {', '.join(ORIENTATION_FORMS)}", param_key
        )
    if "quaternion" in value:
        q = value["quaternion"]
        if isinstance(q, (str, Mapping)) or not isinstance(q, Sequence) or len(q) != 4:
            raise ctx.error(f"{key}.quaternion must be [e0, e1, e2, e3], got {q!r}", param_key)
        return {
            "quaternion": [_scalar(_NUMBER_VALUE, v, ctx, f"{key}.quaternion", set()) for v in q]
        }
    if "axis_angle" in value:
        inner = value["axis_angle"]
        if not isinstance(inner, Mapping) or set(inner) != {"axis", "angle"}:
            raise ctx.error(f"{key}.axis_angle must be {{ axis, angle }}, got {inner!r}", param_key)
        value = inner
    if "axis" in value:
        axis = _vector(_AXIS_VALUE, value["axis"], ctx, f"{key}.axis", param_key)
        angle = _scalar(_ANGLE_VALUE, value["angle"], ctx, f"{key}.angle", set())
        return {"axis_angle": {"axis": axis, "angle": angle}}
    euler, convention = value["euler"], value.get("convention")
    if isinstance(euler, Mapping):
        if set(euler) != {"convention", "angles"} or convention is not None:
            raise ctx.error(
                f"{key}.euler must be {{ convention, angles }}, got {euler!r}", param_key
            )
        euler, convention = euler["angles"], euler["convention"]
    if not isinstance(convention, str):
        raise ctx.error(f'{key}.convention must name the axes, e.g. "ZYX"', param_key)
    angles = _vector(_ANGLE_VALUE, euler, ctx, f"{key}.euler", param_key)
    return {"euler": {"convention": convention, "angles": angles}}


def _inertia(p: Param, value: Any, ctx: _Context, key: str) -> dict[str, Any]:
    """Principal moments ``[J1, J2, J3]`` as ``{"principal": {"moments"}}``, a 3x3 tensor
    as ``{"tensor"}``; the engine's own forms load too. The engine checks that the
    inertia is one a rigid body can have (positive definite, triangle inequality)."""
    if hasattr(value, "tolist") and getattr(value, "ndim", 0) > 0:
        value = value.tolist()
    scalar = Param(p.key, "scalar", p.dim)
    if isinstance(value, Mapping) and set(value) == {"principal"}:
        inner = value["principal"]
        if not isinstance(inner, Mapping) or not set(inner) <= {"moments", "frame"}:
            raise ctx.error(f"{key}.principal must be {{ moments, frame }}, got {inner!r}", p.key)
        out = _inertia(p, inner.get("moments"), ctx, key)
        if inner.get("frame") is not None:
            out["principal"]["frame"] = _orientation(inner["frame"], ctx, f"{key}.frame", p.key)
        return out
    if isinstance(value, Mapping) and set(value) == {"tensor"}:
        value = value["tensor"]
    rows = value if isinstance(value, Sequence) and not isinstance(value, str) else None
    if rows is not None and len(rows) == 3:
        if all(isinstance(r, Sequence) and not isinstance(r, str) for r in rows):
            if all(len(r) == 3 for r in rows):
                tensor = [
                    [_scalar(scalar, v, ctx, f"{key}[{i}][{k}]", set()) for k, v in enumerate(r)]
                    for i, r in enumerate(rows)
                ]
                return {"tensor": tensor}
        elif not any(isinstance(r, (Sequence, Mapping)) and not isinstance(r, str) for r in rows):
            moments = [_scalar(scalar, v, ctx, f"{key}[{i}]", set()) for i, v in enumerate(rows)]
            return {"principal": {"moments": moments}}
    raise ctx.error(
        f"{key} must be principal moments [J1, J2, J3] or a 3x3 tensor [[..], [..], [..]], "
        f"got {value!r}",
        p.key,
    )


def _merge_inertia_frame(body: dict[str, Any], ctx: _Context) -> None:
    """A spatial body's ``inertia_frame`` (the principal axes' orientation) moved into its
    principal inertia, where the engine reads it."""
    frame = body.pop("inertia_frame", None)
    if frame is None:
        return
    principal = body["inertia"].get("principal")
    if principal is None:
        raise ctx.error(
            "inertia_frame goes with principal moments [J1, J2, J3], not with a full tensor",
            "inertia_frame",
        )
    if "frame" in principal:
        raise ctx.error(
            "the principal frame is given twice (inertia_frame and in inertia)", "inertia_frame"
        )
    principal["frame"] = frame


_TITLES = {
    "model": "[model]",
    "ground": "[ground]",
    "body": "[[body]]",
    "joint": '[[joint]] type = "{}"',
    "driver": "[[driver]]",
    "profile": 'profile = {{ type = "{}", ... }}',
    "force": '[[force]] type = "{}"',
    "marker": "[[marker]]",
    "shape": 'shape = {{ type = "{}", ... }}',
    "material": "bearing_material = {{ ... }}, journal_material = {{ ... }}",
    "normal_law": 'normal_law = {{ type = "{}", ... }}',
    "friction": 'friction = {{ type = "{}", ... }}',
    "lubrication": "lubrication = {{ ... }} (lubricated_revolute)",
    "rotation_play": "play = {{ ... }} (revolute_with_play)",
    "travel_play": "play = {{ ... }} (prismatic_with_play)",
    "gear": "gear = {{ ... }} (gear_pair)",
}


def reference_markdown(dimension: int = 2) -> str:
    """Markdown tables of every element's fields, as included in ``docs/model-file.md``:
    those of a planar model, or (``dimension=3``) of a spatial one."""
    lines: list[str] = []
    table = SPATIAL_ELEMENTS if dimension == 3 else ELEMENTS
    form = "[x, y]" if dimension == 2 else "[x, y, z]"
    for kind, entry in table.items():
        groups = entry.items() if isinstance(entry, dict) else [(None, entry)]
        for type_, params in groups:
            lines += [f"#### `{_TITLES[kind].format(type_)}`", ""]
            lines += ["| key | unit | required / default | notes |", "|---|---|---|---|"]
            for p in params:
                if p.key == "type":
                    continue
                notes = _notes(p, form)
                lines.append(f"| `{p.key}` | {_unit_text(p)} | {_default_text(p)} | {notes} |")
            lines.append("")
    return "\n".join(lines)


def _unit_text(p: Param) -> str:
    if p.kind == "contact_stiffness":
        return "N*m/rad^n" if p.dim == u.ANGLE else "N/m^n"
    if p.dim is None or p.dim == u.DIMENSIONLESS:
        return "-"
    dims = p.dim if isinstance(p.dim, tuple) else (p.dim,)
    return " or ".join(d.si_unit() for d in dims)


def _default_text(p: Param) -> str:
    if p.required:
        return "required"
    if p.default is None:
        return "optional"
    if isinstance(p.default, bool):
        return "true" if p.default else "false"
    if isinstance(p.default, tuple):
        return "[" + ", ".join(f"{v:g}" for v in p.default) + "]"
    if isinstance(p.default, dict):
        return "{}"
    if isinstance(p.default, str):
        return f'"{p.default}"'
    return f"{p.default:g}"


def _notes(p: Param, vector: str = "[x, y]") -> str:
    bound = {">0": "> 0; ", ">=0": ">= 0; "}.get(p.bound or "", "")
    form = {"point": f"; a point name or {vector}", "vector": f"; {vector}"}.get(p.kind, "")
    return f"{bound}{p.doc}{form}"
