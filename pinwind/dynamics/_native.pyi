"""Compiled step loop of pinwind (pinwind/dynamics/cpp/): typed structs and the stepper.

Also the compiled parts of the run statistics and of the log's columns.

Every struct is filled from Python (``dynamics/stepper.py``, ``dynamics/compliant.py``,
``dynamics/mesh.py``); SI units throughout. Arrays are float64 (Eigen vectors and row-major
matrices); lists of ints are Pinocchio joint or velocity indices.
"""

import enum

import numpy as np
from numpy.typing import NDArray

Vector = NDArray[np.float64]
Matrix = NDArray[np.float64]
Bytes = NDArray[np.uint8]
Indices = NDArray[np.int64]

class SolverSettings:
    """proxsuite settings (``cpp/constrained_qp.hpp``)."""

    eps_abs: float
    eps_rel: float
    max_iter: int
    iterative: bool  # redundant rows by proxsuite instead of the Schur pseudo-inverse
    def __init__(self) -> None: ...

class JointType(enum.Enum):
    """A joint pinwind models: revolute or prismatic, along an axis of the joint frame or any.

    The prismatic joints are the slides of compliant bearings (``model/gearbox.py``).
    """

    revolute_x = 0
    revolute_y = 1
    revolute_z = 2
    revolute_unaligned = 3
    prismatic_x = 4
    prismatic_y = 5
    prismatic_z = 6
    prismatic_unaligned = 7

class GeneratorLaw(enum.Enum):
    """A generator law (``cpp/generator.hpp``; ``loads/generator.py``)."""

    constant = 0
    linear_slip = 1
    variable_speed = 2  # K ω², constant power above rated
    induction = 3  # steady-state induction machine
    induction_dq = 4  # Krause's dq induction machine

class CpModel(enum.Enum):
    """How a rotor's power coefficient is computed (``cpp/rotor.hpp``)."""

    heier = 0  # Heier's analytical C_p times cp_scale
    table = 1  # bilinear in the table C_p(λ, β)

class ThrustModel(enum.Enum):
    """How a rotor's thrust coefficient is computed (``cpp/rotor.hpp``)."""

    momentum = 0  # actuator-disc momentum theory from C_p
    table = 1  # bilinear in the table C_t(λ, β)

class RunCode(enum.Enum):
    """How a block of steps ended (``cpp/stepper.hpp``)."""

    completed = 0
    diverged = 1
    solver_failed = 2
    conflicting_constraints = 3

class JointTree:
    """The Pinocchio model as arrays: one entry per joint (revolute bearings only)."""

    names: list[str]
    parent: list[int]
    type: list[JointType]
    axis: Matrix  # (joints, 3) axis of revolute_unaligned joints
    placement: list[Matrix]  # 4 × 4 placement in the parent joint's frame
    mass: Vector  # [kg]
    com: Matrix  # (joints, 3) centre of mass in the joint frame [m]
    inertia: Matrix  # (joints, 9) rotational inertia about the com [kg·m²]
    armature: Vector  # [kg·m²]
    gravity: Vector  # (3,) [m/s²]
    def __init__(self) -> None: ...

class MeshConstants:
    """Geometry of every mesh (``cpp/mesh_rows.hpp``; ``dynamics/mesh.py`` MeshSet)."""

    joint_ids: list[int]
    slot_a: list[int]
    slot_b: list[int]
    centre_a: Matrix  # (meshes, 3) [m], gear A's joint frame
    centre_b: Matrix
    axis_a: Matrix
    axis_b: Matrix  # (m, 3) axis of gear B in its joint frame
    mu: Vector
    sigma: Vector
    support: Matrix  # (slots, nv)
    cos_a: Vector
    sin_a: Vector
    eps: Vector
    tan_beta_b: Vector
    joint_a: list[int]
    joint_b: list[int]
    def __init__(self) -> None: ...

