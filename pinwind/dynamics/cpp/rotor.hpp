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
//
// The blade pitch β is ``pitch``, fixed, or with ``pitch_control.enabled`` the state of a
// collective pitch controller (PitchController below; pinwind/loads/pitch_control.py): Jonkman
// et al. 2009 §7's gain-scheduled PI on the rotor speed error, the speed through a single-pole
// low-pass, the command held to [β_min, β_max] and to a rate |dβ/dt| ≤ β̇_max, as Jonkman's
// DISCON (OpenFAST reg_tests/5MW_Baseline/ServoData/Source/DISCON.f90) computes it at each call:
//
//     ω_f ← (1 − α) ω + α ω_f,   α = e^{−ω_c h}
//     e = ω_f − Ω_ref,   I ← clamp(I + e h, β_min/(GK K_I), β_max/(GK K_I))   (anti-windup)
//     β_c = clamp(GK(β) (K_P e + K_I I), β_min, β_max),   GK(β) = 1/(1 + β/θ_K)
//     β ← clamp(β + clamp(β_c − β, −β̇_max h, β̇_max h), β_min, β_max)
//
// called once per step at its end (Element::advance, with the step's new speed, h = dt: DISCON
// with PC_DT = DT), the pitch held over the next step (its torque, thrust and the hub's loads).
// It starts with ω_f = ω(0) and I = β(0)/(GK K_I), so that a run started at its set point keeps
// its pitch. The pitch changes the rotor's torque, not how its work is booked: the torque's work
// stays an applied load's in the energy ledger.
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

// A collective blade-pitch controller (the module comment), bound as _native.PitchControlSpec.
struct PitchControlSpec {
  bool enabled = false;
  double speed_set = 0.0;   // Ω_ref: the rotor speed set point [rad/s]
  double kp = 0.0;          // K_P(0): proportional gain on the rotor speed error at β = 0 [s]
  double ki = 0.0;          // K_I(0): integral gain at β = 0 [-]
  double gain_angle = 0.0;  // θ_K: the pitch at which the gains are halved [rad]
  double corner = 0.0;      // ω_c: corner frequency of the speed's low-pass [rad/s]
  double pitch_min = 0.0;   // β_min [rad]
  double pitch_max = 0.0;   // β_max [rad]
  double rate = 0.0;        // β̇_max: the largest pitch rate [rad/s]
};

// The controller's states and its step (the module comment).
class PitchController {
 public:
  PitchController(const PitchControlSpec& c, double pitch) : c_(c), pitch_(pitch) {}

  double pitch() const { return pitch_; }
  double filtered_speed() const { return filtered_; }

  // GK(β) = 1/(1 + β/θ_K).
  double gain_factor(double pitch) const { return 1.0 / (1.0 + pitch / c_.gain_angle); }

  // One call at time step h [s] with the rotor speed ω [rad/s] at its end; the first call
  // starts the filter at ω_start, the speed at the step's start.
  void step(double omega_start, double omega, double h) {
    if (!started_) {
      filtered_ = omega_start;
      integral_ = pitch_ / (gain_factor(pitch_) * c_.ki);
      started_ = true;
    }
    const double alpha = std::exp(-c_.corner * h);
    filtered_ = (1.0 - alpha) * omega + alpha * filtered_;
    const double error = filtered_ - c_.speed_set;
    // DISCON bounds the integral by the pitch limits over the scheduled gain GK K_I (GK of the
    // pitch before this call), so that GK K_I I alone reaches exactly β_max: over K_I alone it
    // stopped at GK β_max, and above 20.87° (23 m/s) the rotor overspeeded.
    const double gain = gain_factor(pitch_);
    integral_ = std::clamp(integral_ + error * h, c_.pitch_min / (gain * c_.ki),
                           c_.pitch_max / (gain * c_.ki));
    const double command =
        std::clamp(gain * (c_.kp * error + c_.ki * integral_), c_.pitch_min, c_.pitch_max);
    const double most = c_.rate * h;
    pitch_ = std::clamp(pitch_ + std::clamp(command - pitch_, -most, most), c_.pitch_min,
                        c_.pitch_max);
  }

 private:
  PitchControlSpec c_;
  double pitch_;
  double filtered_ = 0.0, integral_ = 0.0;
  bool started_ = false;
};

