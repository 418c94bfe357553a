// Python bindings of the mesh rows of pinwind.dynamics._native (pinwind/dynamics/mesh.py):
// the meshes' constants and their rows at one state (module.cpp gathers the bindings).
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>
#include <nanobind/stl/vector.h>

#include <vector>

#include "bindings.hpp"
#include "mesh_rows.hpp"
#include "spec_checks.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace pinwind {
namespace {

// Rows of every mesh at one state for Python (pinwind/dynamics/mesh.py): their t and r̂ parts,
// the geometry, and both flanks' rows, biases and lines of action, from the step loop's own
// functions.
struct MeshRowSet {
  RowMat jac_t, jac_r, jac_k;             // (meshes, nv)
  Eigen::VectorXd bias_t, bias_r, bias_k;  // (meshes,)
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
  MeshRowSet out{rows.jac_t, rows.jac_r, rows.jac_k, rows.bias_t, rows.bias_r, rows.bias_k,
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

}  // namespace

void bind_mesh_rows(nb::module_& m) {
  nb::class_<MeshConstants>(m, "MeshConstants")
      .def(nb::init<>())
      .def_rw("joint_ids", &MeshConstants::joint_ids)
      .def_rw("slot_a", &MeshConstants::slot_a)
      .def_rw("slot_b", &MeshConstants::slot_b)
      .def_rw("centre_a", &MeshConstants::centre_a)
      .def_rw("centre_b", &MeshConstants::centre_b)
      .def_rw("axis_a", &MeshConstants::axis_a)
      .def_rw("axis_b", &MeshConstants::axis_b)
      .def_rw("mu", &MeshConstants::mu)
      .def_rw("sigma", &MeshConstants::sigma)
      .def_rw("support", &MeshConstants::support)
      .def_rw("cos_a", &MeshConstants::cos_a)
      .def_rw("sin_a", &MeshConstants::sin_a)
      .def_rw("eps", &MeshConstants::eps)
      .def_rw("tan_beta_b", &MeshConstants::tan_beta_b)
      .def_rw("joint_a", &MeshConstants::joint_a)
      .def_rw("joint_b", &MeshConstants::joint_b);

  nb::class_<MeshRowSet>(m, "MeshRows")
      .def_ro("jac_t", &MeshRowSet::jac_t)
      .def_ro("jac_r", &MeshRowSet::jac_r)
      .def_ro("jac_k", &MeshRowSet::jac_k)
      .def_ro("bias_t", &MeshRowSet::bias_t)
      .def_ro("bias_r", &MeshRowSet::bias_r)
      .def_ro("bias_k", &MeshRowSet::bias_k)
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

  m.def("axial_offset", &axial_offset, "k"_a, "k_b"_a, "centre_a"_a, "centre_b"_a,
        "pitch_point"_a,
        "Axial position [m] of gear B's flank relative to gear A's at the pitch point, along "
        "A's axis k (cpp/mesh_rows.hpp axial_offset).");
  m.def("mesh_rows", &mesh_rows, "meshes"_a, "jac"_a, "djac"_a, "v"_a, "origin"_a, "rot"_a,
        "Rows of every mesh at one state, split and per flank (pinwind/dynamics/mesh.py).");
}

}  // namespace pinwind
