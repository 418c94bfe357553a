"""The time-series panels of a log, shared by ``pinwind replay`` (Rerun) and ``pinwind plot``.

A ``Panel`` is one plot: a title that gives the unit and says whether a quantity is absolute or
relative, a group (the replay's tab), and its series, already in the plotted unit and coloured.
Colours are fixed per element: joint and bearing series take the colour of the body they move
(the same colour as the body in the 3D view), mesh series one colour per mesh, the same in every
mesh panel; within a panel no two series share a colour.

``y_range`` is the axis rule of every plot: the range never shrinks below a floor relative to the
values, so that rounding noise on constant data is not magnified to full height.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any, Literal

import numpy as np

from pinwind.dynamics import series
from pinwind.dynamics.result import Result
from pinwind.units import to_display

#: Smallest y span of a plot, as a fraction of the largest |value| shown (or of the reference).
RANGE_FLOOR = 0.05
#: Margin added below and above the data, as a fraction of the span.
RANGE_MARGIN = 0.08
#: Size of a plot in the replay [px] and of its legend, to keep the legend off the data: an entry
#: measured 23 px high in the web viewer at 100 % zoom (19 px let the top line touch it); its
#: width is estimated from the longest name (px per character, plus the colour swatch and
#: padding) and the plot width from the default layout (plots take 2/5 of a 1600 px window).
PLOT_HEIGHT_PX = 300.0
PLOT_WIDTH_PX = 600.0
LEGEND_ENTRY_PX = 23.0
LEGEND_CHAR_PX = 7.5
LEGEND_PAD_PX = 40.0
#: Most of the plot height given to legend room above or below the data; a legend that needs
#: more in every corner overlaps some data rather than squeezing them flat.
LEGEND_ROOM_CAP = 0.35
#: A legend corner: one of Rerun's ``Corner2D`` names.
LegendCorner = Literal["LeftTop", "RightTop", "LeftBottom", "RightBottom"]
#: Corners tried for the legend, in order of preference (Rerun's ``Corner2D`` names).
LEGEND_CORNERS: tuple[LegendCorner, ...] = ("LeftTop", "RightTop", "LeftBottom", "RightBottom")

#: Distinct colours (RGB 0-255) for bodies and meshes, readable on light and dark backgrounds
#: (Tableau 10 without its red and olive, kept for the force arrows, then darker variants).
PALETTE: tuple[tuple[int, int, int], ...] = (
    (31, 119, 180),
    (255, 127, 14),
    (44, 160, 44),
    (148, 103, 189),
    (140, 86, 75),
    (227, 119, 194),
    (127, 127, 127),
    (23, 190, 207),
    (120, 60, 200),
    (0, 128, 128),
    (200, 120, 40),
    (90, 90, 160),
    (160, 80, 120),
    (70, 140, 90),
)
#: Colour of each arrow family in the 3D view.
MESH_ARROW_COLOR = (214, 39, 40)
BEARING_ARROW_COLOR = (188, 189, 34)


def color(index: int) -> tuple[int, int, int]:
    """The ``index``-th palette colour (cycling past the end)."""
    return PALETTE[index % len(PALETTE)]


def body_colors(body_names: Sequence[str], root: str = "") -> dict[str, tuple[int, int, int]]:
    """One distinct colour per body, the root (housing) left out."""
    moving = [name for name in body_names if name != root]
    return {name: color(i) for i, name in enumerate(moving)}


def y_range(
    values: Sequence[np.ndarray] | np.ndarray,
    *,
    reference: float | None = None,
    floor: float = RANGE_FLOOR,
    margin: float = RANGE_MARGIN,
) -> tuple[float, float]:
    """Y-axis limits that show the data without magnifying rounding.

    The span is max − min of the finite values, but at least ``floor`` × the largest |value|
    (or × ``reference`` when given, e.g. the size of the quantities a residual is made of),
    and at least 1e-12 × that and 1e-300 so that all-zero data get the range ±0.5 around zero.
    The data are centred in a span widened by ``margin`` on each side.

    Args:
        values: one array, or several series.
        reference: magnitude the floor is relative to [same unit as the values].
        floor: smallest span as a fraction of the magnitude.
        margin: margin on each side as a fraction of the span.

    Returns:
        (low, high), low < high.
    """
    if isinstance(values, np.ndarray):
        arrays = [values.astype(float).ravel()]
    else:
        arrays = [np.asarray(v, dtype=float).ravel() for v in values]
    data = np.concatenate(arrays) if arrays else np.zeros(0)
    data = data[np.isfinite(data)]
    if data.size == 0:
        return -0.5, 0.5
    low, high = float(data.min()), float(data.max())
    magnitude = max(abs(low), abs(high))
    if reference is not None and math.isfinite(reference):
        magnitude = max(magnitude, abs(reference))
    span = high - low
    least = floor * magnitude
    if magnitude == 0.0:
        least = 1.0
    if span < least:
        mid = 0.5 * (low + high)
        low, high = mid - 0.5 * least, mid + 0.5 * least
        span = least
    return low - margin * span, high + margin * span


@dataclass(frozen=True)
class Series:
    """One line of a panel: its name, its values in the panel's unit, its colour (RGB 0-255)."""

    name: str
    values: np.ndarray
    color: tuple[int, int, int]