struct RotorSpec {
  long index = 0;              // velocity index of the rotor joint
  double radius = 0.0;         // R [m]
  double air_density = 1.225;  // ρ [kg/m³]
  double pitch = 0.0;          // β [rad]: fixed, or the controller's initial pitch
  PitchControlSpec pitch_control;  // the pitch controller (enabled: β is its state)
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

// C_p(λ, β) at pitch β [rad].
inline double rotor_cp(const RotorSpec& r, double tsr, double pitch) {
  return r.cp_model == CpModel::table
             ? bilinear(r.table_tsr, r.table_pitch, r.table_cp, tsr, pitch)
             : heier_cp(tsr, pitch, r.cp_scale);
}

inline double rotor_cp(const RotorSpec& r, double tsr) { return rotor_cp(r, tsr, r.pitch); }

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

// C_t(λ, β) at pitch β [rad].
inline double rotor_ct(const RotorSpec& r, double tsr, double pitch) {
  return r.ct_model == ThrustModel::table
             ? bilinear(r.ct_tsr, r.ct_pitch, r.ct_values, tsr, pitch)
             : momentum_ct(rotor_cp(r, tsr, pitch));
}

inline double rotor_ct(const RotorSpec& r, double tsr) { return rotor_ct(r, tsr, r.pitch); }

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

inline RotorThrust rotor_thrust(const RotorSpec& r, double omega, double wind, double pitch) {
  if (!(wind > 0.0)) return {};
  const double tsr = std::max(omega * r.radius / wind, kMinimumTipSpeedRatio);
  RotorThrust t;
  t.ct = rotor_ct(r, tsr, pitch);
  t.thrust = 0.5 * r.air_density * M_PI * r.radius * r.radius * wind * wind * t.ct;
  return t;
}

inline RotorPoint rotor_point(const RotorSpec& r, double omega, double wind, double pitch) {
  if (!(wind > 0.0)) return {};
  RotorPoint p;
  p.tsr = std::max(omega * r.radius / wind, kMinimumTipSpeedRatio);
  p.cp = rotor_cp(r, p.tsr, pitch);
  p.torque = 0.5 * r.air_density * M_PI * r.radius * r.radius * r.radius * wind * wind * p.cp /
             p.tsr;
  return p;
}

// Aerodynamic torque [N·m] at rotor speed ω [rad/s], wind speed v [m/s] and pitch β [rad].
inline double rotor_torque(const RotorSpec& r, double omega, double wind, double pitch) {
  return rotor_point(r, omega, wind, pitch).torque;
}

inline double rotor_torque(const RotorSpec& r, double omega, double wind) {
  return rotor_torque(r, omega, wind, r.pitch);
}

class RotorAerodynamics : public JointTorqueElement {
 public:
  // slot: this rotor's column in the per-rotor outputs.
  RotorAerodynamics(RotorSpec spec, long slot)
      : JointTorqueElement(spec.index),
        r_(std::move(spec)),
        slot_(slot),
        control_(r_.pitch_control, r_.pitch) {}

  // The blade pitch over the current step [rad]: fixed, or the controller's.
  double pitch() const { return r_.pitch_control.enabled ? control_.pitch() : r_.pitch; }

  // τ at the weighted speed ω_n + κ_v ā and its central difference (torque_and_slope), at the
  // step's pitch, keeping the wind speed for the record.
  TorqueSlope evaluate(const StepView& s, double accel) const override {
    wind_ = s.inputs ? s.inputs[r_.wind_column] : 0.0;
    const double gain = s.weights.speed_gain;
    const double omega = s.v[index_] + gain * accel;
    const double d = 1e-6 * (std::abs(omega) + std::max(wind_, 1.0) / r_.radius);
    const double beta = pitch();
    return {rotor_torque(r_, omega, wind_, beta),
            gain * (rotor_torque(r_, omega + d, wind_, beta) -
                    rotor_torque(r_, omega - d, wind_, beta)) /
                (2.0 * d)};
  }

  // Also the rotor's own outputs: the torque over the step, and at the sample the power
  // P = τ(ω_k) ω_k = ½ ρ π R² v³ C_p, λ, C_p, the wind speed, the thrust and the pitch.
  void record(const StepView& s, long k, const Outputs& out) const override {
    JointTorqueElement::record(s, k, out);
    const double beta = pitch();
    const RotorPoint point = rotor_point(r_, s.v[index_], wind_, beta);
    const long e = out.entry(Family::rotor, k, slot_);
    out.at(Series::rotor_torque, e) = applied();
    out.at(Series::rotor_power, e) = point.torque * s.v[index_];
    out.at(Series::rotor_tip_speed_ratio, e) = point.tsr;
    out.at(Series::rotor_power_coefficient, e) = point.cp;
    out.at(Series::rotor_wind_speed, e) = wind_;
    const RotorThrust thrust = rotor_thrust(r_, s.v[index_], wind_, beta);
    out.at(Series::rotor_thrust, e) = thrust.thrust;
    out.at(Series::rotor_thrust_coefficient, e) = thrust.ct;
    out.at(Series::rotor_pitch, e) = beta;
  }

