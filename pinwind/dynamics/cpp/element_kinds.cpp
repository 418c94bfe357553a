// The registry of element kinds the Stepper builds its elements from (stepper.hpp): the one unit
// that instantiates every element's virtual functions.
#include <memory>
#include <vector>

#include "stepper.hpp"

namespace pinwind {
namespace {

// The registry of element kinds: each adds the elements of its kind that the setup asks for.
// The stepper builds its elements from this table in its order, the order their forces are
// summed in (which the results' last bits depend on).
struct ElementKind {
  const char* name;
  void (*add)(const StepperSetup&, Elements&);
};

const ElementKind kElementKinds[] = {
    {"torsional_springs",
     [](const StepperSetup& s, Elements& out) {
       if (!s.springs.empty()) out.push_back(std::make_unique<TorsionalSprings>(s.springs));
     }},
    {"bearing_damping",
     [](const StepperSetup& s, Elements& out) {
       if (s.bearing_damping.size() && s.bearing_damping.cwiseAbs().maxCoeff() > 0.0) {
         out.push_back(std::make_unique<BearingDamping>(s.bearing_damping));
       }
     }},
    {"bearing_springs",
     [](const StepperSetup& s, Elements& out) {
       if (!s.bearing_springs.empty()) {
         out.push_back(std::make_unique<BearingSprings>(s.bearing_springs));
       }
     }},
    {"compliant_meshes",
     [](const StepperSetup& s, Elements& out) {
       if (s.compliant_meshes.empty()) return;
       out.push_back(std::make_unique<CompliantMeshes>(s.compliant_meshes, s.paths, s.model.nv));
     }},
    {"generators",
     [](const StepperSetup& s, Elements& out) {
       for (size_t i = 0; i < s.generators.size(); ++i) {
         const GeneratorSpec& g = s.generators[i];
         out.push_back(kGeneratorElements[static_cast<size_t>(g.law)](g, static_cast<long>(i)));
       }
     }},
    {"rotors",
     [](const StepperSetup& s, Elements& out) {
       for (size_t i = 0; i < s.rotors.size(); ++i) {
         out.push_back(std::make_unique<RotorAerodynamics>(s.rotors[i], static_cast<long>(i)));
       }
     }},
};

}  // namespace

Elements build_elements(const StepperSetup& s) {
  Elements out;
  for (const auto& kind : kElementKinds) kind.add(s, out);
  return out;
}

}  // namespace pinwind