class MeshPathSpec:
    """Path of contact of one mesh (``cpp/mesh_path.hpp``)."""

    base_pitch: float  # [m]
    path_length: float  # [m]
    roll_start: float  # [m]
    roll_radius_a: float  # [m]
    pitch_position: float  # [m] the pitch point's x from the path start
    entering_front: float  # [m]
    entering_back: float  # [m]
    angle_ref_a: float  # [rad]
    reference_a: Vector  # (3,) unit vector ⟂ axis in gear A's joint frame
    pair_position: Vector  # [m] from the path start
    pair_stiffness: Vector  # [N/m]
    gap_position: Vector  # [m] from the path start; empty: unmodified flanks
    gap_value: Vector  # [m], the profile modifications' gap of a pair (gears/flank_modification.py)
    def __init__(self) -> None: ...

class CompliantMeshSpec:
    """Constants of one compliant mesh (``cpp/compliant_mesh.hpp``)."""

    mesh: int
    stiffness: float  # [N/m]
    damping: float  # [N·s/m]
    backlash: float  # [m]
    base_radius_a: float  # [m], signed
    base_radius_b: float  # [m], signed
    reference_b: Vector  # (3,)
    tangential_ref: float  # [m]
    axial_ref: float  # Z at the reference pose (``axial_offset``) [m]
    base_radius_sum: float  # [m]
    radial_sign: float
    involute_ref: float
    tangential_offset: float  # [m]
    radial_offset: float  # [m]
    friction: float  # μ of the flanks [-] (cpp/flank_friction.hpp); 0: none
    friction_law: FrictionLaw  # constant (friction) or iso14179 (μ_mz in the step)
    iso_face_width: float  # b [m]
    iso_reduced_radius: float  # ρ_redC at the pitch point, normal section [m]
    iso_sum_velocity_per_spin: float  # c_v: v_Σc = c_v |ω_B − ω_A| [m]
    iso_viscosity: float  # η [Pa·s]
    iso_roughness: float  # Ra [m]
    iso_lubricant_factor: float  # X_L [-]
    contact_line_span: float  # Δ = b tan β_b of a single helical contact line [m]; 0: points
    slices: int  # N across the face width; 1: one contact line
    axis_b: Vector  # (3,), gear B's axis in its joint frame
    slice_offset: Vector  # (N,) [m] from the face centre along gear A's axis
    slice_gap: Vector  # (N,) [m] lead modifications' gap, front flank
    slice_gap_back: Vector  # (N,) [m] the back flank's
    slice_shift: Vector  # (N,) [m] helical: each slice's entering-pair shift, front flank
    slice_shift_back: Vector  # (N,) [m] the same, back flank
    slice_path_length: float  # g_α of a helical slice's path [m]
    slice_pair_position: Vector  # helical slice path's pair table: positions [m]
    slice_pair_stiffness: Vector  # and one pair's stiffness over the whole face [N/m]
    face_width: float  # b [m], for the line loads
    def __init__(self) -> None: ...

class FrictionLaw(enum.Enum):
    """How a compliant mesh's μ is found (``cpp/flank_friction.hpp``)."""

    constant = 0
    iso14179 = 1

def iso14179_friction_coefficient(
    force: float,
    face_width: float,
    sum_velocity: float,
    reduced_radius: float,
    viscosity: float,
    roughness: float,
    lubricant_factor: float,
) -> float:
    """ISO/TR 14179-2's μ_mz in SI (the step's restatement of ``mean_friction_coefficient``)."""

class TorsionalSpringSpec:
    """A torsional spring-damper between two joints (``cpp/torsional_spring.hpp``)."""

    index_1: int
    index_2: int  # −1: across joint 1 alone (to the body it turns in)
    stiffness: float  # [N·m/rad]
    damping: float  # [N·m·s/rad]
    preload_angle: float  # [rad]
    def __init__(self) -> None: ...

