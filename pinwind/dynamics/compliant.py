"""Compliant gear meshes: the constants the compiled element needs, and the mesh modes.

A compliant mesh is a spring-damper along the line of action of each flank (IFToMM 2018
eqs. 2-6, IFToMM 2018; Jørgensen 2014 eqs. 14-19):

    F_n = k(x) δ + c δ̇  on each flank in contact,   F_n ≥ 0 (teeth never pull)

with δ the overlap of the two flanks along the line of action computed **from the bodies'
positions** (gear angles relative to the centre line and the centre distance; the formula is in
``cpp/compliant_mesh.hpp``), so it stays consistent with the angles over any run length, and
x the roll position of the tooth pairs along the path of contact (``cpp/mesh_path.hpp``):

- k(x): the sum over the tooth pairs in contact of one pair's stiffness, c′b in the single-pair
  zone and 0.875 c′b each in the double-pair zones (mean ISO 6336-1 c_γα b,
  ``gears/mesh_stiffness.py``); for helical gears in proportion to the total length of the
  contact lines (``contact_line_pair_stiffness``, same mean); a user table (Jørgensen 2014
  Fig. 8), or the constant c_γα b. Stiffnesses act along the transverse line of action;
- backlash j: the back flank's overlap is δ_b = −(rolling part) + (radial part) − j, no force in
  between; each flank pushes where it overlaps, both at once where the centres come closer than
  the teeth allow (the contact is the gradient of Σ_flanks ½ k δ₊²);
- the single-tooth force F k₁/k (Jørgensen 2014 §2.4) of the pair entering the mesh.

Why implicit. Mesh stiffnesses of 1e8 to 5e9 N/m on gears of a few kilograms to a tonne put
modes in the kHz; an explicit spring would need steps of microseconds. The compiled element
takes the force at the time step's weighted state (mid-step for ρ∞ = 1; ``dynamics/
integrator.py``), which makes it linear in the step's acceleration, so it enters the same
constrained solve as the rigid rows: the Hessian gains w JᵀJ. The scheme is second order and stable
at any step; with ρ∞ < 1 it damps the modes it does not resolve (``dynamics/dt_advice.py``). The
run's metadata and summary name the highest mesh mode, its numerical damping ratio at the chosen
dt beside its physical one, and the dt that keeps the numerical one below a tenth of the
physical, then its frequency error at dt and the dt that keeps it within 0.5 %; a run whose
numerical damping of that mode exceeds the physical one, or that takes fewer than
``RESOLVING_STEPS`` steps per period of it, warns with the same line (``StepTooCoarse``).

Position errors of gear centres (planet pin errors) shift the overlaps by n·(e_A − e_B): a
constant offset in the carrier's frame that makes the planets share the load unequally.
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from pinwind.dynamics import _native
from pinwind.dynamics.dt_advice import DEFAULT_SCHEME, RESOLVING_STEPS, dt_advice
from pinwind.dynamics.integrator import Integrator
from pinwind.dynamics.mesh import MeshSet
from pinwind.dynamics.normal_modes import (
    SpringElement,
    element_matrices,
    free_motions,
    natural_modes,
)
from pinwind.errors import InputError, PinwindWarning, StepTooCoarse, UnknownElement
from pinwind.gears.face_load import (
    AUTO_LINE_LOAD,
    expected_misalignment,
    slice_centres,
    slice_count,
)
from pinwind.gears.flank_modification import lead_gap, profile_gap
from pinwind.gears.gear_pair import GearPair
from pinwind.gears.mesh_stiffness import (
    contact_line_pair_stiffness,
    mesh_stiffness,
    pair_stiffness_along_path,
    single_pair_stiffness,
)
from pinwind.losses.mesh_friction import (
    LUBRICANT_FACTORS,
    pitch_point_conditions,
    sum_velocity_per_relative_spin,
)
from pinwind.model.compliance import AUTO_SLICES, MeshCompliance
from pinwind.model.gearbox import Gear, Gearbox, Mesh
from pinwind.model.phasing import direction_at

if TYPE_CHECKING:
    from pinwind.dynamics.result import Result


@dataclass(frozen=True)
class MeshSetup:
    """Everything the step loop needs to know about the meshes of one run.

    Attributes:
        meshes: the gearbox's meshes with this run's rigid/compliant choice.
        rigid: indices of the rigid meshes (constraint rows, in row order).
        paths: every mesh's path-of-contact constants (compiled struct).
        compliant: the compliant meshes' constants (compiled structs).
        highest_mode: frequency of the highest mesh mode [Hz] (0 without compliant meshes).
        highest_mode_damping: that mode's damping ratio from the mesh dashpots [-].
    """

    meshes: list[Mesh]
    rigid: list[int]
    paths: list[_native.MeshPathSpec]
    compliant: list[_native.CompliantMeshSpec]
    highest_mode: float
    highest_mode_damping: float = 0.0

    def compliance(self, spec: _native.CompliantMeshSpec) -> tuple[Mesh, MeshCompliance]:
        """The mesh of a compliant spec and its compliance."""
        mesh = self.meshes[spec.mesh]
        if mesh.compliance is None:
            raise AssertionError(f"mesh {mesh.name} has a compliant spec but no compliance")
        return mesh, mesh.compliance

    def slice_names(self) -> list[str]:
        """The columns of the slice series (``slice_line_load``): every sliced mesh's slices.

        Mesh after mesh in the order of ``compliant`` (the compiled slice family's,
        ``cpp/series.hpp``), each mesh's N slices from face side I (``slice_tables``' z_s
        increasing), named ``slice_name``; a mesh of one slice (a single contact line) has none.
        """
        return [
            slice_name(self.meshes[spec.mesh].name, j)
            for spec in self.compliant
            if spec.slices > 1
            for j in range(spec.slices)
        ]


def slice_name(mesh: str, index: int) -> str:
    """The column of slice ``index`` (0 at face side I) of a sliced mesh: ``<mesh>.<index>``."""
    return f"{mesh}.{index}"


def mesh_choices(gearbox: Gearbox, meshes: Mapping[str, str | MeshCompliance] | None) -> list[Mesh]:
    """The gearbox's meshes with per-run choices applied.

    Args:
        meshes: mesh name (or ``"all"``) → ``"rigid"``, ``"compliant"`` (the file's compliance
            if it has one, else the defaults) or a ``MeshCompliance``.

    Raises:
        UnknownElement: a name that is not a mesh. InputError: an unknown choice.
    """
    chosen = list(gearbox.meshes)
    names = [m.name for m in chosen]
    for key, choice in (meshes or {}).items():
        if key != "all" and key not in names:
            raise UnknownElement("mesh", key, names)
        if isinstance(choice, MeshCompliance):
            problems = choice.problems()
            if problems:
                raise InputError(f'meshes["{key}"]: ' + "; ".join(problems))
        elif choice not in ("rigid", "compliant"):
            raise InputError(
                f'meshes["{key}"] is {choice!r}; give "rigid", "compliant" or a MeshCompliance'
            )
        for i, m in enumerate(chosen):
            if key not in ("all", m.name):
                continue
            compliance: MeshCompliance | None
            if isinstance(choice, MeshCompliance):
                compliance = choice
            elif choice == "compliant":
                # The model file's values if it has them, else the defaults.
                compliance = gearbox.meshes[i].compliance or MeshCompliance()
            else:
                compliance = None
            if compliance is not None and m.path is None:
                raise InputError(
                    f'mesh "{m.name}" has no valid path of contact (loading warned why); it '
                    "cannot be compliant"
                )
            chosen[i] = replace(m, compliance=compliance)
    return [auto_slices(m) for m in chosen]


def auto_slices(mesh: Mesh) -> Mesh:
    """The mesh with ``slices="auto"`` replaced by the rule's N (else the mesh as it is).

    N = `pinwind.gears.face_load.slice_count`(F_β, δ_m) = ⌈10 F_β/δ_m⌉ in [1, 50], with F_β the
    misalignment expected across the face, `pinwind.gears.face_load.expected_misalignment` of
    the two gears' lead modifications (f_Hβ, crowning, end relief) plus the rating's default
    F_βy for what the model does not give, and δ_m = w b/c̄ the mean deflection at the light
    line load w = `pinwind.gears.face_load.AUTO_LINE_LOAD` (100 N/mm) on the face width b
    (``Mesh.face_width``) with the mesh's mean stiffness c̄ (``mean_mesh_stiffness``). The
    compliance keeps (F_β, δ_m) in ``slice_rule``; the run's metadata records both.
    """
    c = mesh.compliance
    if c is None or c.slices != AUTO_SLICES:
        return mesh
    b = mesh.face_width
    misalignment = expected_misalignment(
        mesh.gear_a.spec.modification, mesh.gear_b.spec.modification, b
    )
    deflection = AUTO_LINE_LOAD * b / mean_mesh_stiffness(mesh)
    n = slice_count(misalignment, deflection)
    return replace(mesh, compliance=replace(c, slices=n, slice_rule=(misalignment, deflection)))


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Cross product a × b of two 3-vectors (np.cross takes 30 µs; a set-up makes hundreds)."""
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


