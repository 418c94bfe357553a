// Python bindings of the step loop of pinwind.dynamics._native: the run's spec, the Stepper and
// its outputs (module.cpp gathers the bindings). The Stepper's work is compiled in units of its
// own (stepper.hpp).
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/unique_ptr.h>
#include <nanobind/stl/vector.h>

#include <array>
#include <memory>
#include <stdexcept>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "element_kinds.hpp"
#include "series.hpp"
#include "spec_checks.hpp"
#include "stepper.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace pinwind {
namespace {

using Array = nb::ndarray<double, nb::numpy, nb::c_contig, nb::device::cpu>;

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

// Everything a run needs besides the initial state and the arrays it writes: the model, its
// meshes, each kind's specs (a field each, named by the kind: element_kinds.hpp) and the
// recorded joints and bodies.
struct StepperSpec {
  JointTree tree;
  MeshConstants meshes;
  std::vector<MeshPathSpec> paths;
  KindSpecs kinds;
  long input_columns = 0;
  std::vector<long> bearing_joints;  // the joints recorded as bearings (Family::bearing)
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

// The Stepper's setup from the spec, checked; counts: the elements of each family of series.
StepperSetup setup(const StepperSpec& spec, FamilyCounts& counts) {
  StepperSetup s;
  s.model = build_model(spec.tree);
  const size_t nv = static_cast<size_t>(s.model.nv);
  check_meshes(spec.meshes, nv);
  const size_t nm = static_cast<size_t>(spec.meshes.count());
  check_size("paths", spec.paths, nm);
  for (const auto& p : spec.paths) {
    if (p.pair_position.size() != p.pair_stiffness.size()) {
      throw std::invalid_argument("paths: pair_position and pair_stiffness differ in size");
    }
    if (p.gap_position.size() != p.gap_value.size() ||
        (p.gap_position.size() && !p.pair_position.size())) {
      throw std::invalid_argument("paths: a gap table needs its positions and the pair table");
    }
  }
  check_size("frame_placement", spec.frame_placement, spec.frame_parent.size());
  for (const long j : spec.bearing_joints) {
    if (j < 1 || j >= s.model.njoints) throw std::invalid_argument("bad bearing joint id");
  }
  s.meshes = spec.meshes;
  s.paths = spec.paths;
  s.input_columns = spec.input_columns;
  add_kinds(spec.kinds, {s.model.nv, s.meshes, s.paths, s.input_columns}, s, counts);
  s.bearing_joints = spec.bearing_joints;
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

// A run of the step loop; each call to run() writes one block of samples into the arrays it
// is given, so a run of any length needs memory for one block only.
class PyStepper {
 public:
  PyStepper(const StepperSpec& spec, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
            long samples) {
    StepperSetup s = setup(spec, counts_);
    const auto nv = static_cast<long>(s.model.nv);
    auto count = [&](Family f) -> long& { return counts_[static_cast<size_t>(f)]; };
    count(Family::run) = 1;
    count(Family::joint) = nv;
    count(Family::mesh) = static_cast<long>(s.meshes.count());
    count(Family::bearing) = static_cast<long>(s.bearing_joints.size());
    count(Family::body) = static_cast<long>(s.frame_parent.size());
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
    if (inputs_ && ((inputs.rows() != k1 - k0 && inputs.rows() != 1) || inputs.cols() != inputs_)) {
      throw std::invalid_argument("run: inputs must be (k1 - k0, input_columns) or (1, ...)");
    }
    const long nv = counts_[static_cast<size_t>(Family::joint)];
    if (k1 > k0 && ((torque.rows() != k1 - k0 && torque.rows() != 1) || torque.cols() != nv)) {
      throw std::invalid_argument("run: torque must be (k1 - k0, nv) or (1, nv)");
    }
    if (k1 > k0 && target.cols() && target.rows() < k1 - k0 + 1) {
      throw std::invalid_argument("run: target must have k1 - k0 + 1 rows");
    }
    const long rows = stepper_->kept_rows(k0, k1, stride);
    const Outputs o = outputs(out, static_cast<size_t>(rows), counts_);
    nb::gil_scoped_release release;
    return stepper_->run(k0, k1, torque, target, o, inputs, stride);
  }

  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) { return stepper_->mass_matrix(q); }

  bool constant_mass() const { return stepper_->constant_mass(); }
  std::vector<long> mesh_frames() const { return stepper_->mesh_frames(); }

  EquilibriumStatus equilibrium(const RowMat& torque, const RowMat& target, const RowMat& inputs,
                                long max_iterations, double tolerance, long load_steps) {
    const long nv = counts_[static_cast<size_t>(Family::joint)];
    if (torque.rows() != 1 || torque.cols() != nv || target.rows() != 2 ||
        (inputs_ && (inputs.rows() != 1 || inputs.cols() != inputs_))) {
      throw std::invalid_argument(
          "equilibrium: torque (1, nv), target (2, drivers), inputs (1, input_columns)");
    }
    if (load_steps < 1) throw std::invalid_argument("equilibrium: load_steps must be at least 1");
    return stepper_->equilibrium(torque, target, inputs, max_iterations, tolerance, load_steps);
  }

  Assembly assemble(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    if (q.size() != counts_[static_cast<size_t>(Family::joint)] || v.size() != q.size()) {
      throw std::invalid_argument("assemble: q and v must have nv values");
    }
    return stepper_->assemble(q, v);
  }

  ElementForces element_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    if (q.size() != counts_[static_cast<size_t>(Family::joint)] || v.size() != q.size()) {
      throw std::invalid_argument("element_forces: q and v must have nv values");
    }
    return stepper_->element_forces(q, v);
  }