@dataclass(frozen=True)
class Panel:
    """One plot of a log.

    Attributes:
        key: entity folder in the replay (``plots/<key>/<series>``) and figure file stem.
        group: the replay tab and figure it belongs to.
        title: what is plotted, with its unit, frame and whether absolute or relative.
        unit: the unit of the values, for axis labels.
        series: the lines.
        reference: magnitude the range floor is relative to, when not the values themselves.
        drop_zero: series that are zero at every sample are left out (rigid meshes in the
            compliant deflection panel); ``panels`` applies it unless told to keep them.
    """

    key: str
    group: str
    title: str
    unit: str
    series: list[Series]
    reference: float | None = None
    notes: list[str] = field(default_factory=list)
    drop_zero: bool = False

    def y_range(self) -> tuple[float, float]:
        """The axis range of this panel (``y_range`` over its series)."""
        return y_range([s.values for s in self.series], reference=self.reference)


def legend_layout(
    panel: Panel,
    *,
    plot_height_px: float = PLOT_HEIGHT_PX,
    plot_width_px: float = PLOT_WIDTH_PX,
    cap: float = LEGEND_ROOM_CAP,
) -> tuple[LegendCorner, tuple[float, float]]:
    """The corner of a panel's legend and the y range that keeps the data off it.

    The legend is a box (entries + 0.5) × ``LEGEND_ENTRY_PX`` high and as wide as its longest
    name (``LEGEND_CHAR_PX`` per character + ``LEGEND_PAD_PX``). In each corner it covers the
    first (left) or last (right) samples of every series over its share of the width, the
    series' values taken as evenly spaced in time (the whole run, or the min and max of equal
    time spans as the replay sends them; one more sample is counted for the rounding). The range
    ``panel.y_range()`` is widened on the legend's side until those samples stay a margin off the
    box; the corner that needs the least widening is taken (ties in ``LEGEND_CORNERS`` order),
    and the widening is at most ``cap`` of the plot height (the legend then overlaps some data).

    Args:
        panel: the plot, its series' values in time order.
        plot_height_px, plot_width_px: the plot's size [px].
        cap: largest share of the plot height given to legend room.

    Returns:
        (corner, (low, high)): a ``LEGEND_CORNERS`` name and the y-axis limits.
    """
    low, high = panel.y_range()
    entries = len(panel.series)
    height = min((entries + 0.5) * LEGEND_ENTRY_PX / plot_height_px, 0.95)
    longest = max((len(s.name) for s in panel.series), default=0)
    width = min((longest * LEGEND_CHAR_PX + LEGEND_PAD_PX) / plot_width_px, 1.0)
    # The data span inside the margins of y_range: low + m·S = data low, S (1 + 2m) = range.
    gap = RANGE_MARGIN * (high - low) / (1.0 + 2.0 * RANGE_MARGIN)
    most = cap / (1.0 - cap) * (high - low)  # widening that takes ``cap`` of the new range

    def covered(right: bool) -> np.ndarray:
        parts = []
        for s in panel.series:
            values = np.asarray(s.values, dtype=float)
            count = min(len(values), math.ceil(width * len(values)) + 1)
            part = values[len(values) - count :] if right else values[:count]
            parts.append(part[np.isfinite(part)])
        return np.concatenate(parts) if parts else np.zeros(0)

    candidates = []
    for corner in LEGEND_CORNERS:
        data = covered(corner.startswith("Right"))
        if corner.endswith("Top"):
            # The box spans the top ``height`` of (low, top): top − h (top − low) ≥ data max + gap.
            edge = float(data.max()) + gap if data.size else -math.inf
            top = max(high, (edge - height * low) / (1.0 - height))
            widening, limits = top - high, (low, high + min(top - high, most))
        else:
            edge = float(data.min()) - gap if data.size else math.inf
            bottom = min(low, (edge - height * high) / (1.0 - height))
            widening, limits = low - bottom, (low - min(low - bottom, most), high)
        candidates.append((widening, corner, limits))
    _, corner, limits = min(candidates, key=lambda c: c[0])  # the first of equal ones
    return corner, limits


