// pinocchio::computeJointJacobians with a compliant bearing's slides placed directly
// (joint_algorithms.hpp): the one instantiation of its joint step.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <type_traits>

#include <pinocchio/algorithm/jacobian.hpp>

#include "joint_algorithms.hpp"

namespace pinwind {

std::vector<int> slide_axes(const pinocchio::Model& model) {
  std::vector<int> axes(static_cast<size_t>(model.njoints), -1);
  for (pinocchio::JointIndex i = 1; i < static_cast<pinocchio::JointIndex>(model.njoints); ++i) {
    const std::string kind = model.joints[i].shortname();
    int axis = -1;
    if (kind == "JointModelPX") axis = 0;
    if (kind == "JointModelPY") axis = 1;
    if (kind == "JointModelPZ") axis = 2;
    if (axis >= 0 && model.jointPlacements[i].rotation().isIdentity(0.0)) axes[i] = axis;
  }
  return axes;
}

namespace {

// Pinocchio's JointJacobiansForwardStep for a revolute joint about axis x, y or z of its frame
// (JointModelRevoluteTpl), with each result written where it is kept: Pinocchio builds liMi, oMi
// and the column in temporaries and copies them, and the copies read the temporaries' 3-vector
// stores in pairs that straddle two stores, which the processor cannot forward (a stall each;
// three fifths of this step's time on the drivetrain). The same expressions, so the same
// values: calc's sincos; liMi = placement * M as TransformRevoluteTpl::se3Action computes it
// (two columns turned by (cos, sin), the third their cross product, the placement's
// translation); oMi = oMi_parent * liMi as SE3Tpl::act_impl, (R R_l, t + R t_l), with t + R t_l
// as R t_l + t (a sum, the same either way); the column (t × R_axis, R_axis) as
// JointMotionSubspaceRevoluteTpl::se3Action.
template <int axis, class JointModel>
void revolute_step(const JointModel& joint, pinocchio::Data& data, const pinocchio::Model& model,
                   const Eigen::VectorXd& q) {
  const auto i = joint.id();
  auto& joint_data = boost::get<typename JointModel::JointDataDerived>(data.joints[i].toVariant());
  joint.calc(joint_data, q);
  const double sin = joint_data.M.sin(), cos = joint_data.M.cos();
  const pinocchio::SE3& placement = model.jointPlacements[i];
  const auto& p = placement.rotation();
  const auto place = [&](pinocchio::SE3& local) {
    auto& r = local.rotation();
    if (axis == 0) {
      r.col(0) = p.col(0);
      r.col(1).noalias() = cos * p.col(1) + sin * p.col(2);
      r.col(2).noalias() = r.col(0).cross(r.col(1));
    } else if (axis == 1) {
      r.col(2).noalias() = cos * p.col(2) + sin * p.col(0);
      r.col(1) = p.col(1);
      r.col(0).noalias() = r.col(1).cross(r.col(2));
    } else {
      r.col(0).noalias() = cos * p.col(0) + sin * p.col(1);
      r.col(2) = p.col(2);
      r.col(1).noalias() = r.col(2).cross(r.col(0));
    }
    local.translation() = placement.translation();
  };
  place(data.liMi[i]);
  const auto parent = model.parents[i];
  pinocchio::SE3& world = data.oMi[i];
  if (parent > 0) {
    const pinocchio::SE3& above = data.oMi[parent];
    const pinocchio::SE3& local = data.liMi[i];
    world.rotation().noalias() = above.rotation() * local.rotation();
    world.translation().noalias() = above.rotation() * local.translation();
    world.translation() += above.translation();
  } else {
    place(world);
  }
  auto column = data.J.col(model.idx_vs[i]);
  column.template head<3>() = world.translation().cross(world.rotation().col(axis));
  column.template tail<3>() = world.rotation().col(axis);
}

}  // namespace

void joint_jacobians(const pinocchio::Model& model, pinocchio::Data& data,
                     const Eigen::VectorXd& q, const std::vector<int>& slide_axes) {
  // Pinocchio's own step of computeJointJacobians for every other joint (its impl namespace, as
  // computeJointJacobians itself runs it; pyproject.toml pins pin < 5).
  using Pass = pinocchio::impl::JointJacobiansForwardStep<
      double, 0, pinocchio::JointCollectionDefaultTpl, Eigen::VectorXd, pinocchio::Data::Matrix6x>;
  // A revolute joint about x, y or z (every joint of a gearbox but a compliant bearing's slides)
  // runs the same step by its own type (revolute_step above), without the joint variant's
  // dispatch (a quarter of the step's cost per joint).
  for (pinocchio::JointIndex i = 1; i < static_cast<pinocchio::JointIndex>(model.njoints); ++i) {
    const int axis = slide_axes[i];
    if (axis < 0) {
      const auto& joint = model.joints[i].toVariant();
      if (const auto* rz = boost::get<pinocchio::JointModelRZ>(&joint)) {
        revolute_step<2>(*rz, data, model, q);
      } else if (const auto* rx = boost::get<pinocchio::JointModelRX>(&joint)) {
        revolute_step<0>(*rx, data, model, q);
      } else if (const auto* ry = boost::get<pinocchio::JointModelRY>(&joint)) {
        revolute_step<1>(*ry, data, model, q);
      } else {
        Pass::run(model.joints[i], data.joints[i], Pass::ArgsType(model, data, q, data.J));
      }
      continue;
    }
    // The slide's pose in its parent is its placement moved by q along the axis; in the world,
    // the parent's rotation and the parent's pose applied to that translation.
    pinocchio::SE3& local = data.liMi[i];
    local.rotation().setIdentity();
    local.translation() = model.jointPlacements[i].translation();
    local.translation()[axis] += q[model.idx_qs[i]];
    const auto parent = model.parents[i];
    if (parent > 0) {
      const pinocchio::SE3& above = data.oMi[parent];
      data.oMi[i].rotation() = above.rotation();
      data.oMi[i].translation() = above.translation() + above.rotation() * local.translation();
    } else {
      data.oMi[i] = local;
    }
    auto column = data.J.col(model.idx_vs[i]);
    column.head<3>() = data.oMi[i].rotation().col(axis);
    column.tail<3>().setZero();
  }
}

bool mass_is_constant(const pinocchio::Model& model, const std::vector<int>& slide_axes) {
  const auto nj = static_cast<pinocchio::JointIndex>(model.njoints);
  if (nj < 2) return true;
  for (pinocchio::JointIndex i = 1; i < nj; ++i) {
    const std::string kind = model.joints[i].shortname();
    const bool revolute = kind == "JointModelRX" || kind == "JointModelRY" ||
                          kind == "JointModelRZ" || kind == "JointModelRevoluteUnaligned";
    if (!revolute || slide_axes[i] >= 0) return false;
  }
  pinocchio::Data data(model);
  joint_jacobians(model, data, Eigen::VectorXd::Zero(model.nq), slide_axes);  // every q: 0
  const Eigen::Vector3d k = data.J.col(model.idx_vs[1]).tail<3>().normalized();
  double length = 0.0;
  for (pinocchio::JointIndex i = 1; i < nj; ++i) {
    length = std::max({length, data.oMi[i].translation().norm(), model.inertias[i].lever().norm()});
  }
  const double tol = 64.0 * std::numeric_limits<double>::epsilon() * std::max(length, 1.0);
  const auto perpendicular = [&](const Eigen::Vector3d& d) { return (d - d.dot(k) * k).norm(); };
  for (pinocchio::JointIndex i = 1; i < nj; ++i) {
    const Eigen::Vector3d axis = data.J.col(model.idx_vs[i]).tail<3>();
    if (axis.cross(k).norm() > tol) return false;  // k or −k: a turn about either is about k
  }
  for (pinocchio::JointIndex i = 1; i < nj; ++i) {
    if (model.inertias[i].mass() == 0.0) continue;
    const Eigen::Vector3d centre = data.oMi[i].act(model.inertias[i].lever());
    int levers = perpendicular(centre - data.oMi[i].translation()) > tol ? 1 : 0;
    for (auto j = i; model.parents[j] > 0; j = model.parents[j]) {
      const auto parent = model.parents[j];
      if (perpendicular(data.oMi[j].translation() - data.oMi[parent].translation()) > tol) {
        ++levers;
      }
    }
    if (levers > 1) return false;
  }
  return true;
}

bool is_vector_space(const pinocchio::Model& model) {
  for (pinocchio::JointIndex i = 1; i < static_cast<pinocchio::JointIndex>(model.njoints); ++i) {
    const std::string kind = model.joints[i].shortname();
    const bool plain = kind == "JointModelRX" || kind == "JointModelRY" || kind == "JointModelRZ" ||
                       kind == "JointModelRevoluteUnaligned" || kind == "JointModelPX" ||
                       kind == "JointModelPY" || kind == "JointModelPZ" ||
                       kind == "JointModelPrismaticUnaligned";
    if (!plain) return false;
  }
  return true;
}

}  // namespace pinwind
