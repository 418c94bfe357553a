// Python bindings of the compiled step loop: pinwind.dynamics._native (stub: _native.pyi).
//
// The Python side (pinwind/dynamics/stepper.py) fills typed structs: the Pinocchio joint tree
// (placements, inertias), the mesh geometry, the elements' constants and the Result's arrays to
// write into. stepper_bindings.cpp rebuilds the Pinocchio model from the joint tree; a test checks
// that its mass matrix equals Pinocchio's own.
//
// The bindings are compiled in several units (bindings.hpp), and the step loop's work too
// (stepper.hpp), so that no compiler process needs much memory.
#include <nanobind/nanobind.h>

#include "bindings.hpp"

NB_MODULE(_native, m) {
  using namespace pinwind;
  m.doc() = "Compiled step loop of pinwind (pinwind/dynamics/cpp/).";
  bind_stepper(m);
  bind_elements(m);
  bind_mesh_rows(m);
  bind_columns(m);
  bind_time_step(m);
  bind_bearing_loads(m);
}