class BearingLaw(enum.Enum):
    """A compliant bearing's radial law (``cpp/bearing_spring.hpp``)."""

    linear = 0
    roller_sum = 1

class BearingSpringSpec:
    """A compliant bearing's springs on its slides (``cpp/bearing_spring.hpp``); −1: none."""

    index_x: int
    index_y: int
    radial_stiffness: float  # [N/m]
    radial_damping: float  # [N·s/m], in contact only
    clearance: float  # [m]
    index_axial: int
    axial_stiffness: float  # [N/m]
    index_tilt_x: int
    index_tilt_y: int
    tilt_stiffness: float  # [N·m/rad]
    law: BearingLaw
    rollers: int  # Z, roller_sum
    contact_stiffness: float  # K_n [N/m^n], roller_sum
    load_exponent: float  # n, roller_sum
    def __init__(self) -> None: ...

class BearingRowSpec:
    """A bearing row: a spring-damper at its position (``cpp/bearing_rows.hpp``); −1: none."""

    index_x: int
    index_y: int
    index_axial: int
    index_tilt_x: int
    index_tilt_y: int
    position: float  # a [m] along the bearing axis from the bearing centre
    stiffness: Vector  # (axial, u, w [N/m], about u, about w [N·m/rad])
    damping: Vector  # (axial, u, w [N·s/m], about u, about w [N·m·s/rad])
    has_clearance: bool  # radial directions between two sides (False: linear)
    clearance: float  # c [m] from the centre to a side (negative: a preload)
    def __init__(self) -> None: ...

def bearing_row_map(row: BearingRowSpec, nv: int) -> Matrix:
    """B (5, nv): the row's deflections δ = B q (axial, along u, along w, about u, about w).

    From the velocity coordinates (``cpp/bearing_rows.hpp``), for the linear model.
    """

class BearingSlides:
    """A compliant bearing's slides as a block reads them (``cpp/bearing_spring.hpp``); −1: none."""

    bearing: int  # its column in the bearing series
    x: int  # joint column of the radial slide along u
    y: int  # joint column of the radial slide along w
    z: int  # joint column of the axial slide
    tilt_x: int  # joint column of the tilt hinge about u
    tilt_y: int  # joint column of the tilt hinge about w
    axes: Matrix  # (3, 3) rows u, w, k in the joint frame
    spring: BearingSpringSpec  # its laws (indices unused)
    rows: list[BearingRowSpec]  # its rows, when they are its springs (indices unused)
    def __init__(self) -> None: ...

class GeneratorSpec:
    """A generator law on one joint (``cpp/generator.hpp``; ``loads/generator.py``)."""

    index: int
    law: GeneratorLaw
    torque: float  # [N·m]
    slope: float  # [N·m·s/rad]
    sync_speed: float  # [rad/s]
    gain: float  # [N·m·s²/rad²]
    rated_power: float  # [W]
    rated_torque: float  # [N·m] (0: region 3 at constant power)
    rated_speed: float  # [rad/s]
    slip: float  # region 2½'s slip
    stator_resistance: float  # [Ω]
    rotor_resistance: float  # [Ω]
    stator_leakage: float  # [H]
    rotor_leakage: float  # [H]
    magnetizing: float  # [H]
    voltage: float  # line-to-line RMS [V]
    frequency: float  # [Hz]
    pole_pairs: int
    phases: float
    steady_start: bool
    def __init__(self) -> None: ...

class PitchControlSpec:
    """A collective blade-pitch controller (``cpp/rotor.hpp``; ``loads/pitch_control.py``)."""

    enabled: bool
    speed_set: float  # Ω_ref [rad/s]
    kp: float  # K_P(0) [s]
    ki: float  # K_I(0) [-]
    gain_angle: float  # θ_K [rad]
    corner: float  # ω_c [rad/s]
    pitch_min: float  # [rad]
    pitch_max: float  # [rad]
    rate: float  # β̇_max [rad/s]
    def __init__(self) -> None: ...

