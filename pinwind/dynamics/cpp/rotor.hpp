// Rotor aerodynamics on one joint (the rotor hub: the carrier): the torque of a rotor of radius
// R in a wind of speed v through its power coefficient (pinwind/loads/rotor.py):
//
//     τ = P/ω = ½ ρ π R² v³ C_p(λ, β) / ω = ½ ρ π R³ v² C_p(λ, β) / λ,   λ = ω R / v
//
// with C_p from Heier's analytical fit (CpModel::heier, β in degrees inside the fit):
//
//     C_p = s c₁ (c₂/λ_i − c₃ β − c₄) e^(−c₅/λ_i) + s c₆ λ,   1/λ_i = 1/(λ + 0.08 β) − 0.035/(β³ + 1)
//
// (c = 0.5176, 116, 0.4, 5, 21, 0.0068; s a calibration scale), or bilinear in a table
// C_p(λ, β) (CpModel::table, clamped at its edges). Below λ_min = 0.1 (start-up) the torque is
// held at its value at λ_min, where C_p/λ of a table would grow without bound. No wind (v ≤ 0),
// no torque. The wind speed is the sample's input column ``wind_column``: no Python call per step.
// The rotor's inertia is added to the joint (Pinocchio armature) on the Python side.
//
// Its thrust, at the same operating point, is T = ½ ρ π R² v² C_t(λ, β), with C_t from a table
// (ThrustModel::table, bilinear) or, for a rotor known only by its C_p, from actuator-disc
// momentum theory (ThrustModel::momentum; Burton et al. 2011, Wind Energy Handbook §3.2):
//
//     C_p = 4 a (1 − a)²,   C_t = 4 a (1 − a),   the axial induction a ≤ 1/3 solved from C_p
//
// (C_p above Betz's 16/27 is held there). With a hub (``hub``) the rotor also loads the body it
// sits on (the main shaft) at the rotor centre, in the hub's fixed frame (hub_loads.hpp): the
// thrust along the shaft, the rotor's weight (constant components ``weight``, the shaft tilt in
// them) and the wind-shear moment M_y = ℓ T (``shear_arm`` ℓ [m], pinwind/loads/rotor.py). Like
// the hub loads these are taken at the step's start, explicit.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include <nanobind/nanobind.h>
#include <nanobind/stl/vector.h>

#include "element_kind.hpp"
#include "hub_loads.hpp"
#include "joint_torque.hpp"

