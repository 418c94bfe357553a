// Rolling-bearing friction: a moment −s(ω) M(|ω|) on each bearing's joint [N·m], ω the joint's
// speed relative to its parent body (the bearing's relative speed), after Palmgren's split that
// ISO/TR 14179-2:2001 uses for bearing losses (pinwind/losses/bearing_friction.py computes the
// coefficients and documents the model):
//
//     M(|ω|) = Σ_terms [ max(M0_min, c0 |ω|^(2/3)) + M1 ]
//
// per rolling bearing (a <bearing>, or each of its <row>s) on the joint: the speed- and
// viscosity-dependent no-load moment M0 (c0 = 10⁻⁷ f0 ν^(2/3) d_m³ in SI with n in rpm folded in,
// M0_min its value at ν n = 2000) and the load-dependent M1 = f1 P1 d_m at the bearing's
// load P1. The sign function is regularised: s(ω) = clamp(ω/ω_s, −1, 1), so the moment grows
// linearly from 0 through |ω| < ω_s (a stiff viscous law there, c = M/ω_s) and is the full
// Coulomb-like moment above; ω_s = stick_speed.
//
// Taken at the time step's weighted speed v_n + κ_v ā (time_step.hpp) linearised about v_n, as
// the bearing damping's (bearing_damping.hpp): W = −κ_v dτ/dω ≥ 0, and the moment booked in the
// energy ledger (friction_loss, with the flanks' friction) is the one the step's solve used, so
// the ledger closes.
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nanobind/nanobind.h>

#include "element_kind.hpp"
#include "elements.hpp"

namespace pinwind {

// One rolling bearing's friction on a joint (pinwind/losses/bearing_friction.py fills it).
struct BearingFrictionSpec {
  long index = -1;                   // velocity index of the joint's rotation
  long bearing = -1;                 // its entry in the bearing series (Family::bearing), or −1
  double no_load_coefficient = 0.0;  // c0: M0 = c0 |ω|^(2/3) [N·m·(s/rad)^(2/3)]
  double no_load_minimum = 0.0;      // M0_min [N·m]: M0 at ν n = 2000 mm²/s·rpm and below
  double load_moment = 0.0;          // M1 = f1 P1 d_m [N·m]
  double stick_speed = 0.0;          // ω_s [rad/s] of the regularised sign (> 0)
};

// Every bearing's friction moment, one element for all (it writes the bearing friction series
// of every bearing, 0 for a bearing without friction).
class BearingFriction : public Element {
 public:
  explicit BearingFriction(std::vector<BearingFrictionSpec> specs) : specs_(std::move(specs)) {}

  // The moment τ(ω) of one bearing [N·m] and its slope dτ/dω [N·m·s/rad].
  static std::pair<double, double> moment(const BearingFrictionSpec& sp, double omega) {
    const double speed = std::abs(omega);
    const double viscous = sp.no_load_coefficient * std::cbrt(speed * speed);
    const bool floor = viscous <= sp.no_load_minimum;
    const double magnitude = (floor ? sp.no_load_minimum : viscous) + sp.load_moment;
    // d M/d|ω| times |ω|: finite at ω → 0 (|ω|^(2/3) / |ω| · |ω|)
    const double slope_times_speed = floor ? 0.0 : (2.0 / 3.0) * viscous;
    const double ratio = speed / sp.stick_speed;
    if (ratio < 1.0) {
      // τ = −(ω/ω_s) M(|ω|): dτ/dω = −M/ω_s − (|ω|/ω_s) M'(|ω|)
      return {-omega / sp.stick_speed * magnitude,
              -(magnitude + slope_times_speed) / sp.stick_speed};
    }
    const double sign = omega > 0.0 ? 1.0 : -1.0;
    return {-sign * magnitude, -slope_times_speed / speed};
  }

  void add_implicit(const StepView& s, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    for (const auto& sp : specs_) {
      const auto [torque, slope] = moment(sp, s.v[sp.index]);
      hessian(sp.index, sp.index) -= s.weights.speed_gain * slope;
      force[sp.index] += torque;
    }
  }

  bool settle(const StepView& s, const Eigen::VectorXd& a, bool) override {
    torque_.setZero(s.v.size());
    each_.resize(specs_.size());
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      const auto [torque, slope] = moment(sp, s.v[sp.index]);
      each_[i] = torque + slope * s.weights.speed_gain * a[sp.index];
      torque_[sp.index] += each_[i];
    }
    return false;
  }

  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    return {0.0, 0.0, 0.0, -torque_.dot(v_mid) * s.dt};
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override { return copy_of<BearingFriction, Element>(*this); }
  void restore(const Element& saved) override { restore_from(*this, saved); }

  void record(const StepView& s, long k, const Outputs& out) const override {
    const long bearings = out.count(Family::bearing);
    for (long b = 0; b < bearings; ++b) {
      const long e = out.entry(Family::bearing, k, b);
      out.at(Series::bearing_friction_moment, e) = 0.0;
      out.at(Series::bearing_friction_power, e) = 0.0;
    }
    for (size_t i = 0; i < specs_.size() && i < each_.size(); ++i) {
      const auto& sp = specs_[i];
      if (sp.bearing < 0) continue;
      const long e = out.entry(Family::bearing, k, sp.bearing);
      out.at(Series::bearing_friction_moment, e) += each_[i];
      out.at(Series::bearing_friction_power, e) -= each_[i] * s.v[sp.index];
    }
  }

 private:
  std::vector<BearingFrictionSpec> specs_;
  Eigen::VectorXd torque_;    // the settled moments summed per velocity [N·m]
  std::vector<double> each_;  // each bearing's settled moment [N·m]
};

// The kind (element_kind.hpp): StepperSpec.bearing_friction, one element for all bearings,
// always built, so that the bearing friction series are written (zeros) without any.
struct BearingFrictionKind : KindBase {
  using Specs = std::vector<BearingFrictionSpec>;
  using Built = Elements;
  static constexpr const char* field = "bearing_friction";

  static void check(const Specs& specs, const KindContext& c) {
    for (const auto& sp : specs) {
      if (sp.index < 0 || sp.index >= c.nv || sp.bearing < -1) {
        throw std::invalid_argument("bearing_friction: bad joint or bearing index");
      }
      if (!(sp.stick_speed > 0.0) || !(sp.no_load_coefficient >= 0.0) ||
          !(sp.no_load_minimum >= 0.0) || !(sp.load_moment >= 0.0) ||
          !std::isfinite(sp.stick_speed + sp.no_load_coefficient + sp.no_load_minimum +
                         sp.load_moment)) {
        throw std::invalid_argument(
            "bearing_friction: stick_speed > 0 and finite moments >= 0 are required");
      }
    }
  }

  static void add(const Specs& specs, const KindContext&, Elements& out) {
    out.push_back(std::make_unique<BearingFriction>(specs));
  }

  static void bind(nanobind::module_& m) {
    nanobind::class_<BearingFrictionSpec>(m, "BearingFrictionSpec")
        .def(nanobind::init<>())
        .def_rw("index", &BearingFrictionSpec::index)
        .def_rw("bearing", &BearingFrictionSpec::bearing)
        .def_rw("no_load_coefficient", &BearingFrictionSpec::no_load_coefficient)
        .def_rw("no_load_minimum", &BearingFrictionSpec::no_load_minimum)
        .def_rw("load_moment", &BearingFrictionSpec::load_moment)
        .def_rw("stick_speed", &BearingFrictionSpec::stick_speed);
  }
};

}  // namespace pinwind
