// The kinds of elements and constraints of the step loop, each in one header (element_kind.hpp
// says what a kind holds): a new kind is its header and a line here, and its builder in
// pinwind/dynamics/element_specs.py.
//
// The order of ElementKinds is the order the elements' forces are summed in (which the results'
// last bits depend on); the order of ConstraintKinds is the order of the rows (the name → row
// map of the multipliers: the rigid meshes in file order, then the speed drivers and locks).
#pragma once

#include <cstddef>
#include <tuple>
#include <utility>

#include "bearing_damping.hpp"
#include "bearing_friction.hpp"
#include "bearing_rows.hpp"
#include "bearing_spring.hpp"
#include "compliant_mesh.hpp"
#include "element_kind.hpp"
#include "generator.hpp"
#include "hub_loads.hpp"
#include "rigid_meshes.hpp"
#include "rotor.hpp"
#include "speed_drivers.hpp"
#include "torsional_spring.hpp"

namespace pinwind {

using ElementKinds = std::tuple<TorsionalSpringsKind, BearingDampingKind, BearingSpringsKind,
                                BearingRowsKind, CompliantMeshesKind, GeneratorsKind, RotorsKind,
                                HubLoadsKind, BearingFrictionKind>;
using ConstraintKinds = std::tuple<RigidMeshesKind, SpeedDriversKind>;

// Every kind, the elements' then the constraints': one field of StepperSpec each.
using Kinds = decltype(std::tuple_cat(std::declval<ElementKinds>(),
                                      std::declval<ConstraintKinds>()));

template <class Tuple>
struct SpecsOfKinds;
template <class... K>
struct SpecsOfKinds<std::tuple<K...>> {
  using type = std::tuple<typename K::Specs...>;
};

// The specs of every kind, in the order of Kinds (StepperSpec's per-kind fields).
using KindSpecs = SpecsOfKinds<Kinds>::type;

// Calls f(K{}, std::integral_constant<size_t, i>{}) for each kind K of Kinds, i its place.
template <class F, std::size_t... I>
void for_each_kind(F&& f, std::index_sequence<I...>) {
  (f(std::tuple_element_t<I, Kinds>{}, std::integral_constant<std::size_t, I>{}), ...);
}
template <class F>
void for_each_kind(F&& f) {
  for_each_kind(std::forward<F>(f), std::make_index_sequence<std::tuple_size_v<Kinds>>{});
}

struct StepperSetup;

// Checks each kind's specs (std::invalid_argument naming its field) and gives the setup each
// kind's factory, in the order of the kinds, and the elements per family of the kinds that have
// series of their own (element_kinds.cpp: the one unit that instantiates every element).
void add_kinds(const KindSpecs& specs, const KindContext& context, StepperSetup& setup,
               FamilyCounts& counts);

// Binds each kind's spec, enums and laws (element_bindings.cpp).
void bind_kinds(nanobind::module_& m);

}  // namespace pinwind
