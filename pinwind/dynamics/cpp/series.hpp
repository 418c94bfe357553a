// The series a run writes, declared once: each one's name, family and components, in one table
// (PINWIND_SERIES) from which come the Series enum, its Python binding (_native.Series, with
// _native.series_layout), the size check of each array handed in and the Outputs the step loop
// writes through.
//
// A series of family F with c components is a row-major (samples, count(F), c) array, c = 1
// leaving the last axis out: count(run) = 1, count(joint) = nv, count(bearing) = the bearings
// (StepperSpec.bearing_joints),
// count(mesh), count(body) = the recorded links, count(generator), count(rotor) = the elements',
// count(row) = the compliant bearings' rows (StepperSpec.bearing_rows, bearing_rows.hpp),
// count(slice) = the slices of the sliced compliant meshes (slices > 1), mesh after mesh in the
// order of StepperSpec.compliant_meshes, each mesh's slices from face side I (compliant_mesh.hpp).
// Its name is the Result's; its unit, frame, meaning and how every consumer shows it are declared
// in the Python schema (pinwind/dynamics/series.py; the ledger's terms are keys of
// Result.energy), and tests/dynamics/test_series.py checks that this table and that schema
// agree.
#pragma once

#include <array>
#include <cstddef>

namespace pinwind {

// The families of elements a series has one column per.
enum class Family { run, joint, mesh, bearing, body, generator, rotor, row, slice };
inline constexpr std::size_t kFamilies = 9;

// X(name, family, components).
#define PINWIND_SERIES(X)                       \
  X(time, run, 1)                               \
  X(angle, joint, 1)                            \
  X(speed, joint, 1)                            \
  X(acceleration, joint, 1)                     \
  X(torque, joint, 1)                           \
  X(mesh_normal, mesh, 1)                       \
  X(mesh_tangential, mesh, 1)                   \
  X(mesh_radial, mesh, 1)                       \
  X(mesh_axial, mesh, 1)                        \
  X(mesh_flank, mesh, 1)                        \
  X(mesh_normal_front, mesh, 1)                 \
  X(mesh_normal_back, mesh, 1)                  \
  X(transmission_error, mesh, 1)                \
  X(mesh_force_on_b, mesh, 3)                   \
  X(pitch_point, mesh, 3)                       \
  X(mesh_deflection, mesh, 1)                   \
  X(mesh_contact_position, mesh, 1)             \
  X(mesh_pairs, mesh, 1)                        \
  X(mesh_single_tooth_force, mesh, 1)           \
  X(mesh_face_load_factor, mesh, 1)             \
  X(mesh_load_centre, mesh, 1)                  \
  X(bearing_force, bearing, 3)                  \
  X(bearing_moment, bearing, 3)                 \
  X(bearing_force_local, bearing, 3)            \
  X(bearing_moment_local, bearing, 3)           \
  X(body_position, body, 3)                     \
  X(body_quaternion, body, 4)                   \
  X(constraint_residual, run, 1)                \
  X(kinetic, run, 1)                            \
  X(potential_spring, run, 1)                   \
  X(work_applied, run, 1)                       \
  X(work_drivers, run, 1)                       \
  X(work_springs, run, 1)                       \
  X(work_gravity, run, 1)                       \
  X(work_constraints, run, 1)                   \
  X(dissipated, run, 1)                         \
  X(work_parametric, run, 1)                    \
  X(generator_torque, generator, 1)             \
  X(rotor_torque, rotor, 1)                     \
  X(rotor_power, rotor, 1)                      \
  X(rotor_tip_speed_ratio, rotor, 1)            \
  X(rotor_power_coefficient, rotor, 1)          \
  X(rotor_wind_speed, rotor, 1)                 \
  X(rotor_thrust, rotor, 1)                     \
  X(rotor_thrust_coefficient, rotor, 1)         \
  X(rotor_pitch, rotor, 1)                      \
  X(row_force, row, 3)                          \
  X(row_moment, row, 3)                         \
  X(bearing_friction_moment, bearing, 1)        \
  X(bearing_friction_power, bearing, 1)        \
  X(mesh_sliding_velocity, mesh, 1)             \
  X(mesh_friction_force, mesh, 1)               \
  X(mesh_friction_power, mesh, 1)               \
  X(friction_loss, run, 1)                      \
  X(mesh_peak_line_load, mesh, 1)               \
  X(mesh_mean_line_load, mesh, 1)               \
  X(slice_line_load, slice, 1)

enum class Series {
#define PINWIND_SERIES_NAME(name, family, components) name,
  PINWIND_SERIES(PINWIND_SERIES_NAME)
#undef PINWIND_SERIES_NAME
};

// A series' declaration: its name, family and components (1 scalar, 3 vector, 4 quaternion).
struct SeriesLayout {
  const char* name;
  Family family;
  int components;
};

inline constexpr SeriesLayout kSeriesLayouts[] = {
#define PINWIND_SERIES_LAYOUT(name, family, components) \
  {#name, Family::family, components},
    PINWIND_SERIES(PINWIND_SERIES_LAYOUT)
#undef PINWIND_SERIES_LAYOUT
};
inline constexpr std::size_t kSeriesCount = sizeof(kSeriesLayouts) / sizeof(kSeriesLayouts[0]);

inline constexpr const SeriesLayout& layout(Series s) {
  return kSeriesLayouts[static_cast<std::size_t>(s)];
}

// Where each sample's outputs go: a pointer per series into row-major arrays of one block of
// `samples` samples (null for a family without elements), and the element count per family.
struct Outputs {
  std::array<double*, kSeriesCount> columns{};
  std::array<long, kFamilies> counts{};
  long samples = 0;

  double* column(Series s) const { return columns[static_cast<std::size_t>(s)]; }
  long count(Family f) const { return counts[static_cast<std::size_t>(f)]; }
  // The entry of element e of sample k in every series of family f: the i of at(), computed
  // once for the element's series.
  long entry(Family f, long k, long e = 0) const { return k * count(f) + e; }
  // Component c of entry i of series s (its components a constant: no table look-up).
  double& at(Series s, long i, int c = 0) const {
    return column(s)[i * layout(s).components + c];
  }
};

}  // namespace pinwind