  // The controller's step to t_{n+1} (the module comment).
  void advance(const StepView& s, const Eigen::VectorXd& v_next) override {
    JointTorqueElement::advance(s, v_next);
    if (r_.pitch_control.enabled) control_.step(s.v[index_], v_next[index_], s.dt);
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override {
    return copy_of<RotorAerodynamics, Element>(*this);
  }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  RotorSpec r_;
  long slot_;
  PitchController control_;
  mutable double wind_ = 0.0;
};

// The rotor's loads on its hub (the module comment): the hub's six components
// (T + W_x, W_y, W_z, 0, W_my + ℓ T, 0) from the rotor's speed, wind and pitch at the step's
// start; the torque stays the rotor's own element's (implicit, on its joint).
class RotorHubLoad : public HubLoad {
 public:
  RotorHubLoad(const RotorSpec& spec, const RotorAerodynamics& rotor)
      : HubLoad(spec.hub_load), r_(spec), rotor_(&rotor) {}

  void prepare(const StepView& s) override {
    if (s.inputs == nullptr) {  // no sample (Stepper::element_forces): no wind, no load
      unload();
      return;
    }
    const double thrust =
        rotor_thrust(r_, s.v[r_.index], s.inputs[r_.wind_column], rotor_->pitch()).thrust;
    const double c[6] = {thrust + r_.weight[0], r_.weight[1], r_.weight[2],
                         0.0, r_.shear_arm * thrust, 0.0};
    load(s, c);
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override { return copy_of<RotorHubLoad, Element>(*this); }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  RotorSpec r_;
  // its element (the same run's list), for the pitch: a pointer, so that a saved copy assigns
  const RotorAerodynamics* rotor_;
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
      const PitchControlSpec& p = r.pitch_control;
      if (p.enabled && !(p.ki > 0.0 && p.kp >= 0.0 && p.gain_angle > 0.0 && p.corner > 0.0 &&
                         p.rate > 0.0 && p.pitch_min < p.pitch_max && p.speed_set > 0.0)) {
        throw std::invalid_argument(
            "pitch control: K_I, θ_K, ω_c, β̇_max, Ω_ref > 0, K_P ≥ 0 and β_min < β_max");
      }
    }
  }

  static void add(const Specs& specs, const KindContext&, Elements& out) {
    for (size_t i = 0; i < specs.size(); ++i) {
      auto rotor = std::make_unique<RotorAerodynamics>(specs[i], static_cast<long>(i));
      const RotorAerodynamics& aerodynamics = *rotor;
      out.push_back(std::move(rotor));
      if (specs[i].hub) out.push_back(std::make_unique<RotorHubLoad>(specs[i], aerodynamics));
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

    nb::class_<PitchControlSpec>(m, "PitchControlSpec")
        .def(nb::init<>())
        .def_rw("enabled", &PitchControlSpec::enabled)
        .def_rw("speed_set", &PitchControlSpec::speed_set)
        .def_rw("kp", &PitchControlSpec::kp)
        .def_rw("ki", &PitchControlSpec::ki)
        .def_rw("gain_angle", &PitchControlSpec::gain_angle)
        .def_rw("corner", &PitchControlSpec::corner)
        .def_rw("pitch_min", &PitchControlSpec::pitch_min)
        .def_rw("pitch_max", &PitchControlSpec::pitch_max)
        .def_rw("rate", &PitchControlSpec::rate);

    nb::class_<RotorSpec>(m, "RotorSpec")
        .def(nb::init<>())
        .def_rw("index", &RotorSpec::index)
        .def_rw("radius", &RotorSpec::radius)
        .def_rw("air_density", &RotorSpec::air_density)
        .def_rw("pitch", &RotorSpec::pitch)
        .def_rw("pitch_control", &RotorSpec::pitch_control)
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

    m.def(
        "rotor_torque",
        [](const RotorSpec& r, double speed, double wind) { return rotor_torque(r, speed, wind); },
        "rotor"_a, "speed"_a, "wind"_a,
        "Aerodynamic rotor torque [N·m] at rotor speed [rad/s] and wind speed [m/s].");
    m.def(
        "rotor_cp", [](const RotorSpec& r, double tsr) { return rotor_cp(r, tsr); }, "rotor"_a,
        "tsr"_a, "Power coefficient C_p at tip-speed ratio λ.");
    m.def(
        "rotor_ct", [](const RotorSpec& r, double tsr) { return rotor_ct(r, tsr); }, "rotor"_a,
        "tsr"_a, "Thrust coefficient C_t at tip-speed ratio λ.");
    m.def(
        "rotor_thrust",
        [](const RotorSpec& r, double speed, double wind) {
          return rotor_thrust(r, speed, wind, r.pitch).thrust;
        },
        "rotor"_a, "speed"_a, "wind"_a,
        "Aerodynamic thrust [N] at rotor speed [rad/s] and wind speed [m/s].");
    m.def("momentum_ct", &momentum_ct, "cp"_a,
          "Thrust coefficient of an ideal actuator disc with power coefficient C_p.");
  }
};

}  // namespace pinwind
