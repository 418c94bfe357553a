// Python bindings of the compiled step loop: pinwind.dynamics._native (stub: _native.pyi).
//
// The Python side (pinwind/dynamics/stepper.py) fills typed structs: the Pinocchio joint tree
// (placements, inertias), the mesh geometry, the elements' constants and the Result's arrays to
// write into. This module rebuilds the Pinocchio model from the joint tree; a test checks that
// its mass matrix equals Pinocchio's own.
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "byte_planes.hpp"
#include "column_statistics.hpp"
#include "series.hpp"
#include "stepper.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace pinwind {
namespace {

using Array = nb::ndarray<double, nb::numpy, nb::c_contig, nb::device::cpu>;
// Any float64 matrix, with its strides (a column of a Result, a view of a read log's arrays).
using AnyMatrix = nb::ndarray<const double, nb::ndim<2>, nb::device::cpu>;
using OutMatrix = nb::ndarray<double, nb::ndim<2>, nb::device::cpu>;

// Folds the columns of `values` (or the magnitudes of its x, y, z column triples) into `out`,
// a (5, columns) view (column_statistics.hpp), without the GIL.
void fold_block(const AnyMatrix& values, OutMatrix& out, bool magnitudes) {
  const Strided2 v{values.data(), static_cast<long>(values.shape(0)),
                   static_cast<long>(values.shape(1)), static_cast<long>(values.stride(0)),
                   static_cast<long>(values.stride(1))};
  const long k = magnitudes ? v.cols / 3 : v.cols;
  if (static_cast<long>(out.shape(0)) != kFoldRows || static_cast<long>(out.shape(1)) != k) {
    throw std::invalid_argument("fold: out must be (5, " + std::to_string(k) + "), not (" +
                                std::to_string(out.shape(0)) + ", " +
                                std::to_string(out.shape(1)) + ")");
  }
  double* data = out.data();
  const long o0 = static_cast<long>(out.stride(0)), o1 = static_cast<long>(out.stride(1));
  nb::gil_scoped_release release;
  if (magnitudes) {
    fold_magnitudes(v, data, o0, o1);
  } else {
    fold_values(v, data, o0, o1);
  }
}

using Bytes = nb::ndarray<std::uint8_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using ConstBytes = nb::ndarray<const std::uint8_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;
using Indices = nb::ndarray<const std::int64_t, nb::ndim<1>, nb::c_contig, nb::device::cpu>;

std::string shape_text(long a, long b) {
  return "(" + std::to_string(a) + ", " + std::to_string(b) + ")";
}

// The byte planes (byte_planes.hpp) of the rows `series` of the (k, m) `values` into `planes`
// (8 · V · m bytes, V = len(series)): the V rows' m values, one after the other, shuffled as one
// run of V · m values. Without the GIL.
void shuffle_series(const AnyMatrix& values, const Indices& series, Bytes planes) {
  const long k = static_cast<long>(values.shape(0)), m = static_cast<long>(values.shape(1));
  const long v = static_cast<long>(series.shape(0));
  if (m > 1 && values.stride(1) != 1) {
    throw std::invalid_argument("shuffle_series: the rows of values must be contiguous");
  }
  if (static_cast<long>(planes.shape(0)) != 8 * v * m) {
    throw std::invalid_argument("shuffle_series: planes must hold 8 · " + std::to_string(v) +
                                " · " + std::to_string(m) + " bytes, not " +
                                std::to_string(planes.shape(0)));
  }
  const std::int64_t* rows = series.data();
  for (long j = 0; j < v; ++j) {
    if (rows[j] < 0 || rows[j] >= k) {
      throw std::invalid_argument("shuffle_series: row " + std::to_string(rows[j]) +
                                  " of values " + shape_text(k, m));
    }
  }
  const double* data = values.data();
  const long s0 = static_cast<long>(values.stride(0));
  std::uint8_t* out = planes.data();
  nb::gil_scoped_release release;
  for (long j = 0; j < v; ++j) shuffle_bytes(data + rows[j] * s0, m, out + j * m, v * m);
}

// The inverse, for a read: samples first .. first + count of the V series in `planes` (each of m
// samples) into out[rows[j], at .. at + count], series j skipped where rows[j] < 0. Without the
// GIL (the reading threads place their chunks at once).
void unshuffle_series(const ConstBytes& planes, long m, long first, long count,
                      const Indices& rows, OutMatrix out, long at, bool stream) {
  const long v = static_cast<long>(rows.shape(0));
  const long height = static_cast<long>(out.shape(0)), width = static_cast<long>(out.shape(1));
  if (static_cast<long>(planes.shape(0)) != 8 * v * m) {
    throw std::invalid_argument("unshuffle_series: planes hold " +
                                std::to_string(planes.shape(0)) + " bytes, not 8 · " +
                                std::to_string(v) + " · " + std::to_string(m));
  }
  if (first < 0 || count < 0 || first + count > m || at < 0 || at + count > width) {
    throw std::invalid_argument("unshuffle_series: samples " + std::to_string(first) + " + " +
                                std::to_string(count) + " of " + std::to_string(m) + " to " +
                                std::to_string(at) + " of out " + shape_text(height, width));
  }
  if (count > 1 && out.stride(1) != 1) {
    throw std::invalid_argument("unshuffle_series: the rows of out must be contiguous");
  }
  const std::int64_t* dest = rows.data();
  for (long j = 0; j < v; ++j) {
    if (dest[j] >= height) {
      throw std::invalid_argument("unshuffle_series: row " + std::to_string(dest[j]) +
                                  " of out " + shape_text(height, width));
    }
  }
  const std::uint8_t* in = planes.data();
  double* data = out.data();
  const long s0 = static_cast<long>(out.stride(0));
  nb::gil_scoped_release release;
  for (long j = 0; j < v; ++j) {
    if (dest[j] >= 0) {
      unshuffle_bytes(in + j * m + first, v * m, count, data + dest[j] * s0 + at, stream);
    }
  }
}

// out[rows[j], at .. at + count] = values[j] for every j with rows[j] ≥ 0: a read log's series
// that are constant over a block, and the NaN of the poses between posed samples. Without the
// GIL.
void fill_rows(const nb::ndarray<const double, nb::ndim<1>, nb::c_contig, nb::device::cpu>& values,
               const Indices& rows, OutMatrix out, long at, long count, bool stream) {
  const long c = static_cast<long>(rows.shape(0));
  const long height = static_cast<long>(out.shape(0)), width = static_cast<long>(out.shape(1));
  if (static_cast<long>(values.shape(0)) != c) {
    throw std::invalid_argument("fill_rows: " + std::to_string(values.shape(0)) +
                                " values for " + std::to_string(c) + " rows");
  }
  if (at < 0 || count < 0 || at + count > width || (count > 1 && out.stride(1) != 1)) {
    throw std::invalid_argument("fill_rows: samples " + std::to_string(at) + " + " +
                                std::to_string(count) + " of out " + shape_text(height, width) +
                                " (rows contiguous)");
  }
  const std::int64_t* dest = rows.data();
  for (long j = 0; j < c; ++j) {
    if (dest[j] >= height) {
      throw std::invalid_argument("fill_rows: row " + std::to_string(dest[j]) + " of out " +
                                  shape_text(height, width));
    }
  }
  const double* value = values.data();
  double* data = out.data();
  const long s0 = static_cast<long>(out.stride(0));
  nb::gil_scoped_release release;
  for (long j = 0; j < c; ++j) {
    if (dest[j] >= 0) fill_values(data + dest[j] * s0 + at, count, value[j], stream);
  }
}

using Mat4 = Eigen::Matrix<double, 4, 4, Eigen::RowMajor>;

// The joints pinwind models: revolute about an axis of the joint frame, or about any axis, and
// the prismatic slides of compliant bearings (along an axis of the joint frame, or any axis).
enum class JointType {
  revolute_x,
  revolute_y,
  revolute_z,
  revolute_unaligned,
  prismatic_x,
  prismatic_y,
  prismatic_z,
  prismatic_unaligned
};

// The Pinocchio joint tree, body inertias and gravity (pinwind/dynamics/stepper.py joint_tree).
struct JointTree {
  std::vector<std::string> names;
  std::vector<long> parent;
  std::vector<JointType> type;
  Rows3 axis;                   // axis of *_unaligned joints in the joint frame
  std::vector<Mat4> placement;  // joint placement in the parent joint's frame
  Eigen::VectorXd mass;         // [kg]
  Rows3 com;                    // centre of mass in the joint frame [m]
  RowMat inertia;               // (joints, 9) rotational inertia about the com [kg·m²]
  Eigen::VectorXd armature;     // [kg·m²]
  Vec3 gravity = Vec3(0.0, 0.0, -9.81);  // [m/s²]
};

// Everything a run needs besides the initial state and the arrays it writes.
struct StepperSpec {
  JointTree tree;
  MeshConstants meshes;
  std::vector<MeshPathSpec> paths;
  std::vector<long> rigid_meshes;
  std::vector<CompliantMeshSpec> compliant_meshes;
  std::vector<TorsionalSpringSpec> springs;
  std::vector<BearingSpringSpec> bearing_springs;
  std::vector<GeneratorSpec> generators;
  std::vector<RotorSpec> rotors;
  long input_columns = 0;
  Eigen::VectorXd bearing_damping;
  std::vector<long> driver_index;
  std::vector<long> frame_parent;
  std::vector<Mat4> frame_placement;
  double dt = 1e-3;
  double projection_tol = 1e-14;
  double rho_infinity = 1.0;  // the time step's spectral radius (time_step.hpp)
  SolverSettings solver;
};

// The Result's arrays the run writes into (row-major, float64, n samples long): one per series
// (series.hpp), set from Python by series.
struct OutputArrays {
  std::array<Array, kSeriesCount> arrays;

