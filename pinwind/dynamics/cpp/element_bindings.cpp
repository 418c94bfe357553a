// Python bindings of the elements' specs and laws of pinwind.dynamics._native: the compliant
// meshes' paths, springs, bearing springs, generators and rotors (module.cpp gathers the
// bindings).
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/vector.h>

#include <optional>
#include <stdexcept>
#include <string>

#include "bearing_spring.hpp"
#include "bindings.hpp"
#include "compliant_mesh.hpp"
#include "generator.hpp"
#include "mesh_path.hpp"
#include "rotor.hpp"
#include "torsional_spring.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace pinwind {
namespace {

using Angles = nb::ndarray<const double, nb::ndim<2>, nb::device::cpu>;
using BearingRows = nb::ndarray<double, nb::ndim<3>, nb::c_contig, nb::device::cpu>;

// bearing_slide_series on a block's angle (samples, joints) into (samples, bearings, 3) arrays,
// either of them None (not computed).
void slide_series(const Angles& angle, const std::vector<BearingSlides>& slides,
                  std::optional<BearingRows> displacement, std::optional<BearingRows> elastic) {
  const long samples = static_cast<long>(angle.shape(0)), joints = static_cast<long>(angle.shape(1));
  long bearings = -1;
  for (const std::optional<BearingRows>* out : {&displacement, &elastic}) {
    if (!*out) continue;
    const BearingRows& rows = **out;
    if (static_cast<long>(rows.shape(0)) != samples || rows.shape(2) != 3 ||
        (bearings >= 0 && static_cast<long>(rows.shape(1)) != bearings)) {
      throw std::invalid_argument("displacement and elastic must be (" + std::to_string(samples) +
                                  ", bearings, 3), the same bearings");
    }
    bearings = static_cast<long>(rows.shape(1));
  }
  if (joints > 1 && angle.stride(1) != 1) {
    throw std::invalid_argument("angle: its rows must be contiguous");
  }
  for (const BearingSlides& b : slides) {
    if (b.bearing < 0 || b.bearing >= bearings || b.x >= joints || b.y >= joints ||
        b.z >= joints) {
      throw std::invalid_argument("a bearing's column or slide is outside the arrays");
    }
  }
  nb::gil_scoped_release release;
  bearing_slide_series(angle.data(), samples, static_cast<long>(angle.stride(0)), slides,
                       bearings, displacement ? displacement->data() : nullptr,
                       elastic ? elastic->data() : nullptr);
}

}  // namespace