#: Tabs of the replay and figures of ``pinwind plot``, in order.
GROUPS = (
    "speeds",
    "torques and power",
    "rotor",
    "mesh forces",
    "force components",
    "mesh deflection",
    "bearings",
    "load sharing",
    "energy",
)


def absolute_speeds(result: Result, joints: dict[str, dict[str, Any]]) -> dict[str, np.ndarray]:
    """Each revolute joint's child body speed about the joint axis in the world (absolute) [rad/s].

    ω_child = ω_parent + θ̇ · a, a the joint axis in world (from the child's pose), summed down
    the tree from the root; a planet's absolute speed is its speed on the carrier plus the
    carrier's. Each sample takes the axes from its latest pose (the first pose for samples
    before it): exact while the joint axes keep their direction between poses, as they do in a
    gearbox whose axes are fixed in the housing or parallel to the axes they turn about. No
    speeds without poses.

    Args:
        result: the run (speeds and body poses).
        joints: joint name → ``{"parent", "child", "axis"}`` (axis in the child frame).
    """
    n = len(result)
    omega: dict[str, np.ndarray] = {}
    if not len(result.pose_rows):
        return {}
    pose = np.maximum(np.searchsorted(result.pose_rows, np.arange(n), side="right") - 1, 0)
    out: dict[str, np.ndarray] = {}
    bodies = {name: i for i, name in enumerate(result.body_names)}

    def rotate(q: np.ndarray, v: np.ndarray) -> np.ndarray:
        xyz, w = q[:, :3], q[:, 3:4]
        t = 2.0 * np.cross(xyz, np.broadcast_to(v, xyz.shape))
        return v + w * t + np.cross(xyz, t)

    pending = {j: spec for j, spec in joints.items() if spec.get("child") in bodies}
    while pending:
        progressed = False
        for name, spec in list(pending.items()):
            parent = spec.get("parent", "")
            parent_omega = omega.get(parent)
            if parent_omega is None and any(s["child"] == parent for s in pending.values()):
                continue  # its parent is not done yet
            if parent_omega is None:
                parent_omega = np.zeros((n, 3))
            axis = spec.get("axis")
            axis = np.asarray((0.0, 0.0, 1.0) if axis is None else axis, dtype=float)
            axis = axis / np.linalg.norm(axis)
            axis_in_world = rotate(result.body_quaternion[pose, bodies[spec["child"]]], axis)
            j = result.joint_names.index(name) if name in result.joint_names else -1
            if j >= 0 and result.joint_kinds[j] == "revolute":
                speed = result.speed[:, j]
                child_omega = parent_omega + speed[:, None] * axis_in_world
                out[name] = np.einsum("ij,ij->i", child_omega, axis_in_world)
            else:
                child_omega = parent_omega  # a fixed joint, or a slide: it adds no rotation
            omega[spec["child"]] = child_omega
            del pending[name]
            progressed = True
        if not progressed:
            break
    return out


