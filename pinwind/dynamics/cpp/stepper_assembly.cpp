// A Stepper's start and the assembly the tests check against Pinocchio: Stepper::Stepper,
// Stepper::assemble and Stepper::mass_matrix (stepper_calls.hpp).
#include <utility>

#include "stepper_calls.hpp"

namespace pinwind {

std::unique_ptr<Stepper> start_stepper(StepperSetup setup, const Eigen::VectorXd& q0,
                                       const Eigen::VectorXd& v0, long samples) {
  return std::make_unique<Stepper>(std::move(setup), q0, v0, samples);
}

Assembly stepper_assembly(Stepper& stepper, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  return stepper.assemble(q, v);
}

Eigen::MatrixXd stepper_mass_matrix(Stepper& stepper, const Eigen::VectorXd& q) {
  return stepper.mass_matrix(q);
}

}  // namespace pinwind