def reference_direction(gearbox: Gearbox, gear: Gear, mesh: Mesh) -> np.ndarray:
    """Where a gear's tooth 0 flank crosses a mesh's working pitch circle: a unit vector.

    The vector is ⟂ the gear's axis, in its joint frame, and points where the flank of tooth 0
    facing the gear's positive turn crosses the working pitch circle of ``mesh``.

    For gear A that is its front flank (docs/model_format.md "Mesh sign convention"): with this
    direction along the centre line, the front flank is at the pitch point. The angle is the
    tooth centre's (``gearbox.tooth_phases``, teeth interlocked with the mating gears,
    ``model/phasing.py``) plus half the tooth thickness on that circle (ISO 21771,
    ``gears/involute.half_tooth_angle``), so a gear meshing on two pitch circles (a planet) has
    one set of teeth.
    """
    radius = mesh.working_radius_a if gear is mesh.gear_a else mesh.working_radius_b
    angle = gearbox.tooth_phases[gear.name] + gear.spec.half_tooth_angle(radius)
    return direction_at(gear.axis_in_joint, angle)


def _angle_about(k: np.ndarray, u: np.ndarray, e: np.ndarray) -> float:
    """Angle from u to e about k [rad] (cpp/mesh_path.hpp angle_about)."""
    return math.atan2(float(k @ _cross(u, e)), float(u @ e))