def energy_residual(
    energy: dict[str, np.ndarray], start: dict[str, float] | None = None
) -> np.ndarray:
    """Energy balance residual [J], zero for an exact ledger (dynamics/simulate.py).

    Δkinetic + ΔU_spring − (W_applied + W_drivers + W_gravity + W_constraints + W_parametric
    − dissipated
    − numerical), the changes from the first sample, or from ``start`` (each term's value at the
    first sample of the run [J], for a block of a longer run).
    """

    def term(name: str) -> np.ndarray:
        values = energy.get(name)
        return np.zeros_like(energy["kinetic"]) if values is None else values

    def first(name: str):
        if start is not None:
            return start.get(name, 0.0)
        return term(name)[:1]

    stored = term("kinetic") - first("kinetic") + term("potential_spring")
    stored = stored - first("potential_spring")
    supplied = (
        term("work_applied")
        + term("work_drivers")
        + term("work_gravity")
        + term("work_constraints")
        + term("work_parametric")
        - term("dissipated")
        - term("friction_loss")
        - term("numerical")
    )
    return stored - supplied


def panels(
    result: Result,
    model: dict[str, Any],
    *,
    joints: dict[str, dict[str, Any]] | None = None,
    gearbox=None,
    energy_start: dict[str, float] | None = None,
    keep_zero: bool = False,
) -> list[Panel]:
    """Every panel of a run, in ``GROUPS`` order.

    Given a block of a run (``LogReader.blocks``), every block gives the same panels and series
    when ``keep_zero`` is set; the values of a sample do not depend on the other samples, except
    the load shares, whose "loaded" threshold is relative to the block's largest load.

    Args:
        result: the run (``read_log`` or ``simulate``), or a block of it.
        model: the log's ``pinwind.model`` record (root link, bearings).
        joints: joint name → parent, child and axis (for absolute speeds); default: from the
            ``bearings`` of ``model``, axes along z.
        gearbox: the model, for load sharing (left out when None).
        energy_start: each energy term at the first sample of the run [J] (the balance residual
            counts changes from there); default: the first sample of ``result``.
        keep_zero: keep the series of ``drop_zero`` panels that are zero at every sample of
            ``result`` (a later block may not be).
    """
    res = result
    root = model.get("root_link", "")
    colors = body_colors(res.body_names, root)
    bearings = model.get("bearings", {})
    if joints is None:
        joints = {name: {**spec, "axis": (0.0, 0.0, 1.0)} for name, spec in bearings.items()}

    def joint_color(name: str, i: int) -> tuple[int, int, int]:
        child = (joints.get(name) or bearings.get(name) or {}).get("child", "")
        return colors.get(child, color(i))

    joint_index = {name: i for i, name in enumerate(res.joint_names)}

    def element_color(family: str, name: str, i: int) -> tuple[int, int, int]:
        # Joint, bearing, generator and rotor series take the colour of the body they turn;
        # meshes one colour each.
        if family == "mesh":
            return color(i)
        return joint_color(name, joint_index.get(name, i))

    def lines(s: series.Series, values: np.ndarray) -> list[Series]:
        if s.family == "run":
            return [Series(s.quantity, values, color(0))]
        names = res.names(s.family)
        # a panel's unit is the series' declared one (rpm, kN·m): no slide (m/s, N) in it
        return [
            Series(name, values[:, i], element_color(s.family, name, i))
            for i, name in enumerate(names)
            if res.kind_of(s.family, i) == "revolute"
        ]

    def plotted(s: series.Series) -> np.ndarray:
        values = getattr(res, s.name)
        if s.plot is None:
            return values
        if s.plot.magnitude:
            values = np.linalg.norm(values, axis=-1)
        return to_display(values, s.plot.unit)

    out: list[Panel] = []
    # Within a group, vectors in world axes after the loads about each element's own axis: a
    # bearing's radial force, tilting moment and shaft torque before its world |F| (its world
    # |M|, mostly the shaft's torque, is not a bearing load and not drawn).
    for s in sorted(series.schema(), key=lambda s: s.frame == "world"):
        if s.plot is None or s.per == "pose" or (s.family != "run" and not res.names(s.family)):
            continue
        p = s.plot
        reference = None
        if p.relative_to is not None:
            reference = float(np.max(np.abs(plotted(series.get(p.relative_to))), initial=0.0))
        out.append(
            Panel(p.key, p.group, p.title, p.unit, lines(s, plotted(s)), reference, [], p.drop_zero)
        )
        if s.name == "speed":
            absolute = absolute_speeds(res, joints)
            if absolute:
                out.append(
                    Panel(
                        "body_speed",
                        "speeds",
                        "body speeds, absolute (about the own axis, in the world) [rpm]",
                        "rpm",
                        [
                            Series(name, to_display(absolute[name], "rpm"), joint_color(name, i))
                            for i, name in enumerate(res.joint_names)
                            if name in absolute
                        ],
                    )
                )
        if s.name == "torque":
            out.append(
                Panel(
                    "power",
                    "torques and power",
                    "joint power T·ω, ω relative to the parent [kW]",
                    "kW",
                    lines(s, res.torque * res.speed / 1e3),
                )
            )
    if gearbox is not None and res.mesh_names:
        from pinwind.analysis.load_sharing import load_sharing

        shares, factors = [], []
        for k, sharing in enumerate(load_sharing(res, gearbox)):
            for name, values in zip(sharing.meshes, sharing.share.T, strict=True):
                shares.append(Series(name, values, color(res.mesh_names.index(name))))
            factors.append(Series(sharing.gear, sharing.factor, color(k)))
        if shares:
            out += [
                Panel(
                    "load_sharing",
                    "load sharing",
                    "planet load share F_n / mean F_n of the meshes of one gear [-]",
                    "-",
                    shares,
                    reference=1.0,
                ),
                Panel(
                    "load_factor",
                    "load sharing",
                    "load factor K_γ = max / mean planet load per central gear, IEC 61400-4 [-]",
                    "-",
                    factors,
                    reference=1.0,
                ),
            ]
    if res.energy and "kinetic" in res.energy and len(res.energy["kinetic"]) == len(res):
        terms = [Series(k, v / 1e3, color(i)) for i, (k, v) in enumerate(res.energy.items())]
        largest = max(float(np.max(np.abs(s.values), initial=0.0)) for s in terms)
        out += [
            Panel(
                "energy",
                "energy",
                # kinetic and potential_spring are the energies held; the others add up from 0
                "energy ledger: kinetic and spring energy, works and losses since t = 0 [kJ]",
                "kJ",
                terms,
            ),
            Panel(
                "energy_balance",
                "energy",
                "energy balance residual Δ(kinetic + spring) − net work [kJ]",
                "kJ",
                [Series("residual", energy_residual(res.energy, energy_start) / 1e3, color(0))],
                reference=largest,
            ),
        ]
    if not keep_zero:
        out = [without_zero_series(p) for p in out]
        out = [p for p in out if p.series or not p.drop_zero]
    return sorted(out, key=lambda p: GROUPS.index(p.group))