class RotorSpec:
    """Rotor aerodynamics on one joint (``cpp/rotor.hpp``; ``loads/rotor.py``)."""

    index: int
    radius: float  # [m]
    air_density: float  # [kg/m³]
    pitch: float  # [rad]: fixed, or the controller's initial pitch
    pitch_control: PitchControlSpec
    cp_model: CpModel
    cp_scale: float
    table_tsr: list[float]
    table_pitch: list[float]  # [rad]
    table_cp: list[float]  # row-major (tsr, pitch)
    wind_column: int
    ct_model: ThrustModel
    ct_tsr: list[float]
    ct_pitch: list[float]  # [rad]
    ct_values: list[float]  # row-major (tsr, pitch)
    hub: bool  # the thrust, weight and shear moment load hub_load's body
    hub_load: HubLoadSpec  # where (its column unused)
    weight: Vector  # the rotor's weight [N] in the hub's fixed axes
    shear_arm: float  # ℓ [m]: the shear moment about the hub's y is ℓ T
    def __init__(self) -> None: ...

class GeneralizedAlpha:
    """The generalized-α method's constants for a spectral radius ρ∞ (time_step.hpp; read-only)."""

    rho_infinity: float
    alpha_m: float
    alpha_f: float
    gamma: float
    beta: float

def generalized_alpha(rho_infinity: float) -> GeneralizedAlpha:
    """The constants the step uses for ρ∞ (clamped to [0, 1]; Integrator checks the range)."""

def shaft_speed_torque(generator: GeneratorSpec, speed: float) -> float:
    """Torque on the shaft τ(ω) [N·m] of a law of the shaft speed (−T_gen; not the dq machine)."""

def induction_torque(generator: GeneratorSpec, speed: float) -> float:
    """Steady-state induction machine torque on the shaft [N·m] at speed [rad/s] (motoring > 0)."""

def rotor_torque(rotor: RotorSpec, speed: float, wind: float) -> float:
    """Aerodynamic rotor torque [N·m] at rotor speed [rad/s] and wind speed [m/s]."""

def rotor_cp(rotor: RotorSpec, tsr: float) -> float:
    """Power coefficient C_p at tip-speed ratio λ."""

def rotor_ct(rotor: RotorSpec, tsr: float) -> float:
    """Thrust coefficient C_t at tip-speed ratio λ."""

def rotor_thrust(rotor: RotorSpec, speed: float, wind: float) -> float:
    """Aerodynamic thrust [N] at rotor speed [rad/s] and wind speed [m/s]."""

def momentum_ct(cp: float) -> float:
    """Thrust coefficient of an ideal actuator disc with power coefficient C_p."""

def bearing_slide_series(
    angle: Matrix,
    slides: list[BearingSlides],
    displacement: Matrix | None,
    elastic: Matrix | None = None,
) -> None:
    """Each bearing's displacement [m] and springs' elastic force [N] from joint coordinates.

    ``angle`` (samples, joints) is a block's; the outputs are (samples, bearings, 3), joint frame,
    either None: not computed.
    """

def split_about_axes(
    vectors: Matrix, axes: Matrix, along: Matrix | None, across: Matrix | None = None
) -> None:
    """v·k and |v − (v·k) k| of vectors (samples, bearings, 3) about unit axes (bearings, 3).

    Into (samples, bearings) C-contiguous float64 arrays, either None (not computed); the
    operations of numpy's element-wise formula in its order (``dynamics/bearing_load.py``).
    Raises ValueError for shapes that do not fit.
    """

def fold_columns(values: Matrix, out: Matrix) -> None:
    """min, max, sum, sum of squares and last value of each column of an (m, k) block.

    ``values`` may have any strides; ``out`` is a (5, k) float64 view, written in place.
    """

