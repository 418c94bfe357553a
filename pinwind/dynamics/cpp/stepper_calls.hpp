// The Stepper's entry points, each compiled in a unit of its own: the step loop (stepper_run.cpp),
// the static equilibrium (stepper_equilibrium.cpp), the start and the checks' assembly
// (stepper_assembly.cpp). Each unit instantiates the Pinocchio and proxsuite templates its entry
// point uses, inlined there as before; compiled in one unit, they needed 4.3 GB at once.
#pragma once

#include <memory>

#include "stepper.hpp"

namespace pinwind {

// A Stepper at (q0, v0) for a run of `samples` samples (Stepper::Stepper).
std::unique_ptr<Stepper> start_stepper(StepperSetup setup, const Eigen::VectorXd& q0,
                                       const Eigen::VectorXd& v0, long samples);

// Stepper::run.
RunStatus run_stepper(Stepper& stepper, long k0, long k1, const RowMat& torque,
                      const RowMat& target, const Outputs& out, const RowMat& inputs,
                      long stride);

// Stepper::equilibrium.
EquilibriumStatus stepper_equilibrium(Stepper& stepper, const RowMat& torque,
                                      const RowMat& target, const RowMat& inputs,
                                      long max_iterations, double tolerance);

// Stepper::assemble.
Assembly stepper_assembly(Stepper& stepper, const Eigen::VectorXd& q, const Eigen::VectorXd& v);

// Stepper::mass_matrix.
Eigen::MatrixXd stepper_mass_matrix(Stepper& stepper, const Eigen::VectorXd& q);

}  // namespace pinwind
