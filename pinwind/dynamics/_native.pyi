"""Compiled step loop of pinwind (pinwind/dynamics/cpp/): typed structs and the stepper.

Also the compiled parts of the run statistics and of the log's columns.

Every struct is filled from Python (``dynamics/stepper.py``, ``dynamics/compliant.py``,
``dynamics/mesh.py``); SI units throughout. Arrays are float64 (Eigen vectors and row-major
matrices); lists of ints are Pinocchio joint or velocity indices.
"""

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

class JointTree:
    """The Pinocchio model as arrays: one entry per joint (revolute bearings only)."""

    names: list[str]
    parent: list[int]
    type: list[int]  # 0, 1, 2 = revolute about x, y, z of the joint frame; 3 = unaligned
    axis: Matrix  # (joints, 3) axis of type-3 joints
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
    mu: Vector
    sigma: Vector
    support: Matrix  # (slots, nv)
    cos_a: Vector
    sin_a: Vector
    eps: Vector
    tan_beta: Vector
    joint_a: list[int]
    joint_b: list[int]
    def __init__(self) -> None: ...

class MeshPathSpec:
    """Path of contact of one mesh (``cpp/mesh_path.hpp``)."""

    base_pitch: float  # [m]
    path_length: float  # [m]
    roll_start: float  # [m]
    roll_radius_a: float  # [m]
    entering_front: float  # [m]
    entering_back: float  # [m]
    angle_ref_a: float  # [rad]
    reference_a: Vector  # (3,) unit vector ⟂ axis in gear A's joint frame
    pair_position: Vector  # [m] from the path start
    pair_stiffness: Vector  # [N/m]
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
    base_radius_sum: float  # [m]
    radial_sign: float
    involute_ref: float
    tangential_offset: float  # [m]
    radial_offset: float  # [m]
    def __init__(self) -> None: ...

class TorsionalSpringSpec:
    """A torsional spring-damper between two joints (``cpp/torsional_spring.hpp``)."""

    index_1: int
    index_2: int
    stiffness: float  # [N·m/rad]
    damping: float  # [N·m·s/rad]
    preload_angle: float  # [rad]
    def __init__(self) -> None: ...

class GeneratorSpec:
    """A generator law on one joint (``cpp/generator.hpp``; ``loads/generator.py``).

    law: 0 constant, 1 linear slip, 2 variable speed (K ω², constant power above rated),
    3 steady-state induction machine, 4 dq induction machine (Krause).
    """

    index: int
    law: int
    torque: float  # [N·m]
    slope: float  # [N·m·s/rad]
    sync_speed: float  # [rad/s]
    gain: float  # [N·m·s²/rad²]
    rated_power: float  # [W]
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

class RotorSpec:
    """Rotor aerodynamics on one joint (``cpp/rotor.hpp``; ``loads/rotor.py``).

    cp_model: 0 Heier's analytical C_p times cp_scale, 1 the table C_p(λ, β).
    """

    index: int
    radius: float  # [m]
    air_density: float  # [kg/m³]
    pitch: float  # [rad]
    cp_model: int
    cp_scale: float
    table_tsr: list[float]
    table_pitch: list[float]  # [rad]
    table_cp: list[float]  # row-major (tsr, pitch)
    wind_column: int
    def __init__(self) -> None: ...

def induction_torque(generator: GeneratorSpec, speed: float) -> float:
    """Steady-state induction machine torque on the shaft [N·m] at speed [rad/s] (motoring > 0)."""

def rotor_torque(rotor: RotorSpec, speed: float, wind: float) -> float:
    """Aerodynamic rotor torque [N·m] at rotor speed [rad/s] and wind speed [m/s]."""

def rotor_cp(rotor: RotorSpec, tsr: float) -> float:
    """Power coefficient C_p at tip-speed ratio λ."""

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

class StepperSpec:
    """Everything a run needs besides the initial state."""

    tree: JointTree
    meshes: MeshConstants
    paths: list[MeshPathSpec]
    rigid_meshes: list[int]
    compliant_meshes: list[CompliantMeshSpec]
    springs: list[TorsionalSpringSpec]
    generators: list[GeneratorSpec]
    rotors: list[RotorSpec]
    input_columns: int  # per-sample inputs of the elements (wind speeds)
    bearing_damping: Vector  # [N·m·s/rad] per velocity
    driver_index: list[int]
    frame_parent: list[int]
    frame_placement: list[Matrix]
    dt: float  # [s]
    projection_tol: float
    implicit_theta: float
    solver: SolverSettings
    def __init__(self) -> None: ...

class OutputArrays:
    """The arrays of one block of samples, written in place (a Result's, row-major)."""

    time: Vector
    angle: Matrix
    speed: Matrix
    acceleration: Matrix
    torque: Matrix
    mesh_normal: Matrix
    mesh_tangential: Matrix
    mesh_radial: Matrix
    mesh_axial: Matrix
    mesh_flank: Matrix
    transmission_error: Matrix
    mesh_force_on_b: NDArray[np.float64]
    pitch_point: NDArray[np.float64]
    mesh_deflection: Matrix
    mesh_contact_position: Matrix
    mesh_pairs: Matrix
    mesh_single_tooth_force: Matrix
    bearing_force: NDArray[np.float64]
    bearing_moment: NDArray[np.float64]
    bearing_force_local: NDArray[np.float64]
    bearing_moment_local: NDArray[np.float64]
    body_position: NDArray[np.float64]
    body_quaternion: NDArray[np.float64]
    constraint_residual: Vector
    kinetic: Vector
    potential_spring: Vector
    work_applied: Vector
    work_drivers: Vector
    work_springs: Vector
    work_gravity: Vector
    work_constraints: Vector
    dissipated: Vector
    generator_torque: Matrix
    rotor_torque: Matrix
    rotor_power: Matrix
    rotor_tip_speed_ratio: Matrix
    rotor_power_coefficient: Matrix
    rotor_wind_speed: Matrix
    def __init__(self) -> None: ...

class RunStatus:
    """How a block ended: code 0 completed, 1 diverged, 2 solver failed, 3 conflicting rows."""

    code: int
    sample: int
    step: int
    time: float
    what: str
    residual: float
    primal: float
    dual: float
    iterations: int

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
    ) -> RunStatus:
        """Steps samples [k0, k1) into rows 0 … k1 − k0 − 1 of out; inputs (k1 − k0, columns)."""
    def mass_matrix(self, q: Vector) -> Matrix:
        """Joint-space inertia at q from the compiled copy of the model [kg·m²]."""

def mesh_rows(
    meshes: MeshConstants, jac: Matrix, djac: Matrix, v: Vector, origin: Matrix, rot: Matrix
) -> tuple[
    Matrix,
    Matrix,
    Vector,
    Vector,
    Matrix,
    Matrix,
    Matrix,
    Matrix,
    Matrix,
    Matrix,
    Vector,
    Vector,
    Matrix,
    Matrix,
]:
    """Rows of every mesh at one state.

    J_t, J_r, γ_t, γ_r, t, r̂, P, k, then the rows, biases and lines of action of the front (+1)
    and back (−1) flanks.
    """
