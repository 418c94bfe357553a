"""Result of a run: time series of every joint, mesh, bearing and body, keyed by model names.

A Result is plain arrays (float64, SI units) plus names, so that ``simulate`` and ``read_log``
build exactly the same object; which arrays there are is declared once, in the schema of
``dynamics/series.py``. Accessors give one element's series by quantity:

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

from collections.abc import Collection
from typing import Any, Protocol

import numpy as np

from pinwind.dynamics import series
from pinwind.dynamics.series import Schema, Series
from pinwind.errors import InputError, UnknownElement


class FoldedStatistics(Protocol):
    """Statistics of every series over a run (``analysis/run_statistics.RunningStatistics``)."""

    count: int

    def row(self, group: str, element: str, quantity: str, component: str = "") -> Any:
        """The statistics of one series."""

    def rows(self) -> list[Any]:
        """One row per series."""


class ElementSeries:
    """The time series of one element (a joint, mesh, bearing, body, generator or rotor).

    One attribute per series of its family in the schema (``dynamics/series.py``), named by the
    series' quantity, sample first: ``res.mesh("sun_planet1").normal`` is (n,) [N],
    ``res.bearing("carrier").force`` (n, 3) [N] in world axes. A body's series are at the
    samples that have a pose, whose times are ``time``. ``units`` gives each field's SI unit
    (a slide's, ``kind`` prismatic, its own: ``Series.unit_for``).
    """

    def __init__(
        self, family: str, name: str, values: dict[str, np.ndarray], kind: str = "revolute"
    ):
        self.family = family
        self.name = name
        self.kind = kind
        self._values = values

    def __getattr__(self, quantity: str) -> np.ndarray:
        try:
            return self.__dict__["_values"][quantity]
        except KeyError:
            fields = ", ".join(self.__dict__["_values"])
            raise AttributeError(
                f'{self.__dict__["family"]} series have no "{quantity}"; they have: {fields}'
            ) from None

    def __dir__(self) -> list[str]:
        return [*self._values, "family", "name", "kind", "units"]

    @property
    def units(self) -> dict[str, str]:
        """Field → SI unit."""
        out = {s.quantity: s.unit_for(self.kind) for s in series.of_family(self.family)}
        if self.family == "body":
            out["time"] = "s"
        return out

    def __repr__(self) -> str:
        return f"ElementSeries({self.family} {self.name!r}: {', '.join(self._values)})"


#: Arrays of a Result indexed by pose (``Result.pose_rows``) rather than by sample.
POSE_ARRAYS = tuple(s.name for s in series.pose_series())


class Result:
    """All time series of a run (SI units, float64), sample k at ``time[k]``.

    One array per series of the schema (``dynamics/series.py``; ``Result.ARRAYS`` lists their
    names), as an attribute of that name, indexed ``[sample, element, component]`` with the
    elements in the order of their family's name list (``joint_names``, ``mesh_names``, ...):
    ``res.mesh_normal`` is (n, meshes) [N], ``res.bearing_force`` (n, bearings, 3) [N]. The
    accessors ``joint``, ``mesh``, ``bearing``, ``body``, ``generator`` and ``rotor`` give one
    element's series by quantity (``ElementSeries``).

    Attributes:
        time: sample times [s], (n,).
        joint_names, mesh_names, bearing_names, body_names: element names from the model file.
        generator_names, rotor_names: joints carrying a generator law or a rotor (empty without).
        row_names: the compliant bearings' rows that are their springs, ``<joint>.<row>``
            (``Gearbox.row_names``; empty without).
        slice_names: the slices of the sliced compliant meshes, ``<mesh>.<index>`` (index 0 at
            face side I; ``MeshSetup.slice_names``; empty without): the columns of
            ``slice_line_load``. Their face positions are in the metadata
            (``slice_line_loads``).
        joint_kinds: each joint's kind, in ``joint_names`` order (``series.JointKind``):
            ``revolute``, or ``prismatic`` for a slide (a compliant bearing's or the support's),
            whose joint series are a length [m], speed [m/s], acceleration [m/s²] and force
            [N] (``Series.unit_for``); all revolute when not given (logs written before slides).
        pose_rows: the samples that have a link pose, increasing, (p,): every sample in a
            Result of ``simulate``, those at the log's pose rate in one read from a log. The
            body series (``body_position`` (p, bodies, 3), ``body_quaternion`` (p, bodies, 4)
            xyzw) have a row per pose.
        energy: energy ledger [J], term → (n,), the terms of ``series.ENERGY_TERMS``:
            ``kinetic``, ``work_applied``, ``work_drivers``, ``work_springs``,
            ``work_gravity``, ``work_constraints``, ``dissipated``, ``potential_spring``,
            ``numerical``.
        metadata: model name, file hash, dt, solver settings, loads and status.
        status: ``"completed"``, or why the run stopped early.
        statistics: min, max, mean, RMS and final value of every series over every simulated
            sample (``analysis/run_statistics.RunningStatistics``), when ``simulate`` folded them
            (by default when the Result does not keep every sample); None otherwise, and in a
            Result read from a log or cut from another (``take``, ``rows``).
        schema: the immutable schema of its arrays (``series.Schema``): the one of the run's
            start (``series.current()``), kept by every Result cut from it; its names are the
            Result's ``ARRAYS``.

    A series that a log does not hold (written before it was declared) reads as NaN.
    """

    #: Names of the array attributes, for writers, readers and comparisons: every series of
    #: the schema, read when iterated (those of ``POSE_ARRAYS`` have a row per pose). A
    #: Result's own are its schema's (``Result.schema``).
    ARRAYS: Collection[str] = series.Names()

    def __init__(
        self,
        *,
        joint_names: list[str],
        mesh_names: list[str],
        bearing_names: list[str],
        body_names: list[str],
        generator_names: list[str] | None = None,
        rotor_names: list[str] | None = None,
        row_names: list[str] | None = None,
        slice_names: list[str] | None = None,
        joint_kinds: list[str] | None = None,
        energy: dict[str, np.ndarray] | None = None,
        metadata: dict[str, Any] | None = None,
        status: str = "completed",
        statistics: FoldedStatistics | None = None,
        pose_rows: np.ndarray | None = None,
        schema: Schema | None = None,
        **arrays: np.ndarray,
    ):
        self.joint_names = joint_names
        self.mesh_names = mesh_names
        self.bearing_names = bearing_names
        self.body_names = body_names
        self.generator_names = list(generator_names or [])
        self.rotor_names = list(rotor_names or [])
        self.row_names = list(row_names or [])
        self.slice_names = list(slice_names or [])
        self.joint_kinds = (
            ["revolute"] * len(joint_names) if joint_kinds is None else list(joint_kinds)
        )
        if len(self.joint_kinds) != len(joint_names):
            raise ValueError(
                f"{len(self.joint_kinds)} joint kinds for {len(joint_names)} joints {joint_names}"
            )
        self.energy = {} if energy is None else energy
        self.metadata = {} if metadata is None else metadata
        self.status = status
        self.statistics = statistics
        self.schema = series.current() if schema is None else schema
        self.ARRAYS = self.schema.names
        unknown = set(arrays) - set(self.ARRAYS)
        if unknown:
            raise TypeError(
                f"Result has no series {sorted(unknown)}; declared: {list(self.ARRAYS)}"
            )
        self.time = np.asarray(arrays["time"])
        n = len(self.time)
        poses = arrays.get("body_position")
        self.pose_rows = (
            np.arange(len(poses) if poses is not None else n) if pose_rows is None else pose_rows
        )
        for s in self.schema.series:
            if s.name in arrays:
                setattr(self, s.name, arrays[s.name])
                continue
            elements = len(self.names(s.family)) if s.family != "run" else 1
            rows = len(self.pose_rows) if s.per == "pose" else n
            # a family without elements has nothing to record; otherwise the series was not
            # recorded (a log older than its declaration)
            fill = 0.0 if elements == 0 else np.nan
            setattr(self, s.name, np.full((rows, *s.shape(elements)), fill))
        if not len(self.pose_rows) == len(self.body_position) == len(self.body_quaternion):
            raise ValueError(
                f"{len(self.pose_rows)} pose rows for {len(self.body_position)} positions and "
                f"{len(self.body_quaternion)} quaternions"
            )

    def __getattr__(self, name: str) -> np.ndarray:
        # Only reached for a name that is not set: the arrays are plain attributes. Typed so
        # that the arrays of series declared at run time type-check as arrays.
        raise AttributeError(f"Result has no attribute {name!r}")

    def names(self, family: str) -> list[str]:
        """The element names of a family (``joint`` → ``joint_names``); ``run`` has none."""
        return getattr(self, series.NAMES_OF[family]) if family in series.NAMES_OF else []

    def kind_of(self, family: str, element: int) -> str:
        """The joint kind of a family's element number ``element``.

        ``joint_kinds`` for a joint; ``revolute`` (the declared units) for every other family.
        """
        return self.joint_kinds[element] if family == "joint" else "revolute"

    def unit(self, series: Series, element: int) -> str:
        """The SI unit of ``series`` on its family's element number ``element``.

        The declared one, but a joint series' on a prismatic joint (``Series.unit_for``).
        """
        return series.unit_for(self.kind_of(series.family, element))

    def arrays(self) -> dict[str, np.ndarray]:
        """Every series' array by name (``ARRAYS`` order)."""
        return {name: getattr(self, name) for name in self.ARRAYS}

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

    def element(self, family: str, name: str) -> ElementSeries:
        """Every series of one element of a family, by quantity.

        Raises:
            UnknownElement: no element of that family has this name.
        """
        i = self._index(family, self.names(family), name)
        values = {s.quantity: getattr(self, s.name)[:, i] for s in self.schema.of_family(family)}
        if family == "body":
            values["time"] = self.pose_time
        return ElementSeries(family, name, values, self.kind_of(family, i))

    def joint(self, name: str) -> ElementSeries:
        """A bearing's (joint's) angle [rad], speed [rad/s], acceleration [rad/s²], torques [N·m].

        A slide's (``joint_kinds`` prismatic): displacement [m], speed [m/s], acceleration
        [m/s²], force [N], under the same names.

        ``torque`` is the net torque from outside the gear train (applied + speed driver or lock
        + generator + rotor; 0 at a constant speed driven against a generator alone);
        the driver's own torque is ``torque`` + T_gen − T_rotor of the joint (docs/series.md).
        """
        return self.element("joint", name)

    def mesh(self, name: str) -> ElementSeries:
        """A gear mesh's forces [N], transmission error and deflection [m], contact state.

        Sign convention: docs/model_format.md; ``force_on_b`` and ``pitch_point`` (n, 3) in
        world.
        """
        return self.element("mesh", name)

    def bearing(self, name: str) -> ElementSeries:
        """A bearing's reaction on the child body at its centre (the joint origin).

        ``force`` [N] and ``moment`` [N·m] (n, 3) in world axes, ``force_local`` and
        ``moment_local`` in the joint frame: the spatial force Pinocchio's RNEA finds
        transmitted through the joint. Its component about the shaft axis is the net torque
        applied at that joint; the rolling bearing itself carries none.
        """
        return self.element("bearing", name)

    def body(self, name: str) -> ElementSeries:
        """A link's world pose at the samples that have one (``pose_rows``).

        ``position`` (p, 3) [m], ``quaternion`` (p, 4) xyzw, ``time`` (p,) [s].
        """
        return self.element("body", name)

    def generator(self, name: str) -> ElementSeries:
        """The generator law on a joint: ``torque`` T_gen [N·m], > 0 generating."""
        return self.element("generator", name)

    def rotor(self, name: str) -> ElementSeries:
        """The rotor on a joint: torque [N·m], power [W], λ, C_p and wind speed [m/s]."""
        return self.element("rotor", name)

    def row(self, name: str) -> ElementSeries:
        """A bearing row's load on the shaft (``<joint>.<row>``, ``row_names``).

        ``force`` (F_u, F_w, F_k) [N] and ``moment`` (M_u, M_w, 0) [N·m], (n, 3), along its
        bearing's radial axes u, w and axis k (``cpp/bearing_rows.hpp``).
        """
        return self.element("row", name)

    def slice_line_loads(self, mesh: str) -> tuple[np.ndarray, np.ndarray]:
        """The line load across the face of a sliced mesh: (z (N,) [m], w (n, N) [N/m]).

        z: each slice's centre from the face centre along gear A's axis, side I first (the
        run's metadata, ``meshes.<mesh>.slice_positions``); w: its line load on the loaded
        flank, ``slice_line_load``'s columns of the mesh (views).

        Raises:
            UnknownElement: no mesh of that name.
            InputError: the mesh was not cut into slices in this run.
        """
        self._index("mesh", self.mesh_names, mesh)
        prefix = f"{mesh}."
        columns = [
            i
            for i, name in enumerate(self.slice_names)
            if name.startswith(prefix) and name[len(prefix) :].isdigit()
        ]
        positions = self.metadata.get("meshes", {}).get(mesh, {}).get("slice_positions")
        if not columns or positions is None or len(positions) != len(columns):
            raise InputError(
                f'mesh "{mesh}" has no slices in this run (sliced meshes: '
                f"{sorted({n.rsplit('.', 1)[0] for n in self.slice_names})}); cut it into "
                'slices across the face: MeshCompliance(slices=8) or slices="auto"'
            )
        lo, hi = columns[0], columns[-1] + 1
        return np.asarray(positions, dtype=float), self.slice_line_load[:, lo:hi]

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

    def series_of(self, schema: Schema, *, poses: bool = True) -> Result:
        """The same samples holding only the series of ``schema`` (part of this one's; views).

        Without ``poses`` it keeps no link pose (no pose rows; a schema always has the pose
        series).
        """
        arrays = {name: getattr(self, name) for name in schema.names}
        pose_rows = self.pose_rows
        if not poses:
            pose_rows = pose_rows[:0]
            for name in POSE_ARRAYS:
                arrays[name] = arrays[name][:0]
        kept = self.holding(arrays, self.energy, pose_rows, schema=schema)
        kept.metadata, kept.statistics = self.metadata, self.statistics  # the same run's
        return kept

    def holding(
        self,
        arrays: dict[str, Any],
        energy: dict[str, np.ndarray],
        pose_rows: np.ndarray,
        *,
        schema: Schema | None = None,
    ) -> Result:
        """A Result with these names, metadata (a copy) and status, holding other samples.

        ``arrays``: every name of ``ARRAYS`` (of ``schema``, default this one's) → its array.
        """
        return Result(
            joint_names=self.joint_names,
            mesh_names=self.mesh_names,
            bearing_names=self.bearing_names,
            body_names=self.body_names,
            generator_names=self.generator_names,
            rotor_names=self.rotor_names,
            row_names=self.row_names,
            slice_names=self.slice_names,
            joint_kinds=self.joint_kinds,
            energy=energy,
            metadata=dict(self.metadata),
            status=self.status,
            pose_rows=pose_rows,
            schema=self.schema if schema is None else schema,
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
    arrays = {name: np.concatenate([getattr(p, name) for p in parts]) for name in parts[0].ARRAYS}
    energy = {k: np.concatenate([p.energy[k] for p in parts]) for k in first.energy}
    starts = np.cumsum([0] + [len(p) for p in parts[:-1]])
    pose_rows = np.concatenate([p.pose_rows + at for p, at in zip(parts, starts, strict=True)])
    return first.holding(arrays, energy, pose_rows)
