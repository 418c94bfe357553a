"""Result of a run: time series of every joint, mesh, bearing and body, keyed by model names.

A Result is plain arrays (float64, SI units) plus names, so that ``simulate`` and ``read_log``
build exactly the same object. Accessors return small views with named fields:

    res.joint("sun").speed           # (n,) rad/s
    res.mesh("sun_planet1").normal   # (n,) N
    res.bearing("carrier").force     # (n, 3) N, world frame
    res.generator("sun").torque      # (n,) N·m, > 0 generating
    res.rotor("carrier").power       # (n,) W
    res.body("carrier").position     # (p, 3) m at the p samples with a pose (``pose_rows``)

Link poses are kept at their own samples: every sample in a Result of ``simulate``, the pose
rate of the log (a display rate) in one read from a log.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from pinwind.errors import UnknownElement

if TYPE_CHECKING:
    from pinwind.analysis.run_statistics import RunningStatistics


@dataclass(frozen=True)
class JointSeries:
    """Time series of one bearing (joint).

    Attributes:
        angle: joint angle [rad], unwrapped, (n,).
        speed: joint speed [rad/s] (relative to the parent body), (n,).
        acceleration: joint acceleration [rad/s²] over the step that starts at each sample, (n,).
        torque: applied torque plus speed-driver or lock torque on the joint [N·m], (n,).
    """

    angle: np.ndarray
    speed: np.ndarray
    acceleration: np.ndarray
    torque: np.ndarray


@dataclass(frozen=True)
class MeshSeries:
    """Time series of one gear mesh A–B (sign convention: docs/model_format.md).

    Attributes:
        normal: tooth normal force F_n ≥ 0 [N], (n,).
        tangential: F_t = F_n cos α_w [N], (n,).
        radial: F_r = F_n sin α_w [N], (n,).
        axial: F_a = F_t |tan β| [N], (n,); its direction is in ``force_on_b``.
        flank: loaded flank s = ±1, (n,): +1 when A turning positively drives B.
        transmission_error: rigid mesh: position mismatch accumulated along the row [m];
            compliant mesh: the front flank's overlap δ_f from the gear positions [m], (n,).
        force_on_b: tooth force on gear B in world [N], (n, 3).
        pitch_point: pitch point in world [m], (n, 3).
        deflection: compliant mesh: overlap δ of the loaded flank [m] (0 for rigid meshes;
            negative: the gap to the nearer flank while out of contact), (n,).
        contact_position: roll position of the tooth pair entering the mesh, measured along
            the line of action from gear A's base-circle tangency point [m], (n,)
            (003_83d3049daebcd276.txt Fig. 7, Table 6).
        pairs: tooth pairs in contact, (n,).
        single_tooth_force: normal force on the entering pair, F_n k₁/k (003 §2.4) [N], (n,).
    """

    normal: np.ndarray
    tangential: np.ndarray
    radial: np.ndarray
    axial: np.ndarray
    flank: np.ndarray
    transmission_error: np.ndarray
    force_on_b: np.ndarray
    pitch_point: np.ndarray
    deflection: np.ndarray
    contact_position: np.ndarray
    pairs: np.ndarray
    single_tooth_force: np.ndarray


@dataclass(frozen=True)
class BearingSeries:
    """Reaction transmitted by one bearing from its parent body to its child body.

    Force and moment are taken at the bearing centre (the joint origin): the spatial force that
    Pinocchio's RNEA finds transmitted through the joint. Its component about the shaft axis is
    the net torque applied at that joint (applied torque, speed driver or lock, torsional springs
    and dampers acting there); the rolling bearing itself carries none.

    Attributes:
        force: force on the child [N] in world axes, (n, 3).
        moment: moment on the child about the bearing centre [N·m] in world axes, (n, 3).
        force_local: the same force in the joint frame [N], (n, 3).
        moment_local: the same moment in the joint frame [N·m], (n, 3).
    """

    force: np.ndarray
    moment: np.ndarray
    force_local: np.ndarray
    moment_local: np.ndarray


@dataclass(frozen=True)
class BodySeries:
    """World pose of one link at the p samples that have one (``Result.pose_rows``).

    Attributes:
        position: link frame origin in world [m], (p, 3).
        quaternion: link orientation in world, (p, 4), scalar last (x, y, z, w).
        time: the times of those samples [s], (p,).
    """

    position: np.ndarray
    quaternion: np.ndarray
    time: np.ndarray


@dataclass(frozen=True)
class GeneratorSeries:
    """Time series of one generator law on its shaft (``pinwind.loads.generator``).

    Attributes:
        torque: generator torque T_gen on the shaft [N·m], positive when generating (the shaft
            feels −T_gen, which is part of the joint's torque), over the step that starts at
            each sample; for the dq machine, the electromagnetic torque of the fluxes at the
            step's end, (n,).
    """

    torque: np.ndarray


@dataclass(frozen=True)
class RotorSeries:
    """Time series of one rotor (``pinwind.loads.rotor``).

    Attributes:
        torque: aerodynamic torque on the hub over the step that starts at each sample [N·m]
            (part of the joint's torque), (n,).
        power: aerodynamic power at the sample, P = ½ ρ π R² v³ C_p = τ(ω) ω [W], (n,).
        tip_speed_ratio: λ = ω R / v at the sample (held at its floor 0.1 at start-up; 0
            without wind) [-], (n,).
        power_coefficient: C_p(λ, β) [-], (n,).
        wind_speed: wind speed at the rotor v [m/s], (n,).
    """

    torque: np.ndarray
    power: np.ndarray
    tip_speed_ratio: np.ndarray
    power_coefficient: np.ndarray
    wind_speed: np.ndarray


#: Arrays of a Result indexed by pose (``Result.pose_rows``) rather than by sample.
POSE_ARRAYS = ("body_position", "body_quaternion")
#: Per-element arrays of a Result: (n, generators) and (n, rotors).
GENERATOR_ARRAYS = ("generator_torque",)
ROTOR_ARRAYS = (
    "rotor_torque",
    "rotor_power",
    "rotor_tip_speed_ratio",
    "rotor_power_coefficient",
    "rotor_wind_speed",
)


@dataclass
class Result:
    """All time series of a run (SI units, float64), sample k at ``time[k]``.

    Arrays are indexed ``[sample, element, ...]`` with elements in the order of the name lists.

    Attributes:
        time: sample times [s], (n,).
        joint_names, mesh_names, bearing_names, body_names: element names from the model file.
        angle, speed, acceleration, torque: (n, joints).
        mesh_normal, mesh_tangential, mesh_radial, mesh_axial, mesh_flank,
        transmission_error, mesh_deflection, mesh_contact_position, mesh_pairs,
        mesh_single_tooth_force: (n, meshes).
        mesh_force_on_b, pitch_point: (n, meshes, 3).
        bearing_force, bearing_moment, bearing_force_local, bearing_moment_local:
            (n, bearings, 3).
        pose_rows: the samples that have a link pose, increasing, (p,): every sample in a
            Result of ``simulate``, those at the log's pose rate in one read from a log.
        body_position: (p, bodies, 3); body_quaternion: (p, bodies, 4) xyzw, at ``pose_rows``.
        constraint_residual: max |J v − target| after each step [m/s or rad/s], (n,).
        generator_names, rotor_names: joints carrying a generator law or a rotor, in the
            order of the columns below (empty without them).
        generator_torque: T_gen [N·m], (n, generators) (``GeneratorSeries``).
        rotor_torque [N·m], rotor_power [W], rotor_tip_speed_ratio, rotor_power_coefficient,
            rotor_wind_speed [m/s]: (n, rotors) (``RotorSeries``).
        energy: energy ledger [J], name → (n,): ``kinetic``, ``potential_gravity``,
            ``potential_spring``, ``work_applied`` (applied torques and gravity-free inputs),
            ``work_drivers`` (speed drivers and locks), ``dissipated`` (dampers).
        metadata: model name, file hash, dt, solver settings, loads and status.
        status: ``"completed"``, or why the run stopped early.
        statistics: min, max, mean, RMS and final value of every series over every simulated
            sample (``analysis/run_statistics.RunningStatistics``), when ``simulate`` folded them
            (by default when the Result does not keep every sample); None otherwise, and in a
            Result read from a log or cut from another (``take``, ``rows``).
    """

    time: np.ndarray
    joint_names: list[str]
    mesh_names: list[str]
    bearing_names: list[str]
    body_names: list[str]
    angle: np.ndarray
    speed: np.ndarray
    acceleration: np.ndarray
    torque: np.ndarray
    mesh_normal: np.ndarray
    mesh_tangential: np.ndarray
    mesh_radial: np.ndarray
    mesh_axial: np.ndarray
    mesh_flank: np.ndarray
    transmission_error: np.ndarray
    mesh_force_on_b: np.ndarray
    pitch_point: np.ndarray
    mesh_deflection: np.ndarray
    mesh_contact_position: np.ndarray
    mesh_pairs: np.ndarray
    mesh_single_tooth_force: np.ndarray
    bearing_force: np.ndarray
    bearing_moment: np.ndarray
    bearing_force_local: np.ndarray
    bearing_moment_local: np.ndarray
    body_position: np.ndarray
    body_quaternion: np.ndarray
    constraint_residual: np.ndarray
    energy: dict[str, np.ndarray] = field(default_factory=dict)
    metadata: dict[str, Any] = field(default_factory=dict)
    status: str = "completed"
    generator_names: list[str] = field(default_factory=list)
    rotor_names: list[str] = field(default_factory=list)
    generator_torque: np.ndarray = None  # type: ignore[assignment]  # (n, 0) when not given
    rotor_torque: np.ndarray = None  # type: ignore[assignment]
    rotor_power: np.ndarray = None  # type: ignore[assignment]
    rotor_tip_speed_ratio: np.ndarray = None  # type: ignore[assignment]
    rotor_power_coefficient: np.ndarray = None  # type: ignore[assignment]
    rotor_wind_speed: np.ndarray = None  # type: ignore[assignment]
    statistics: RunningStatistics | None = None
    pose_rows: np.ndarray = None  # type: ignore[assignment]  # every sample when not given

    #: Names of the array attributes, for writers, readers and comparisons; those of
    #: ``POSE_ARRAYS`` have a row per pose (``pose_rows``), the others a row per sample.
    ARRAYS = (
        "time",
        "angle",
        "speed",
        "acceleration",
        "torque",
        "mesh_normal",
        "mesh_tangential",
        "mesh_radial",
        "mesh_axial",
        "mesh_flank",
        "transmission_error",
        "mesh_force_on_b",
        "pitch_point",
        "mesh_deflection",
        "mesh_contact_position",
        "mesh_pairs",
        "mesh_single_tooth_force",
        "bearing_force",
        "bearing_moment",
        "bearing_force_local",
        "bearing_moment_local",
        "body_position",
        "body_quaternion",
        "constraint_residual",
        *GENERATOR_ARRAYS,
        *ROTOR_ARRAYS,
    )

    def __post_init__(self) -> None:
        # Runs without generators or rotors, and logs written before these outputs: no columns.
        n = len(self.time)
        for names, arrays in ((self.generator_names, GENERATOR_ARRAYS),
                              (self.rotor_names, ROTOR_ARRAYS)):  # fmt: skip
            for name in arrays:
                if getattr(self, name) is None:
                    setattr(self, name, np.zeros((n, len(names))))
        if self.pose_rows is None:
            self.pose_rows = np.arange(len(self.body_position))
        if not len(self.pose_rows) == len(self.body_position) == len(self.body_quaternion):
            raise ValueError(
                f"{len(self.pose_rows)} pose rows for {len(self.body_position)} positions and "
                f"{len(self.body_quaternion)} quaternions"
            )

    @property
    def pose_time(self) -> np.ndarray:
        """Times of the samples that have a link pose [s], (p,)."""
        return self.time[self.pose_rows]

    def __len__(self) -> int:
        return len(self.time)

    @staticmethod
    def _index(kind: str, names: list[str], name: str) -> int:
        try:
            return names.index(name)
        except ValueError:
            raise UnknownElement(kind, name, names) from None

    def joint(self, name: str) -> JointSeries:
        """Time series of a bearing's angle, speed, acceleration and torque."""
        i = self._index("joint", self.joint_names, name)
        return JointSeries(
            self.angle[:, i], self.speed[:, i], self.acceleration[:, i], self.torque[:, i]
        )

    def mesh(self, name: str) -> MeshSeries:
        """Time series of a gear mesh's forces and transmission error."""
        i = self._index("mesh", self.mesh_names, name)
        return MeshSeries(
            normal=self.mesh_normal[:, i],
            tangential=self.mesh_tangential[:, i],
            radial=self.mesh_radial[:, i],
            axial=self.mesh_axial[:, i],
            flank=self.mesh_flank[:, i],
            transmission_error=self.transmission_error[:, i],
            force_on_b=self.mesh_force_on_b[:, i],
            pitch_point=self.pitch_point[:, i],
            deflection=self.mesh_deflection[:, i],
            contact_position=self.mesh_contact_position[:, i],
            pairs=self.mesh_pairs[:, i],
            single_tooth_force=self.mesh_single_tooth_force[:, i],
        )

    def bearing(self, name: str) -> BearingSeries:
        """Time series of a bearing's reaction force and moment (world and joint frame)."""
        i = self._index("bearing", self.bearing_names, name)
        return BearingSeries(
            self.bearing_force[:, i],
            self.bearing_moment[:, i],
            self.bearing_force_local[:, i],
            self.bearing_moment_local[:, i],
        )

    def body(self, name: str) -> BodySeries:
        """A link's world pose at the samples that have one (``pose_rows``)."""
        i = self._index("body", self.body_names, name)
        return BodySeries(self.body_position[:, i], self.body_quaternion[:, i], self.pose_time)

    def generator(self, name: str) -> GeneratorSeries:
        """Time series of the generator law on a joint."""
        i = self._index("generator", self.generator_names, name)
        return GeneratorSeries(self.generator_torque[:, i])

    def rotor(self, name: str) -> RotorSeries:
        """Time series of the rotor on a joint: torque, power, λ, C_p and wind speed."""
        i = self._index("rotor", self.rotor_names, name)
        return RotorSeries(*(getattr(self, a)[:, i] for a in ROTOR_ARRAYS))

    def truncated(self, n: int) -> Result:
        """The first ``n`` samples (used when a run stops early)."""
        return self.rows(0, n)

    def rows(self, start: int, stop: int) -> Result:
        """Samples start:stop as a Result (views of these arrays)."""
        return self.take(slice(start, stop))

    def posed(self) -> Result:
        """The samples that have a link pose, as a Result (a pose at every sample)."""
        if len(self.pose_rows) == len(self):
            return self
        return self.take(self.pose_rows)

    def pose_at_samples(self, name: str) -> np.ndarray:
        """A pose array (``POSE_ARRAYS``) with a row per sample, (n, bodies, 3 or 4).

        NaN at the samples without a pose; a new array.
        """
        poses = getattr(self, name)
        out = np.full((len(self), *poses.shape[1:]), np.nan)
        out[self.pose_rows] = poses
        return out

    def take(self, rows: slice | np.ndarray) -> Result:
        """The samples ``rows`` (a slice gives views, indices copies) as a Result.

        The poses kept are those of the samples taken (``pose_rows`` renumbered).
        """
        arrays = {n: getattr(self, n)[rows] for n in self.ARRAYS if n not in POSE_ARRAYS}
        picked, pose_rows = self._poses_of(rows)
        for name in POSE_ARRAYS:
            arrays[name] = getattr(self, name)[picked]
        return self.holding(arrays, {k: v[rows] for k, v in self.energy.items()}, pose_rows)

    def holding(
        self, arrays: dict[str, Any], energy: dict[str, np.ndarray], pose_rows: np.ndarray
    ) -> Result:
        """A Result with these names, metadata (a copy) and status, holding other samples.

        ``arrays``: every name of ``ARRAYS`` → its array.
        """
        return Result(
            joint_names=self.joint_names,
            mesh_names=self.mesh_names,
            bearing_names=self.bearing_names,
            body_names=self.body_names,
            generator_names=self.generator_names,
            rotor_names=self.rotor_names,
            energy=energy,
            metadata=dict(self.metadata),
            status=self.status,
            pose_rows=pose_rows,
            **arrays,
        )

    def _poses_of(self, rows: slice | np.ndarray) -> tuple[slice | np.ndarray, np.ndarray]:
        """The poses of the samples ``rows``, and where those samples are among ``rows``.

        The poses as a slice when ``rows`` is one (consecutive samples), else as indices.
        """
        n, posed = len(self), self.pose_rows
        if isinstance(rows, slice):
            start, stop, step = rows.indices(n)
            if step == 1:
                lo, hi = np.searchsorted(posed, [start, max(start, stop)])
                return slice(int(lo), int(hi)), posed[lo:hi] - start
            rows = np.arange(start, stop, step)
        rows = np.asarray(rows)
        if rows.dtype == bool:
            rows = np.flatnonzero(rows)
        rows = np.where(rows < 0, rows + n, rows)
        where = np.minimum(np.searchsorted(posed, rows), max(len(posed) - 1, 0))
        has = posed[where] == rows if len(posed) else np.zeros(len(rows), dtype=bool)
        return where[has], np.flatnonzero(has)


def concatenate(parts: list[Result]) -> Result:
    """One Result of consecutive parts of a run (the names, metadata and status of the first)."""
    first = parts[0]
    if len(parts) == 1:
        return first
    arrays = {name: np.concatenate([getattr(p, name) for p in parts]) for name in Result.ARRAYS}
    energy = {k: np.concatenate([p.energy[k] for p in parts]) for k in first.energy}
    starts = np.cumsum([0] + [len(p) for p in parts[:-1]])
    pose_rows = np.concatenate([p.pose_rows + at for p, at in zip(parts, starts, strict=True)])
    return first.holding(arrays, energy, pose_rows)
