// What a kind of element or constraint of the step loop is made of, in the one header of the kind
// (torsional_spring.hpp, bearing_damping.hpp, bearing_spring.hpp, compliant_mesh.hpp,
// generator.hpp, rotor.hpp; rigid_meshes.hpp, speed_drivers.hpp): its spec, the struct Python
// fills; its checks; its nanobind binding; and its factory, which adds the elements (or
// constraints) its specs ask for to the stepper's list. element_kinds.hpp lists the kinds, in the
// order their forces are summed and their rows stacked; the stepper knows none by name (after
// Pinocchio's constraint models and Chrono's ChLink, each of which holds its own data).
//
// A kind K is a struct (deriving from KindBase) with
//
//     using Specs = ...;                  // what _native.StepperSpec holds of it (a list of specs)
//     using Built = Elements;             // or Constraints: the list its factory adds to
//     static constexpr const char* field; // its field of _native.StepperSpec
//     static void check(const Specs&, const KindContext&);     // std::invalid_argument: the field
//     static void add(const Specs&, const KindContext&, Built&);  // the factory
//     static void bind(nanobind::module_&);                    // its spec's class and enums
//     static void count(const Specs&, FamilyCounts&);          // its series family, if any
//
// This header names no kind and includes no nanobind: the step loop's units include it alone.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

#include "constraints.hpp"
#include "elements.hpp"
#include "mesh_path.hpp"
#include "mesh_rows.hpp"
#include "series.hpp"

namespace pinwind {

// What a kind's checks and factory read besides its own specs: the model's size, the meshes
// (their constants and paths of contact) and the inputs a run hands in per sample.
struct KindContext {
  Eigen::Index nv = 0;
  const MeshConstants& meshes;
  const std::vector<MeshPathSpec>& paths;
  long input_columns = 0;
};

using Elements = std::vector<std::unique_ptr<Element>>;
using Constraints = std::vector<std::unique_ptr<Constraint>>;

// Elements per family of series (series.hpp), as the Outputs take them.
using FamilyCounts = std::array<long, kFamilies>;

// A kind's specs bound to its factory: what the stepper keeps to build its list, at the start
// and again, each element new, for Stepper::element_forces.
template <class Built>
using Factory = std::function<void(const KindContext&, Built&)>;

// What every kind has unless it says otherwise: no series family of its own.
struct KindBase {
  template <class Specs>
  static void count(const Specs&, FamilyCounts&) {}
};

}  // namespace pinwind