namespace pinwind {

// How C_p(λ, β) is computed (module comment), bound to Python as _native.CpModel.
enum class CpModel { heier, table };

// How C_t(λ, β) is computed (module comment), bound to Python as _native.ThrustModel.
enum class ThrustModel { momentum, table };

struct RotorSpec {
  long index = 0;              // velocity index of the rotor joint
  double radius = 0.0;         // R [m]
  double air_density = 1.225;  // ρ [kg/m³]
  double pitch = 0.0;          // β [rad]
  CpModel cp_model = CpModel::heier;
  double cp_scale = 1.0;       // s (heier)
  std::vector<double> table_tsr;    // λ grid, increasing
  std::vector<double> table_pitch;  // β grid [rad], increasing (one entry: C_p(λ) only)
  std::vector<double> table_cp;     // C_p, row-major (λ, β)
  long wind_column = 0;        // input column of the wind speed [m/s]
  ThrustModel ct_model = ThrustModel::momentum;
  std::vector<double> ct_tsr;    // λ grid of the C_t table, increasing
  std::vector<double> ct_pitch;  // β grid [rad], increasing
  std::vector<double> ct_values; // C_t, row-major (λ, β)
  bool hub = false;              // the thrust, weight and shear moment load hub_load's body
  HubLoadSpec hub_load;          // where (its ``column`` unused: no input columns)
  Eigen::Vector3d weight = Eigen::Vector3d::Zero();  // the rotor's weight, hub fixed axes [N]
  double shear_arm = 0.0;        // ℓ [m]: the wind-shear moment about the hub's y is ℓ T
};

inline constexpr double kMinimumTipSpeedRatio = 0.1;

// C_p of the Heier fit at λ and β [rad].
inline double heier_cp(double tsr, double pitch, double scale) {
  const double beta = pitch * 180.0 / M_PI;
  const double inv = 1.0 / (tsr + 0.08 * beta) - 0.035 / (beta * beta * beta + 1.0);
  return scale * (0.5176 * (116.0 * inv - 0.4 * beta - 5.0) * std::exp(-21.0 * inv) +
                  0.0068 * tsr);
}

// Index i and weight w with x between grid[i] and grid[i + 1] (clamped at the edges).
inline void bracket(const std::vector<double>& grid, double x, size_t& i, double& w) {
  if (grid.size() < 2 || x <= grid.front()) {
    i = 0;
    w = 0.0;
    return;
  }
  if (x >= grid.back()) {
    i = grid.size() - 2;
    w = 1.0;
    return;
  }
  i = static_cast<size_t>(std::upper_bound(grid.begin(), grid.end(), x) - grid.begin()) - 1;
  w = (x - grid[i]) / (grid[i + 1] - grid[i]);
}

// Bilinear in a table of values at (tsr[i], pitch[j]), row-major, clamped at its edges.
inline double bilinear(const std::vector<double>& tsr, const std::vector<double>& pitch,
                       const std::vector<double>& values, double x, double y) {
  size_t i, j;
  double wi, wj;
  bracket(tsr, x, i, wi);
  bracket(pitch, y, j, wj);
  const size_t nb = pitch.size();
  auto at = [&](size_t a, size_t b) {
    a = std::min(a, tsr.size() - 1);
    b = std::min(b, nb - 1);
    return values[a * nb + b];
  };
  return (1 - wi) * ((1 - wj) * at(i, j) + wj * at(i, j + 1)) +
         wi * ((1 - wj) * at(i + 1, j) + wj * at(i + 1, j + 1));
}

inline double rotor_cp(const RotorSpec& r, double tsr) {
  return r.cp_model == CpModel::table ? bilinear(r.table_tsr, r.table_pitch, r.table_cp, tsr,
                                                 r.pitch)
                                      : heier_cp(tsr, r.pitch, r.cp_scale);
}

// C_t of an ideal actuator disc with power coefficient C_p (module comment): the axial
// induction a of C_p = 4a(1 − a)², increasing on a ≤ 1/3, by bisection to the last bit.
inline double momentum_ct(double cp) {
  constexpr double betz = 16.0 / 27.0;
  double lo = -1.0, hi = 1.0 / 3.0;  // C_p(−1) = −16: below it, held there
  if (cp >= betz) {
    lo = hi;
  } else if (cp <= -16.0) {
    hi = lo;
  }
  while (hi - lo > 1e-16) {
    const double a = 0.5 * (lo + hi);
    if (a == lo || a == hi) break;
    (4.0 * a * (1.0 - a) * (1.0 - a) < cp ? lo : hi) = a;
  }
  const double a = 0.5 * (lo + hi);
  return 4.0 * a * (1.0 - a);
}

inline double rotor_ct(const RotorSpec& r, double tsr) {
  return r.ct_model == ThrustModel::table
             ? bilinear(r.ct_tsr, r.ct_pitch, r.ct_values, tsr, r.pitch)
             : momentum_ct(rotor_cp(r, tsr));
}

// The rotor's operating point: tip-speed ratio λ (held at λ_min below it), C_p(λ, β) and the
// aerodynamic torque [N·m]; all 0 without wind.
struct RotorPoint {
  double tsr = 0.0, cp = 0.0, torque = 0.0;
};

// The rotor's thrust [N] at rotor speed ω [rad/s] and wind speed v [m/s] (λ held at λ_min below
// it, as the torque's), and C_t: T = ½ ρ π R² v² C_t(λ, β); 0 without wind.
struct RotorThrust {
  double ct = 0.0, thrust = 0.0;
};

inline RotorThrust rotor_thrust(const RotorSpec& r, double omega, double wind) {
  if (!(wind > 0.0)) return {};
  const double tsr = std::max(omega * r.radius / wind, kMinimumTipSpeedRatio);
  RotorThrust t;
  t.ct = rotor_ct(r, tsr);
  t.thrust = 0.5 * r.air_density * M_PI * r.radius * r.radius * wind * wind * t.ct;
  return t;
}

inline RotorPoint rotor_point(const RotorSpec& r, double omega, double wind) {
  if (!(wind > 0.0)) return {};
  RotorPoint p;
  p.tsr = std::max(omega * r.radius / wind, kMinimumTipSpeedRatio);
  p.cp = rotor_cp(r, p.tsr);
  p.torque = 0.5 * r.air_density * M_PI * r.radius * r.radius * r.radius * wind * wind * p.cp /
             p.tsr;
  return p;
}

// Aerodynamic torque [N·m] at rotor speed ω [rad/s] and wind speed v [m/s].
inline double rotor_torque(const RotorSpec& r, double omega, double wind) {
  return rotor_point(r, omega, wind).torque;
}

class RotorAerodynamics : public JointTorqueElement {
 public:
  // slot: this rotor's column in the per-rotor outputs.
  RotorAerodynamics(RotorSpec spec, long slot)
      : JointTorqueElement(spec.index), r_(std::move(spec)), slot_(slot) {}

