// The factories of the kinds of elements and constraints (element_kinds.hpp): the one unit that
// instantiates every element's and constraint's virtual functions.
#include <tuple>
#include <type_traits>
#include <utility>

#include "element_kinds.hpp"
#include "stepper.hpp"

namespace pinwind {

void add_kinds(const KindSpecs& specs, const KindContext& context, StepperSetup& setup,
               FamilyCounts& counts) {
  for_each_kind([&](auto kind, auto i) {
    using Kind = decltype(kind);
    using Built = typename Kind::Built;
    const auto& own = std::get<decltype(i)::value>(specs);
    Kind::check(own, context);
    Kind::count(own, counts);
    Factory<Built> factory = [own](const KindContext& c, Built& out) { Kind::add(own, c, out); };
    if constexpr (std::is_same_v<Built, Elements>) {
      setup.elements.push_back(std::move(factory));
    } else {
      setup.constraints.push_back(std::move(factory));
    }
  });
}

}  // namespace pinwind