def _position_error_in_world(
    gearbox: Gearbox, data: pin.Data, gear: Gear, error: tuple[float, float]
) -> np.ndarray:
    """A gear centre's (tangential, radial) position error as a world vector [m].

    Radial is from the axis of the body that carries the gear's bearing (a planet's carrier) to
    the gear centre; tangential is that axis × radial.
    """
    tangential, radial = error
    if tangential == 0.0 and radial == 0.0:
        return np.zeros(3)
    model = gearbox.model
    parent = model.parents[gear.joint_id]
    centre = data.oMi[gear.joint_id].act(gear.centre_in_joint)
    if parent == 0:
        raise InputError(
            f'gear "{gear.name}" has a position error, but its bearing sits on the ground, so '
            "tangential and radial have no carrier to refer to; position errors are for gears "
            "on a carrier (planets)"
        )
    axis = data.oMi[parent].rotation @ gearbox._joint_axis(parent)
    offset = centre - data.oMi[parent].translation
    offset = offset - (offset @ axis) * axis
    if np.linalg.norm(offset) < 1e-9:
        raise InputError(
            f'gear "{gear.name}" sits on the axis of the body that carries it, so its position '
            "error has no radial direction; position errors are for planets"
        )
    r = offset / np.linalg.norm(offset)
    return tangential * _cross(axis, r) + radial * r