  // τ at the weighted speed ω_n + κ_v ā and its central difference (torque_and_slope), keeping
  // the wind speed for the record.
  TorqueSlope evaluate(const StepView& s, double accel) const override {
    wind_ = s.inputs ? s.inputs[r_.wind_column] : 0.0;
    const double gain = s.weights.speed_gain;
    const double omega = s.v[index_] + gain * accel;
    const double d = 1e-6 * (std::abs(omega) + std::max(wind_, 1.0) / r_.radius);
    return {rotor_torque(r_, omega, wind_), gain * (rotor_torque(r_, omega + d, wind_) -
                                                    rotor_torque(r_, omega - d, wind_)) /
                                                (2.0 * d)};
  }

  // Also the rotor's own outputs: the torque over the step, and at the sample the power
  // P = τ(ω_k) ω_k = ½ ρ π R² v³ C_p, λ, C_p and the wind speed.
  void record(const StepView& s, long k, const Outputs& out) const override {
    JointTorqueElement::record(s, k, out);
    const RotorPoint point = rotor_point(r_, s.v[index_], wind_);
    const long e = out.entry(Family::rotor, k, slot_);
    out.at(Series::rotor_torque, e) = applied();
    out.at(Series::rotor_power, e) = point.torque * s.v[index_];
    out.at(Series::rotor_tip_speed_ratio, e) = point.tsr;
    out.at(Series::rotor_power_coefficient, e) = point.cp;
    out.at(Series::rotor_wind_speed, e) = wind_;
    const RotorThrust thrust = rotor_thrust(r_, s.v[index_], wind_);
    out.at(Series::rotor_thrust, e) = thrust.thrust;
    out.at(Series::rotor_thrust_coefficient, e) = thrust.ct;
  }

 private:
  RotorSpec r_;
  long slot_;
  mutable double wind_ = 0.0;
};

// The rotor's loads on its hub (the module comment): the hub's six components
// (T + W_x, W_y, W_z, 0, W_my + ℓ T, 0) from the rotor's speed and wind at the step's start;
// the torque stays the rotor's own element's (implicit, on its joint).
class RotorHubLoad : public HubLoad {
 public:
  explicit RotorHubLoad(const RotorSpec& spec) : HubLoad(spec.hub_load), r_(spec) {}

  void prepare(const StepView& s) override {
    if (s.inputs == nullptr) {  // no sample (Stepper::element_forces): no wind, no load
      unload();
      return;
    }
    const double thrust = rotor_thrust(r_, s.v[r_.index], s.inputs[r_.wind_column]).thrust;
    const double c[6] = {thrust + r_.weight[0], r_.weight[1], r_.weight[2],
                         0.0, r_.shear_arm * thrust, 0.0};
    load(s, c);
  }