  Array& operator[](Series s) { return arrays[static_cast<size_t>(s)]; }
};

pinocchio::SE3 placement(const Mat4& h) {
  return pinocchio::SE3(Eigen::Matrix3d(h.topLeftCorner<3, 3>()), Vec3(h.topRightCorner<3, 1>()));
}

template <class T>
void check_size(const char* what, const T& values, size_t size) {
  if (static_cast<size_t>(values.size()) != size) {
    throw std::invalid_argument(std::string(what) + " has " + std::to_string(values.size()) +
                                " entries, expected " + std::to_string(size));
  }
}

pinocchio::Model build_model(const JointTree& t) {
  const size_t nj = t.names.size();
  check_size("tree.parent", t.parent, nj);
  check_size("tree.type", t.type, nj);
  check_size("tree.placement", t.placement, nj);
  check_size("tree.mass", t.mass, nj);
  if (static_cast<size_t>(t.axis.rows()) != nj || static_cast<size_t>(t.com.rows()) != nj ||
      static_cast<size_t>(t.inertia.rows()) != nj || t.inertia.cols() != 9) {
    throw std::invalid_argument("tree.axis, tree.com and tree.inertia need one row per joint");
  }
  pinocchio::Model model;
  for (size_t i = 0; i < nj; ++i) {
    const auto r = static_cast<Eigen::Index>(i);
    const pinocchio::SE3 placement_i = placement(t.placement[i]);
    const auto p = static_cast<pinocchio::JointIndex>(t.parent[i]);
    pinocchio::JointIndex id;
    switch (t.type[i]) {
      case JointType::revolute_x:
        id = model.addJoint(p, pinocchio::JointModelRX(), placement_i, t.names[i]);
        break;
      case JointType::revolute_y:
        id = model.addJoint(p, pinocchio::JointModelRY(), placement_i, t.names[i]);
        break;
      case JointType::revolute_z:
        id = model.addJoint(p, pinocchio::JointModelRZ(), placement_i, t.names[i]);
        break;
      case JointType::revolute_unaligned:
        id = model.addJoint(p, pinocchio::JointModelRevoluteUnaligned(Vec3(t.axis.row(r))),
                            placement_i, t.names[i]);
        break;
      case JointType::prismatic_x:
        id = model.addJoint(p, pinocchio::JointModelPX(), placement_i, t.names[i]);
        break;
      case JointType::prismatic_y:
        id = model.addJoint(p, pinocchio::JointModelPY(), placement_i, t.names[i]);
        break;
      case JointType::prismatic_z:
        id = model.addJoint(p, pinocchio::JointModelPZ(), placement_i, t.names[i]);
        break;
      case JointType::prismatic_unaligned:
        id = model.addJoint(p, pinocchio::JointModelPrismaticUnaligned(Vec3(t.axis.row(r))),
                            placement_i, t.names[i]);
        break;
      default:
        throw std::invalid_argument("joint " + t.names[i] + ": unsupported joint type");
    }
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rotational(
        t.inertia.row(r).data());
    model.inertias[id] =
        pinocchio::Inertia(t.mass[r], Vec3(t.com.row(r)), Eigen::Matrix3d(rotational));
  }
  check_size("tree.armature", t.armature, static_cast<size_t>(model.nv));
  model.armature = t.armature;
  model.gravity = pinocchio::Motion(t.gravity, Vec3::Zero());
  return model;
}

void check_meshes(const MeshConstants& mc, size_t nv) {
  const size_t nm = mc.slot_a.size(), slots = mc.joint_ids.size();
  check_size("meshes.slot_b", mc.slot_b, nm);
  check_size("meshes.mu", mc.mu, nm);
  check_size("meshes.sigma", mc.sigma, nm);
  check_size("meshes.cos_a", mc.cos_a, nm);
  check_size("meshes.sin_a", mc.sin_a, nm);
  check_size("meshes.eps", mc.eps, nm);
  check_size("meshes.tan_beta_b", mc.tan_beta_b, nm);
  check_size("meshes.joint_a", mc.joint_a, nm);
  check_size("meshes.joint_b", mc.joint_b, nm);
  if (static_cast<size_t>(mc.centre_a.rows()) != nm ||
      static_cast<size_t>(mc.centre_b.rows()) != nm ||
      static_cast<size_t>(mc.axis_a.rows()) != nm) {
    throw std::invalid_argument("meshes.centre_a, centre_b and axis_a need one row per mesh");
  }
  if (static_cast<size_t>(mc.support.rows()) != slots ||
      static_cast<size_t>(mc.support.cols()) != nv) {
    throw std::invalid_argument("meshes.support must be (slots, nv)");
  }
}

StepperSetup setup(const StepperSpec& spec) {
  StepperSetup s;
  s.model = build_model(spec.tree);
  const size_t nv = static_cast<size_t>(s.model.nv);
  check_meshes(spec.meshes, nv);
  const size_t nm = static_cast<size_t>(spec.meshes.count());
  check_size("paths", spec.paths, nm);
  for (long m : spec.rigid_meshes) {
    if (m < 0 || static_cast<size_t>(m) >= nm) throw std::invalid_argument("bad rigid mesh");
  }
  for (const auto& c : spec.compliant_meshes) {
    if (c.mesh < 0 || static_cast<size_t>(c.mesh) >= nm) {
      throw std::invalid_argument("bad compliant mesh");
    }
  }
  for (const auto& p : spec.paths) {
    if (p.pair_position.size() != p.pair_stiffness.size()) {
      throw std::invalid_argument("paths: pair_position and pair_stiffness differ in size");
    }
  }
  for (const auto& sp : spec.springs) {
    if (sp.index_1 < 0 || sp.index_2 < 0 || static_cast<size_t>(sp.index_1) >= nv ||
        static_cast<size_t>(sp.index_2) >= nv) {
      throw std::invalid_argument("bad spring joint index");
    }
  }
  for (const auto& b : spec.bearing_springs) {
    for (long i : {b.index_x, b.index_y, b.index_axial, b.index_tilt_x, b.index_tilt_y}) {
      if (i < -1 || i >= static_cast<long>(nv)) {
        throw std::invalid_argument("bad bearing spring joint index");
      }
    }
    if ((b.index_x < 0) != (b.index_y < 0) || (b.index_tilt_x < 0) != (b.index_tilt_y < 0)) {
      throw std::invalid_argument("bearing spring: radial and tilt joints come in pairs");
    }
  }
  for (const auto& g : spec.generators) {
    if (g.index < 0 || static_cast<size_t>(g.index) >= nv) {
      throw std::invalid_argument("bad generator joint index");
    }
    const bool induction =
        g.law == GeneratorLaw::induction || g.law == GeneratorLaw::induction_dq;
    if (induction && (g.pole_pairs < 1 || !(g.frequency > 0.0))) {
      throw std::invalid_argument("induction machine: pole_pairs ≥ 1 and frequency > 0");
    }
  }
  for (const auto& r : spec.rotors) {
    if (r.index < 0 || static_cast<size_t>(r.index) >= nv) {
      throw std::invalid_argument("bad rotor joint index");
    }
    if (r.wind_column < 0 || r.wind_column >= spec.input_columns) {
      throw std::invalid_argument("rotor wind_column outside the input columns");
    }
    if (r.cp_model == CpModel::table &&
        (r.table_tsr.empty() || r.table_pitch.empty() ||
         r.table_cp.size() != r.table_tsr.size() * r.table_pitch.size())) {
      throw std::invalid_argument("rotor table: table_cp must hold tsr × pitch values");
    }
  }
  check_size("bearing_damping", spec.bearing_damping, nv);
  check_size("frame_placement", spec.frame_placement, spec.frame_parent.size());
  s.meshes = spec.meshes;
  s.paths = spec.paths;
  s.rigid_meshes = spec.rigid_meshes;
  s.compliant_meshes = spec.compliant_meshes;
  s.springs = spec.springs;
  s.bearing_springs = spec.bearing_springs;
  s.generators = spec.generators;
  s.rotors = spec.rotors;
  s.input_columns = spec.input_columns;
  s.bearing_damping = spec.bearing_damping;
  s.driver_index = spec.driver_index;
  s.frame_parent = spec.frame_parent;
  for (const auto& h : spec.frame_placement) s.frame_placement.push_back(placement(h));
  s.dt = spec.dt;
  s.projection_tol = spec.projection_tol;
  s.rho_infinity = spec.rho_infinity;
  s.solver = spec.solver;
  return s;
}

// Pointers into the block's arrays, each checked against the block length n, its family's count
// and its components (series.hpp); a family without elements needs no arrays.
Outputs outputs(const OutputArrays& out, size_t n, const std::array<long, kFamilies>& counts) {
  Outputs o;
  o.samples = static_cast<long>(n);
  o.counts = counts;
  for (size_t i = 0; i < kSeriesCount; ++i) {
    const SeriesLayout& l = kSeriesLayouts[i];
    const Array& a = out.arrays[i];
    const size_t count = static_cast<size_t>(counts[static_cast<size_t>(l.family)]);
    if (count == 0 && !a.is_valid()) continue;
    const size_t size = n * count * static_cast<size_t>(l.components);
    if (!a.is_valid() || a.size() != size) {
      throw std::invalid_argument(std::string("out[Series.") + l.name + "] must hold " +
                                  std::to_string(size) + " float64 values");
    }
    o.columns[i] = count ? a.data() : nullptr;
  }
  return o;
}

// Rows of every mesh at one state for Python (pinwind/dynamics/mesh.py): their t and r̂ parts,
// the geometry, and both flanks' rows, biases and lines of action, from the step loop's own
// functions.
struct MeshRowSet {
  RowMat jac_t, jac_r;              // (meshes, nv)
  Eigen::VectorXd bias_t, bias_r;   // (meshes,)
  RowMat tangent, radial, pitch_point, axis;  // (meshes, 3) in world
  RowMat row_front, row_back;       // J of the front (+1) and back (−1) flanks
  Eigen::VectorXd bias_front, bias_back;
  RowMat normal_front, normal_back;  // their lines of action n in world
};

MeshRowSet mesh_rows(const MeshConstants& mc, const Eigen::MatrixXd& jac,
                     const Eigen::MatrixXd& djac, const Eigen::VectorXd& v, const RowMat& origin,
                     const RowMat& rot) {
  check_meshes(mc, static_cast<size_t>(v.size()));
  std::vector<Vec3> o(mc.joint_ids.size());
  std::vector<Eigen::Matrix3d> r(mc.joint_ids.size());
  for (size_t i = 0; i < o.size(); ++i) {
    o[i] = origin.row(static_cast<Eigen::Index>(i)).transpose();
    r[i] = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
        rot.row(static_cast<Eigen::Index>(i)).data());
  }
  const Eigen::Index nm = mc.count(), nv = v.size();
  MeshRows rows;
  rows.resize(nm, nv);
  evaluate_mesh_rows(mc, jac, djac, v, o, r, rows);
  MeshRowSet out{rows.jac_t, rows.jac_r, rows.bias_t, rows.bias_r,
                 rows.tangent, rows.radial, rows.pitch_point, rows.axis,
                 RowMat(nm, nv), RowMat(nm, nv), Eigen::VectorXd(nm), Eigen::VectorXd(nm),
                 RowMat(nm, 3), RowMat(nm, 3)};
  for (Eigen::Index m = 0; m < nm; ++m) {
    flank_row(mc, rows, m, 1.0, out.row_front.row(m), out.bias_front[m]);
    flank_row(mc, rows, m, -1.0, out.row_back.row(m), out.bias_back[m]);
    out.normal_front.row(m) = line_of_action(mc, rows, m, 1.0).transpose();
    out.normal_back.row(m) = line_of_action(mc, rows, m, -1.0).transpose();
  }
  return out;
}

