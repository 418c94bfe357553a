// Python bindings of the compiled step loop: pinwind.dynamics._native.
//
// The Python side (pinwind/dynamics/stepper.py) hands over the Pinocchio model as plain arrays
// (joint tree, placements, inertias), rebuilds nothing else, and checks that this copy's mass
// matrix and bias forces equal Pinocchio's own.
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "stepper.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace pinwind {
namespace {

using Array = nb::ndarray<double, nb::numpy, nb::c_contig, nb::device::cpu>;
using IntArray = nb::ndarray<int64_t, nb::numpy, nb::c_contig, nb::device::cpu>;

Array array(const nb::dict& d, const char* key, size_t size) {
  if (!d.contains(key)) throw std::invalid_argument(std::string("missing array ") + key);
  Array a;
  if (!nb::try_cast<Array>(d[key], a)) {
    throw std::invalid_argument(std::string(key) + " must be a C-contiguous float64 array");
  }
  if (a.size() != size) {
    throw std::invalid_argument(std::string(key) + " has " + std::to_string(a.size()) +
                                " values, expected " + std::to_string(size));
  }
  return a;
}

std::vector<long> longs(const nb::dict& d, const char* key, size_t size) {
  IntArray a;
  if (!d.contains(key) || !nb::try_cast<IntArray>(d[key], a)) {
    throw std::invalid_argument(std::string(key) + " must be a C-contiguous int64 array");
  }
  if (a.size() != size) throw std::invalid_argument(std::string(key) + " has the wrong size");
  return std::vector<long>(a.data(), a.data() + size);
}

Eigen::VectorXd vec(const nb::dict& d, const char* key, size_t size) {
  Array a = array(d, key, size);
  return Eigen::Map<const Eigen::VectorXd>(a.data(), static_cast<Eigen::Index>(size));
}

Rows3 rows3(const nb::dict& d, const char* key, size_t rows) {
  Array a = array(d, key, 3 * rows);
  return Eigen::Map<const Rows3>(a.data(), static_cast<Eigen::Index>(rows), 3);
}

pinocchio::SE3 placement(const double* h) {
  const Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> m(h);
  return pinocchio::SE3(Eigen::Matrix3d(m.topLeftCorner<3, 3>()), Vec3(m.topRightCorner<3, 1>()));
}

// The Pinocchio model from its joint tree: types 0, 1, 2 = revolute about x, y, z of the joint
// frame; 3 = revolute about an unaligned axis.
pinocchio::Model build_model(const nb::dict& d) {
  const size_t nj = nb::cast<size_t>(d["joints"]);
  const auto parent = longs(d, "joint_parent", nj);
  const auto type = longs(d, "joint_type", nj);
  const Array axis = array(d, "joint_axis", 3 * nj);
  const Array place = array(d, "joint_placement", 16 * nj);
  const Array mass = array(d, "body_mass", nj);
  const Array com = array(d, "body_com", 3 * nj);
  const Array inertia = array(d, "body_inertia", 9 * nj);
  const auto names = nb::cast<std::vector<std::string>>(d["joint_names"]);
  pinocchio::Model model;
  for (size_t i = 0; i < nj; ++i) {
    const pinocchio::SE3 placement_i = placement(place.data() + 16 * i);
    const auto p = static_cast<pinocchio::JointIndex>(parent[i]);
    pinocchio::JointIndex id;
    switch (type[i]) {
      case 0:
        id = model.addJoint(p, pinocchio::JointModelRX(), placement_i, names[i]);
        break;
      case 1:
        id = model.addJoint(p, pinocchio::JointModelRY(), placement_i, names[i]);
        break;
      case 2:
        id = model.addJoint(p, pinocchio::JointModelRZ(), placement_i, names[i]);
        break;
      case 3:
        id = model.addJoint(p, pinocchio::JointModelRevoluteUnaligned(Vec3(axis.data() + 3 * i)),
                            placement_i, names[i]);
        break;
      default:
        throw std::invalid_argument("joint " + names[i] + ": unsupported joint type");
    }
    const Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>> rotational(
        inertia.data() + 9 * i);
    model.inertias[id] = pinocchio::Inertia(mass.data()[i], Vec3(com.data() + 3 * i),
                                            Eigen::Matrix3d(rotational));
  }
  model.armature = vec(d, "armature", static_cast<size_t>(model.nv));
  const Eigen::VectorXd gravity = vec(d, "gravity", 3);
  model.gravity = pinocchio::Motion(gravity, Vec3::Zero());
  return model;
}

MeshConstants mesh_constants(const nb::dict& d, size_t nv) {
  MeshConstants mc;
  const size_t nm = nb::cast<size_t>(d["meshes"]);
  const size_t slots = nb::cast<size_t>(d["slots"]);
  mc.joint_ids = longs(d, "slot_joint", slots);
  mc.slot_a = longs(d, "slot_a", nm);
  mc.slot_b = longs(d, "slot_b", nm);
  mc.centre_a = rows3(d, "centre_a", nm);
  mc.centre_b = rows3(d, "centre_b", nm);
  mc.axis_a = rows3(d, "axis_a", nm);
  mc.mu = vec(d, "mu", nm);
  mc.sigma = vec(d, "sigma", nm);
  const Array support = array(d, "support", slots * nv);
  mc.support = Eigen::Map<const RowMat>(support.data(), static_cast<Eigen::Index>(slots),
                                        static_cast<Eigen::Index>(nv));
  return mc;
}

StepperSetup setup(const nb::dict& d) {
  StepperSetup s;
  s.model = build_model(d);
  const size_t nv = static_cast<size_t>(s.model.nv);
  const size_t nm = nb::cast<size_t>(d["meshes"]);
  s.meshes = mesh_constants(d, nv);
  s.mesh_forces.cos_a = vec(d, "cos_a", nm);
  s.mesh_forces.sin_a = vec(d, "sin_a", nm);
  s.mesh_forces.eps = vec(d, "eps", nm);
  s.mesh_forces.tan_beta = vec(d, "tan_beta", nm);
  s.mesh_forces.joint_a = longs(d, "joint_a", nm);
  s.mesh_forces.joint_b = longs(d, "joint_b", nm);
  const size_t ns = nb::cast<size_t>(d["springs"]);
  s.elements.index_1 = longs(d, "spring_index_1", ns);
  s.elements.index_2 = longs(d, "spring_index_2", ns);
  s.elements.stiffness = vec(d, "spring_stiffness", ns);
  s.elements.damping = vec(d, "spring_damping", ns);
  s.elements.preload = vec(d, "spring_preload", ns);
  s.elements.bearing_damping = vec(d, "bearing_damping", nv);
  const size_t drivers = nb::cast<size_t>(d["drivers"]);
  s.driver_index = longs(d, "driver_index", drivers);
  const size_t frames = nb::cast<size_t>(d["frames"]);
  s.frame_parent = longs(d, "frame_parent", frames);
  const Array fp = array(d, "frame_placement", 16 * frames);
  for (size_t f = 0; f < frames; ++f) s.frame_placement.push_back(placement(fp.data() + 16 * f));
  s.dt = nb::cast<double>(d["dt"]);
  s.projection_tol = nb::cast<double>(d["projection_tol"]);
  s.solver.eps_abs = nb::cast<double>(d["eps_abs"]);
  s.solver.eps_rel = nb::cast<double>(d["eps_rel"]);
  s.solver.max_iter = nb::cast<long>(d["max_iter"]);
  return s;
}

// A Stepper that keeps the Result's arrays it writes into alive.
class PyStepper {
 public:
  PyStepper(const nb::dict& spec, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
            const nb::dict& out, long samples)
      : keep_(out) {
    StepperSetup s = setup(spec);
    const size_t nv = static_cast<size_t>(s.model.nv);
    const size_t nj = static_cast<size_t>(s.model.njoints - 1);
    const size_t nm = static_cast<size_t>(s.meshes.count());
    const size_t nb_ = s.frame_parent.size();
    const size_t n = static_cast<size_t>(samples);
    if (static_cast<size_t>(q0.size()) != nv || static_cast<size_t>(v0.size()) != nv) {
      throw std::invalid_argument("q0 and v0 must have nv values");
    }
    Outputs o{};
    o.samples = samples;
    auto ptr = [&](const char* key, size_t size) { return array(out, key, size).data(); };
    o.time = ptr("time", n);
    o.angle = ptr("angle", n * nv);
    o.speed = ptr("speed", n * nv);
    o.acceleration = ptr("acceleration", n * nv);
    o.torque = ptr("torque", n * nv);
    o.mesh_normal = ptr("mesh_normal", n * nm);
    o.mesh_tangential = ptr("mesh_tangential", n * nm);
    o.mesh_radial = ptr("mesh_radial", n * nm);
    o.mesh_axial = ptr("mesh_axial", n * nm);
    o.mesh_flank = ptr("mesh_flank", n * nm);
    o.transmission_error = ptr("transmission_error", n * nm);
    o.mesh_force_on_b = ptr("mesh_force_on_b", 3 * n * nm);
    o.pitch_point = ptr("pitch_point", 3 * n * nm);
    o.bearing_force = ptr("bearing_force", 3 * n * nj);
    o.bearing_moment = ptr("bearing_moment", 3 * n * nj);
    o.bearing_force_local = ptr("bearing_force_local", 3 * n * nj);
    o.bearing_moment_local = ptr("bearing_moment_local", 3 * n * nj);
    o.body_position = ptr("body_position", 3 * n * nb_);
    o.body_quaternion = ptr("body_quaternion", 4 * n * nb_);
    o.constraint_residual = ptr("constraint_residual", n);
    o.kinetic = ptr("kinetic", n);
    o.potential_spring = ptr("potential_spring", n);
    const char* work[6] = {"work_applied",     "work_drivers", "work_springs",
                           "work_gravity",     "work_constraints", "dissipated"};
    for (int i = 0; i < 6; ++i) o.work[i] = ptr(work[i], n);
    stepper_ = std::make_unique<Stepper>(std::move(s), q0, v0, o);
  }