 private:
  RotorSpec r_;
};

// The kind (element_kind.hpp): StepperSpec.rotors, an element each (and one for its hub's
// loads, with a hub), its column of the rotor series its place in the list; each reads its wind
// speed from an input column.
struct RotorsKind : KindBase {
  using Specs = std::vector<RotorSpec>;
  using Built = Elements;
  static constexpr const char* field = "rotors";

  static void check(const Specs& specs, const KindContext& c) {
    for (const auto& r : specs) {
      if (r.index < 0 || r.index >= c.nv) throw std::invalid_argument("bad rotor joint index");
      if (r.wind_column < 0 || r.wind_column >= c.input_columns) {
        throw std::invalid_argument("rotor wind_column outside the input columns");
      }
      if (r.cp_model == CpModel::table &&
          (r.table_tsr.empty() || r.table_pitch.empty() ||
           r.table_cp.size() != r.table_tsr.size() * r.table_pitch.size())) {
        throw std::invalid_argument("rotor table: table_cp must hold tsr × pitch values");
      }
      if (r.ct_model == ThrustModel::table &&
          (r.ct_tsr.empty() || r.ct_pitch.empty() ||
           r.ct_values.size() != r.ct_tsr.size() * r.ct_pitch.size())) {
        throw std::invalid_argument("rotor thrust table: ct_values must hold tsr × pitch values");
      }
      if (r.hub) HubLoadsKind::check_placement(r.hub_load, c);
    }
  }

  static void add(const Specs& specs, const KindContext&, Elements& out) {
    for (size_t i = 0; i < specs.size(); ++i) {
      out.push_back(std::make_unique<RotorAerodynamics>(specs[i], static_cast<long>(i)));
      if (specs[i].hub) out.push_back(std::make_unique<RotorHubLoad>(specs[i]));
    }
  }

  static void count(const Specs& specs, FamilyCounts& counts) {
    counts[static_cast<size_t>(Family::rotor)] = static_cast<long>(specs.size());
  }

  static void bind(nanobind::module_& m) {
    namespace nb = nanobind;
    using namespace nb::literals;
    nb::enum_<CpModel>(m, "CpModel")
        .value("heier", CpModel::heier)
        .value("table", CpModel::table);
    nb::enum_<ThrustModel>(m, "ThrustModel")
        .value("momentum", ThrustModel::momentum)
        .value("table", ThrustModel::table);

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
        .def_rw("wind_column", &RotorSpec::wind_column)
        .def_rw("ct_model", &RotorSpec::ct_model)
        .def_rw("ct_tsr", &RotorSpec::ct_tsr)
        .def_rw("ct_pitch", &RotorSpec::ct_pitch)
        .def_rw("ct_values", &RotorSpec::ct_values)
        .def_rw("hub", &RotorSpec::hub)
        .def_rw("hub_load", &RotorSpec::hub_load)
        .def_rw("weight", &RotorSpec::weight)
        .def_rw("shear_arm", &RotorSpec::shear_arm);

    m.def("rotor_torque", &rotor_torque, "rotor"_a, "speed"_a, "wind"_a,
          "Aerodynamic rotor torque [N·m] at rotor speed [rad/s] and wind speed [m/s].");
    m.def("rotor_cp", &rotor_cp, "rotor"_a, "tsr"_a,
          "Power coefficient C_p at tip-speed ratio λ.");
    m.def("rotor_ct", &rotor_ct, "rotor"_a, "tsr"_a,
          "Thrust coefficient C_t at tip-speed ratio λ.");
    m.def(
        "rotor_thrust",
        [](const RotorSpec& r, double speed, double wind) {
          return rotor_thrust(r, speed, wind).thrust;
        },
        "rotor"_a, "speed"_a, "wind"_a,
        "Aerodynamic thrust [N] at rotor speed [rad/s] and wind speed [m/s].");
    m.def("momentum_ct", &momentum_ct, "cp"_a,
          "Thrust coefficient of an ideal actuator disc with power coefficient C_p.");
  }
};

}  // namespace pinwind
