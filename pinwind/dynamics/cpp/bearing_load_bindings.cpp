// Python binding of a bearing's reaction split about its axis (bearing_load.hpp):
// _native.split_about_axes, the compiled part of the derived series bearing_radial,
// bearing_axial, bearing_tilting and bearing_torque (module.cpp gathers the bindings).
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>

#include <optional>
#include <stdexcept>
#include <string>

#include "bearing_load.hpp"
#include "bindings.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace pinwind {
namespace {

using Vectors = nb::ndarray<const double, nb::ndim<3>, nb::device::cpu>;
using Axes = nb::ndarray<const double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;
using Split = nb::ndarray<double, nb::ndim<2>, nb::c_contig, nb::device::cpu>;

void split(const Vectors& vectors, const Axes& axes, std::optional<Split> along,
           std::optional<Split> across) {
  const long samples = static_cast<long>(vectors.shape(0));
  const long bearings = static_cast<long>(vectors.shape(1));
  const std::string shape = "(" + std::to_string(samples) + ", " + std::to_string(bearings) + ")";
  if (vectors.shape(2) != 3 || static_cast<long>(axes.shape(0)) != bearings ||
      axes.shape(1) != 3) {
    throw std::invalid_argument("split_about_axes: vectors must be (samples, bearings, 3) and "
                                "axes (bearings, 3); got " +
                                std::to_string(vectors.shape(2)) + " components and axes (" +
                                std::to_string(axes.shape(0)) + ", " +
                                std::to_string(axes.shape(1)) + ") for " + shape);
  }
  for (const std::optional<Split>* out : {&along, &across}) {
    if (*out && (static_cast<long>((*out)->shape(0)) != samples ||
                 static_cast<long>((*out)->shape(1)) != bearings)) {
      throw std::invalid_argument("split_about_axes: along and across must be " + shape);
    }
  }
  const double* v = vectors.data();
  const long s0 = static_cast<long>(vectors.stride(0)), s1 = static_cast<long>(vectors.stride(1));
  const long s2 = static_cast<long>(vectors.stride(2));
  double* a = along ? along->data() : nullptr;
  double* c = across ? across->data() : nullptr;
  nb::gil_scoped_release release;
  split_about_axes(v, samples, bearings, s0, s1, s2, axes.data(), a, c);
}

}  // namespace

void bind_bearing_loads(nb::module_& m) {
  m.def("split_about_axes", &split, "vectors"_a, "axes"_a, "along"_a.none(),
        "across"_a.none() = nb::none(),
        "v·k and |v − (v·k) k| of vectors (samples, bearings, 3) about unit axes (bearings, 3) "
        "into (samples, bearings) arrays, either None (bearing_load.hpp).");
}

}  // namespace pinwind
