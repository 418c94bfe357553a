"""The schema of a run's outputs: every time series declared once, read by every consumer.

A ``Series`` says what one Result array holds: its name, the family of elements it has a value
for (each joint, mesh, bearing, body, generator, rotor, bearing row or slice of a sliced
mesh, or one per run), its components and frame, its SI unit and a one-line meaning, the MCAP
topic it is logged on, how the statistics, the report and the plots show it, and, for a series
computed in Python rather than by the compiled step, the function that derives it from a block
of samples. The Result's arrays and accessors, the log's topics and columns, the run
statistics, ``pinwind report``, ``pinwind export``, the plot panels and the replay all iterate
the schema (the typed-record idea of rerun's archetypes): a new series is one declaration.

The series the compiled step writes (``derive`` is None) are the compiled module's own list
(``_native.Series``, from the one table of ``cpp/series.hpp``): their names, order, families and
components are read from it at import, and this module adds what each means (``_MEANINGS``);
the import fails if the two name different series. The series computed in Python follow
(``_DERIVED``, a declaration each).

A ``Schema`` is immutable: a run takes the schema of its start (``current()``) and keeps it,
whatever is declared later. ``declare`` and ``withdraw`` do not change a schema: they make the
next one, which the runs started after them take.

The energy ledger is a dict of one value per run and sample (``Result.energy``), its terms
declared in ``ENERGY_TERMS``.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping
from dataclasses import dataclass, fields
from types import MappingProxyType
from typing import Any, Literal, cast

import numpy as np

from pinwind.dynamics import _native, bearing_load, bearing_springs

#: Kinds of element a series has values for; ``run``: one value per sample.
Family = Literal["run", "joint", "mesh", "bearing", "body", "generator", "rotor", "row", "slice"]

#: Result attribute that names the elements of each family, in the order of their columns.
NAMES_OF: dict[str, str] = {
    "joint": "joint_names",
    "mesh": "mesh_names",
    "bearing": "bearing_names",
    "body": "body_names",
    "generator": "generator_names",
    "rotor": "rotor_names",
    "row": "row_names",
    "slice": "slice_names",
}

#: Folder of each family's MCAP topics (``/meshes/normal``).
TOPIC_FOLDERS: dict[str, str] = {
    "run": "/run",
    "joint": "/joints",
    "mesh": "/meshes",
    "bearing": "/bearings",
    "generator": "/generators",
    "rotor": "/rotors",
    "row": "/rows",
    "slice": "/slices",
}

#: Order of the families on the log's viewer topics (as logs have always had them).
TOPIC_ORDER: tuple[str, ...] = (
    "joint",
    "mesh",
    "bearing",
    "run",
    "generator",
    "rotor",
    "row",
    "slice",
)

#: Kinds of joint (``Result.joint_kinds``): a revolute joint turns about its axis (its
#: coordinate an angle), a prismatic one (a slide of a compliant bearing or of the support)
#: moves along it (its coordinate a length).
JointKind = Literal["revolute", "prismatic"]

#: A joint series' unit on a prismatic joint, by its unit on a revolute one (the declared one).
PRISMATIC_UNITS: dict[str, str] = {"rad": "m", "rad/s": "m/s", "rad/s^2": "m/s^2", "N*m": "N"}


@dataclass(frozen=True)
class Plot:
    """How a series is plotted (``io/panels.py``): one panel, a line per element.

    Attributes:
        key: the panel's key (replay entity folder, figure file stem).
        group: the replay tab and figure (``panels.GROUPS``).
        title: what is plotted, with its display unit in brackets.
        unit: the display unit (``units.to_display`` converts to it).
        magnitude: plot |v| of a vector series.
        relative_to: the range floor is relative to the largest |value| of this other series
            (same scale), e.g. force components relative to the normal force.
        drop_zero: series that are zero at every sample are left out.
    """

    key: str
    group: str
    title: str
    unit: str
    magnitude: bool = False
    relative_to: str | None = None
    drop_zero: bool = False


@dataclass(frozen=True)
class About:
    """What a compiled series means: a ``Series`` but its name, family and components.

    The compiled table (``cpp/series.hpp``) declares those three; the fields here are
    ``Series``'s of the same names.
    """

    quantity: str
    unit: str
    meaning: str
    frame: str = ""
    per: Literal["sample", "pose"] = "sample"
    logged: bool = True
    label: str = ""
    short: str = ""
    statistics: bool = True
    headline: bool = True
    plot: Plot | None = None


#: A function that computes a derived series for a block of samples: (block, gearbox) → array
#: of shape (samples, elements[, components]); the block is a ``Result`` of the run's other
#: series (this module imports nothing of pinwind, so it names no type of it).
Derive = Callable[[Any, Any], np.ndarray]


@dataclass(frozen=True)
class Series:
    """One output series of a run: an array (samples, elements[, components]) of a Result.

    Attributes:
        name: the Result attribute (``mesh_normal``); unique.
        family: which elements it has values for (``Family``).
        quantity: its name within the family: the accessor field (``res.mesh(m).normal``), the
            log topic ``/meshes/normal`` and the export column ``mesh/m/normal_N``.
        unit: SI unit in ASCII (``N``, ``N*m``, ``rad/s^2``, ``1`` for none).
        meaning: one line, for docs, logs and the report's JSON.
        components: ``""`` for a scalar, ``"xyz"`` for a vector, ``"xyzw"`` for a quaternion.
        frame: ``world``, ``joint`` or ``bearing`` (a bearing row's: along its bearing's radial
            axes u, w and axis k, ``cpp/bearing_rows.hpp``): the axes of a vector's components.
        per: ``sample`` (a row per sample) or ``pose`` (a row per ``Result.pose_rows``).
        logged: on its own viewer topic (False: carried by ``/joints`` or ``/tf``).
        label: its name in the statistics and the report (default: ``quantity`` in words).
        short: its label in the printed report tables (default: ``label``).
        statistics: folded into the run statistics and the report.
        headline: in the engineer's table that ``pinwind report`` prints by default (False:
            only with ``--all``); a vector shows there its magnitude only.
        plot: its panel, or None.
        derive: None for a series the compiled step writes; else the function that computes
            it from a block's other series, in Python, before the block is logged.
    """

    name: str
    family: Family
    quantity: str
    unit: str
    meaning: str
    components: str = ""
    frame: str = ""
    per: Literal["sample", "pose"] = "sample"
    logged: bool = True
    label: str = ""
    short: str = ""
    statistics: bool = True
    headline: bool = True
    plot: Plot | None = None
    derive: Derive | None = None

    @property
    def topic(self) -> str:
        """Its MCAP topic (``/meshes/normal``)."""
        return f"{TOPIC_FOLDERS.get(self.family, '/' + self.family)}/{self.quantity}"

    @property
    def title(self) -> str:
        """Its statistics label (``transmission error``)."""
        return self.label or self.quantity.replace("_", " ")

    @property
    def width(self) -> int:
        """Values per element and sample."""
        return len(self.components) or 1

    def shape(self, elements: int) -> tuple[int, ...]:
        """Shape of one sample for ``elements`` elements (``()`` for a run scalar)."""
        if self.family == "run":
            return (self.width,) if self.components else ()
        return (elements, self.width) if self.components else (elements,)

    def unit_for(self, kind: str = "revolute") -> str:
        """Its SI unit on an element of joint kind ``kind`` (``JointKind``).

        ``unit`` for every series but a joint series on a prismatic joint, whose coordinate is a
        length: ``rad`` → ``m``, ``rad/s`` → ``m/s``, ``rad/s^2`` → ``m/s^2``, ``N*m`` → ``N``.
        """
        if self.family == "joint" and kind == "prismatic":
            return PRISMATIC_UNITS.get(self.unit, self.unit)
        return self.unit

    def column_unit(self, kind: str = "revolute") -> str:
        """The unit as a column name suffix: ``N*m`` → ``N_m``, ``rad/s^2`` → ``rad_s2``.

        ``kind``: the joint kind of the element (``unit_for``).
        """
        unit = self.unit_for(kind)
        if unit == "1":
            return ""
        return unit.replace("*", "_").replace("/", "_").replace("^", "").replace(" ", "_")


@dataclass(frozen=True)
class EnergyTerm:
    """One term of the energy ledger (``Result.energy``), cumulative from t = 0 [J]."""

    name: str
    meaning: str


#: The energy ledger, in the order of ``Result.energy`` (``dynamics/simulate.py`` gives the
#: balance they close).
ENERGY_TERMS: tuple[EnergyTerm, ...] = (
    EnergyTerm("kinetic", "kinetic energy ½ vᵀ M v"),
    EnergyTerm("work_applied", "work of the applied torques, generators and rotors"),
    EnergyTerm("work_drivers", "work of the speed drivers and locks"),
    EnergyTerm("work_springs", "work of the spring forces (torsional springs, compliant meshes)"),
    EnergyTerm("work_gravity", "work of gravity"),
    EnergyTerm("work_constraints", "work of the rigid mesh forces (zero up to drift)"),
    EnergyTerm("dissipated", "energy taken by the dampers"),
    EnergyTerm(
        "friction_loss",
        "energy taken by friction (tooth flanks of compliant meshes, rolling bearings)",
    ),
    EnergyTerm(
        "work_parametric",
        "work of the meshes' time-varying stiffness on the stored energy, Σ ½ Δk δ² "
        "(the parametric excitation; physics, not numerics)",
    ),
    EnergyTerm("potential_spring", "energy stored in the springs"),
    EnergyTerm("numerical", "the integrator's own loss: W_parametric − (ΔU_spring + W_springs)"),
)

#: What each series the compiled step writes means, by its name in ``_native.Series``: all of a
#: ``Series`` but its name, family and components, which the compiled table declares
#: (``cpp/series.hpp``; ``_compiled_series`` reads it). The ledger's terms are ``ENERGY_TERMS``.
_MEANINGS: dict[str, About] = {
    "time": About("time", "s", "sample time (exact; log time is rounded to 1 ns)",
           statistics=False),
    "angle": About("angle", "rad", "joint angle, unwrapped", logged=False,
           headline=False),
    "speed": About("speed", "rad/s", "joint speed relative to the parent body",
           logged=False,
           plot=Plot("speed", "speeds", "joint speeds, relative to the parent body [rpm]", "rpm")),
    "acceleration": About("acceleration", "rad/s^2",
           "joint acceleration over the step that starts at the sample", short="accel.",
           headline=False),
    "torque": About("torque", "N*m",
           "net torque from outside the gear train on the joint: applied + speed driver or lock "
           "+ generator + rotor (0 at a constant speed driven against a generator)",
           logged=False,
           plot=Plot("torque", "torques and power", "joint torques, applied + driver/lock "
                     "[kN·m]", "kN·m")),
    "mesh_normal": About("normal", "N", "tooth normal force F_n >= 0 on the loaded flank",
           plot=Plot("mesh_force", "mesh forces", "mesh normal forces F_n [kN]", "kN")),
    "mesh_tangential": About("tangential", "N", "F_t = F_n cos(alpha_w)",
           plot=Plot("mesh_tangential", "force components",
                     "mesh force components: tangential F_t [kN]", "kN",
                     relative_to="mesh_normal")),
    "mesh_radial": About("radial", "N", "F_r = F_n sin(alpha_w)",
           plot=Plot("mesh_radial", "force components",
                     "mesh force components: radial F_r (separating) [kN]", "kN",
                     relative_to="mesh_normal")),
    "mesh_axial": About("axial", "N", "F_a = F_n tan(beta_b)",
           plot=Plot("mesh_axial", "force components",
                     "mesh force components: axial F_a [kN]", "kN",
                     relative_to="mesh_normal")),
    "mesh_flank": About("flank", "1",
           "loaded flank s = +1 when A turning positively drives B, else -1 (of a compliant "
           "mesh on both flanks: the one pushing harder)", headline=False),
    "mesh_normal_front": About("normal_front", "N",
           "normal force on the front flank (s = +1) >= 0", short="F_n front", headline=False),
    "mesh_normal_back": About("normal_back", "N",
           "normal force on the back flank (s = -1) >= 0", short="F_n back", headline=False),
    "transmission_error": About("transmission_error", "m",
           "position mismatch along the line of action", short="TE",
           plot=Plot("transmission_error", "mesh deflection",
                     "transmission error along the line of action [µm]", "µm")),
    "mesh_force_on_b": About("force_on_b", "N", "tooth force on gear B (both flanks')",
           frame="world",
           label="force on B (world)", short="F on B", headline=False),
    "pitch_point": About("pitch_point", "m", "pitch point", frame="world",
           statistics=False),
    "mesh_deflection": About("deflection", "m",
           "compliant mesh: overlap of the loaded flank (negative: gap); rigid: 0",
           short="defl.",
           plot=Plot("mesh_deflection", "mesh deflection", "compliant mesh deflections δ [µm]",
                     "µm", drop_zero=True)),
    "mesh_contact_position": About("contact_position", "m",
           "roll position of the entering tooth pair from gear A's base tangency point (a "
           "helical mesh's: in the transverse section at the face centre)",
           short="contact", headline=False),
    "mesh_pairs": About("pairs", "1", "tooth pairs in contact", headline=False),
    "mesh_single_tooth_force": About("single_tooth_force", "N",
           "normal force on the entering tooth pair, F_n k1/k", short="F 1 tooth",
           plot=Plot("single_tooth_force", "mesh forces",
                     "single-tooth forces (entering pair) [kN]", "kN")),
    "mesh_face_load_factor": About("face_load_factor", "1",
           "K_Hbeta = peak over mean line load across the face, loaded flank (compliant mesh "
           "with slices; 1 for one contact line; 0 without load or rigid)", short="K_Hb",
           headline=False),
    "mesh_load_centre": About("load_centre", "m",
           "where the flank force acts across the face, from the face centre along gear A's "
           "axis (compliant mesh with slices; 0 otherwise)", short="load centre",
           headline=False),
    "bearing_force": About("force", "N", "force on the child body at the bearing centre",
           frame="world", label="force (world)", short="F world",
           plot=Plot("bearing_force", "bearings",
                     "bearing forces |F| on the child body, world [kN]", "kN",
                     magnitude=True)),
    "bearing_moment": About("moment", "N*m",
           "moment on the child body about the bearing centre", frame="world",
           label="moment (world)", short="M world", headline=False),  # not plotted: its |M|
    # is mostly the shaft's torque, which the bearing does not carry (bearing_tilting, _torque)
    "bearing_force_local": About("force_local", "N",
           "force on the child body at the bearing centre", frame="joint",
           label="force (joint frame)", short="F joint", headline=False),
    "bearing_moment_local": About("moment_local", "N*m",
           "moment on the child body about the bearing centre", frame="joint",
           label="moment (joint frame)", short="M joint", headline=False),
    "body_position": About("position", "m", "link frame origin", frame="world",
           per="pose", logged=False, statistics=False),
    "body_quaternion": About("quaternion", "1", "link orientation, scalar last",
           frame="world", per="pose", logged=False, statistics=False),
    "constraint_residual": About("constraint_residual", "m/s or rad/s",
           "max |J v - target| after the step", short="|J v|"),
    "generator_torque": About("torque", "N*m",
           "generator torque T_gen on the shaft, > 0 generating",
           plot=Plot("generator_torque", "torques and power",
                     "generator torque T_gen on the shaft, > 0 generating [kN·m]", "kN·m")),
    "rotor_torque": About("torque", "N*m", "aerodynamic torque on the hub",
           plot=Plot("rotor_torque", "torques and power",
                     "rotor aerodynamic torque on the hub [kN·m]", "kN·m")),
    "rotor_power": About("power", "W", "aerodynamic power 0.5 rho pi R^2 v^3 Cp",
           plot=Plot("rotor_power", "torques and power",
                     "rotor aerodynamic power P = ½ ρ π R² v³ C_p [kW]", "kW")),
    "rotor_tip_speed_ratio": About("tip_speed_ratio", "1", "tip-speed ratio wR/v",
           label="tip-speed ratio", short="TSR",
           plot=Plot("rotor_tip_speed_ratio", "rotor", "tip-speed ratio λ = ω R / v [-]", "-")),
    "rotor_power_coefficient": About("power_coefficient", "1",
           "power coefficient Cp", short="Cp",
           plot=Plot("rotor_power_coefficient", "rotor", "power coefficient C_p(λ, β) [-]",
                     "-")),
    "rotor_wind_speed": About("wind_speed", "m/s", "wind speed at the rotor",
           short="wind",
           plot=Plot("rotor_wind_speed", "rotor", "wind speed at the rotor v [m/s]", "m/s")),
    "rotor_thrust": About("thrust", "N", "aerodynamic thrust 0.5 rho pi R^2 v^2 Ct along the shaft",
           short="thrust",
           plot=Plot("rotor_thrust", "rotor", "rotor thrust T = ½ ρ π R² v² C_t [kN]", "kN")),
    "rotor_thrust_coefficient": About("thrust_coefficient", "1", "thrust coefficient Ct",
           short="Ct",
           plot=Plot("rotor_thrust_coefficient", "rotor", "thrust coefficient C_t(λ, β) [-]",
                     "-")),
    "rotor_pitch": About("pitch", "rad",
           "blade pitch: fixed, or the pitch controller's (loads/pitch_control.py)",
           short="pitch",
           plot=Plot("rotor_pitch", "rotor", "blade pitch β [deg]", "deg")),
    "row_force": About("force", "N",
           "bearing row's force on the shaft (F_u, F_w, F_k): its springs and dampers at its "
           "position (docs/model_format.md, Bearing rows)", frame="bearing",
           label="row force", short="F row", headline=False),
    "row_moment": About("moment", "N*m",
           "bearing row's own tilting moment on the shaft (M_u, M_w, 0)",
           frame="bearing", label="row moment", short="M row", headline=False),
    "bearing_friction_moment": About("friction_moment", "N*m",
           "rolling-bearing friction moment on the child body about the joint axis, opposing "
           "its relative speed: Palmgren's M0 + M1 (ISO/TR 14179-2; docs/losses.md); 0 "
           "without a friction_model", short="M friction",
           plot=Plot("bearing_friction_moment", "bearings",
                     "bearing friction moments about the joint axes [N·m]", "N·m",
                     drop_zero=True)),
    "bearing_friction_power": About("friction_power", "W",
           "power the bearing's friction takes, -M_friction * omega_rel >= 0 (heat to the oil)",
           short="P friction",
           plot=Plot("bearing_friction_power", "bearings", "bearing friction power losses [kW]",
                     "kW", drop_zero=True)),
    "mesh_sliding_velocity": About("sliding_velocity", "m/s",
           "sliding speed of the entering tooth pair's flanks, B's on A's along k x n of the "
           "loaded flank (compliant mesh; zero at the pitch point; docs/simulation.md, Flank "
           "friction)",
           short="v slide", headline=False),
    "mesh_friction_force": About("friction_force", "N",
           "flank friction on gear A along k x n of the loaded flank, sum of mu F_j sgn(v_s,j) "
           "over its pairs (the sign of the pair's sliding in rigid rolling, from its side of "
           "the pitch point), F_j a pair's share of the normal force F_bt/cos(beta_b), a helical "
           "pair's averaged along its contact line (compliant mesh with friction_coefficient; "
           "0 otherwise)",
           short="F friction", headline=False),
    "mesh_friction_power": About("friction_power", "W",
           "power the flank friction takes, sum of mu F_j sgn(v_s,j) v_s,j over the pairs of "
           "both flanks at their actual sliding velocities; below 0 for a moment where the "
           "gears' vibration reverses a pair's sliding near the pitch point (compliant mesh "
           "with friction_coefficient; 0 otherwise)",
           short="P friction",
           plot=Plot("mesh_friction_power", "mesh forces", "mesh friction loss [kW]", "kW",
                     drop_zero=True)),
    "mesh_peak_line_load": About("peak_line_load", "N/m",
           "peak line load across the face, loaded flank: N max_s F_s / b (compliant mesh with "
           "slices; F_n / b for one contact line; 0 without load or rigid)", short="w max",
           headline=False),
    "mesh_mean_line_load": About("mean_line_load", "N/m",
           "mean line load across the face, loaded flank: F_n / b (compliant mesh; 0 without "
           "load or rigid); peak_line_load / mean_line_load = face_load_factor", short="w mean",
           headline=False),
    "slice_line_load": About("line_load", "N/m",
           "line load of one slice of a sliced compliant mesh, loaded flank: its normal force "
           "over its width, N F_s / b (0 out of contact or without load); mesh_peak_line_load "
           "is the largest of its mesh's, mesh_mean_line_load their mean; the slice's face "
           "position is in the run's metadata (meshes.<mesh>.slice_positions)",
           label="slice line load", short="w slice", headline=False, statistics=False),
}  # fmt: skip


#: A compiled series' components (1 scalar, 3 vector, 4 quaternion) as ``Series.components``.
_COMPONENTS = {1: "", 3: "xyz", 4: "xyzw"}


def _compiled_series() -> tuple[Series, ...]:
    """The compiled step's series in its order (``_native.Series``), with their meanings.

    The ledger's terms (``ENERGY_TERMS``) are ``Result.energy``'s, not series.

    Raises:
        ImportError: a compiled series has no meaning here, or a meaning names no compiled
            series (the compiled module and this one are of different versions).
    """
    ledger = {t.name for t in ENERGY_TERMS}
    names = [m.name for m in _native.Series if m.name not in ledger]
    unknown = sorted(set(names) ^ set(_MEANINGS))
    if unknown:
        raise ImportError(
            f"series {unknown} are in one of _native.Series and series._MEANINGS only: "
            "rebuild the compiled module, or declare what the new series means"
        )
    out = []
    for name in names:
        family, components = _native.series_layout(getattr(_native.Series, name))
        about = _MEANINGS[name]
        values = {f.name: getattr(about, f.name) for f in fields(About)}
        kind = cast(Family, family.name)
        out.append(Series(name=name, family=kind, components=_COMPONENTS[components], **values))
    return tuple(out)


#: Every series the compiled step writes, in the order of the Result's arrays (and of the log's
#: columns).
_BUILT_IN: tuple[Series, ...] = _compiled_series()

_B: Family = "bearing"

#: Series computed in Python from the compiled ones (``derive``), after them in the Result.
_DERIVED: tuple[Series, ...] = (
    Series("bearing_displacement", _B, "displacement", "m",
           "compliant bearing: the body's displacement in the bearing (radial: the orbit); "
           "ideal: 0", "xyz", "joint", label="displacement in the bearing", short="orbit",
           headline=False, derive=bearing_springs.displacement),
    Series("bearing_elastic_force", _B, "elastic_force", "N",
           "compliant bearing: the bearing springs' force on the body; ideal or floating: 0",
           "xyz", "joint", label="elastic force", short="F spring", headline=False,
           derive=bearing_springs.elastic_force),
    Series("bearing_radial", _B, "radial", "N",
           "radial force: the force on the child body normal to the bearing axis, >= 0",
           label="radial force", short="F radial", derive=bearing_load.radial_force,
           plot=Plot("bearing_radial", "bearings",
                     "bearing radial forces F_r, normal to the bearing axis [kN]", "kN")),
    Series("bearing_axial", _B, "axial", "N",
           "axial force: the force on the child body along the bearing axis (signed)",
           label="axial force", short="F axial", derive=bearing_load.axial_force,
           plot=Plot("bearing_axial", "bearings",
                     "bearing axial forces F_a, along the bearing axis [kN]", "kN",
                     drop_zero=True)),
    Series("bearing_tilting", _B, "tilting", "N*m",
           "tilting moment: the moment on the child body normal to the bearing axis, >= 0",
           label="tilting moment", short="M tilting", derive=bearing_load.tilting_moment,
           plot=Plot("bearing_tilting", "bearings",
                     "bearing tilting moments M_t, normal to the bearing axis [kN·m]", "kN·m",
                     drop_zero=True)),
    Series("row_radial", "row", "radial", "N",
           "bearing row's radial force on the shaft |(F_u, F_w)|, >= 0", label="row radial force",
           short="F radial row", headline=False, derive=bearing_load.row_radial_force,
           plot=Plot("row_radial", "bearings",
                     "bearing rows' radial forces on their shafts [kN]", "kN")),
    Series("row_axial", "row", "axial", "N",
           "bearing row's axial force on the shaft F_k (signed along the axis)",
           label="row axial force", short="F axial row", headline=False,
           derive=bearing_load.row_axial_force,
           plot=Plot("row_axial", "bearings", "bearing rows' axial forces on their shafts [kN]",
                     "kN", drop_zero=True)),
    Series("row_load_zone", "row", "load_zone", "rad",
           "bearing row's load-zone angle 2 psi_l: the arc of its rolling elements in contact "
           "(180 deg at zero clearance under a radial load; ISO/TS 16281 load distribution); "
           "NaN without an internal geometry (size_mm)",
           label="row load zone", short="zone row", headline=False,
           derive=bearing_load.row_load_zone,
           plot=Plot("row_load_zone", "bearings", "bearing rows' load-zone angles [deg]",
                     "deg")),
    Series("row_max_element_load", "row", "max_element_load", "N",
           "bearing row's largest rolling-element load Q_max (ISO/TS 16281 load distribution; "
           "4.08 F_r/Z for rollers at zero clearance, Stribeck); NaN without an internal "
           "geometry (size_mm)",
           label="row max element load", short="Q max row", headline=False,
           derive=bearing_load.row_max_element_load,
           plot=Plot("row_max_element_load", "bearings",
                     "bearing rows' largest rolling-element loads Q_max [kN]", "kN")),
    Series("bearing_torque", _B, "torque", "N*m",
           "transmitted torque: the moment on the child body along the bearing axis (signed; "
           "the shaft's torque, not a bearing load)",
           label="transmitted torque", short="T axis",
           derive=bearing_load.transmitted_torque,
           plot=Plot("bearing_torque", "bearings",
                     "torques the shafts transmit about the bearing axes (not a bearing load) "
                     "[kN·m]", "kN·m")),
)  # fmt: skip


def _checked(series: Series, taken: Iterable[str]) -> Series:
    """``series`` if it can join a schema of the names ``taken``.

    Raises:
        ValueError: its name is taken, it has no ``derive``, or its family is unknown.
    """
    if series.name in taken:
        raise ValueError(f'a series named "{series.name}" is already declared')
    if series.derive is None:
        raise ValueError(
            f'series "{series.name}": give derive=, the function that computes it from a block '
            "(the compiled step writes only the series of _native.Series)"
        )
    if series.family not in ("run", *NAMES_OF):
        raise ValueError(f'series "{series.name}": unknown family "{series.family}"')
    return series


class Schema(Mapping[str, Series]):
    """An immutable schema: its series in the order of the Result's arrays, by name.

    A run is given one (``current()`` at its start) and keeps it; ``with_series`` and
    ``without`` make new ones.
    """

    __slots__ = ("_by_name", "_series")
    _series: tuple[Series, ...]
    _by_name: Mapping[str, Series]

    def __init__(self, series: Iterable[Series]):
        items = tuple(series)
        by_name = {s.name: s for s in items}
        if len(by_name) != len(items):
            twice = sorted({s.name for s in items if sum(t.name == s.name for t in items) > 1})
            raise ValueError(f"series {twice} are declared twice")
        object.__setattr__(self, "_series", items)
        object.__setattr__(self, "_by_name", MappingProxyType(by_name))

    def __setattr__(self, name: str, value: object) -> None:
        raise AttributeError(f"a Schema is immutable; {name} cannot be set (Schema.with_series)")

    def __reduce__(self) -> tuple[type[Schema], tuple[tuple[Series, ...]]]:
        # Pickled as its series (a Result sent back by a sweep's worker holds its schema).
        return (Schema, (self._series,))

    def __getitem__(self, name: str) -> Series:
        return self._by_name[name]

    def __iter__(self) -> Iterator[str]:
        return iter(self._by_name)

    def __len__(self) -> int:
        return len(self._series)

    def __repr__(self) -> str:
        return f"Schema({list(self._by_name)})"

    @property
    def series(self) -> tuple[Series, ...]:
        """Every series, in the order of the Result's arrays."""
        return self._series

    @property
    def names(self) -> tuple[str, ...]:
        """Their names, in the same order (``Result.ARRAYS`` of a Result of this schema)."""
        return tuple(self._by_name)

    def of_family(self, family: str) -> tuple[Series, ...]:
        """The series of one family, in schema order."""
        return tuple(s for s in self._series if s.family == family)

    def compiled(self) -> tuple[Series, ...]:
        """The series the compiled step writes (``_native.Series``)."""
        return tuple(s for s in self._series if s.derive is None)

    def derived(self) -> tuple[Series, ...]:
        """The series computed in Python (``Series.derive``), in schema order."""
        return tuple(s for s in self._series if s.derive is not None)

    def pose_series(self) -> tuple[Series, ...]:
        """The series with a row per pose (``Result.pose_rows``) rather than per sample."""
        return tuple(s for s in self._series if s.per == "pose")

    def with_series(self, series: Series) -> Schema:
        """A new schema with a derived series added last (this one unchanged).

        Raises:
            ValueError: its name is taken, it has no ``derive``, or its family is unknown.
        """
        return Schema((*self._series, _checked(series, self._by_name)))

    def only(self, names: Iterable[str]) -> Schema:
        """A new schema of the series named, in this schema's order, and the link poses.

        The poses (``body_position``, ``body_quaternion``) stay: a Result has them, with a row
        per pose (none kept: no rows).

        Raises:
            KeyError: a name that is not a series of this schema.
        """
        wanted = set(names)
        unknown = wanted - set(self._by_name)
        if unknown:
            raise KeyError(f"no series {sorted(unknown)}; the series are: {list(self._by_name)}")
        keep = wanted | {"time"} | {s.name for s in self._series if s.per == "pose"}
        return Schema(s for s in self._series if s.name in keep)

    def without(self, name: str) -> Schema:
        """A new schema without the derived series ``name`` (this one unchanged).

        Raises:
            KeyError: no such series.
            ValueError: the compiled step writes it.
        """
        if self[name].derive is None:
            raise ValueError(f'series "{name}" is written by the compiled step')
        return Schema(s for s in self._series if s.name != name)