  nb::dict run(long k0, long k1, const RowMat& torque, const RowMat& target) {
    RunStatus st;
    {
      nb::gil_scoped_release release;
      st = stepper_->run(k0, k1, torque, target);
    }
    nb::dict r;
    r["code"] = st.code;
    r["sample"] = st.sample;
    r["step"] = st.step;
    r["time"] = st.time;
    r["what"] = st.what;
    r["residual"] = st.residual;
    r["primal"] = st.primal;
    r["dual"] = st.dual;
    r["iterations"] = st.iterations;
    return r;
  }

  Eigen::MatrixXd mass_matrix(const Eigen::VectorXd& q) { return stepper_->mass_matrix(q); }

 private:
  nb::dict keep_;
  std::unique_ptr<Stepper> stepper_;
};

}  // namespace
}  // namespace pinwind

NB_MODULE(_native, m) {
  using namespace pinwind;
  m.doc() = "Compiled step loop of pinwind (pinwind/dynamics/cpp/).";

  nb::class_<PyStepper>(m, "Stepper")
      .def(nb::init<const nb::dict&, const Eigen::VectorXd&, const Eigen::VectorXd&,
                    const nb::dict&, long>(),
           "spec"_a, "q0"_a, "v0"_a, "out"_a, "samples"_a)
      .def("run", &PyStepper::run, "k0"_a, "k1"_a, "torque"_a, "target"_a,
           "Steps samples [k0, k1); returns the status of the run.")
      .def("mass_matrix", &PyStepper::mass_matrix, "q"_a,
           "Joint-space inertia at q, from this module's copy of the model [kg·m²].");

  m.def(
      "mesh_rows",
      [](const nb::dict& spec, const Eigen::MatrixXd& jac, const Eigen::MatrixXd& djac,
         const Eigen::VectorXd& v, const RowMat& origin, const RowMat& rot) {
        const MeshConstants mc = mesh_constants(spec, static_cast<size_t>(v.size()));
        std::vector<Vec3> o(mc.joint_ids.size());
        std::vector<Eigen::Matrix3d> r(mc.joint_ids.size());
        for (size_t i = 0; i < o.size(); ++i) {
          o[i] = origin.row(static_cast<Eigen::Index>(i)).transpose();
          r[i] = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(
              rot.row(static_cast<Eigen::Index>(i)).data());
        }
        MeshRows rows;
        rows.resize(mc.count(), v.size());
        evaluate_mesh_rows(mc, jac, djac, v, o, r, rows);
        return nb::make_tuple(rows.jac_t, rows.jac_r, rows.bias_t, rows.bias_r, rows.tangent,
                              rows.radial, rows.pitch_point, rows.axis);
      },
      "spec"_a, "jac"_a, "djac"_a, "v"_a, "origin"_a, "rot"_a,
      "Rows of every mesh at one state (pinwind/dynamics/mesh.py).");
}
