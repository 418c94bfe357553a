// Hub loads: six load components (forces and moments) on a body at a point of it, such as the
// rotor's thrust, shear forces, torque and bending moments on the main shaft
// (pinwind/loads/hub_loads.py, docs/loads.md "Hub loads"). The components are the sample's input
// columns ``column … column + 5``: F_x, F_y, F_z [N], M_x, M_y, M_z [N·m] along the hub axes,
// x the shaft axis. The hub axes are ``axes`` (columns: x, y, z) in the frame of the body's
// joint: turning with it (rotating), or held in the bearing's housing (fixed: ``parent`` is the
// joint the bearing sits in, above a compliant bearing's slides and tilts, and ``placement``
// the body joint's undeflected orientation in it, so that the load neither turns with the shaft
// nor tilts with the bearing's deflection):
//
//     R_world = oMi[joint] · axes                          (rotating)
//     R_world = oMi[parent] · placement · axes             (fixed)
//     f = R_world F,   m = R_world M,   p = oMi[joint] · point      (world)
//
// and the load's generalised force is its virtual work through the body's motion, the spatial
// force at the world origin dotted with each supporting joint's column of the world Jacobian
// (Featherstone 2008 §2; Pinocchio's WORLD convention):
//
//     τ_c = J_c · (f, p × f + m),     c = the velocity columns of the joints from the body down
//
// It is taken at the step's start (q_k), with no implicit part: the load depends on the
// configuration only through the shaft's small bearing deflections and, in the rotating frame,
// through the shaft angle over one step. The same spatial force joins the body's applied forces,
// so the bearing reactions (by RNEA) carry it.
#pragma once

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>
#include <nanobind/stl/vector.h>

#include "element_kind.hpp"

namespace pinwind {

struct HubLoadSpec {
  long joint = -1;                               // the body's joint (Pinocchio joint index)
  long parent = 0;                               // the joint its bearing sits in (0: world)
  std::vector<long> columns;                     // velocity columns of the joints supporting it
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // hub axes (x, y, z) in the joint frame
  Eigen::Matrix3d placement = Eigen::Matrix3d::Identity();  // the joint's rotation in parent's
  Eigen::Vector3d point = Eigen::Vector3d::Zero();  // where the force acts, joint frame [m]
  bool rotating = false;                         // the axes turn with the joint
  long column = 0;                               // the first of its six input columns
};

class HubLoad : public Element {
 public:
  explicit HubLoad(HubLoadSpec spec) : s_(std::move(spec)) {}

  void prepare(const StepView& s) override {
    if (s.inputs == nullptr) {  // no sample's inputs (Stepper::element_forces): no load
      unload();
      return;
    }
    load(s, s.inputs + s_.column);
  }

 protected:
  // No load this step.
  void unload() {
    wrench_.setZero();
    std::fill(tau_.begin(), tau_.end(), 0.0);
  }

  // The load of the six components c (F_x, F_y, F_z [N], M_x, M_y, M_z [N·m], hub axes) at the
  // step's start: the spatial force in the world and its generalised force (the header).
  void load(const StepView& s, const double* c) {
    const auto& body = s.data.oMi[static_cast<size_t>(s_.joint)];
    const Eigen::Matrix3d world =
        s_.rotating ? Eigen::Matrix3d(body.rotation() * s_.axes)
                    : Eigen::Matrix3d(s.data.oMi[static_cast<size_t>(s_.parent)].rotation() *
                                      s_.placement * s_.axes);
    const Eigen::Vector3d f = world * Eigen::Vector3d(c[0], c[1], c[2]);
    const Eigen::Vector3d m = world * Eigen::Vector3d(c[3], c[4], c[5]);
    const Eigen::Vector3d p = body.act(s_.point);
    wrench_.head<3>() = f;
    wrench_.tail<3>() = p.cross(f) + m;
    for (size_t i = 0; i < s_.columns.size(); ++i) {
      tau_[i] = s.data.J.col(s_.columns[i]).dot(wrench_);
    }
  }

 public:
  void add_force(const StepView&, Eigen::VectorXd& force) override {
    for (size_t i = 0; i < s_.columns.size(); ++i) force[s_.columns[i]] += tau_[i];
  }

  void add_body_forces(const StepView&, BodyForces& forces) const override {
    auto& on = forces.of_joint[static_cast<size_t>(s_.joint)];
    on.linear() += wrench_.head<3>();
    on.angular() += wrench_.tail<3>();
  }

  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    StepWork w;
    for (size_t i = 0; i < s_.columns.size(); ++i) w.applied += tau_[i] * v_mid[s_.columns[i]];
    w.applied *= s.dt;
    return w;
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override { return copy_of<HubLoad, Element>(*this); }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  HubLoadSpec s_;
  Eigen::Matrix<double, 6, 1> wrench_ = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<double> tau_ = std::vector<double>(s_.columns.size(), 0.0);
};

// The kind (element_kind.hpp): StepperSpec.hub_loads, an element each, reading six input
// columns each.
struct HubLoadsKind : KindBase {
  using Specs = std::vector<HubLoadSpec>;
  using Built = Elements;
  static constexpr const char* field = "hub_loads";

  static void check(const Specs& specs, const KindContext& c) {
    for (const auto& h : specs) {
      check_placement(h, c);
      if (h.column < 0 || h.column + 6 > c.input_columns) {
        throw std::invalid_argument("hub load: its six input columns are outside the inputs");
      }
    }
  }

  // The checks of where a load acts, shared with the rotor's loads on its hub (rotor.hpp).
  static void check_placement(const HubLoadSpec& h, const KindContext& c) {
    if (h.joint < 1) throw std::invalid_argument("hub load on a joint index below 1");
    if (h.parent < 0 || h.parent >= h.joint) {
      throw std::invalid_argument("hub load: its joint's parent must come before it");
    }
    if (h.columns.empty()) throw std::invalid_argument("hub load on a body that cannot move");
    for (long col : h.columns) {
      if (col < 0 || col >= c.nv) throw std::invalid_argument("hub load velocity column");
    }
    const double orthonormal = (h.axes.transpose() * h.axes - Eigen::Matrix3d::Identity())
                                   .cwiseAbs()
                                   .maxCoeff();
    if (!(orthonormal < 1e-9) || h.axes.determinant() < 0.0) {
      throw std::invalid_argument("hub load axes must be a right-handed orthonormal frame");
    }
  }

  static void add(const Specs& specs, const KindContext&, Elements& out) {
    for (const auto& h : specs) out.push_back(std::make_unique<HubLoad>(h));
  }

  static void bind(nanobind::module_& m) {
    namespace nb = nanobind;
    nb::class_<HubLoadSpec>(m, "HubLoadSpec")
        .def(nb::init<>())
        .def_rw("joint", &HubLoadSpec::joint)
        .def_rw("parent", &HubLoadSpec::parent)
        .def_rw("columns", &HubLoadSpec::columns)
        .def_rw("axes", &HubLoadSpec::axes)
        .def_rw("placement", &HubLoadSpec::placement)
        .def_rw("point", &HubLoadSpec::point)
        .def_rw("rotating", &HubLoadSpec::rotating)
        .def_rw("column", &HubLoadSpec::column);
  }
};

}  // namespace pinwind
