// Pinocchio's whole-tree algorithms that the Stepper calls, behind plain functions.
//
// Each of Pinocchio's algorithms is a template over the joint variant (every joint type's visit),
// and instantiating one costs the compiler several hundred MB: the Stepper's units call these
// functions instead, and each is instantiated once, in a small unit of its own
// (joint_jacobians.cpp, joint_configuration.cpp), so that no unit needs much more compiler
// memory than Pinocchio's headers alone. A call per step costs nothing beside the algorithm.
#pragma once

#include <Eigen/Core>
#include <pinocchio/multibody.hpp>

namespace pinwind {

// Joint placements data.oMi and the world Jacobian data.J at q (pinocchio::computeJointJacobians).
void joint_jacobians(const pinocchio::Model& model, pinocchio::Data& data,
                     const Eigen::VectorXd& q);

// q_out = q ⊕ dq: the configuration dq [rad or m] away from q (pinocchio::integrate).
void integrate(const pinocchio::Model& model, const Eigen::VectorXd& q,
               const Eigen::VectorXd& dq, Eigen::VectorXd& q_out);

// dq = q1 ⊖ q0: the displacement [rad or m] from q0 to q1 (pinocchio::difference).
void difference(const pinocchio::Model& model, const Eigen::VectorXd& q0,
                const Eigen::VectorXd& q1, Eigen::VectorXd& dq);

}  // namespace pinwind