#: The schema of the compiled series and the derived ones declared above.
BUILT_IN = Schema((*_BUILT_IN, *_DERIVED))

#: The schema runs take at their start: ``BUILT_IN`` and what ``declare`` added since. Rebound
#: (never changed in place) by ``declare`` and ``withdraw``.
_current: Schema = BUILT_IN


def current() -> Schema:
    """The schema a run started now takes (it keeps it to its end)."""
    return _current


def schema() -> tuple[Series, ...]:
    """Every series of the current schema, in the order of the Result's arrays."""
    return _current.series


def declare(series: Series) -> Series:
    """Declare a derived series: the runs started after it have it in every consumer.

    Their Result, log, report, export and plots. A series computed in Python needs ``derive``;
    the compiled step's own are read from it. The current schema is replaced by a new one
    (``Schema.with_series``); runs already started keep theirs.

    Raises:
        ValueError: its name is taken, or it has no ``derive``.
    """
    global _current
    _current = _current.with_series(series)
    return series


def withdraw(name: str) -> None:
    """Withdraw a declared (derived) series from the runs started after: ``declare``'s inverse."""
    global _current
    _current = _current.without(name)


def get(name: str) -> Series:
    """The series named ``name`` in the current schema.

    Raises:
        KeyError: no such series.
    """
    return _current[name]