def fold_magnitudes(values: Matrix, out: Matrix) -> None:
    """The same for the magnitudes of the vectors of an (m, 3e) block into a (5, e) ``out``.

    Columns 3j, 3j + 1, 3j + 2 are vector j's x, y, z; |v| = √((x² + y²) + z²).
    """

def shuffle_series(values: Matrix, series: Indices, planes: Bytes) -> None:
    """The byte planes of the rows ``series`` of a (k, m) block into ``planes`` (8 · V · m).

    The V rows' values, one row after the other, as one run of V · m float64 values: byte 0
    (little-endian) of every value, then byte 1, ..., byte 7 (``cpp/byte_planes.hpp``). The
    rows of ``values`` must be contiguous.
    """

def unshuffle_series(
    planes: Bytes,
    m: int,
    first: int,
    count: int,
    rows: Indices,
    out: Matrix,
    at: int,
    stream: bool = False,
) -> None:
    """Samples ``first`` to ``first + count`` of V shuffled series into ``out[rows[j], at:]``.

    Each series has m samples; series j is skipped where ``rows[j]`` < 0. ``out``: float64
    (series, samples) with contiguous rows. ``stream``: non-temporal stores, for memory not read
    soon. Raises ValueError for sizes or indices that do not fit.
    """

def fill_rows(
    values: Vector, rows: Indices, out: Matrix, at: int, count: int, stream: bool = False
) -> None:
    """``out[rows[j], at:at + count] = values[j]`` where ``rows[j]`` ≥ 0 (as unshuffle_series)."""

def place_columns_chunk(
    chunk: Bytes,
    channel: int,
    width: int,
    pose_width: int,
    row_of: Indices,
    out: Matrix,
    at: int,
    room: int,
    start: float | None,
    stop: float | None,
    pose_series: Indices,
    posed: bool,
    zeroed_from: int = 0,
) -> tuple[int, np.ndarray, np.ndarray, str, int]:
    """A decompressed chunk's columns records placed into ``out`` from sample ``at``.

    Every record of ``channel`` (docs/log_format.md, "Columns", layout 3), its samples with
    start ≤ t ≤ stop [s] (None: no bound) one record after the other: varying series j
    unshuffled and constant ones filled into ``out[row_of[j]]`` (skipped where < 0), but a
    constant +0.0 in the rows from ``zeroed_from`` on (they are +0.0 wherever nothing is placed:
    new memory; in the rows before it, memory an earlier read used, every value is written),
    around the caches (``cpp/column_chunks.hpp``). Returns (samples, pose rows, poses, damage,
    highest), highest the last row given a value other than +0.0 (-1: none):
    the posed samples in the window (their samples in ``out``) and their ``pose_series``,
    (len(pose_series), posed samples), when ``posed``; damage is "" or why the chunk's records
    do not fit their lengths. Nothing is placed when damage is not "", when samples is -1 (a
    record's samples in the window are not consecutive) or more than ``room``. Raises
    ValueError for sizes or indices that do not fit ``out``.
    """

def kind_fields() -> list[str]:
    """The fields of ``StepperSpec`` that hold a kind of element or constraint.

    In the kinds' order: the elements' (their forces summed in it), then the constraints' (their
    rows).
    """

class HubLoadSpec:
    """Six load components on a body at a point (``cpp/hub_loads.hpp``; ``loads/hub_loads.py``)."""

    joint: int  # Pinocchio id of the body's joint
    parent: int  # the joint its bearing sits in (above a compliant bearing's slides; 0: world)
    columns: list[int]  # velocity columns of the joints that move the body
    axes: Matrix  # 3 × 3: the hub axes x, y, z (columns) in the joint frame
    placement: Matrix  # 3 × 3: the joint's undeflected rotation in that joint's frame
    point: Vector  # where the force acts, in the joint frame [m]
    rotating: bool  # the axes turn with the joint
    column: int  # the first of its six input columns (F_x, F_y, F_z [N], M_x, M_y, M_z [N·m])
    def __init__(self) -> None: ...

