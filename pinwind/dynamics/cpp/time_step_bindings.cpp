// Python binding of the time step's constants (time_step.hpp): the generalized-α method's αm, αf,
// γ and β for a spectral radius ρ∞, computed once, here, and read by pinwind.dynamics.integrator
// (module.cpp gathers the bindings).
#include <nanobind/nanobind.h>

#include "bindings.hpp"
#include "time_step.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace pinwind {

void bind_time_step(nb::module_& m) {
  nb::class_<GeneralizedAlpha>(m, "GeneralizedAlpha",
                               "The generalized-α method's constants for a spectral radius ρ∞ "
                               "(Chung & Hulbert 1993 eqs. 17, 20, 25; time_step.hpp).")
      .def_ro("rho_infinity", &GeneralizedAlpha::rho_infinity)
      .def_ro("alpha_m", &GeneralizedAlpha::alpha_m)
      .def_ro("alpha_f", &GeneralizedAlpha::alpha_f)
      .def_ro("gamma", &GeneralizedAlpha::gamma)
      .def_ro("beta", &GeneralizedAlpha::beta);
  m.def(
      "generalized_alpha", [](double rho_infinity) { return GeneralizedAlpha(rho_infinity); },
      "rho_infinity"_a,
      "The constants the step uses for ρ∞ (clamped to [0, 1]; Integrator checks the range).");
}

}  // namespace pinwind
