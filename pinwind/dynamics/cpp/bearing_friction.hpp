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
// load P1.
//
// P1 follows the load, lagged one step: after each step's solve the stepper hands the element
// the bearings' reactions in their joint frames and the compliant rows' forces
// (Stepper::hand_bearing_loads: the force each bearing or row element computed and settled in
// that step, the reaction of an ideal joint from the step's multipliers), and the next step
// takes P1 from them by the type's rule (friction_load below, the one of
// pinwind/losses/bearing_friction.py friction_load: radial F_r, axial F_a). Within a step P1 is
// a constant, so the moment the solve uses is the one booked (the ledger closes) and the step
// stays linear in ā. A row of a compliant bearing reads its own force; a bearing without rows
// its joint's reaction (a compliant one's is its springs' and dampers' force); the first step
// of a run, with no step before it, has P1 = 0. A spec with a fixed load (the model's
// friction_load_kN) keeps M1 = load_moment. The sign function is regularised: s(ω) = clamp(ω/ω_s, −1, 1), so the moment grows
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
#include <nanobind/eigen/dense.h>
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
  double load_moment = 0.0;          // M1 = f1 P1 d_m [N·m] of a fixed load (follow_load false)
  double stick_speed = 0.0;          // ω_s [rad/s] of the regularised sign (> 0)
  // P1 from the step's loads (the header's comment): M1 = load_coefficient P1.
  bool follow_load = false;
  long row = -1;                     // its row in the row series (−1: the bearing's reaction)
  double load_coefficient = 0.0;     // f1 d_m [m]
  int load_rule = 0;                 // 0 F_r, 1 ball, 2 angular ball, 3 roller (friction_load)
  double contact_cot = 0.0;          // cot α of the axial rules 2 and 3 [-]
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // the bearing axis k in its joint frame
};

// Every bearing's friction moment, one element for all (it writes the bearing friction series
// of every bearing, 0 for a bearing without friction).
class BearingFriction : public Element {
 public:
  explicit BearingFriction(std::vector<BearingFrictionSpec> specs)
      : specs_(std::move(specs)), load_moment_(specs_.size(), 0.0) {
    for (size_t i = 0; i < specs_.size(); ++i) {
      if (!specs_[i].follow_load) load_moment_[i] = specs_[i].load_moment;
    }
  }

  // P1 [N] of a bearing under radial load F_r and axial load F_a [N] by its type's rule
  // (pinwind/losses/bearing_friction.py friction_load, PALMGREN_FACTORS): 1 ball
  // max(3 F_a − 0.1 F_r, F_r), 2 angular ball max(0.9 F_a cot α − 0.1 F_r, F_r), 3 roller
  // max(0.8 F_a cot α, F_r), else F_r; F_a of either sign.
  static double friction_load(int rule, double contact_cot, double radial, double axial) {
    const double fr = std::abs(radial), fa = std::abs(axial);
    switch (rule) {
      case 1: return std::max(3.0 * fa - 0.1 * fr, fr);
      case 2: return std::max(0.9 * fa * contact_cot - 0.1 * fr, fr);
      case 3: return std::max(0.8 * fa * contact_cot, fr);
      default: return fr;
    }
  }

  bool wants_bearing_loads() const override {
    for (const auto& sp : specs_) {
      if (sp.follow_load) return true;
    }
    return false;
  }

  void bearing_loads(const std::vector<Eigen::Vector3d>& bearings,
                     const std::vector<Eigen::Vector3d>& rows) override {
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      if (!sp.follow_load) continue;
      double radial = 0.0, axial = 0.0;
      if (sp.row >= 0 && static_cast<size_t>(sp.row) < rows.size()) {
        const Eigen::Vector3d& f = rows[sp.row];  // (F_u, F_w, F_k)
        radial = std::hypot(f[0], f[1]);
        axial = f[2];
      } else if (sp.row < 0 && sp.bearing >= 0 && static_cast<size_t>(sp.bearing) < bearings.size()) {
        const Eigen::Vector3d& f = bearings[sp.bearing];
        axial = f.dot(sp.axis);
        radial = (f - axial * sp.axis).norm();
      }
      load_moment_[i] =
          sp.load_coefficient * friction_load(sp.load_rule, sp.contact_cot, radial, axial);
    }
  }

  // The moment τ(ω) of one bearing [N·m] and its slope dτ/dω [N·m·s/rad], M1 = load [N·m].
  static std::pair<double, double> moment(const BearingFrictionSpec& sp, double omega,
                                          double load) {
    const double speed = std::abs(omega);
    const double viscous = sp.no_load_coefficient * std::cbrt(speed * speed);
    const bool floor = viscous <= sp.no_load_minimum;
    const double magnitude = (floor ? sp.no_load_minimum : viscous) + load;
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
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      const auto [torque, slope] = moment(sp, s.v[sp.index], load_moment_[i]);
      hessian(sp.index, sp.index) -= s.weights.speed_gain * slope;
      force[sp.index] += torque;
    }
  }

  bool settle(const StepView& s, const Eigen::VectorXd& a, bool) override {
    torque_.setZero(s.v.size());
    each_.resize(specs_.size());
    for (size_t i = 0; i < specs_.size(); ++i) {
      const auto& sp = specs_[i];
      const auto [torque, slope] = moment(sp, s.v[sp.index], load_moment_[i]);
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
  std::vector<double> load_moment_;  // each bearing's M1 in this step [N·m]
};

// The kind (element_kind.hpp): StepperSpec.bearing_friction, one element for all bearings,
// always built, so that the bearing friction series are written (zeros) without any.
struct BearingFrictionKind : KindBase {
  using Specs = std::vector<BearingFrictionSpec>;
  using Built = Elements;
  static constexpr const char* field = "bearing_friction";

  static void check(const Specs& specs, const KindContext& c) {
    for (const auto& sp : specs) {
      if (sp.index < 0 || sp.index >= c.nv || sp.bearing < -1 || sp.row < -1 ||
          sp.load_rule < 0 || sp.load_rule > 3) {
        throw std::invalid_argument("bearing_friction: bad joint or bearing index");
      }
      if (!(sp.stick_speed > 0.0) || !(sp.no_load_coefficient >= 0.0) ||
          !(sp.no_load_minimum >= 0.0) || !(sp.load_moment >= 0.0) ||
          !(sp.load_coefficient >= 0.0) || !(sp.contact_cot >= 0.0) ||
          !std::isfinite(sp.stick_speed + sp.no_load_coefficient + sp.no_load_minimum +
                         sp.load_moment + sp.load_coefficient + sp.contact_cot)) {
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
        .def_rw("stick_speed", &BearingFrictionSpec::stick_speed)
        .def_rw("follow_load", &BearingFrictionSpec::follow_load)
        .def_rw("row", &BearingFrictionSpec::row)
        .def_rw("load_coefficient", &BearingFrictionSpec::load_coefficient)
        .def_rw("load_rule", &BearingFrictionSpec::load_rule)
        .def_rw("contact_cot", &BearingFrictionSpec::contact_cot)
        .def_rw("axis", &BearingFrictionSpec::axis);
    m.def("bearing_friction_load", &BearingFriction::friction_load, nanobind::arg("rule"),
          nanobind::arg("contact_cot"), nanobind::arg("radial"), nanobind::arg("axial"),
          "P1 [N] of a bearing under F_r and F_a [N] by load rule 0-3 (bearing_friction.hpp)");
  }
};

}  // namespace pinwind