void bind_elements(nb::module_& m) {
  nb::enum_<GeneratorLaw>(m, "GeneratorLaw")
      .value("constant", GeneratorLaw::constant)
      .value("linear_slip", GeneratorLaw::linear_slip)
      .value("variable_speed", GeneratorLaw::variable_speed)
      .value("induction", GeneratorLaw::induction)
      .value("induction_dq", GeneratorLaw::induction_dq);

  nb::enum_<CpModel>(m, "CpModel")
      .value("heier", CpModel::heier)
      .value("table", CpModel::table);

  nb::class_<MeshPathSpec>(m, "MeshPathSpec")
      .def(nb::init<>())
      .def_rw("base_pitch", &MeshPathSpec::base_pitch)
      .def_rw("path_length", &MeshPathSpec::path_length)
      .def_rw("roll_start", &MeshPathSpec::roll_start)
      .def_rw("roll_radius_a", &MeshPathSpec::roll_radius_a)
      .def_rw("entering_front", &MeshPathSpec::entering_front)
      .def_rw("entering_back", &MeshPathSpec::entering_back)
      .def_rw("angle_ref_a", &MeshPathSpec::angle_ref_a)
      .def_rw("reference_a", &MeshPathSpec::reference_a)
      .def_rw("pair_position", &MeshPathSpec::pair_position)
      .def_rw("pair_stiffness", &MeshPathSpec::pair_stiffness);

  nb::class_<CompliantMeshSpec>(m, "CompliantMeshSpec")
      .def(nb::init<>())
      .def_rw("mesh", &CompliantMeshSpec::mesh)
      .def_rw("stiffness", &CompliantMeshSpec::stiffness)
      .def_rw("damping", &CompliantMeshSpec::damping)
      .def_rw("backlash", &CompliantMeshSpec::backlash)
      .def_rw("base_radius_a", &CompliantMeshSpec::base_radius_a)
      .def_rw("base_radius_b", &CompliantMeshSpec::base_radius_b)
      .def_rw("reference_b", &CompliantMeshSpec::reference_b)
      .def_rw("tangential_ref", &CompliantMeshSpec::tangential_ref)
      .def_rw("base_radius_sum", &CompliantMeshSpec::base_radius_sum)
      .def_rw("radial_sign", &CompliantMeshSpec::radial_sign)
      .def_rw("involute_ref", &CompliantMeshSpec::involute_ref)
      .def_rw("tangential_offset", &CompliantMeshSpec::tangential_offset)
      .def_rw("radial_offset", &CompliantMeshSpec::radial_offset);

  nb::class_<TorsionalSpringSpec>(m, "TorsionalSpringSpec")
      .def(nb::init<>())
      .def_rw("index_1", &TorsionalSpringSpec::index_1)
      .def_rw("index_2", &TorsionalSpringSpec::index_2)
      .def_rw("stiffness", &TorsionalSpringSpec::stiffness)
      .def_rw("damping", &TorsionalSpringSpec::damping)
      .def_rw("preload_angle", &TorsionalSpringSpec::preload_angle);

  nb::enum_<BearingLaw>(m, "BearingLaw")
      .value("linear", BearingLaw::linear)
      .value("roller_sum", BearingLaw::roller_sum);

  nb::class_<BearingSpringSpec>(m, "BearingSpringSpec")
      .def(nb::init<>())
      .def_rw("index_x", &BearingSpringSpec::index_x)
      .def_rw("index_y", &BearingSpringSpec::index_y)
      .def_rw("radial_stiffness", &BearingSpringSpec::radial_stiffness)
      .def_rw("radial_damping", &BearingSpringSpec::radial_damping)
      .def_rw("clearance", &BearingSpringSpec::clearance)
      .def_rw("index_axial", &BearingSpringSpec::index_axial)
      .def_rw("axial_stiffness", &BearingSpringSpec::axial_stiffness)
      .def_rw("index_tilt_x", &BearingSpringSpec::index_tilt_x)
      .def_rw("index_tilt_y", &BearingSpringSpec::index_tilt_y)
      .def_rw("tilt_stiffness", &BearingSpringSpec::tilt_stiffness)
      .def_rw("law", &BearingSpringSpec::law)
      .def_rw("rollers", &BearingSpringSpec::rollers)
      .def_rw("contact_stiffness", &BearingSpringSpec::contact_stiffness)
      .def_rw("load_exponent", &BearingSpringSpec::load_exponent);

  nb::class_<BearingSlides>(m, "BearingSlides")
      .def(nb::init<>())
      .def_rw("bearing", &BearingSlides::bearing)
      .def_rw("x", &BearingSlides::x)
      .def_rw("y", &BearingSlides::y)
      .def_rw("z", &BearingSlides::z)
      .def_rw("axes", &BearingSlides::axes)
      .def_rw("spring", &BearingSlides::spring);

  nb::class_<GeneratorSpec>(m, "GeneratorSpec")
      .def(nb::init<>())
      .def_rw("index", &GeneratorSpec::index)
      .def_rw("law", &GeneratorSpec::law)
      .def_rw("torque", &GeneratorSpec::torque)
      .def_rw("slope", &GeneratorSpec::slope)
      .def_rw("sync_speed", &GeneratorSpec::sync_speed)
      .def_rw("gain", &GeneratorSpec::gain)
      .def_rw("rated_power", &GeneratorSpec::rated_power)
      .def_rw("stator_resistance", &GeneratorSpec::stator_resistance)
      .def_rw("rotor_resistance", &GeneratorSpec::rotor_resistance)
      .def_rw("stator_leakage", &GeneratorSpec::stator_leakage)
      .def_rw("rotor_leakage", &GeneratorSpec::rotor_leakage)
      .def_rw("magnetizing", &GeneratorSpec::magnetizing)
      .def_rw("voltage", &GeneratorSpec::voltage)
      .def_rw("frequency", &GeneratorSpec::frequency)
      .def_rw("pole_pairs", &GeneratorSpec::pole_pairs)
      .def_rw("phases", &GeneratorSpec::phases)
      .def_rw("steady_start", &GeneratorSpec::steady_start);

  nb::class_<RotorSpec>(m, "RotorSpec")
      .def(nb::init<>())
      .def_rw("index", &RotorSpec::index)
      .def_rw("radius", &RotorSpec::radius)
      .def_rw("air_density", &RotorSpec::air_density)
      .def_rw("pitch", &RotorSpec::pitch)
      .def_rw("cp_model", &RotorSpec::cp_model)
      .def_rw("cp_scale", &RotorSpec::cp_scale)
      .def_rw("table_tsr", &RotorSpec::table_tsr)
      .def_rw("table_pitch", &RotorSpec::table_pitch)
      .def_rw("table_cp", &RotorSpec::table_cp)
      .def_rw("wind_column", &RotorSpec::wind_column);

  m.def("induction_torque", &induction_torque, "generator"_a, "speed"_a,
        "Steady-state induction machine torque on the shaft at speed [rad/s] (motor convention).");
  m.def("rotor_torque", &rotor_torque, "rotor"_a, "speed"_a, "wind"_a,
        "Aerodynamic rotor torque [N·m] at rotor speed [rad/s] and wind speed [m/s].");
  m.def("rotor_cp", &rotor_cp, "rotor"_a, "tsr"_a, "Power coefficient C_p at tip-speed ratio λ.");
  m.def("bearing_slide_series", &slide_series, "angle"_a, "slides"_a, "displacement"_a.none(),
        "elastic"_a.none() = nb::none(),
        "Each bearing's displacement [m] and its springs' elastic force [N] (joint frame) from "
        "a block's joint coordinates, into (samples, bearings, 3) arrays (bearing_spring.hpp).");
}

}  // namespace pinwind