  bool saves_state() const { return stepper_->saves_state(); }

  std::unique_ptr<StepperState> save() const { return stepper_->save(); }

  void restore(const StepperState& state) { stepper_->restore(state); }

 private:
  FamilyCounts counts_{};  // elements per family (series.hpp)
  long inputs_ = 0;
  std::unique_ptr<Stepper> stepper_;
};

}  // namespace

void bind_stepper(nb::module_& m) {
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

  auto spec = nb::class_<StepperSpec>(m, "StepperSpec");
  spec.def(nb::init<>())
      .def_rw("tree", &StepperSpec::tree)
      .def_rw("meshes", &StepperSpec::meshes)
      .def_rw("paths", &StepperSpec::paths);
  // Each kind's specs, under the kind's field (element_kinds.hpp).
  for_each_kind([&](auto kind, auto i) {
    using Specs = typename decltype(kind)::Specs;
    constexpr size_t at = decltype(i)::value;
    spec.def_prop_rw(
        decltype(kind)::field, [](const StepperSpec& s) { return std::get<at>(s.kinds); },
        [](StepperSpec& s, Specs values) { std::get<at>(s.kinds) = std::move(values); });
  });
  spec.def_rw("input_columns", &StepperSpec::input_columns)
      .def_rw("bearing_joints", &StepperSpec::bearing_joints)
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
      .value("rotor", Family::rotor)
      .value("row", Family::row)
      .value("slice", Family::slice);

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
      .def_ro("largest", &EquilibriumStatus::largest)
      .def_ro("residual", &EquilibriumStatus::residual)
      .def_ro("flank_switches", &EquilibriumStatus::flank_switches);

  nb::class_<Assembly>(m, "Assembly")
      .def_ro("mass", &Assembly::mass)
      .def_ro("bias", &Assembly::bias)
      .def_ro("jac", &Assembly::jac)
      .def_ro("gamma", &Assembly::gamma);

  nb::class_<ElementForces>(m, "ElementForces")
      .def_ro("force", &ElementForces::force)
      .def_ro("stiffness", &ElementForces::stiffness)
      .def_ro("damping", &ElementForces::damping)
      .def_ro("potential", &ElementForces::potential);

  nb::class_<StepperState>(m, "StepperState",
                           "A run's state between two samples (Stepper.save): opaque, of the "
                           "model's size whatever the run's length.");

  nb::class_<PyStepper>(m, "Stepper")
      .def(nb::init<const StepperSpec&, const Eigen::VectorXd&, const Eigen::VectorXd&, long>(),
           "spec"_a, "q0"_a, "v0"_a, "samples"_a)
      .def("run", &PyStepper::run, "k0"_a, "k1"_a, "torque"_a, "target"_a, "out"_a, "inputs"_a,
           "stride"_a = 1,
           "Steps samples [k0, k1) into rows 0 … k1 − k0 − 1 of out (stride > 1: only every "
           "stride-th sample from 0 and the run's last, in consecutive rows); returns the status.")
      .def("equilibrium", &PyStepper::equilibrium, "torque"_a, "target"_a, "inputs"_a,
           "max_iterations"_a, "tolerance"_a, "load_steps"_a = 1,
           "Moves the start to static equilibrium under the first sample's loads (the torques "
           "in load_steps equal steps).")
      .def("mass_matrix", &PyStepper::mass_matrix, "q"_a,
           "Joint-space inertia at q, from this module's copy of the model [kg·m²].")
      .def_prop_ro("constant_mass", &PyStepper::constant_mass,
                   "Whether M(q) is the same at every q (joint_algorithms.hpp mass_is_constant): "
                   "the step then takes it once instead of by CRBA at every step.")
      .def_prop_ro("mesh_frames", &PyStepper::mesh_frames,
                   "Per mesh, the joint whose frame carries its geometry when its rows are the "
                   "same at every q (0: the world), taken once with γ = 0; -1: evaluated at "
                   "every step.")
      .def("assemble", &PyStepper::assemble, "q"_a, "v"_a,
           "M, b, J and γ of the step at (q, v), with the rows' current flanks.")
      .def("element_forces", &PyStepper::element_forces, "q"_a, "v"_a,
           "The elements' force, stiffness −∂f/∂q, damping −∂f/∂v and stored energy at (q, v), "
           "each element new (in contact wherever it overlaps).")
      .def_prop_ro("saves_state", &PyStepper::saves_state,
                   "Whether every element and constraint copies its state, so that save() works.")
      .def("save", &PyStepper::save,
           "The run's state before its next sample: q, v, the generalized-α memory, the energy "
           "ledger, every element's and constraint's internal states and the solver's.")
      .def("restore", &PyStepper::restore, "state"_a,
           "Takes the run back to a state save() gave (ValueError for another run's); the next "
           "run() from the sample after it steps bit for bit as it did then.");

}

}  // namespace pinwind
