// The parts of the Python bindings of pinwind.dynamics._native, each compiled in a unit of its own
// (module.cpp calls them): in one unit with the step loop, the compiler needed 4.3 GB at once.
#pragma once

#include <nanobind/nanobind.h>

namespace pinwind {

// The run's spec (joint tree, solver settings), the Stepper, its outputs and statuses
// (stepper_bindings.cpp).
void bind_stepper(nanobind::module_& m);

// The elements' specs and laws: the meshes' paths, then each kind's own binding (element_kinds.hpp;
// element_bindings.cpp).
void bind_elements(nanobind::module_& m);

// The meshes' constants and their rows at one state (mesh_row_bindings.cpp).
void bind_mesh_rows(nanobind::module_& m);

// Statistics of a Result's columns and the byte planes of a log's series (column_bindings.cpp).
void bind_columns(nanobind::module_& m);

// A bearing's reaction split about its axis, for the derived bearing loads
// (bearing_load_bindings.cpp).
void bind_bearing_loads(nanobind::module_& m);

// The time step's constants for a spectral radius (time_step_bindings.cpp).
void bind_time_step(nanobind::module_& m);

}  // namespace pinwind
