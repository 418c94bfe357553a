// Size checks of the specs that Python fills: the error names the field (stepper_bindings.cpp,
// mesh_row_bindings.cpp, the kinds' checks: bearing_damping.hpp).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

#include "mesh_rows.hpp"

namespace pinwind {

template <class T>
void check_size(const char* what, const T& values, size_t size) {
  if (static_cast<size_t>(values.size()) != size) {
    throw std::invalid_argument(std::string(what) + " has " + std::to_string(values.size()) +
                                " entries, expected " + std::to_string(size));
  }
}

inline void check_meshes(const MeshConstants& mc, size_t nv) {
  const size_t nm = mc.slot_a.size(), slots = mc.joint_ids.size();
  check_size("meshes.slot_b", mc.slot_b, nm);
  check_size("meshes.mu", mc.mu, nm);
  check_size("meshes.sigma", mc.sigma, nm);
  check_size("meshes.cos_a", mc.cos_a, nm);
  check_size("meshes.sin_a", mc.sin_a, nm);
  check_size("meshes.eps", mc.eps, nm);
  check_size("meshes.tan_beta_b", mc.tan_beta_b, nm);
  check_size("meshes.joint_a", mc.joint_a, nm);
  check_size("meshes.joint_b", mc.joint_b, nm);
  if (static_cast<size_t>(mc.centre_a.rows()) != nm ||
      static_cast<size_t>(mc.centre_b.rows()) != nm ||
      static_cast<size_t>(mc.axis_a.rows()) != nm ||
      static_cast<size_t>(mc.axis_b.rows()) != nm) {
    throw std::invalid_argument(
        "meshes.centre_a, centre_b, axis_a and axis_b need one row per mesh");
  }
  if (static_cast<size_t>(mc.support.rows()) != slots ||
      static_cast<size_t>(mc.support.cols()) != nv) {
    throw std::invalid_argument("meshes.support must be (slots, nv)");
  }
}

}  // namespace pinwind