// A run of the step loop; each call to run() writes one block of samples into the arrays it
// is given, so a run of any length needs memory for one block only.
class PyStepper {
 public:
  PyStepper(const StepperSpec& spec, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
            long samples) {
    StepperSetup s = setup(spec);
    const auto nv = static_cast<long>(s.model.nv);
    auto count = [&](Family f) -> long& { return counts_[static_cast<size_t>(f)]; };
    count(Family::run) = 1;
    count(Family::joint) = nv;
    count(Family::mesh) = static_cast<long>(s.meshes.count());
    count(Family::bearing) = static_cast<long>(s.model.njoints - 1);
    count(Family::body) = static_cast<long>(s.frame_parent.size());
    count(Family::generator) = static_cast<long>(s.generators.size());
    count(Family::rotor) = static_cast<long>(s.rotors.size());
    if (q0.size() != nv || v0.size() != nv) {
      throw std::invalid_argument("q0 and v0 must have nv values");
    }
    inputs_ = s.input_columns;
    stepper_ = std::make_unique<Stepper>(std::move(s), q0, v0, samples);
  }

  RunStatus run(long k0, long k1, const RowMat& torque, const RowMat& target,
                const OutputArrays& out, const RowMat& inputs, long stride) {
    if (k1 < k0) throw std::invalid_argument("run: k1 < k0");
    if (stride < 1) throw std::invalid_argument("run: stride < 1");
    if (inputs_ && (inputs.rows() != k1 - k0 || inputs.cols() != inputs_)) {
      throw std::invalid_argument("run: inputs must be (k1 - k0, input_columns)");
    }
    const long rows = stepper_->kept_rows(k0, k1, stride);
    const Outputs o = outputs(out, static_cast<size_t>(rows), counts_);
    nb::gil_scoped_release release;
    return stepper_->run(k0, k1, torque, target, o, inputs, stride);
  }

  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) { return stepper_->mass_matrix(q); }

  EquilibriumStatus equilibrium(const RowMat& torque, const RowMat& target, const RowMat& inputs,
                                long max_iterations, double tolerance) {
    const long nv = counts_[static_cast<size_t>(Family::joint)];
    if (torque.rows() != 1 || torque.cols() != nv || target.rows() != 2 ||
        (inputs_ && (inputs.rows() != 1 || inputs.cols() != inputs_))) {
      throw std::invalid_argument(
          "equilibrium: torque (1, nv), target (2, drivers), inputs (1, input_columns)");
    }
    return stepper_->equilibrium(torque, target, inputs, max_iterations, tolerance);
  }

  Assembly assemble(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    if (q.size() != counts_[static_cast<size_t>(Family::joint)] || v.size() != q.size()) {
      throw std::invalid_argument("assemble: q and v must have nv values");
    }
    return stepper_->assemble(q, v);
  }

 private:
  std::array<long, kFamilies> counts_{};  // elements per family (series.hpp)
  long inputs_ = 0;
  std::unique_ptr<Stepper> stepper_;
};

}  // namespace
}  // namespace pinwind