class BearingFrictionSpec:
    """One rolling bearing's friction moment on its joint (``cpp/bearing_friction.hpp``)."""

    index: int  # velocity index of the joint's rotation
    bearing: int  # its column of the bearing series, or -1
    no_load_coefficient: float  # c0 of M0 = max(c0 |ω|^(2/3), M0_min) [N·m·(s/rad)^(2/3)]
    no_load_minimum: float  # M0_min [N·m]
    load_moment: float  # M1 = f1 P1 d_m [N·m] of a fixed load (follow_load False)
    stick_speed: float  # ω_s of the regularised sign [rad/s] (> 0)
    follow_load: bool  # P1 from the step before's loads (bearing_friction.hpp)
    row: int  # its column of the row series, or -1: the bearing's reaction
    load_coefficient: float  # f1 d_m [m]: M1 = load_coefficient P1
    load_rule: int  # 0 F_r, 1 ball, 2 angular ball, 3 roller (losses.LOAD_RULES)
    contact_cot: float  # cot α of rules 2 and 3 [-]
    axis: Vector  # the bearing axis k in its joint frame [-]
    def __init__(self) -> None: ...

def bearing_friction_load(rule: int, contact_cot: float, radial: float, axial: float) -> float:
    """P1 [N] under F_r and F_a [N] by load rule 0-3 (``cpp/bearing_friction.hpp``)."""

class StepperSpec:
    """Everything a run needs besides the initial state.

    A field per kind of element and constraint (``kind_fields``; ``cpp/element_kinds.hpp``),
    filled by ``dynamics/element_specs.py``.
    """

    tree: JointTree
    meshes: MeshConstants
    paths: list[MeshPathSpec]
    springs: list[TorsionalSpringSpec]
    bearing_damping: Vector  # [N·m·s/rad] per velocity
    bearing_springs: list[BearingSpringSpec]
    bearing_rows: list[BearingRowSpec]
    compliant_meshes: list[CompliantMeshSpec]
    generators: list[GeneratorSpec]
    rotors: list[RotorSpec]
    hub_loads: list[HubLoadSpec]
    bearing_friction: list[BearingFrictionSpec]
    rigid_meshes: list[int]
    driver_index: list[int]
    input_columns: int  # per-sample inputs of the elements (wind speeds, hub loads)
    bearing_joints: list[int]  # Pinocchio ids of the joints recorded as bearings
    frame_parent: list[int]
    frame_placement: list[Matrix]
    dt: float  # [s]
    projection_tol: float
    rho_infinity: float
    solver: SolverSettings
    def __init__(self) -> None: ...

class Family(enum.Enum):
    """The elements a series has one column per (``cpp/series.hpp``)."""

    run = 0  # one: the run itself
    joint = 1  # one per velocity
    mesh = 2
    bearing = 3  # one per bearing (StepperSpec.bearing_joints)
    body = 4  # one per recorded link
    generator = 5
    rotor = 6
    row = 7  # one per bearing row (StepperSpec.bearing_rows)
    slice = 8  # one per slice of every sliced compliant mesh (CompliantMeshSpec.slices > 1)