def without_zero_series(panel: Panel, zero: Sequence[bool] | None = None) -> Panel:
    """The panel without the series that are zero at every sample, if it is a ``drop_zero`` one.

    ``zero`` says per series whether it is all zero (default: from the values).
    """
    if not panel.drop_zero:
        return panel
    if zero is None:
        zero = [not np.any(s.values) for s in panel.series]
    kept = [s for s, z in zip(panel.series, zero, strict=True) if not z]
    return replace(panel, series=kept)


def model_of_log(log) -> tuple[Any, dict[str, dict[str, Any]] | None]:
    """(Gearbox rebuilt from the model text a log carries, its joints), or (None, None).

    The joints map name → type, parent, child and axis (child frame). A log whose model no
    longer loads (a model written by another pinwind version) gives (None, None): the plots that
    need it (load sharing, absolute speeds) are left out.
    """
    from pinwind.errors import PinwindError
    from pinwind.model.gearbox import loads

    text = log.model_text
    if not text:
        return None, None
    try:
        gearbox = loads(text, path=str(log.path))
    except PinwindError:
        return None, None
    joints = getattr(getattr(gearbox, "source", None), "joints", None)
    return gearbox, joints


def log_panels(log) -> list[Panel]:
    """Every panel of a ``LogFile`` (``open_log``), the model rebuilt from the log itself."""
    gearbox, joints = model_of_log(log)
    return panels(log.result, log.model, joints=joints, gearbox=gearbox)