def mesh_setup(
    gearbox: Gearbox,
    meshes: list[Mesh],
    *,
    driver_index: list[int],
    dt: float | None,
    position_errors: Mapping[str, tuple[float, float]] | None = None,
    scheme: Integrator = DEFAULT_SCHEME,
    mass: np.ndarray | None = None,
    flank: np.ndarray | None = None,
) -> MeshSetup:
    """Constants of every mesh for the compiled step loop, at the reference pose.

    Args:
        meshes: the run's meshes (``mesh_choices``).
        driver_index: velocity indices of the speed drivers and locks (for the mesh modes).
        dt: time step [s] (for the coarse-step warning); None: no run, no warning.
        position_errors: gear name → (tangential, radial) position error [m], replacing the
            model file's.
        scheme: the run's time step (for the numerical-damping warning).
        mass: M [kg·m², kg] of the machine the run steps, the rotors' inertias added
            (``Drivetrain.mass``); default the bodies' alone. The mesh modes and the damping a
            damping ratio gives (2 ζ √(k m_eq)) are taken with it.
        flank: ±1 per mesh, the flanks the static load presses (``loaded_flanks``): the rows
            of the mesh modes and of m_eq; default every front flank.
    """
    meshes = [auto_slices(m) for m in meshes]
    errors = {name: g.spec.position_error for name, g in gearbox.gears.items()}
    for name, value in (position_errors or {}).items():
        if name not in gearbox.gears:
            raise UnknownElement("gear", name, list(gearbox.gears))
        t, r = (float(x) for x in value)
        if not (math.isfinite(t) and math.isfinite(r)):
            raise InputError(f'position_errors["{name}"] = {value!r} must be finite [m]')
        errors[name] = (t, r)
    for name, (t, r) in errors.items():
        module = gearbox.gears[name].spec.module
        if max(abs(t), abs(r)) > module:
            # 1e30 µm (--position-error sun=1e30,0) ran without a word
            raise InputError(
                f'gear "{name}": position error (tangential, radial) = ({t * 1e6:g}, '
                f"{r * 1e6:g}) µm is more than its module {module * 1e3:g} mm, which would "
                "move its teeth out of mesh; give the error of the pin or bearing seat in µm "
                "(typically tens of µm)"
            )
    model = gearbox.model
    data = model.createData()
    q = gearbox.neutral()
    pin.computeJointJacobiansTimeVariation(model, data, q, np.zeros(model.nv))
    ms = MeshSet(gearbox, meshes)
    rows = ms.evaluate(model, data)
    paths, compliant, rigid = [], [], []
    for i, mesh in enumerate(meshes):
        a, b = mesh.gear_a, mesh.gear_b
        k, r_hat, t = rows.axis[i], rows.radial[i], rows.tangent[i]
        point = rows.pitch_point[i]
        centre_a = data.oMi[a.joint_id].act(a.centre_in_joint)
        centre_b = data.oMi[b.joint_id].act(b.centre_in_joint)
        u = ms.sigma[i] * r_hat
        ref_a, ref_b = reference_direction(gearbox, a, mesh), reference_direction(gearbox, b, mesh)
        psi_a = _angle_about(k, u, data.oMi[a.joint_id].rotation @ ref_a)
        psi_b = _angle_about(k, u, data.oMi[b.joint_id].rotation @ ref_b)
        paths.append(_path_spec(mesh, ref_a, 2.0 * a.spec.half_tooth_angle(mesh.working_radius_a)))
        if mesh.compliance is None:
            rigid.append(i)
            continue
        gaps = profile_gap_table(mesh)
        if gaps is not None:
            paths[-1].gap_position, paths[-1].gap_value = gaps
        cos_w = math.cos(mesh.working_pressure_angle)
        rho_a = float(_cross(k, point - centre_a) @ t)
        rho_b = float(_cross(k, point - centre_b) @ t)
        spec = _native.CompliantMeshSpec()
        spec.mesh = i
        spec.base_radius_a = cos_w * rho_a
        spec.base_radius_b = cos_w * rho_b
        spec.reference_b = ref_b
        spec.tangential_ref = spec.base_radius_a * psi_a - spec.base_radius_b * psi_b
        # The flanks' relative axial position at the reference pose: a helical overlap's axial
        # part tan β_b (Z − Z_ref) is zero there (cpp/compliant_mesh.hpp mesh_pose).
        spec.axis_b = b.axis_in_joint
        spec.axial_ref = _native.axial_offset(
            k, data.oMi[b.joint_id].rotation @ b.axis_in_joint, centre_a, centre_b, point
        )
        spec.base_radius_sum = mesh.centre_distance * cos_w
        internal = a.spec.internal or b.spec.internal
        spec.radial_sign = 1.0 if internal else -1.0
        spec.involute_ref = math.tan(mesh.working_pressure_angle) - mesh.working_pressure_angle
        shift = _position_error_in_world(gearbox, data, a, errors[a.name]) - (
            _position_error_in_world(gearbox, data, b, errors[b.name])
        )
        spec.tangential_offset = cos_w * float(t @ shift)
        spec.radial_offset = (
            ms.eps[i] * math.sin(mesh.working_pressure_angle) * float(r_hat @ shift)
        )
        c = mesh.compliance
        spec.backlash = c.backlash
        _set_friction(spec, mesh, c)
        spec.stiffness = mean_mesh_stiffness(mesh)
        spec.face_width = mesh.face_width
        if c.slice_number > 1:
            spec.slices = c.slice_number
            spec.slice_offset, spec.slice_gap, spec.slice_gap_back = slice_tables(mesh)
            helical = helical_slices(mesh, spec.slice_offset)
            if helical is not None:
                spec.slice_shift, spec.slice_shift_back = helical.shift, helical.shift_back
                spec.slice_path_length = helical.path_length
                spec.slice_pair_position, spec.slice_pair_stiffness = helical.pair_table
        compliant.append(spec)
    setup = MeshSetup(meshes, rigid, paths, compliant, 0.0)
    if compliant:
        if mass is None:
            mass = pin.crba(model, data, q)
            mass = np.triu(mass) + np.triu(mass, 1).T
        jac, _ = ms.combine(rows, np.ones(len(meshes)) if flank is None else flank)
        constraints = _rigid_rows(jac, rigid, driver_index, model.nv)
        for spec in compliant:
            mesh, c = setup.compliance(spec)
            row = jac[spec.mesh]
            m_eq = effective_mass(mass, constraints, row)
            if not math.isfinite(m_eq):
                warnings.warn(
                    f'mesh "{mesh.name}" is compliant, but the rigid meshes and speed drivers '
                    "around it fix its deflection, so it carries no load; make the meshes in its "
                    'loop compliant too (e.g. meshes={"all": "compliant"})',
                    PinwindWarning,
                    stacklevel=3,
                )
            if c.damping is not None:
                spec.damping = c.damping
            else:
                spec.damping = (
                    2.0 * c.damping_ratio * math.sqrt(spec.stiffness * m_eq)
                    if math.isfinite(m_eq)
                    else 0.0
                )
        frequency, damping = highest_mesh_mode_and_damping(mass, constraints, jac, setup)
        setup = MeshSetup(meshes, rigid, paths, compliant, frequency, damping)
        if dt is not None:
            _warn_if_damped_numerically(frequency, dt, damping, scheme)
    return setup