class Series(enum.Enum):
    """Every series the compiled run writes, named as the Result's array or ledger term.

    Declared once in ``cpp/series.hpp``, with its family and components (``series_layout``).
    """

    time = 0
    angle = 1
    speed = 2
    acceleration = 3
    torque = 4
    mesh_normal = 5
    mesh_tangential = 6
    mesh_radial = 7
    mesh_axial = 8
    mesh_flank = 9
    mesh_normal_front = 10
    mesh_normal_back = 11
    transmission_error = 12
    mesh_force_on_b = 13
    pitch_point = 14
    mesh_deflection = 15
    mesh_contact_position = 16
    mesh_pairs = 17
    mesh_single_tooth_force = 18
    mesh_face_load_factor = 19
    mesh_load_centre = 20
    bearing_force = 21
    bearing_moment = 22
    bearing_force_local = 23
    bearing_moment_local = 24
    body_position = 25
    body_quaternion = 26
    constraint_residual = 27
    kinetic = 28
    potential_spring = 29
    work_applied = 30
    work_drivers = 31
    work_springs = 32
    work_gravity = 33
    work_constraints = 34
    dissipated = 35
    work_parametric = 36
    generator_torque = 37
    rotor_torque = 38
    rotor_power = 39
    rotor_tip_speed_ratio = 40
    rotor_power_coefficient = 41
    rotor_wind_speed = 42
    rotor_thrust = 43
    rotor_thrust_coefficient = 44
    rotor_pitch = 45
    row_force = 46
    row_moment = 47
    bearing_friction_moment = 48
    bearing_friction_power = 49
    mesh_sliding_velocity = 50
    mesh_friction_force = 51
    mesh_friction_power = 52
    friction_loss = 53
    mesh_peak_line_load = 54
    mesh_mean_line_load = 55
    slice_line_load = 56

def series_layout(series: Series) -> tuple[Family, int]:
    """The family of a series and its components (1 scalar, 3 vector, 4 quaternion)."""

class OutputArrays:
    """The arrays of one block of samples, one per ``Series``, written in place.

    Series s of family F with c components is a row-major float64 array of
    samples × count(F) × c values (a Result's array); a family without elements needs none.
    """

    def __init__(self) -> None: ...
    def set(self, series: Series, values: NDArray[np.float64]) -> None:
        """The array the run writes ``series`` into."""
    def __setitem__(self, series: Series, values: NDArray[np.float64]) -> None: ...
    def __getitem__(self, series: Series) -> NDArray[np.float64] | None: ...

class RunStatus:
    """How a block ended, and where (the step and time the error names)."""

    code: RunCode
    sample: int
    step: int
    time: float
    what: str
    residual: float
    primal: float
    dual: float
    iterations: int

class Assembly:
    """The terms of a step's equations of motion at one state (``cpp/stepper.hpp``)."""

    mass: Matrix  # M(q) (nv, nv) [kg·m²]
    bias: Vector  # b = C(q, v) v + g(q) (nv,) [N·m]
    jac: Matrix  # J (rows, nv): rigid meshes in file order, then drivers and locks
    gamma: Vector  # γ = J̇ v (rows,) [m/s² or rad/s²]

class Stepper:
    """One run of the compiled step loop."""

    def __init__(self, spec: StepperSpec, q0: Vector, v0: Vector, samples: int) -> None: ...
    def run(
        self,
        k0: int,
        k1: int,
        torque: Matrix,
        target: Matrix,
        out: OutputArrays,
        inputs: Matrix,
        stride: int = 1,
    ) -> RunStatus:
        """Steps samples [k0, k1) into rows 0 … k1 − k0 − 1 of out; inputs (k1 − k0, columns).

        torque (k1 − k0, nv) or inputs (k1 − k0, columns) of one row only: held over the block.

        With stride > 1 only every stride-th sample from 0 and the run's last are recorded, in
        consecutive rows of out.
        """
    def equilibrium(
        self,
        torque: Matrix,
        target: Matrix,
        inputs: Matrix,
        max_iterations: int,
        tolerance: float,
        load_steps: int = 1,
    ) -> EquilibriumStatus:
        """Moves the start to static equilibrium under the first sample's loads.

        With load_steps > 1 the torques in that many equal steps, each solved from the last.
        """
    def mass_matrix(self, q: Vector) -> Matrix:
        """Joint-space inertia at q from the compiled copy of the model [kg·m²]."""
    @property
    def constant_mass(self) -> bool:
        """Whether M(q) is the same at every q: the step then takes it once, not by CRBA."""
    @property
    def mesh_frames(self) -> list[int]:
        """Per mesh, the joint carrying its geometry if its row is constant (0: world), else -1."""
    def assemble(self, q: Vector, v: Vector) -> Assembly:
        """M, b, J and γ of the step at (q, v), with the rows' current flanks; no step taken."""
    def element_forces(self, q: Vector, v: Vector) -> ElementForces:
        """The elements' force, tangents and stored energy at (q, v), each element new."""
    @property
    def saves_state(self) -> bool:
        """Whether every element and constraint copies its state, so that save() works."""
    def save(self) -> StepperState:
        """The run's state before its next sample (``cpp/stepper.hpp`` StepperState)."""
    def restore(self, state: StepperState) -> None:
        """Takes the run back to a state save() gave (ValueError for another run's)."""