def of_family(family: str) -> tuple[Series, ...]:
    """The series of one family, in schema order."""
    return _current.of_family(family)


def compiled() -> tuple[Series, ...]:
    """The series the compiled step writes (``_native.Series``)."""
    return _current.compiled()


def pose_series() -> tuple[Series, ...]:
    """The series with a row per pose (``Result.pose_rows``) rather than per sample."""
    return _current.pose_series()


class Names:
    """The names of the current schema's series, read when iterated (``Result.ARRAYS``)."""

    def __init__(self, select: Callable[[Series], bool] = lambda s: True):
        self._select = select

    def __iter__(self) -> Iterator[str]:
        return iter([s.name for s in _current.series if self._select(s)])

    def __contains__(self, name: object) -> bool:
        return any(s.name == name for s in _current.series if self._select(s))

    def __len__(self) -> int:
        return sum(1 for s in _current.series if self._select(s))

    def __repr__(self) -> str:
        return f"Names({list(self)})"


def markdown_table() -> str:
    """The built-in schema as the Markdown table of ``docs/series.md`` (a test keeps the two equal).

    The built-in one, whatever a user declared since: the documentation describes what every
    run has.
    """
    lines = [
        "| Result array | family | quantity | shape per sample | unit | frame | topic | meaning |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for s in BUILT_IN.series:
        per: str = "" if s.family == "run" else s.family
        if s.components:
            per = f"{per}, {s.components}" if per else s.components
        topic = f"`{s.topic}`" if s.logged else ("`/tf`" if s.per == "pose" else "`/joints`")
        lines.append(
            f"| `{s.name}` | {s.family} | {s.quantity} | [{per or 'value'}] | {s.unit} | "
            f"{s.frame or '-'} | {topic} | {s.meaning.replace('|', '&#124;')} |"
        )
    lines += ["", "| energy term | meaning |", "|---|---|"]
    lines += [f"| `{t.name}` | {t.meaning} |" for t in ENERGY_TERMS]
    return "\n".join(lines) + "\n"
