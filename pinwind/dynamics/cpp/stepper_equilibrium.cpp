// The static equilibrium at a run's start, Stepper::equilibrium (stepper_calls.hpp).
#include "stepper_calls.hpp"

namespace pinwind {

EquilibriumStatus stepper_equilibrium(Stepper& stepper, const RowMat& torque,
                                      const RowMat& target, const RowMat& inputs,
                                      long max_iterations, double tolerance) {
  return stepper.equilibrium(torque, target, inputs, max_iterations, tolerance);
}

}  // namespace pinwind
