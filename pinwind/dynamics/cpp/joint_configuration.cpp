// The one instantiation of pinocchio::integrate and pinocchio::difference (joint_algorithms.hpp).
#include <pinocchio/algorithm/joint-configuration.hpp>

#include "joint_algorithms.hpp"

namespace pinwind {

void integrate(const pinocchio::Model& model, const Eigen::VectorXd& q,
               const Eigen::VectorXd& dq, Eigen::VectorXd& q_out) {
  pinocchio::integrate(model, q, dq, q_out);
}

void difference(const pinocchio::Model& model, const Eigen::VectorXd& q0,
                const Eigen::VectorXd& q1, Eigen::VectorXd& dq) {
  pinocchio::difference(model, q0, q1, dq);
}

}  // namespace pinwind
