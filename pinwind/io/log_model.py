"""The model a log records (the ``pinwind.model`` metadata record): names and gear geometry.

The names of the joints, meshes, bearings, links, energy terms and elements say what each
element of a logged array is, and the joints' kinds (revolute or prismatic) its unit; the
geometry of gears, meshes and bearings lets a replay draw the model without building it
(docs/log_format.md, "Metadata records").
"""

from __future__ import annotations

from typing import Any

from pinwind.dynamics.result import Result
from pinwind.gears.involute import pitch_radius


def model_names(result: Result) -> dict[str, list[str]]:
    """The names of the elements of a run's arrays, by their key in the ``pinwind.model`` record."""
    return {
        "joint_names": list(result.joint_names),
        "joint_kinds": list(result.joint_kinds),
        "mesh_names": list(result.mesh_names),
        "bearing_names": list(result.bearing_names),
        "body_names": list(result.body_names),
        "energy_terms": list(result.energy),
        "generator_names": list(result.generator_names),
        "rotor_names": list(result.rotor_names),
        "row_names": list(result.row_names),
        "slice_names": list(result.slice_names),
    }


def model_geometry(gearbox) -> dict[str, Any]:
    """Gears, meshes and bearings of a model, for the ``pinwind.model`` record (and replay).

    Gear centres and axes are in the frame of the link that carries the gear; radii, widths and
    distances in m, angles in rad.
    """
    import pinocchio as pin

    model = gearbox.model
    gears = {}
    for name, gear in gearbox.gears.items():
        spec = gear.spec
        frame = model.frames[model.getFrameId(spec.link, pin.BODY)]
        joint_from_link = frame.placement
        gears[name] = {
            "link": spec.link,
            "teeth": spec.teeth,
            "module": spec.module,
            "face_width": spec.face_width,
            "pressure_angle": spec.pressure_angle,
            "helix_angle": spec.helix_angle,
            "profile_shift": spec.profile_shift,
            "internal": spec.internal,
            "pitch_radius": pitch_radius(spec.teeth, spec.module, spec.helix_angle),
            "centre_in_link": joint_from_link.actInv(gear.centre_in_joint).tolist(),
            "axis_in_link": (joint_from_link.rotation.T @ gear.axis_in_joint).tolist(),
        }
    meshes = {
        m.name: {
            "gear_a": m.gear_a.name,
            "gear_b": m.gear_b.name,
            "working_pressure_angle": m.working_pressure_angle,
            "centre_distance": m.centre_distance,
            "working_radius_a": m.working_radius_a,
            "working_radius_b": m.working_radius_b,
        }
        for m in gearbox.meshes
    }
    source_joints = getattr(getattr(gearbox, "source", None), "joints", {}) or {}
    bearings = {
        name: {
            "parent": source_joints.get(name, {}).get("parent", ""),
            "child": source_joints.get(name, {}).get("child", ""),
        }
        for name in gearbox.joint_names
    }
    return {
        "model_name": gearbox.name,
        "root_link": getattr(getattr(gearbox, "source", None), "root_link", ""),
        "locked_joints": list(gearbox.locked_joints),
        "gears": gears,
        "meshes": meshes,
        "bearings": bearings,
    }