def slice_tables(mesh: Mesh) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each slice's centre and lead gaps of a sliced compliant mesh (``cpp/compliant_mesh.hpp``).

    The face width b = min(b_A, b_B) (``Mesh.face_width``) cut into N equal slices: centres z_s
    from the face centre along gear A's axis k [m], side I at −b/2 (so a gear B turned by θ
    about k × n closes its flank at −z); gaps e_s [m] of both gears' lead modifications,
    `pinwind.gears.flank_modification.lead_gap` at z_s + b/2 from side I (crowning, end
    relief, helix slope deviation f_Hβ: the same gaps as `pinwind.gears.face_load`), on the
    front flank; on the back flank the same crowning and end relief, and f_Hβ as a misalignment
    acts there, mirrored: f_Hβ (1 − z/b), opening towards side I (a tilted tooth, not a
    tapered one). Profile relief acts on each slice's pairs through the mesh's gap table
    (``profile_gap_table``, the same at every slice); a helical mesh's slices follow its
    inclined contact lines (``helical_slices``).

    Returns:
        z_s [m], e_s of the front flank [m], e_s of the back flank [m], each (N,).
    """
    c = mesh.compliance
    slices = 1 if c is None else c.slice_number
    mod_a, mod_b = mesh.gear_a.spec.modification, mesh.gear_b.spec.modification
    b = mesh.face_width
    z = slice_centres(b, slices)
    slope = mod_a.helix_slope_deviation + mod_b.helix_slope_deviation
    back = lead_gap(
        replace(mod_a, helix_slope_deviation=-mod_a.helix_slope_deviation),
        replace(mod_b, helix_slope_deviation=-mod_b.helix_slope_deviation),
        b,
        z,
    )
    return z - 0.5 * b, lead_gap(mod_a, mod_b, b, z), back + slope


@dataclass(frozen=True)
class HelicalSlices:
    """The path constants of a helical mesh's slices (``cpp/compliant_mesh.hpp`` SlicedMeshes).

    Attributes:
        shift: each slice's entering-pair shift along the front flank's path, −ζ_s tan β_b [m].
        shift_back: the same along the back flank's path, −(b − ζ_s) tan β_b [m].
        path_length: g_α, the transverse path a slice's pairs touch over [m].
        pair_table: one pair's stiffness along a slice's path for the whole face (positions [m],
            [N/m]); each slice takes 1/N of it. Empty arrays: the constant mesh stiffness.
    """

    shift: np.ndarray
    shift_back: np.ndarray
    path_length: float
    pair_table: tuple[np.ndarray, np.ndarray]


def helical_slices(mesh: Mesh, slice_offset: np.ndarray) -> HelicalSlices | None:
    """A helical mesh's slices as thin spur sections along its inclined contact lines.

    A pair whose contact point in the front face section (side I) sits at y from A touches the
    section ζ = z + b/2 from side I at y − ζ tan β_b (``contact_line_pair_stiffness``), tan β_b
    = Δ/b with Δ = ε_β p_bt: slice s's pairs are the mesh's pairs shifted by −ζ_s tan β_b along
    the front flank's path. The back flank's contacts move the other way along its own path as
    the tooth twists, so that section enters last: shift −(b − ζ_s) tan β_b. Each slice's pairs
    touch over the transverse path g_α; where the mesh stiffness follows the contact lines, a
    pair on a slice has the stiffness per unit face width c̄ p_bt/(g_α b) (c̄ the mean mesh
    stiffness, the single-line law's scale) over the slice's width b/N, so the slices' sum is
    the midpoint rule over the face of the single line's contact length. With a user pair table
    each slice takes 1/N of it; with a constant stiffness, 1/N of that.

    Args:
        slice_offset: z_s, the slices' centres from the face centre [m] (``slice_tables``).

    Returns:
        The constants, or None for a spur mesh (ε_β = 0).
    """
    path = mesh.path
    if path is None or not path.overlap_ratio > 0.0:
        return None
    b = mesh.face_width
    tan_beta_b = path.overlap_ratio * path.base_pitch / b
    zeta = np.asarray(slice_offset, dtype=float) + 0.5 * b
    g = path.length
    if _follows_contact_lines(mesh):
        line = _contact_line_mean(mesh) * path.base_pitch / g
        table = (np.array([0.0, g]), np.array([line, line]))
    else:
        user = pair_table(mesh)
        table = user if user is not None else (np.zeros(0), np.zeros(0))
    return HelicalSlices(-zeta * tan_beta_b, -(b - zeta) * tan_beta_b, g, table)


def _set_friction(spec: _native.CompliantMeshSpec, mesh: Mesh, c: MeshCompliance) -> None:
    """The flanks' friction of a compliant spec (``cpp/flank_friction.hpp``).

    μ a number, or ISO/TR 14179-2's μ_mz at the operating point (``"iso14179"``): the step
    takes v_Σc = c_v |ω_B − ω_A| (``sum_velocity_per_relative_spin``), ρ_redC and b from the
    pair (``pitch_point_conditions``), η from the oil, Ra and X_L. A helical pair's friction is
    integrated along its contact line over Δ = ``overlap_span`` (0: the pairs as points).
    """
    spec.contact_line_span = overlap_span(mesh)
    if c.friction_law == "constant":
        spec.friction = float(c.friction_coefficient)
        return
    if c.oil is None or c.roughness is None:
        raise AssertionError(f"mesh {mesh.name}: friction law without its data passed problems()")
    pair = GearPair.from_mesh(mesh)
    _, reduced = pitch_point_conditions(pair, 1.0)
    spec.friction_law = _native.FrictionLaw.iso14179
    spec.iso_face_width = pair.face_width
    spec.iso_reduced_radius = abs(reduced)
    spec.iso_sum_velocity_per_spin = sum_velocity_per_relative_spin(pair)
    spec.iso_viscosity = c.oil.dynamic_viscosity()
    spec.iso_roughness = c.roughness
    spec.iso_lubricant_factor = LUBRICANT_FACTORS[c.base_oil]


def _path_spec(mesh: Mesh, reference_a: np.ndarray, tooth_a: float) -> _native.MeshPathSpec:
    """Path-of-contact constants of a mesh: where its tooth pairs are at the reference pose.

    Args:
        reference_a: ``reference_direction`` of gear A in its joint frame.
        tooth_a: A's tooth thickness on the working pitch circle, as an angle [rad].
    """
    spec = _native.MeshPathSpec()
    spec.reference_a = reference_a
    path = mesh.path
    if path is None:
        spec.roll_start = math.nan
        return spec
    # A helical pair touches over the roll span g_α + Δ (``overlap_span``), its position taken
    # in the front face section, Δ/2 ahead of the mid-face section where P and the reference
    # directions lie.
    overlap = overlap_span(mesh)
    spec.base_pitch = path.base_pitch
    spec.path_length = path.length + overlap
    spec.roll_start = path.start_roll_1 - 0.5 * overlap
    spec.roll_radius_a = mesh.base_radius_a
    # Tooth 0 of gear A has its front flank at the pitch point when its reference direction
    # points at the pitch point. Its back flank (the other side of the tooth) is then the
    # tooth thickness behind, on the back line of action (the mirror image of the front one
    # about the centre line): r_b,A times the thickness angle further along the path.
    pitch = (path.pitch_roll_1 - path.start_roll_1 + 0.5 * overlap) % path.base_pitch
    spec.entering_front = pitch
    spec.pitch_position = path.pitch_roll_1 - path.start_roll_1 + 0.5 * overlap
    spec.entering_back = (pitch + mesh.base_radius_a * tooth_a) % path.base_pitch
    # ψ_A is measured from the centre line towards B's centre (cpp/mesh_path.hpp gear_a_angle);
    # with B internal the pitch point lies the other way, half a turn round A, so the front
    # flank is at the pitch point when the reference direction points away from B's centre (for
    # an odd tooth count that is half a base pitch away from pointing at it).
    spec.angle_ref_a = math.pi if mesh.line_sign < 0 else 0.0
    table = pair_table(mesh)
    if table is not None:
        spec.pair_position, spec.pair_stiffness = table
    return spec


def _stiffness_pair(mesh: Mesh) -> GearPair:
    """The mesh's gears as a `GearPair` for ISO 6336-1, pinion first (`GearPair.from_mesh`).

    The pinion is the external gear with fewer teeth; an internal gear goes second.
    """
    return GearPair.from_mesh(mesh)


def single_pair(mesh: Mesh) -> float:
    """Single-pair stiffness c′b of a compliant mesh [N/m].

    Given, or from a given mean c_γα b as c_γα b / (0.75 ε_α + 0.25) (ISO 6336-1's relation
    backwards), or ISO 6336-1 method B.
    """
    c = mesh.compliance
    if c is not None and c.stiffness is not None:
        return c.stiffness
    if c is not None and c.mean_stiffness is not None:
        if mesh.path is None:
            return c.mean_stiffness
        return c.mean_stiffness / (0.75 * mesh.path.contact_ratio + 0.25)
    return single_pair_stiffness(_stiffness_pair(mesh))


def _follows_contact_lines(mesh: Mesh) -> bool:
    """Whether the mesh stiffness follows the contact-line length: a helical mesh on ``path``."""
    c = mesh.compliance
    if c is not None and (c.pair_stiffness is not None or c.variation == "constant"):
        return False
    return mesh.path is not None and mesh.path.overlap_ratio > 0.0


def _contact_line_mean(mesh: Mesh) -> float:
    """The mean mesh stiffness the contact-line law scales to, c′b (0.75 ε_α + 0.25) [N/m]."""
    path = mesh.path
    single = single_pair(mesh) if mesh.compliance is not None else 1.0
    return single * (0.75 * path.contact_ratio + 0.25) if path is not None else single


def unsliced_mesh(result: Result, mesh: str) -> str | None:
    """How the run modelled ``mesh`` if it did not cut it into slices (else None).

    Read from ``result.metadata["meshes"]``: "rigid", "with one contact line", or "with no
    record of its slices (a run of an older pinwind)"; such a mesh's ``mesh_face_load_factor``
    is not computed.
    """
    how = ((result.metadata or {}).get("meshes") or {}).get(mesh, {})
    slices = int(how.get("slices", 1)) if how.get("type") == "compliant" else 0
    if slices >= 2:
        return None
    if not how:
        return "with no record of its slices (a run of an older pinwind)"
    return "rigid" if how.get("type") == "rigid" else "with one contact line"


def overlap_span(mesh: Mesh) -> float:
    """Roll length Δ = b tan β_b = ε_β p_bt a helical pair stays in contact beyond g_α [m].

    0 unless the mesh stiffness follows the contact lines (``contact_line_pair_stiffness``):
    with a user table or a constant stiffness the path is the transverse one, g_α.
    """
    if not _follows_contact_lines(mesh) or mesh.path is None:
        return 0.0
    return mesh.path.overlap_ratio * mesh.path.base_pitch


def pair_table(mesh: Mesh) -> tuple[np.ndarray, np.ndarray] | None:
    """Stiffness of one tooth pair along the path of contact (positions [m], [N/m]).

    Positions run from A over g_α + ``overlap_span``. None where the mesh stiffness is constant.
    Spur: the ISO shape (``pair_stiffness_along_path``); helical: in proportion to the pair's
    contact-line length (``contact_line_pair_stiffness``), with ISO's mean c′b (0.75 ε_α + 0.25)
    either way. A rigid mesh gets the shape too: its ratios split the force between the pairs
    for the single-tooth force.
    """
    c = mesh.compliance
    if c is not None and c.pair_stiffness is not None:
        s, k = (np.asarray(x, dtype=float) for x in c.pair_stiffness)
        return s, k
    if c is not None and c.variation == "constant":
        return None
    path = mesh.path
    if path is None:
        return None
    if _follows_contact_lines(mesh):
        return contact_line_pair_stiffness(path, _contact_line_mean(mesh))
    single = single_pair(mesh) if c is not None else 1.0
    if not 1.0 <= path.contact_ratio <= 2.0:
        return None
    return pair_stiffness_along_path(path, single)


#: Positions per gap table over the path of contact, besides the reliefs' ends.
GAP_TABLE_POINTS = 257


def profile_gap_table(mesh: Mesh) -> tuple[np.ndarray, np.ndarray] | None:
    """The gap the gears' profile reliefs leave a tooth pair along the path (positions [m], [m]).

    Positions from A over g_α, as ``pair_table``'s; piecewise linear, exact for linear reliefs
    (their ends are breakpoints), within C (h/L)²/8 of a parabolic one over its length L
    (chords h = g_α/256). The
    gap is `pinwind.gears.flank_modification.profile_gap` with gear A first, or gear B first
    where gear A is internal: along the path from A the external gear's tip comes last. None:
    neither gear has a profile relief.

    A helical mesh's slices (``helical_slices``) each roll along the transverse path g_α, so
    the table is theirs: slice s's pairs, its face section lagging the front one by ζ_s tan β_b,
    take the gap at their own roll position.

    Raises:
        InputError: a helical mesh with profile relief and one contact line (its pairs touch
            along inclined lines: one gap per pair does not hold it; slices do), or a mesh
            whose stiffness has no pair table (``variation = "constant"``).
    """
    mod_a, mod_b = mesh.gear_a.spec.modification, mesh.gear_b.spec.modification
    if not any(m.tip_relief or m.root_relief for m in (mod_a, mod_b)):
        return None
    path = mesh.path
    if path is None:
        return None
    slices = mesh.compliance.slice_number if mesh.compliance is not None else 1
    if path.overlap_ratio > 0.0 and slices < 2:
        raise InputError(
            f'mesh "{mesh.name}": profile relief on a helical mesh (ε_β = '
            f"{path.overlap_ratio:.3g}) with one contact line: its pairs touch along inclined "
            "lines, which one spring per pair does not hold; cut it into slices across the "
            'face (slices="8" on its <mesh>, or MeshCompliance(slices=8)), whose pairs each '
            "take the relief at their own roll position"
        )
    if pair_table(mesh) is None:
        raise InputError(
            f'mesh "{mesh.name}": profile relief needs the stiffness of each tooth pair along '
            'the path; remove variation = "constant" from its compliance'
        )
    first, second = (mod_b, mod_a) if mesh.gear_a.spec.internal else (mod_a, mod_b)
    g = path.length
    ends = [
        g - first.tip_relief_length, first.root_relief_length,
        second.tip_relief_length, g - second.root_relief_length,
    ]  # fmt: skip
    x = np.linspace(0.0, g, GAP_TABLE_POINTS)
    x = np.unique(np.concatenate([x, [e for e in ends if 0.0 < e < g]]))
    return x, profile_gap(first, second, g, x)


def mean_mesh_stiffness(mesh: Mesh) -> float:
    """Mean mesh stiffness of a compliant mesh over one base pitch [N/m].

    With the ISO shape: c′b (0.75 ε_α + 0.25) (ISO 6336-1 c_γα), in closed form (the shape's
    mean by construction, ``pair_table``; a mean sampled at 2000 points of the spur shape's
    steps was up to 2e-4 off it); with a table of one pair's stiffness, its mean; the value
    given when the mesh gives its mean (``MeshCompliance.mean_stiffness``).
    """
    c = mesh.compliance
    if c is not None and c.mean_stiffness is not None:
        return c.mean_stiffness
    path = mesh.path
    if c is not None and c.pair_stiffness is None and path is not None:
        return single_pair(mesh) * (0.75 * path.contact_ratio + 0.25)
    table = pair_table(mesh)
    if table is not None and path is not None:
        s, k = table
        length = path.length + overlap_span(mesh)
        x = np.linspace(0.0, path.base_pitch, 2001)[:-1]
        total = sum(
            np.where(x + j * path.base_pitch <= length + 1e-12, 1.0, 0.0)
            * np.interp(x + j * path.base_pitch, s, k)
            for j in range(int(length / path.base_pitch) + 1)
        )
        return float(np.mean(total))
    if c is not None and c.stiffness is not None:
        return c.stiffness * (0.75 * path.contact_ratio + 0.25) if path else c.stiffness
    return mesh_stiffness(_stiffness_pair(mesh))


def _rigid_rows(jac: np.ndarray, rigid: list[int], driver_index: list[int], nv: int):
    """The rigid meshes' rows (of ``jac``, the rows on the loaded flanks), then the drivers'."""
    out = [jac[i] for i in rigid]
    for j in driver_index:
        e = np.zeros(nv)
        e[j] = 1.0
        out.append(e)
    return np.array(out).reshape(-1, nv)


def effective_mass(mass: np.ndarray, constraints: np.ndarray, row: np.ndarray) -> float:
    """Mass along a mesh's line of action [kg]: 1 / (J M⁻¹ Jᵀ) over the allowed motions.

    Infinite when the allowed motions cannot deflect the mesh (the rigid rows fix it).
    """
    basis = free_motions(constraints, mass.shape[0])
    j = row @ basis
    if basis.shape[1] == 0 or np.linalg.norm(j) <= 1e-9 * np.linalg.norm(row):
        return math.inf
    m = basis.T @ mass @ basis
    return 1.0 / float(j @ np.linalg.solve(m, j))


def highest_mesh_mode(mass, constraints, jac: np.ndarray, setup: MeshSetup) -> float:
    """Frequency of the highest mode of the mesh springs at their stiffest [Hz].

    Generalised eigenvalues of (Σ k_max JᵢᵀJᵢ, M) over the motions the rigid rows allow; ``jac``
    the meshes' rows (m, nv) on their loaded flanks.
    """
    return highest_mesh_mode_and_damping(mass, constraints, jac, setup)[0]


def highest_mesh_mode_and_damping(
    mass, constraints, jac: np.ndarray, setup: MeshSetup
) -> tuple[float, float]:
    """Frequency [Hz] and damping ratio [-] of the highest mesh-spring mode at its stiffest.

    Generalised eigenvalues of (K, M), K = Σ k_max JᵢᵀJᵢ (Jᵢ the rows of ``jac``, (m, nv), on the
    loaded flanks), over the motions the rigid rows allow;
    the damping ratio of that mode φ is φᵀ C φ / (2 ω φᵀ M φ) with C = Σ cᵢ JᵢᵀJᵢ, the mesh
    dashpots (the damping the mode has physically, whatever the step).
    """
    elements = []
    for spec, path in ((s, setup.paths[s.mesh]) for s in setup.compliant):
        k_max = spec.stiffness
        if len(path.pair_stiffness):
            # The mesh stiffness at 400 entering positions over a base pitch: the sum over the
            # pairs in contact, whole arrays at a time (a loop over the positions cost more
            # than the short runs it sets up).
            x = np.linspace(0.0, path.base_pitch, 400)
            total = np.zeros_like(x)
            for j in range(int(path.path_length / path.base_pitch) + 1):
                at = x + j * path.base_pitch
                pair = np.interp(at, path.pair_position, path.pair_stiffness)
                total += np.where(at <= path.path_length, pair, 0.0)
            k_max = float(total.max())
        row = jac[spec.mesh]
        elements.append(SpringElement(str(spec.mesh), "mesh", k_max, spec.damping, row))
    stiffness, damping = element_matrices(elements, mass.shape[0])
    modes = natural_modes(mass, stiffness, damping, constraints)
    if not modes:
        return 0.0, 0.0
    return modes[-1].frequency, modes[-1].damping_ratio


def _warn_if_damped_numerically(
    frequency: float, dt: float, physical_ratio: float, scheme: Integrator
) -> None:
    """Warn when the step damps the highest mesh mode more than its dashpots, or steps it coarsely.

    Coarsely: fewer than ``RESOLVING_STEPS`` steps per period; stable, but then its
    period and response are the step's, not the mesh's.
    """
    advice = dt_advice(frequency, dt, physical_ratio, scheme)
    if advice.numerical_ratio > physical_ratio:
        why = "the step, not the mesh damping, sets how much that mode responds"
    elif frequency > 0.0 and advice.steps_per_period < RESOLVING_STEPS:
        why = "the step does not resolve that mode, so it sets its period and response"
    else:
        return
    warnings.warn(StepTooCoarse(advice.text() + "; " + why), stacklevel=4)
