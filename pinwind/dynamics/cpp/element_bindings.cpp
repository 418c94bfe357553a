// Python bindings of the elements' specs and laws of pinwind.dynamics._native: the meshes'
// paths of contact (shared by rigid and compliant meshes), then each kind's own binding
// (element_kinds.hpp; module.cpp gathers the bindings).
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/vector.h>

#include <string>
#include <vector>

#include "bindings.hpp"
#include "element_kinds.hpp"
#include "mesh_path.hpp"

namespace nb = nanobind;

namespace pinwind {

void bind_kinds(nb::module_& m) {
  for_each_kind([&](auto kind, auto) { decltype(kind)::bind(m); });
  std::vector<std::string> fields;
  for_each_kind([&](auto kind, auto) { fields.emplace_back(decltype(kind)::field); });
  m.def(
      "kind_fields", [fields] { return fields; },
      "The fields of StepperSpec that hold a kind of element or constraint, in the order of the "
      "kinds: the elements' (the order their forces are summed in), then the constraints' (the "
      "order of their rows) (element_kinds.hpp).");
}

void bind_elements(nb::module_& m) {
  nb::class_<MeshPathSpec>(m, "MeshPathSpec")
      .def(nb::init<>())
      .def_rw("base_pitch", &MeshPathSpec::base_pitch)
      .def_rw("path_length", &MeshPathSpec::path_length)
      .def_rw("roll_start", &MeshPathSpec::roll_start)
      .def_rw("roll_radius_a", &MeshPathSpec::roll_radius_a)
      .def_rw("pitch_position", &MeshPathSpec::pitch_position)
      .def_rw("entering_front", &MeshPathSpec::entering_front)
      .def_rw("entering_back", &MeshPathSpec::entering_back)
      .def_rw("angle_ref_a", &MeshPathSpec::angle_ref_a)
      .def_rw("reference_a", &MeshPathSpec::reference_a)
      .def_rw("pair_position", &MeshPathSpec::pair_position)
      .def_rw("gap_position", &MeshPathSpec::gap_position)
      .def_rw("gap_value", &MeshPathSpec::gap_value)
      .def_rw("pair_stiffness", &MeshPathSpec::pair_stiffness);
  bind_kinds(m);
}

}  // namespace pinwind
