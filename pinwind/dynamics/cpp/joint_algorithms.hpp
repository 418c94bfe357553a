// Pinocchio's whole-tree algorithms that the Stepper calls, behind plain functions.
//
// Each of Pinocchio's algorithms is a template over the joint variant (every joint type's visit),
// and instantiating one costs the compiler several hundred MB: the Stepper's units call these
// functions instead, and each is instantiated once, in a small unit of its own
// (joint_jacobians.cpp, joint_configuration.cpp), so that no unit needs much more compiler
// memory than Pinocchio's headers alone. A call per step costs nothing beside the algorithm.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <pinocchio/multibody.hpp>

namespace pinwind {

// For each joint, the axis (0, 1, 2: x, y, z of its frame) of a slide: a prismatic joint along an
// axis of its frame, placed in its parent without rotation (a compliant bearing's slides, which
// the model's loader builds so); -1 for any other joint and for the universe.
std::vector<int> slide_axes(const pinocchio::Model& model);

// Joint placements data.oMi and the world Jacobian data.J at q, as pinocchio::computeJointJacobians
// computes them, with the slides of slide_axes(model) placed directly: the same values, since
// Pinocchio's products with their identity rotations are exact, without its general pose
// products (a planetary stage with five compliant bearings has ten slides of sixteen joints).
void joint_jacobians(const pinocchio::Model& model, pinocchio::Data& data,
                     const Eigen::VectorXd& q, const std::vector<int>& slide_axes);

// Whether the joint-space inertia M(q) is the same at every q, from the model's structure alone:
// every joint revolute (one angle), all axes parallel (k: then every rotation is about k and they
// stay parallel), and, on the path from the world to each body with mass, at most one nonzero
// lever among the perpendicular offsets of each joint's axis from its parent joint's axis and of
// the body's centre of mass from its own axis. Why: with θ̇_l about the axis through p_l, the
// centre of mass c of the body moves at Σ_l θ̇_l k × (c − p_l), and c − p_l is a sum of those
// offsets d_m, each turning with the angles above it; the kinetic energy's coefficients are the
// products d_m·d_m', which depend on the angles between m and m' unless m = m' or one offset is
// zero. The rotation's part, ½ I_kk (Σ θ̇)², and the armature do not depend on q. A planet on its
// carrier (one offset: its axis from the carrier's, its centre of mass on its own axis) and a
// gear on a fixed axis with an offset centre of mass pass; a gear on a carrier-borne crank does
// not. Offsets below 64 ε times the model's largest length count as zero (rounding).
bool mass_is_constant(const pinocchio::Model& model, const std::vector<int>& slide_axes);

// Whether every joint's configuration is its one coordinate (revolute about a fixed axis, or a
// slide): Pinocchio's integrate is then q + dq and its difference q1 − q0.
bool is_vector_space(const pinocchio::Model& model);

// q_out = q ⊕ dq: the configuration dq [rad or m] away from q (pinocchio::integrate).
void integrate(const pinocchio::Model& model, const Eigen::VectorXd& q,
               const Eigen::VectorXd& dq, Eigen::VectorXd& q_out);

// dq = q1 ⊖ q0: the displacement [rad or m] from q0 to q1 (pinocchio::difference).
void difference(const pinocchio::Model& model, const Eigen::VectorXd& q0,
                const Eigen::VectorXd& q1, Eigen::VectorXd& dq);

}  // namespace pinwind