class StepperState:
    """A run's state between two samples (``Stepper.save``): opaque, of the model's size."""

class ElementForces:
    """The elements' forces at one state and their derivatives (``cpp/stepper.hpp``)."""

    force: Vector  # Σ f_e at (q, v) [N·m or N]
    stiffness: Matrix  # K = −∂f/∂q as the step takes it
    damping: Matrix  # C = −∂f/∂v as the step takes it
    potential: float  # Σ U_e at q [J]

class EquilibriumStatus:
    """How a static start went (``cpp/stepper.hpp`` Stepper::equilibrium)."""

    iterations: int  # Newton iterations taken
    converged: bool  # the last correction fell below the tolerance
    correction: float  # max |Δq| of the last iteration [rad or m]
    displacement: float  # max |q − q₀| [rad or m]
    largest: int  # the velocity coordinate where |q − q₀| is largest
    residual: float  # relative residual of the last linear solve
    flank_switches: int  # compliant meshes that handed their load to the other flank

class MeshRows:
    """Rows of all meshes at one state, split in their tangential, radial and axial parts.

    For flank s the row is ``cos_a * s * jac_t + sin_a * eps * jac_r - s * tan_beta_b * jac_k``
    (same for the bias; ``jac_k`` is zero for spur meshes, whose rows have no axial part);
    ``row_*``, ``bias_*`` and ``normal_*`` are formed by ``cpp/mesh_rows.hpp`` flank_row and
    line_of_action, the functions the step loop uses. Read-only views.
    """

    jac_t: Matrix  # (m, nv) row part along t
    jac_r: Matrix  # (m, nv) row part along r̂
    jac_k: Matrix  # (m, nv) row part along k (helical meshes; 0 for spur ones)
    bias_t: Vector  # (m,) parts of ċ − J q̈
    bias_r: Vector
    bias_k: Vector
    tangent: Matrix  # (m, 3) unit t in world
    radial: Matrix  # (m, 3) unit r̂ in world
    pitch_point: Matrix  # (m, 3) P in world [m]
    axis: Matrix  # (m, 3) unit axis k of gear A in world
    row_front: Matrix  # (m, nv) row J of the front (+1) flank
    row_back: Matrix  # (m, nv) row J of the back (−1) flank
    bias_front: Vector  # (m,) their biases
    bias_back: Vector
    normal_front: Matrix  # (m, 3) their lines of action n in world
    normal_back: Matrix

def axial_offset(
    k: Vector, k_b: Vector, centre_a: Vector, centre_b: Vector, pitch_point: Vector
) -> float:
    """Axial position [m] of gear B's flank relative to gear A's at the pitch point.

    Along A's axis k: (c_B − P)·k_B / (k·k_B) + (P − c_A)·k (``cpp/mesh_rows.hpp`` axial_offset).
    """

def mesh_rows(
    meshes: MeshConstants, jac: Matrix, djac: Matrix, v: Vector, origin: Matrix, rot: Matrix
) -> MeshRows:
    """Rows of every mesh at one state (``MeshRows``)."""
