"""The 3D scene of ``pinwind replay``: the whole machine, its motion and its forces.

Drawn from the log alone (the ``pinwind.model`` record and the model text it carries, read by
the model's own reader, ``model/urdf.read_model_file``):

- every gear as a solid with its teeth (``gear_mesh``), phased so that meshing teeth interlock
  at the pitch point in the first frame (``tooth_phases``), with a dark **angle mark** from the
  axis to the tip of tooth 0 on both faces, so that turning is visible; the carrier gets a mark
  too; in a machine with a planetary stage the parallel stages' gears are translucent
  (``parallel_stage_gears``), so that the planetary stage behind them shows;
- the model's own ``<visual>`` shapes that are not gears (carrier cheeks as wireframes so that
  they do not hide the planets, pins, shafts), a shaft through the gears of each shaft link,
  **bearings** as two rings (inner and outer race) at both ends of each turning body, and the
  housing as a wireframe box around the machine;
- one label per body (``gearbox/labels``), placed beside the body on the face toward the camera,
  coaxial bodies at different angles so that their names do not stack;
- force **arrows** drawn on the face of the gear (mesh forces, at the pitch point) or of the
  body (bearing forces, on the axis) toward the camera, outside the solids, one scale for every
  arrow, the force in newtons in each arrow's label (shown on hover; a bearing's gives its
  radial and axial force and tilting moment about its axis, and apart the torque its shaft
  transmits), each family its own entity
  (``gearbox/mesh_forces``, ``gearbox/bearing_forces``) so that it can be switched off;
- the default camera (``camera``), oblique from the side opposite the parallel stages.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from pinwind.errors import ModelError
from pinwind.io.panels import BEARING_ARROW_COLOR, MESH_ARROW_COLOR, body_colors
from pinwind.model.builders.gear_bodies import RING_RIM_MODULES
from pinwind.model.phasing import interlocking_phases, mesh_point_through
from pinwind.model.urdf import ModelFile, VisualSpec, read_model_file

#: Largest arrow of the run, as a fraction of the largest pitch radius.
ARROW_FRACTION = 0.5
#: Direction from the machine's centre to the default camera (world, y up).
CAMERA_DIRECTION = np.array([0.55, 0.45, -1.0])
MARK_COLOR = (25, 25, 25)
LABEL_COLOR = (30, 100, 255)
HOUSING_COLOR = (150, 150, 150)
#: Opacity (0–255) of the parallel stages' gears in a machine with a planetary stage: the first
#: wheel of a drivetrain is as wide as the planetary stage and sits in front of it.
PARALLEL_STAGE_ALPHA = 90


# --- geometry helpers ---------------------------------------------------------------------------


def rotation_from_z(axis) -> np.ndarray:
    """The rotation matrix that turns the z axis onto ``axis`` (shortest arc)."""
    a = np.asarray(axis, dtype=float)
    a = a / np.linalg.norm(a)
    z = np.array([0.0, 0.0, 1.0])
    v = np.cross(z, a)
    s, c = np.linalg.norm(v), float(z @ a)
    if s < 1e-12:
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
    k = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]]) / s
    angle = math.atan2(s, c)
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * (k @ k)


def quaternion_matrix(q) -> np.ndarray:
    """Rotation matrices of quaternions (x, y, z, w), shape (..., 3, 3)."""
    q = np.asarray(q, dtype=float)
    x, y, z, w = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    return np.stack(
        [
            np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)], -1),
            np.stack([2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)], -1),
            np.stack([2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)], -1),
        ],
        -2,
    )


def _circle(radius: float, z: float, points: int = 48) -> np.ndarray:
    a = np.linspace(0.0, 2.0 * math.pi, points + 1)
    return np.stack([radius * np.cos(a), radius * np.sin(a), np.full_like(a, z)], axis=1)


# --- gears: frames, tooth phases, solids --------------------------------------------------------


def gear_pose(gear: dict, result, k: int, bodies: dict[str, int]) -> tuple[np.ndarray, np.ndarray]:
    """(centre, rotation) of a gear's frame (z = its axis) in world at sample ``k``.

    ``result`` has a pose at every sample (``Result.posed``).
    """
    i = bodies[gear["link"]]
    rotation = quaternion_matrix(result.body_quaternion[k, i])
    centre = result.body_position[k, i] + rotation @ np.asarray(gear["centre_in_link"])
    return centre, rotation @ rotation_from_z(gear["axis_in_link"])


def pitch_fraction(gear: dict, centre, rotation, point, phase: float) -> float:
    """Where ``point`` falls in the tooth pitch of a gear, in [0, 1).

    0 at a tooth centre, 0.5 at a gap centre; teeth are centred at ``phase`` + j·2π/z about the
    gear's axis (z of ``rotation``).
    """
    v = np.asarray(rotation).T @ (np.asarray(point) - np.asarray(centre))
    theta = math.atan2(v[1], v[0])
    return ((theta - phase) / (2.0 * math.pi / gear["teeth"])) % 1.0


def _pitch_point(mesh: dict, centre_a, centre_b, internal_b: bool) -> np.ndarray:
    direction = np.asarray(centre_b) - np.asarray(centre_a)
    direction = direction / np.linalg.norm(direction)
    if internal_b:
        direction = -direction
    return np.asarray(centre_a) + mesh["working_radius_a"] * direction


def tooth_phases(model: dict, result) -> dict[str, float]:
    """Tooth-0 angle of every gear in its own frame [rad], so that meshing teeth interlock.

    The interlock is the model's (``pinwind.model.phasing.interlocking_phases``, the rule the
    physics phases its teeth with): gears are visited mesh by mesh from the first gear of each
    train, and for every mesh A-B reached from a phased gear, B's pitch fraction at the pitch
    point is 0.5 + s·(A's), s = +1 when both gears' angles grow in the same direction along the
    common tangent there (internal mesh), −1 otherwise (external mesh). What differs is where
    the drawing starts, because it works from the log alone: angles are in the drawing frame of
    each gear (``gear_pose``) at the first sample, and the first gear of each train puts a tooth
    centre on its first mesh's pitch point, so the drawing does not show the physics' tooth 0.
    """
    gears: dict = model.get("gears", {})
    meshes: dict = model.get("meshes", {})
    bodies = {name: i for i, name in enumerate(result.body_names)}
    if not len(result) or not gears:
        return {name: 0.0 for name in gears}
    pose = {
        name: gear_pose(g, result, 0, bodies) for name, g in gears.items() if g["link"] in bodies
    }

    def point_of(name: str, mesh: dict) -> np.ndarray:
        if name in result.mesh_names and result.pitch_point.shape[0]:
            return result.pitch_point[0, result.mesh_names.index(name)]
        a, b = mesh["gear_a"], mesh["gear_b"]
        return _pitch_point(mesh, pose[a][0], pose[b][0], gears[b]["internal"])

    z = np.array([0.0, 0.0, 1.0])  # a gear's axis in its drawing frame (``gear_pose``)
    points = []
    for name, mesh in meshes.items():
        a, b = mesh["gear_a"], mesh["gear_b"]
        if a not in pose or b not in pose:
            continue
        (ca, ra), (cb, rb) = pose[a], pose[b]
        points.append(
            mesh_point_through(
                a,
                b,
                point_of(name, mesh),
                centre_a=ca,
                centre_b=cb,
                world_from_a=ra,
                world_from_b=rb,
                axis_a=z,
                axis_b=z,
            )  # fmt: skip
        )
    teeth = {name: g["teeth"] for name, g in gears.items()}
    phases = interlocking_phases(points, teeth)
    return {name: phases.get(name, 0.0) for name in gears}


def tooth_outline(gear: dict, z: float, phase: float = 0.0) -> np.ndarray:
    """Closed outline of a gear face in the gear frame (axis z), straight-flanked teeth [m].

    Addendum m and dedendum 1.25 m about the pitch radius (tips inward for an internal gear);
    the tooth is 0.6 of the pitch at its root line and 0.25 at its tip, tooth j centred at
    ``phase`` + j·2π/z.
    """
    teeth, module, radius = gear["teeth"], gear["module"], gear["pitch_radius"]
    sign = -1.0 if gear["internal"] else 1.0
    tip, root = radius + sign * module, radius - sign * 1.25 * module
    step = 2.0 * math.pi / teeth
    offsets = np.array([-0.3, -0.125, 0.125, 0.3])
    radii = np.array([root, tip, tip, root])
    angles = (phase + step * (np.arange(teeth)[:, None] + offsets[None, :])).ravel()
    r = np.tile(radii, teeth)
    angles, r = np.append(angles, angles[0]), np.append(r, r[0])
    return np.stack([r * np.cos(angles), r * np.sin(angles), np.full_like(angles, z)], axis=1)


def outer_radius(gear: dict) -> float:
    """Radius of the gear's solid: the tip circle, or the rim of an internal gear [m]."""
    if gear["internal"]:
        return gear["pitch_radius"] + RING_RIM_MODULES * gear["module"]
    return gear["pitch_radius"] + gear["module"]


def parallel_stage_gears(model: dict) -> set[str]:
    """The gears of the parallel stages of a machine that also has a planetary stage.

    The meshes join gears into stages (gears on one shaft in different stages stay apart); a
    stage with an internal gear (a ring) is planetary. Empty when no stage is planetary: a
    parallel gearbox alone hides nothing behind it.
    """
    gears: dict = model.get("gears", {})
    stage = {name: name for name in gears}

    def find(name: str) -> str:
        while stage[name] != name:
            name = stage[name]
        return name

    for mesh in model.get("meshes", {}).values():
        stage[find(mesh["gear_a"])] = find(mesh["gear_b"])
    planetary = {find(name) for name, gear in gears.items() if gear["internal"]}
    if not planetary:
        return set()
    return {name for name in gears if find(name) not in planetary}


def gear_mesh(gear: dict, phase: float = 0.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A triangle mesh of the gear body with its teeth: (vertices, triangles, normals).

    An external gear is its tooth outline extruded over the face width (caps fanned from the
    axis); an internal gear the solid between its tooth outline and a rim 3.5 modules outside
    the pitch circle. Faces have their own vertices, so the shading is flat.
    """
    half = 0.5 * gear["face_width"]
    ring = tooth_outline(gear, 0.0, phase)[:-1, :2]
    m = len(ring)
    verts: list[np.ndarray] = []
    norms: list[np.ndarray] = []

    def quad(p0, p1, p2, p3, normal) -> None:
        verts.extend([p0, p1, p2, p0, p2, p3])
        norms.extend([normal] * 6)

    nxt = np.roll(np.arange(m), -1)
    if gear["internal"]:
        rim = outer_radius(gear)
        angles = np.arctan2(ring[:, 1], ring[:, 0])
        outer = np.stack([rim * np.cos(angles), rim * np.sin(angles)], axis=1)
    for j in range(m):
        a, b = ring[j], ring[nxt[j]]
        edge = b - a
        side_normal = np.array([edge[1], -edge[0], 0.0]) / max(np.linalg.norm(edge), 1e-12)
        if gear["internal"]:
            side_normal = -side_normal
        quad(np.r_[a, -half], np.r_[b, -half], np.r_[b, half], np.r_[a, half], side_normal)
        for z, nz in ((half, 1.0), (-half, -1.0)):
            if gear["internal"]:
                oa, ob = outer[j], outer[nxt[j]]
                quad(np.r_[a, z], np.r_[b, z], np.r_[ob, z], np.r_[oa, z], np.array([0, 0, nz]))
            else:
                verts.extend([np.array([0.0, 0.0, z]), np.r_[a, z], np.r_[b, z]])
                norms.extend([np.array([0.0, 0.0, nz])] * 3)
        if gear["internal"]:
            oa, ob = outer[j], outer[nxt[j]]
            normal = np.array([oa[0] + ob[0], oa[1] + ob[1], 0.0])
            normal /= max(np.linalg.norm(normal), 1e-12)
            quad(np.r_[oa, -half], np.r_[ob, -half], np.r_[ob, half], np.r_[oa, half], normal)
    vertices = np.array(verts)
    normals = np.array(norms, dtype=float)
    triangles = np.arange(len(vertices)).reshape(-1, 3)
    # Triangles wound toward their normals (Rerun draws both sides; the order is for tools).
    return vertices, triangles, normals


# --- the scene ----------------------------------------------------------------------------------


@dataclass
class Scene:
    """What the scene computed that the blueprint and the legend need."""

    camera_position: np.ndarray
    camera_target: np.ndarray
    arrow_scale: float = 1.0
    notes: list[str] = field(default_factory=list)


def _model_file(text: str, problem: str = "") -> tuple[ModelFile | None, str]:
    """The log's model text read by the model's reader, or (None, why it could not be).

    The text was loaded when the run was made; a log of an older pinwind may hold one that
    today's reader refuses, and the replay then draws without the model's shapes. ``problem``:
    why the log gives no text (a damaged attachment).
    """
    if not text:
        return None, problem or "the log holds no model text"
    try:
        return read_model_file("<model of the log>", text), ""
    except ModelError as err:
        return None, str(err)


def _extent(model: dict, visuals: list[VisualSpec], link: str) -> tuple[float, float, float]:
    """(z min, z max, outer radius) of what a link carries, along z of the link frame."""
    zs, radii = [], []
    for g in model.get("gears", {}).values():
        if g["link"] == link:
            c = g["centre_in_link"][2]
            zs += [c - 0.5 * g["face_width"], c + 0.5 * g["face_width"]]
            radii.append(outer_radius(g))
    for v in visuals:
        if v.link == link and v.kind == "cylinder":
            zs += [v.xyz[2] - 0.5 * v.size[1], v.xyz[2] + 0.5 * v.size[1]]
            radii.append(v.size[0])
    if not zs:
        return -0.05, 0.05, 0.05
    return min(zs), max(zs), max(radii)


def _shaft_radius(model: dict, visuals: list[VisualSpec], link: str) -> float:
    roots = [
        g["pitch_radius"] - 1.25 * g["module"]
        for g in model.get("gears", {}).values()
        if g["link"] == link and not g["internal"]
    ]
    if roots:
        return 0.35 * min(roots)
    return 0.15 * _extent(model, visuals, link)[2]


def _is_gear_visual(v: VisualSpec, model: dict) -> bool:
    for g in model.get("gears", {}).values():
        if (
            g["link"] == v.link
            and v.kind == "cylinder"
            and abs(v.size[0] - g["pitch_radius"]) < 0.02 * g["pitch_radius"]
            and abs(v.xyz[2] - g["centre_in_link"][2]) < 0.02 * g["face_width"] + 1e-9
        ):
            return True
    return False


def camera(model: dict, result, visuals: list[VisualSpec]) -> tuple[np.ndarray, np.ndarray, float]:
    """(eye position, look target, radius) framing every gear and visual of the first sample."""
    points = []
    bodies = {name: i for i, name in enumerate(result.body_names)}
    for g in model.get("gears", {}).values():
        if g["link"] in bodies and len(result):
            centre, rot = gear_pose(g, result, 0, bodies)
            r, h = outer_radius(g), 0.5 * g["face_width"]
            for sx, sy, sz in np.ndindex(2, 2, 2):
                points.append(centre + rot @ [r * (2 * sx - 1), r * (2 * sy - 1), h * (2 * sz - 1)])
    for v in visuals:
        if v.link in bodies and len(result) and v.kind == "cylinder":
            i = bodies[v.link]
            rot = quaternion_matrix(result.body_quaternion[0, i])
            centre = result.body_position[0, i] + rot @ v.xyz
            points.append(centre + rot @ v.rotation @ [0, 0, 0.5 * v.size[1]])
            points.append(centre - rot @ v.rotation @ [0, 0, 0.5 * v.size[1]])
    if not points:
        return np.array([0.0, 0.0, -3.0]), np.zeros(3), 1.0
    pts = np.array(points)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    target = 0.5 * (lo + hi)
    radius = 0.5 * float(np.linalg.norm(hi - lo))
    direction = CAMERA_DIRECTION / np.linalg.norm(CAMERA_DIRECTION)
    return target + 2.4 * radius * direction, target, radius


def first_view(log) -> Scene:
    """The default camera on the first frame of ``log`` (a ``LogFile``), before the rest loads."""
    source, _ = _model_file(log.model_text, log.model_problem)
    eye, target, _ = camera(log.model, log.result.posed(), source.visuals if source else [])
    return Scene(camera_position=eye, camera_target=target)


def send_scene(
    log, recording, send: Callable[[str, Any], None], colors: dict | None = None
) -> Scene:
    """Log the machine, its labels and the force arrows; return the camera and the legend.

    ``send(path, columns)`` sends columns on the time axis (the replay's helper).
    """
    import rerun as rr

    res = log.result.posed()  # the frames drawn: samples with a pose
    model = log.model
    gears: dict = model.get("gears", {})
    source, unread = _model_file(log.model_text, log.model_problem)
    visuals = source.visuals if source else []
    joints = source.joints if source else {}
    root = model.get("root_link", "")
    colors = colors or body_colors(res.body_names, root)
    bodies = {name: i for i, name in enumerate(res.body_names)}
    eye, target, _ = camera(model, res, visuals)
    view = eye - target
    view = view / np.linalg.norm(view)

    def log_static(path: str, *archetypes) -> None:
        for archetype in archetypes:
            rr.log(path, archetype, static=True, recording=recording)

    # Bodies: poses over time (the existing ``gearbox/<link>`` transforms) come from replay.py.
    phases = tooth_phases(model, res)
    translucent = parallel_stage_gears(model)
    line = rr.Radius.ui_points(1.0)
    mark = rr.Radius.ui_points(3.0)
    for name, gear in gears.items():
        color = colors.get(gear["link"], (160, 160, 160))
        path = f"gearbox/{gear['link']}/{name}"
        log_static(
            path,
            rr.Transform3D(
                translation=gear["centre_in_link"], mat3x3=rotation_from_z(gear["axis_in_link"])
            ),
        )
        vertices, triangles, normals = gear_mesh(gear, phases[name])
        log_static(
            f"{path}/body",
            rr.Mesh3D(
                vertex_positions=vertices,
                triangle_indices=triangles,
                vertex_normals=normals,
                albedo_factor=(*color, PARALLEL_STAGE_ALPHA if name in translucent else 255),
            ),
        )
        half = 0.5 * gear["face_width"] * 1.002
        edge = tuple(int(0.55 * c) for c in color)
        log_static(
            f"{path}/teeth",
            rr.LineStrips3D(
                [tooth_outline(gear, -half, phases[name]), tooth_outline(gear, half, phases[name])],
                colors=[edge],
                radii=line,
            ),
        )
        direction = np.array([math.cos(phases[name]), math.sin(phases[name]), 0.0])
        if gear["internal"]:  # across the rim, not across the machine
            inner, outer = gear["pitch_radius"] - gear["module"], outer_radius(gear)
        else:
            inner, outer = 0.0, outer_radius(gear)
        strips = [
            np.array([direction * inner + [0, 0, z], direction * outer + [0, 0, z]])
            for z in (-half * 1.004, half * 1.004)
        ]
        log_static(f"{path}/angle_mark", rr.LineStrips3D(strips, colors=[MARK_COLOR], radii=mark))

    # The model's own shapes, shafts, bearings.
    largest = max((g["pitch_radius"] for g in gears.values()), default=0.1)
    for k, v in enumerate(visuals):
        if v.link not in bodies or _is_gear_visual(v, model):
            continue
        color = colors.get(v.link, HOUSING_COLOR)
        path = f"gearbox/{v.link}/visual{k}"
        log_static(path, rr.Transform3D(translation=v.xyz, mat3x3=v.rotation))
        if v.kind == "cylinder":
            wide = v.size[0] > 0.3 * largest
            log_static(
                path,
                rr.Cylinders3D(
                    lengths=[v.size[1]],
                    radii=[v.size[0]],
                    colors=[color],
                    fill_mode="majorwireframe" if wide else "solid",
                    line_radii=rr.Radius.ui_points(1.5),
                ),
            )
        elif v.kind == "box":
            log_static(path, rr.Boxes3D(sizes=[v.size], colors=[color], fill_mode="solid"))
        else:
            log_static(path, rr.Ellipsoids3D(radii=[v.size * 3], colors=[color], fill_mode="solid"))
    for spec in joints.values():
        link = spec["child"]
        if link not in bodies or link == root:
            continue
        color = colors.get(link, HOUSING_COLOR)
        z0, z1, reach = _extent(model, visuals, link)
        shaft = _shaft_radius(model, visuals, link)
        own = [g for g in gears.values() if g["link"] == link and not g["internal"]]
        if own and spec["parent"] == root:
            overhang = 0.25 * max(g["face_width"] for g in own)
            log_static(
                f"gearbox/{link}/shaft",
                rr.Transform3D(translation=[0, 0, 0.5 * (z0 + z1)]),
                rr.Cylinders3D(
                    lengths=[z1 - z0 + 2 * overhang],
                    radii=[shaft],
                    colors=[tuple(int(0.7 * c) for c in color)],
                    fill_mode="solid",
                ),
            )
            z0, z1 = z0 - overhang, z1 + overhang
        if spec["type"] in ("continuous", "revolute"):
            rot = rotation_from_z(spec["axis"])
            races = []
            for z in (z0, z1):
                for r in (shaft * 1.05, shaft * 1.7):
                    races.append((rot @ _circle(r, z).T).T)
            log_static(
                f"gearbox/{link}/bearing",
                rr.LineStrips3D(races, colors=[HOUSING_COLOR], radii=rr.Radius.ui_points(2.5)),
            )

    # Carrier-like bodies without gears: an angle mark on their widest visual.
    for link in bodies:
        if link == root or any(g["link"] == link for g in gears.values()):
            continue
        discs = [v for v in visuals if v.link == link and v.kind == "cylinder"]
        if len(discs) < 1 or max(v.size[0] for v in discs) < 0.3 * largest:
            continue
        disc = max(discs, key=lambda v: v.size[0])
        strips = []
        for v in discs:
            if v.size[0] < 0.9 * disc.size[0]:
                continue
            for z in (v.xyz[2] - 0.52 * v.size[1], v.xyz[2] + 0.52 * v.size[1]):
                strips.append(np.array([[0.3 * v.size[0], 0.0, z], [v.size[0], 0.0, z]]))
        log_static(
            f"gearbox/{link}/angle_mark",
            rr.LineStrips3D(strips, colors=[MARK_COLOR], radii=mark),
        )

    _send_housing(model, res, visuals, log_static)
    _send_labels(model, res, visuals, colors, root, view, send, log_static)
    scene = Scene(camera_position=eye, camera_target=target)
    if unread:
        scene.notes.append(f"the model's own shapes and bearings are not drawn: {unread}")
    _send_arrows(model, res, visuals, view, scene, send, log_static)
    return scene


def _send_housing(model, res, visuals, log_static) -> None:
    import rerun as rr

    bodies = {name: i for i, name in enumerate(res.body_names)}
    points = []
    for g in model.get("gears", {}).values():
        if g["link"] in bodies and len(res):
            centre, rot = gear_pose(g, res, 0, bodies)
            r, h = outer_radius(g), 0.5 * g["face_width"]
            for sx, sy, sz in np.ndindex(2, 2, 2):
                points.append(centre + rot @ [r * (2 * sx - 1), r * (2 * sy - 1), h * (2 * sz - 1)])
    if not points:
        return
    pts = np.array(points)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    margin = 0.06 * float(np.max(hi - lo))
    log_static(
        "gearbox/housing_outline",
        rr.Boxes3D(
            centers=[0.5 * (lo + hi)],
            half_sizes=[0.5 * (hi - lo) + margin],
            colors=[HOUSING_COLOR],
            fill_mode="majorwireframe",
            radii=rr.Radius.ui_points(1.0),
        ),
    )


def _send_labels(model, res, visuals, colors, root, view, send, log_static) -> None:
    """One label per body beside it, on the face toward the camera; coaxial labels fanned."""
    import rerun as rr

    n = len(res)
    if not n:
        return
    bodies = {name: i for i, name in enumerate(res.body_names)}
    gears = model.get("gears", {})
    shown = []
    for link in res.body_names:
        if link == root:
            continue
        has_gear = any(g["link"] == link for g in gears.values())
        z0, z1, reach = _extent(model, visuals, link)
        if not has_gear and reach < 0.3 * max(
            (g["pitch_radius"] for g in gears.values()), default=0.1
        ):
            continue  # pins and small parts: named on hover of their shapes only
        shown.append((link, z0, z1, reach))
    # Bodies sharing an origin (sun, carrier, ring, ...) get labels at different angles.
    groups: dict[tuple, list] = {}
    for item in shown:
        key = tuple(np.round(res.body_position[0, bodies[item[0]]], 3))
        groups.setdefault(key, []).append(item)
    fan = [math.radians(a) for a in (60.0, 180.0, 300.0, 0.0, 120.0, 240.0, 30.0, 150.0, 270.0)]
    names, offsets = [], []
    for members in groups.values():
        members.sort(key=lambda item: item[3])
        for j, (link, z0, z1, reach) in enumerate(members):
            rot = quaternion_matrix(res.body_quaternion[0, bodies[link]])
            axis = rot[:, 2]
            z = z1 if float(axis @ view) >= 0 else z0
            if len(members) == 1:
                radial = np.zeros(3)
            else:
                angle = fan[j % len(fan)]
                radial = 0.8 * reach * np.array([math.cos(angle), math.sin(angle), 0.0])
            names.append(link)
            offsets.append(radial + np.array([0.0, 0.0, z * 1.02 + math.copysign(0.01, z)]))
    # Offsets are fixed in world (labels do not spin); they follow each body's origin.
    index = [bodies[name] for name in names]
    positions = res.body_position[:, index] + np.array(offsets)[None]
    log_static(
        "gearbox/labels",
        # One blue for every name, not the body's colour (which vanishes on the body itself):
        # it reads on the light box of the light theme and the dark box of the dark theme.
        rr.Points3D.from_fields(
            labels=names, colors=[LABEL_COLOR], radii=rr.Radius.ui_points(0.5), show_labels=True
        ),
    )
    send(
        "gearbox/labels",
        rr.Points3D.columns(positions=positions.reshape(-1, 3)).partition([len(names)] * n),
    )


def _kn(values: np.ndarray, unit: str = "N") -> list[str]:
    return [f"{v:,.0f} {unit}".replace(",", " ") for v in values]


def _force_labels(names: list[str], forces: np.ndarray) -> list[str]:
    """``name: |F| N`` of each arrow of each frame, frame after frame."""
    magnitude = np.linalg.norm(forces, axis=-1)
    return [f"{names[j]}: {text}" for row in magnitude for j, text in enumerate(_kn(row))]


def _bearing_labels(names: list[str], res, shown: list[int]) -> list[str]:
    """Each bearing's loads about its own axis, frame after frame.

    Radial and axial force and tilting moment (``dynamics/bearing_load.py``), and apart the
    torque its shaft transmits, which is not a load on the bearing.
    """
    loads = [
        getattr(res, f"bearing_{q}")[:, shown] for q in ("radial", "axial", "tilting", "torque")
    ]
    return [
        f"{name}: radial {radial}, axial {axial}, tilting {tilting}; shaft torque {torque}"
        for frame in range(len(res))
        for name, radial, axial, tilting, torque in zip(
            names,
            _kn(loads[0][frame]),
            _kn(loads[1][frame]),
            _kn(loads[2][frame], "N·m"),
            _kn(loads[3][frame], "N·m"),
            strict=True,
        )
    ]


def _send_arrows(model, res, visuals, view, scene: Scene, send, log_static) -> None:
    """Mesh and bearing force arrows on the faces toward the camera, one scale for all."""
    import rerun as rr

    n = len(res)
    gears = model.get("gears", {})
    meshes = model.get("meshes", {})
    bearings = model.get("bearings", {})
    bodies = {name: i for i, name in enumerate(res.body_names)}
    largest_radius = max((g["pitch_radius"] for g in gears.values()), default=0.1)
    families = []
    if res.mesh_names and res.mesh_force_on_b.shape[0]:
        offsets = np.zeros((n, len(res.mesh_names), 3))
        for m, name in enumerate(res.mesh_names):
            gear = gears.get(meshes.get(name, {}).get("gear_b", ""))
            if gear is None or gear["link"] not in bodies:
                continue
            rot = quaternion_matrix(res.body_quaternion[:, bodies[gear["link"]]])
            axis = rot @ (rotation_from_z(gear["axis_in_link"])[:, 2])
            side = np.where(axis @ view >= 0, 1.0, -1.0)
            offsets[:, m] = (
                axis * (side * (0.5 * gear["face_width"] + 0.01 * largest_radius))[:, None]
            )
        families.append(
            (
                "gearbox/mesh_forces",
                res.pitch_point + offsets,
                res.mesh_force_on_b,
                _force_labels(list(res.mesh_names), res.mesh_force_on_b),
                MESH_ARROW_COLOR,
                "red",
                "tooth force on gear B of each mesh, at the pitch point, on B's face toward you",
            )
        )
    shown = [
        i
        for i, name in enumerate(res.bearing_names)
        if bearings.get(name, {}).get("child", "") in bodies
    ]
    if shown and res.bearing_force.shape[0]:
        origins = np.zeros((n, len(shown), 3))
        for j, i in enumerate(shown):
            link = bearings[res.bearing_names[i]]["child"]
            z0, z1, _ = _extent(model, visuals, link)
            rot = quaternion_matrix(res.body_quaternion[:, bodies[link]])
            axis = rot[:, :, 2]
            side = np.where(axis @ view >= 0, 1.0, -1.0)
            reach = np.where(side > 0, z1, -z0) + 0.03 * largest_radius
            origins[:, j] = res.body_position[:, bodies[link]] + axis * (side * reach)[:, None]
        families.append(
            (
                "gearbox/bearing_forces",
                origins,
                res.bearing_force[:, shown],
                _bearing_labels([res.bearing_names[i] for i in shown], res, shown),
                BEARING_ARROW_COLOR,
                "olive",
                "force of each bearing on its child body, on the body's axis at its face toward "
                "you; its label gives the radial and axial force and the tilting moment about "
                "the bearing's axis, and apart the torque the shaft transmits",
            )
        )
    if not families:
        return
    largest = max(float(np.max(np.linalg.norm(f[2], axis=-1), initial=0.0)) for f in families)
    scale = ARROW_FRACTION * largest_radius / largest if largest > 0 else 1.0
    scene.arrow_scale = scale
    for path, origins, forces, labels, color, color_name, what in families:
        k = forces.shape[1]
        send(
            path,
            rr.Arrows3D.columns(
                origins=origins.reshape(-1, 3),
                vectors=(forces * scale).reshape(-1, 3),
                labels=labels,
            ).partition([k] * n),
        )
        log_static(
            path,
            rr.Arrows3D.from_fields(
                colors=[color], show_labels=False, radii=rr.Radius.ui_points(3.0)
            ),
        )
        scene.notes.append(f"**{color_name}** ({path.split('/')[-1]}): {what}")
    scene.notes.append(
        f"one scale for every arrow: 1 m of arrow = {1e-3 / scale:,.1f} kN "
        f"(1 mm = {1e-3 / scale:,.0f} N); the largest force of the run "
        f"({largest / 1e3:,.1f} kN) is drawn {ARROW_FRACTION * largest_radius:.3g} m long"
    )
    scene.notes.append(
        "hover an arrow for its force in newtons; switch a family off with the eye icon of its "
        "entity in the blueprint panel"
    )