NB_MODULE(_native, m) {
  using namespace pinwind;
  m.doc() = "Compiled step loop of pinwind (pinwind/dynamics/cpp/).";

  nb::class_<SolverSettings>(m, "SolverSettings")
      .def(nb::init<>())
      .def_rw("eps_abs", &SolverSettings::eps_abs)
      .def_rw("eps_rel", &SolverSettings::eps_rel)
      .def_rw("max_iter", &SolverSettings::max_iter)
      .def_rw("iterative", &SolverSettings::iterative);

  nb::enum_<JointType>(m, "JointType")
      .value("revolute_x", JointType::revolute_x)
      .value("revolute_y", JointType::revolute_y)
      .value("revolute_z", JointType::revolute_z)
      .value("revolute_unaligned", JointType::revolute_unaligned)
      .value("prismatic_x", JointType::prismatic_x)
      .value("prismatic_y", JointType::prismatic_y)
      .value("prismatic_z", JointType::prismatic_z)
      .value("prismatic_unaligned", JointType::prismatic_unaligned);

  nb::enum_<GeneratorLaw>(m, "GeneratorLaw")
      .value("constant", GeneratorLaw::constant)
      .value("linear_slip", GeneratorLaw::linear_slip)
      .value("variable_speed", GeneratorLaw::variable_speed)
      .value("induction", GeneratorLaw::induction)
      .value("induction_dq", GeneratorLaw::induction_dq);

  nb::enum_<CpModel>(m, "CpModel")
      .value("heier", CpModel::heier)
      .value("table", CpModel::table);

  nb::enum_<RunCode>(m, "RunCode")
      .value("completed", RunCode::completed)
      .value("diverged", RunCode::diverged)
      .value("solver_failed", RunCode::solver_failed)
      .value("conflicting_constraints", RunCode::conflicting_constraints);

  nb::class_<JointTree>(m, "JointTree")
      .def(nb::init<>())
      .def_rw("names", &JointTree::names)
      .def_rw("parent", &JointTree::parent)
      .def_rw("type", &JointTree::type)
      .def_rw("axis", &JointTree::axis)
      .def_rw("placement", &JointTree::placement)
      .def_rw("mass", &JointTree::mass)
      .def_rw("com", &JointTree::com)
      .def_rw("inertia", &JointTree::inertia)
      .def_rw("armature", &JointTree::armature)
      .def_rw("gravity", &JointTree::gravity);

  nb::class_<MeshConstants>(m, "MeshConstants")
      .def(nb::init<>())
      .def_rw("joint_ids", &MeshConstants::joint_ids)
      .def_rw("slot_a", &MeshConstants::slot_a)
      .def_rw("slot_b", &MeshConstants::slot_b)
      .def_rw("centre_a", &MeshConstants::centre_a)
      .def_rw("centre_b", &MeshConstants::centre_b)
      .def_rw("axis_a", &MeshConstants::axis_a)
      .def_rw("mu", &MeshConstants::mu)
      .def_rw("sigma", &MeshConstants::sigma)
      .def_rw("support", &MeshConstants::support)
      .def_rw("cos_a", &MeshConstants::cos_a)
      .def_rw("sin_a", &MeshConstants::sin_a)
      .def_rw("eps", &MeshConstants::eps)
      .def_rw("tan_beta_b", &MeshConstants::tan_beta_b)
      .def_rw("joint_a", &MeshConstants::joint_a)
      .def_rw("joint_b", &MeshConstants::joint_b);

  nb::class_<MeshPathSpec>(m, "MeshPathSpec")
      .def(nb::init<>())
      .def_rw("base_pitch", &MeshPathSpec::base_pitch)
      .def_rw("path_length", &MeshPathSpec::path_length)
      .def_rw("roll_start", &MeshPathSpec::roll_start)
      .def_rw("roll_radius_a", &MeshPathSpec::roll_radius_a)
      .def_rw("entering_front", &MeshPathSpec::entering_front)
      .def_rw("entering_back", &MeshPathSpec::entering_back)
      .def_rw("angle_ref_a", &MeshPathSpec::angle_ref_a)
      .def_rw("reference_a", &MeshPathSpec::reference_a)
      .def_rw("pair_position", &MeshPathSpec::pair_position)
      .def_rw("pair_stiffness", &MeshPathSpec::pair_stiffness);

  nb::class_<CompliantMeshSpec>(m, "CompliantMeshSpec")
      .def(nb::init<>())
      .def_rw("mesh", &CompliantMeshSpec::mesh)
      .def_rw("stiffness", &CompliantMeshSpec::stiffness)
      .def_rw("damping", &CompliantMeshSpec::damping)
      .def_rw("backlash", &CompliantMeshSpec::backlash)
      .def_rw("base_radius_a", &CompliantMeshSpec::base_radius_a)
      .def_rw("base_radius_b", &CompliantMeshSpec::base_radius_b)
      .def_rw("reference_b", &CompliantMeshSpec::reference_b)
      .def_rw("tangential_ref", &CompliantMeshSpec::tangential_ref)
      .def_rw("base_radius_sum", &CompliantMeshSpec::base_radius_sum)
      .def_rw("radial_sign", &CompliantMeshSpec::radial_sign)
      .def_rw("involute_ref", &CompliantMeshSpec::involute_ref)
      .def_rw("tangential_offset", &CompliantMeshSpec::tangential_offset)
      .def_rw("radial_offset", &CompliantMeshSpec::radial_offset);

  nb::class_<TorsionalSpringSpec>(m, "TorsionalSpringSpec")
      .def(nb::init<>())
      .def_rw("index_1", &TorsionalSpringSpec::index_1)
      .def_rw("index_2", &TorsionalSpringSpec::index_2)
      .def_rw("stiffness", &TorsionalSpringSpec::stiffness)
      .def_rw("damping", &TorsionalSpringSpec::damping)
      .def_rw("preload_angle", &TorsionalSpringSpec::preload_angle);

  nb::class_<BearingSpringSpec>(m, "BearingSpringSpec")
      .def(nb::init<>())
      .def_rw("index_x", &BearingSpringSpec::index_x)
      .def_rw("index_y", &BearingSpringSpec::index_y)
      .def_rw("radial_stiffness", &BearingSpringSpec::radial_stiffness)
      .def_rw("radial_damping", &BearingSpringSpec::radial_damping)
      .def_rw("clearance", &BearingSpringSpec::clearance)
      .def_rw("index_axial", &BearingSpringSpec::index_axial)
      .def_rw("axial_stiffness", &BearingSpringSpec::axial_stiffness)
      .def_rw("index_tilt_x", &BearingSpringSpec::index_tilt_x)
      .def_rw("index_tilt_y", &BearingSpringSpec::index_tilt_y)
      .def_rw("tilt_stiffness", &BearingSpringSpec::tilt_stiffness);

  nb::class_<GeneratorSpec>(m, "GeneratorSpec")
      .def(nb::init<>())
      .def_rw("index", &GeneratorSpec::index)
      .def_rw("law", &GeneratorSpec::law)
      .def_rw("torque", &GeneratorSpec::torque)
      .def_rw("slope", &GeneratorSpec::slope)
      .def_rw("sync_speed", &GeneratorSpec::sync_speed)
      .def_rw("gain", &GeneratorSpec::gain)
      .def_rw("rated_power", &GeneratorSpec::rated_power)
      .def_rw("stator_resistance", &GeneratorSpec::stator_resistance)
      .def_rw("rotor_resistance", &GeneratorSpec::rotor_resistance)
      .def_rw("stator_leakage", &GeneratorSpec::stator_leakage)
      .def_rw("rotor_leakage", &GeneratorSpec::rotor_leakage)
      .def_rw("magnetizing", &GeneratorSpec::magnetizing)
      .def_rw("voltage", &GeneratorSpec::voltage)
      .def_rw("frequency", &GeneratorSpec::frequency)
      .def_rw("pole_pairs", &GeneratorSpec::pole_pairs)
      .def_rw("phases", &GeneratorSpec::phases)
      .def_rw("steady_start", &GeneratorSpec::steady_start);

  nb::class_<RotorSpec>(m, "RotorSpec")
      .def(nb::init<>())
      .def_rw("index", &RotorSpec::index)
      .def_rw("radius", &RotorSpec::radius)
      .def_rw("air_density", &RotorSpec::air_density)
      .def_rw("pitch", &RotorSpec::pitch)
      .def_rw("cp_model", &RotorSpec::cp_model)
      .def_rw("cp_scale", &RotorSpec::cp_scale)
      .def_rw("table_tsr", &RotorSpec::table_tsr)
      .def_rw("table_pitch", &RotorSpec::table_pitch)
      .def_rw("table_cp", &RotorSpec::table_cp)
      .def_rw("wind_column", &RotorSpec::wind_column);

  m.def("induction_torque", &induction_torque, "generator"_a, "speed"_a,
        "Steady-state induction machine torque on the shaft at speed [rad/s] (motor convention).");
  m.def("rotor_torque", &rotor_torque, "rotor"_a, "speed"_a, "wind"_a,
        "Aerodynamic rotor torque [N·m] at rotor speed [rad/s] and wind speed [m/s].");
  m.def("rotor_cp", &rotor_cp, "rotor"_a, "tsr"_a, "Power coefficient C_p at tip-speed ratio λ.");
  m.def(
      "fold_columns", [](const AnyMatrix& values, OutMatrix out) { fold_block(values, out, false); },
      "values"_a, "out"_a,
      "min, max, sum, sum of squares and last value of each column of an (m, k) block into the "
      "rows of out (5, k).");
  m.def(
      "fold_magnitudes",
      [](const AnyMatrix& values, OutMatrix out) { fold_block(values, out, true); }, "values"_a,
      "out"_a,
      "The same for the magnitudes of the vectors of an (m, 3e) block (x, y, z of each vector "
      "side by side) into out (5, e).");

  m.def("shuffle_series", &shuffle_series, "values"_a, "series"_a, "planes"_a,
        "The byte planes of the rows `series` of an (k, m) block, as one run of values.");
  m.def("unshuffle_series", &unshuffle_series, "planes"_a, "m"_a, "first"_a, "count"_a,
        "rows"_a, "out"_a, "at"_a, "stream"_a = false,
        "Samples first .. first + count of the shuffled series into out[rows[j], at ..].");

  m.def("fill_rows", &fill_rows, "values"_a, "rows"_a, "out"_a, "at"_a, "count"_a,
        "stream"_a = false,
        "out[rows[j], at .. at + count] = values[j] where rows[j] >= 0.");

  nb::class_<StepperSpec>(m, "StepperSpec")
      .def(nb::init<>())
      .def_rw("tree", &StepperSpec::tree)
      .def_rw("meshes", &StepperSpec::meshes)
      .def_rw("paths", &StepperSpec::paths)
      .def_rw("rigid_meshes", &StepperSpec::rigid_meshes)
      .def_rw("compliant_meshes", &StepperSpec::compliant_meshes)
      .def_rw("springs", &StepperSpec::springs)
      .def_rw("bearing_springs", &StepperSpec::bearing_springs)
      .def_rw("generators", &StepperSpec::generators)
      .def_rw("rotors", &StepperSpec::rotors)
      .def_rw("input_columns", &StepperSpec::input_columns)
      .def_rw("bearing_damping", &StepperSpec::bearing_damping)
      .def_rw("driver_index", &StepperSpec::driver_index)
      .def_rw("frame_parent", &StepperSpec::frame_parent)
      .def_rw("frame_placement", &StepperSpec::frame_placement)
      .def_rw("dt", &StepperSpec::dt)
      .def_rw("projection_tol", &StepperSpec::projection_tol)
      .def_rw("rho_infinity", &StepperSpec::rho_infinity)
      .def_rw("solver", &StepperSpec::solver);

  nb::enum_<Family>(m, "Family")
      .value("run", Family::run)
      .value("joint", Family::joint)
      .value("mesh", Family::mesh)
      .value("bearing", Family::bearing)
      .value("body", Family::body)
      .value("generator", Family::generator)
      .value("rotor", Family::rotor);

  auto series = nb::enum_<Series>(m, "Series");
  for (size_t i = 0; i < kSeriesCount; ++i) {
    series.value(kSeriesLayouts[i].name, static_cast<Series>(i));
  }

  m.def(
      "series_layout",
      [](Series s) { return std::make_pair(layout(s).family, layout(s).components); },
      "series"_a, "The family of a series and its components (1 scalar, 3 vector, 4 quaternion).");

  auto set_array = [](OutputArrays& out, Series s, Array values) { out[s] = std::move(values); };
  nb::class_<OutputArrays>(m, "OutputArrays")
      .def(nb::init<>())
      .def("set", set_array, "series"_a, "values"_a,
           "The array the run writes series into (row-major float64, written in place).")
      .def("__setitem__", set_array, "series"_a, "values"_a)
      .def(
          "__getitem__",
          [](OutputArrays& out, Series s) -> nb::object {
            return out[s].is_valid() ? nb::cast(out[s]) : nb::none();
          },
          "series"_a);

  nb::class_<RunStatus>(m, "RunStatus")
      .def_ro("code", &RunStatus::code)
      .def_ro("sample", &RunStatus::sample)
      .def_ro("step", &RunStatus::step)
      .def_ro("time", &RunStatus::time)
      .def_ro("what", &RunStatus::what)
      .def_ro("residual", &RunStatus::residual)
      .def_ro("primal", &RunStatus::primal)
      .def_ro("dual", &RunStatus::dual)
      .def_ro("iterations", &RunStatus::iterations);

  nb::class_<EquilibriumStatus>(m, "EquilibriumStatus")
      .def_ro("iterations", &EquilibriumStatus::iterations)
      .def_ro("converged", &EquilibriumStatus::converged)
      .def_ro("correction", &EquilibriumStatus::correction)
      .def_ro("displacement", &EquilibriumStatus::displacement)
      .def_ro("residual", &EquilibriumStatus::residual)
      .def_ro("flank_switches", &EquilibriumStatus::flank_switches);

  nb::class_<Assembly>(m, "Assembly")
      .def_ro("mass", &Assembly::mass)
      .def_ro("bias", &Assembly::bias)
      .def_ro("jac", &Assembly::jac)
      .def_ro("gamma", &Assembly::gamma);

  nb::class_<PyStepper>(m, "Stepper")
      .def(nb::init<const StepperSpec&, const Eigen::VectorXd&, const Eigen::VectorXd&, long>(),
           "spec"_a, "q0"_a, "v0"_a, "samples"_a)
      .def("run", &PyStepper::run, "k0"_a, "k1"_a, "torque"_a, "target"_a, "out"_a, "inputs"_a,
           "stride"_a = 1,
           "Steps samples [k0, k1) into rows 0 … k1 − k0 − 1 of out (stride > 1: only every "
           "stride-th sample from 0 and the run's last, in consecutive rows); returns the status.")
      .def("equilibrium", &PyStepper::equilibrium, "torque"_a, "target"_a, "inputs"_a,
           "max_iterations"_a, "tolerance"_a,
           "Moves the start to static equilibrium under the first sample's loads.")
      .def("mass_matrix", &PyStepper::mass_matrix, "q"_a,
           "Joint-space inertia at q, from this module's copy of the model [kg·m²].")
      .def("assemble", &PyStepper::assemble, "q"_a, "v"_a,
           "M, b, J and γ of the step at (q, v), with the rows' current flanks.");

  nb::class_<MeshRowSet>(m, "MeshRows")
      .def_ro("jac_t", &MeshRowSet::jac_t)
      .def_ro("jac_r", &MeshRowSet::jac_r)
      .def_ro("bias_t", &MeshRowSet::bias_t)
      .def_ro("bias_r", &MeshRowSet::bias_r)
      .def_ro("tangent", &MeshRowSet::tangent)
      .def_ro("radial", &MeshRowSet::radial)
      .def_ro("pitch_point", &MeshRowSet::pitch_point)
      .def_ro("axis", &MeshRowSet::axis)
      .def_ro("row_front", &MeshRowSet::row_front)
      .def_ro("row_back", &MeshRowSet::row_back)
      .def_ro("bias_front", &MeshRowSet::bias_front)
      .def_ro("bias_back", &MeshRowSet::bias_back)
      .def_ro("normal_front", &MeshRowSet::normal_front)
      .def_ro("normal_back", &MeshRowSet::normal_back);

  m.def("mesh_rows", &mesh_rows, "meshes"_a, "jac"_a, "djac"_a, "v"_a, "origin"_a, "rot"_a,
        "Rows of every mesh at one state, split and per flank (pinwind/dynamics/mesh.py).");
}
