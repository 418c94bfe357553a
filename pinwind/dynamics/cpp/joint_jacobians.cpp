// The one instantiation of pinocchio::computeJointJacobians (joint_algorithms.hpp).
#include <pinocchio/algorithm/jacobian.hpp>

#include "joint_algorithms.hpp"

namespace pinwind {

void joint_jacobians(const pinocchio::Model& model, pinocchio::Data& data,
                     const Eigen::VectorXd& q) {
  pinocchio::computeJointJacobians(model, data, q);
}

}  // namespace pinwind
