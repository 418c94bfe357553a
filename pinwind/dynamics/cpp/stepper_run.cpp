// The step loop, Stepper::run (stepper_calls.hpp).
#include "stepper_calls.hpp"

namespace pinwind {

RunStatus run_stepper(Stepper& stepper, long k0, long k1, const RowMat& torque,
                      const RowMat& target, const Outputs& out, const RowMat& inputs,
                      long stride) {
  return stepper.run(k0, k1, torque, target, out, inputs, stride);
}

}  // namespace pinwind
