// Compliant bearings: the springs that hold a body in its bearing (pinwind/model/gearbox.py
// gives the body two radial slides, an axial slide and two tilt hinges between the housing and
// its bearing joint; docs/model_format.md "Compliant bearings"). Per bearing, on the
// coordinates of those joints (the displacement of the body in the bearing, joint frame):
//
//     radial   linear:      F = −k max(|r| − c, 0) r/|r|
//              roller_sum:  F = −Σ_j K_n max(r·e_j − c, 0)ⁿ e_j      (Harris & Kotzalas,
//                           Rolling Bearing Analysis: the radial load summed over the Z rolling
//                           elements at ψ_j = 2πj/Z from the radial axis u, e_j = (cos ψ_j,
//                           sin ψ_j); n = 10/9 line contact, 3/2 point contact)
//              and the damper − c_r ṙ (in contact only);  r = (x, y) [m], clearance c ≥ 0 [m]
//     axial    F_z = −k_a z,   tilt   M = −k_t θ   (linear)
//
// Like the torsional springs (torsional_spring.hpp) the forces are taken at the time step's
// weighted state r_n + dq₀ + κ_q ā, linear in ā: the radial law is linearised about
// r₀ = r_n + dq₀, F ≈ F(r₀) − K(r₀) κ_q ā with the tangent stiffness
//
//     linear       K = k [(1 − c/|r₀|) I + (c/|r₀|) r̂ r̂ᵀ]       (K = k I without clearance: exact)
//     roller_sum   K = Σ_j n K_n max(r₀·e_j − c, 0)ⁿ⁻¹ e_j e_jᵀ
//
// For the linear law with clearance the contact (|r| > c) is an active set that settle()
// updates after each solve, as a compliant mesh's contact loss is. The roller sum is smooth
// (n > 1: each element's force and stiffness start from 0 at its contact), so its step is
// linearly implicit (the law's error is second order in the step's Δr), and a body inside the
// clearance feels no force until an element touches at r₀. In a static solve (Stepper::
// equilibrium) an unloaded roller-sum bearing has no stiffness to start Newton's iteration from:
// it starts from the stiffness with every element pressed by kStartDeflection. The radial damper,
// at the weighted speed ṙ_n + κ_v ā, acts in contact only (a rolling element loses touch with the
// race inside the clearance). Without clearance the linear law's step is the torsional springs'
// one, second order and, with ρ∞ = 1, energy-keeping. The axial and tilt dampers are the slides'
// own viscous damping (BearingDamping, bearing_damping.hpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/vector.h>

#include "bearing_rows.hpp"
#include "element_kind.hpp"
#include "elements.hpp"

namespace pinwind {

// A compliant bearing's radial law (the header's comment).
enum class BearingLaw { linear, roller_sum };

struct BearingSpringSpec {
  long index_x = -1, index_y = -1;  // velocity indices of the radial slides (−1: none)
  double radial_stiffness = 0.0;    // k [N/m]
  double radial_damping = 0.0;      // c_r [N·s/m]
  double clearance = 0.0;           // radial clearance c [m]
  long index_axial = -1;            // velocity index of the axial slide (−1: none)
  double axial_stiffness = 0.0;     // k_a [N/m]
  long index_tilt_x = -1, index_tilt_y = -1;  // the tilt hinges (−1: none)
  double tilt_stiffness = 0.0;                // k_t [N·m/rad]
  BearingLaw law = BearingLaw::linear;        // the radial law
  long rollers = 0;                           // Z: rolling elements (roller_sum)
  double contact_stiffness = 0.0;             // K_n [N/mⁿ] of one element's contact (roller_sum)
  double load_exponent = 1.0;                 // n (roller_sum)
};

// A bearing's slides as a block of samples reads them (pinwind/dynamics/bearing_springs.py):
// the series bearing_displacement and bearing_elastic_force of one bearing.
struct BearingSlides {
  long bearing = -1;                  // its column in the bearing series
  long x = -1, y = -1, z = -1;        // joint columns of the radial and axial slides (−1: none)
  long tilt_x = -1, tilt_y = -1;      // joint columns of the tilt hinges (−1: none)
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();  // rows u, w, k in the joint frame
  BearingSpringSpec spring;           // its law (no stiffness: a floating bearing)
  // Its rows (bearing_rows.hpp; their indices unused): when given, they are its springs.
  std::vector<BearingRowSpec> rows;
};

// Over samples rows of angle (row-major, stride angle_stride: the joints' coordinates [m for a
// slide]): each bearing's displacement u x + w y + k z [m] and its springs' force on the body,
// the radial law at (x, y) and −k_a z axially [N] (a bearing with rows: the sum of its rows'
// springs' forces, −Σ k_j δ_j of bearing_rows.hpp), both in the joint frame, into the rows of
// displacement and elastic (row-major (samples, bearings, 3); either may be null: not
// computed). Bearings not in slides are left as they are.
void bearing_slide_series(const double* angle, long samples, long angle_stride,
                          const std::vector<BearingSlides>& slides, long bearings,
                          double* displacement, double* elastic);

class BearingSprings : public Element {
 public:
  // A roller-sum bearing's deflection per element at which a static solve starts when no
  // element carries load [m]: a rolling bearing deflects µm to tens of µm under its load.
  static constexpr double kStartDeflection = 1e-6;

  explicit BearingSprings(std::vector<BearingSpringSpec> specs)
      : specs_(std::move(specs)),
        contact_(specs_.size(), false),
        direction_(specs_.size(), Eigen::Vector2d(1.0, 0.0)),
        stiffness_(specs_.size(), Eigen::Matrix2d::Zero()),
        force0_(specs_.size(), Eigen::Vector2d::Zero()),
        rollers_(specs_.size()),
        linear_(specs_.size()) {
    for (size_t b = 0; b < specs_.size(); ++b) {
      const BearingSpringSpec& sp = specs_[b];
      if (sp.index_axial >= 0) linear_[b].push_back({sp.index_axial, sp.axial_stiffness});
      if (sp.index_tilt_x >= 0) linear_[b].push_back({sp.index_tilt_x, sp.tilt_stiffness});
      if (sp.index_tilt_y >= 0) linear_[b].push_back({sp.index_tilt_y, sp.tilt_stiffness});
      if (specs_[b].law == BearingLaw::roller_sum) rollers_[b] = roller_directions(sp.rollers);
    }
  }

  // e_j = (cos ψ_j, sin ψ_j), ψ_j = 2πj/Z: the directions of a roller sum's Z elements.
  static std::vector<Eigen::Vector2d> roller_directions(long z) {
    std::vector<Eigen::Vector2d> out;
    for (long j = 0; j < z; ++j) {
      const double psi = 2.0 * M_PI * static_cast<double>(j) / static_cast<double>(z);
      out.emplace_back(std::cos(psi), std::sin(psi));
    }
    return out;
  }

  // F(r) [N] of sp's radial law at the displacement r [m] (the header's comment; rollers: e_j
  // of a roller sum), whatever the step's active set.
  static Eigen::Vector2d radial_force(const BearingSpringSpec& sp,
                                      const std::vector<Eigen::Vector2d>& rollers,
                                      const Eigen::Vector2d& r) {
    if (sp.law == BearingLaw::roller_sum) {
      Eigen::Vector2d f = Eigen::Vector2d::Zero();
      for (const Eigen::Vector2d& e : rollers) {
        const double d = e.dot(r) - sp.clearance;
        if (d > 0.0) f -= sp.contact_stiffness * std::pow(d, sp.load_exponent) * e;
      }
      return f;
    }
    if (sp.clearance <= 0.0) return -sp.radial_stiffness * r;
    const double n = std::hypot(r[0], r[1]);
    return n > sp.clearance
               ? Eigen::Vector2d(-sp.radial_stiffness * ((n - sp.clearance) / n) * r)
               : Eigen::Vector2d::Zero();
  }

  // A bearing with clearance starts in contact where its body is already beyond the clearance
  // (a run or a check from a displaced state): its force is then the gradient of its energy
  // from the first state on, as a compliant mesh's flanks start (compliant_mesh.hpp).
  void prepare(const StepView& s) override {
    if (started_) return;
    started_ = true;
    for (size_t b = 0; b < specs_.size(); ++b) {
      const BearingSpringSpec& sp = specs_[b];
      if (sp.index_x < 0 || sp.law != BearingLaw::linear || sp.clearance <= 0.0) continue;
      const Eigen::Vector2d r(s.q[sp.index_x], s.q[sp.index_y]);
      contact_[b] = r.norm() > sp.clearance;
      if (contact_[b]) direction_[b] = r.normalized();
    }
  }

  void add_implicit(const StepView& s, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    const double kq = s.weights.position_gain, kv = s.weights.speed_gain;
    for (size_t b = 0; b < specs_.size(); ++b) {
      const BearingSpringSpec& sp = specs_[b];
      for (const auto& [i, k] : linear_[b]) {
        hessian(i, i) += kq * k;
        force[i] -= k * (s.q[i] + s.dq_free[i]);
      }
      if (sp.index_x < 0) continue;
      if (sp.law == BearingLaw::roller_sum) {
        roller_sum(b, start(sp, s), s.weights.statics);
      } else {
        linearise(b, start(sp, s), s.weights.statics);
      }
      const long ix = sp.index_x, iy = sp.index_y;
      const double c = touching(b) ? sp.radial_damping : 0.0;
      hessian(ix, ix) += kq * stiffness_[b](0, 0) + kv * c;
      hessian(ix, iy) += kq * stiffness_[b](0, 1);
      hessian(iy, ix) += kq * stiffness_[b](1, 0);
      hessian(iy, iy) += kq * stiffness_[b](1, 1) + kv * c;
      force[ix] += force0_[b][0] - c * s.v[ix];
      force[iy] += force0_[b][1] - c * s.v[iy];
    }
  }

  bool settle(const StepView& s, const Eigen::VectorXd& a, bool last) override {
    const double kq = s.weights.position_gain, kv = s.weights.speed_gain;
    bool changed = false;
    elastic_.setZero(s.q.size());
    damping_.setZero(s.q.size());
    for (size_t b = 0; b < specs_.size(); ++b) {
      const BearingSpringSpec& sp = specs_[b];
      for (const auto& [i, k] : linear_[b]) elastic_[i] -= k * (s.q[i] + s.dq_free[i] + kq * a[i]);
      if (sp.index_x < 0) continue;
      const Eigen::Vector2d step(a[sp.index_x], a[sp.index_y]);
      if (touching(b)) {
        damping_[sp.index_x] = -sp.radial_damping * (s.v[sp.index_x] + kv * step[0]);
        damping_[sp.index_y] = -sp.radial_damping * (s.v[sp.index_y] + kv * step[1]);
      }
      if (sp.clearance > 0.0 && sp.law == BearingLaw::linear && s.weights.statics) {
        // A static solve keeps a bearing in contact once it is, and takes one out of contact to
        // the wall the load pushes it to (the probe's displacement, linearise): the body is
        // free within its clearance, so any load carries it across (a displacement of rounding,
        // below 1e-9 of the clearance, is no load).
        if (!contact_[b] && step.norm() > 1e-9 * sp.clearance && !last) {
          contact_[b] = true;
          direction_[b] = step.normalized();
          changed = true;
        }
      } else if (sp.clearance > 0.0 && sp.law == BearingLaw::linear) {
        const Eigen::Vector2d r = start(sp, s) + kq * step;
        const bool now = r.norm() > sp.clearance;
        if (now != contact_[b] && !last) {
          contact_[b] = now;
          if (now) direction_[b] = r.normalized();
          changed = true;
        }
      }
      const Eigen::Vector2d f = force0_[b] - kq * (stiffness_[b] * step);
      elastic_[sp.index_x] += f[0];
      elastic_[sp.index_y] += f[1];
    }
    return changed;
  }

  double potential(const StepView& s) const override {
    double energy = 0.0;
    for (size_t b = 0; b < specs_.size(); ++b) {
      const BearingSpringSpec& sp = specs_[b];
      for (const auto& [i, k] : linear_[b]) energy += 0.5 * k * s.q[i] * s.q[i];
      if (sp.index_x < 0) continue;
      if (sp.law == BearingLaw::roller_sum) {
        // ∫ K_n δⁿ dδ = K_n δⁿ⁺¹ / (n + 1) per element in contact.
        const Eigen::Vector2d r(s.q[sp.index_x], s.q[sp.index_y]);
        const double n = sp.load_exponent;
        for (const Eigen::Vector2d& e : rollers_[b]) {
          const double d = e.dot(r) - sp.clearance;
          if (d > 0.0) energy += sp.contact_stiffness * std::pow(d, n + 1.0) / (n + 1.0);
        }
        continue;
      }
      const double over =
          std::max(std::hypot(s.q[sp.index_x], s.q[sp.index_y]) - sp.clearance, 0.0);
      energy += 0.5 * sp.radial_stiffness * over * over;
    }
    return energy;
  }

  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    return {elastic_.dot(v_mid) * s.dt, -damping_.dot(v_mid) * s.dt, 0.0};
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override { return copy_of<BearingSprings, Element>(*this); }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  struct Linear {
    long index;
    double stiffness;
  };

  // Bearing b's radial spring and damper act: in contact, or always without clearance (the
  // linear law; a roller sum's elements touch or not whatever the clearance).
  bool touching(size_t b) const {
    const BearingSpringSpec& sp = specs_[b];
    return (sp.law == BearingLaw::linear && sp.clearance <= 0.0) || contact_[b];
  }

  // r₀: the radial displacement at the weighted state with ā = 0 [m].
  static Eigen::Vector2d start(const BearingSpringSpec& sp, const StepView& s) {
    return {s.q[sp.index_x] + s.dq_free[sp.index_x], s.q[sp.index_y] + s.dq_free[sp.index_y]};
  }

  // F(r₀) and the tangent stiffness K(r₀) of bearing b's radial law, for its contact state. A
  // static solve out of contact probes with the law's stiffness (no force), so that the
  // displacement shows where the load pushes the body (settle then puts it in contact there).
  void linearise(size_t b, const Eigen::Vector2d& r, bool statics) {
    const BearingSpringSpec& sp = specs_[b];
    const double k = sp.radial_stiffness, c = sp.clearance;
    if (c <= 0.0) {
      stiffness_[b] = k * Eigen::Matrix2d::Identity();
      force0_[b] = -k * r;
      return;
    }
    if (!contact_[b]) {
      stiffness_[b] = statics ? Eigen::Matrix2d(k * Eigen::Matrix2d::Identity())
                              : Eigen::Matrix2d::Zero();
      force0_[b].setZero();
      return;
    }
    const double n = r.norm();
    if (n > c) {
      const Eigen::Vector2d u = r / n;
      direction_[b] = u;
      stiffness_[b] = k * ((1.0 - c / n) * Eigen::Matrix2d::Identity() + (c / n) * u * u.transpose());
      force0_[b] = -k * (n - c) * u;
    } else {
      // Entering contact within the step: the wall's normal is where the body meets it.
      const Eigen::Vector2d& u = direction_[b];
      stiffness_[b] = k * u * u.transpose();
      force0_[b] = -k * (u.dot(r) - c) * u;
    }
  }

  // F(r₀) and K(r₀) of bearing b's roller sum (the header's comment), its contact: whether an
  // element carries load. A static solve from no load starts from every element pressed by
  // kStartDeflection.
  void roller_sum(size_t b, const Eigen::Vector2d& r, bool statics) {
    const BearingSpringSpec& sp = specs_[b];
    const double n = sp.load_exponent, kn = sp.contact_stiffness;
    stiffness_[b].setZero();
    force0_[b].setZero();
    for (const Eigen::Vector2d& e : rollers_[b]) {
      const double d = e.dot(r) - sp.clearance;
      if (d <= 0.0) continue;
      const double slope = kn * std::pow(d, n - 1.0);  // K_n δⁿ⁻¹ [N/m]
      force0_[b] -= slope * d * e;
      stiffness_[b] += n * slope * e * e.transpose();
    }
    contact_[b] = stiffness_[b].trace() > 0.0;
    if (statics && !contact_[b]) {
      const double slope = n * kn * std::pow(kStartDeflection, n - 1.0);
      for (const Eigen::Vector2d& e : rollers_[b]) stiffness_[b] += slope * e * e.transpose();
    }
  }

  std::vector<BearingSpringSpec> specs_;
  std::vector<bool> contact_;                // radial contact (clearance taken up), per bearing
  std::vector<Eigen::Vector2d> direction_;   // the last contact normal r̂
  std::vector<Eigen::Matrix2d> stiffness_;   // K(r₀) of the current step
  std::vector<Eigen::Vector2d> force0_;      // F(r₀) of the current step [N]
  std::vector<std::vector<Eigen::Vector2d>> rollers_;  // e_j of a roller sum's elements
  std::vector<std::vector<Linear>> linear_;  // each bearing's axial slide and tilt hinges, those it has
  bool started_ = false;  // contact_ set from the first state prepared
  Eigen::VectorXd elastic_, damping_;  // the settled spring and damper forces [N or N·m]
};

// The force of a bearing's rows' springs on the body, along u, w, k [N], at one sample's joint
// coordinates row (bearing_rows.hpp: F_u = −Σ k_u δ_u, F_w = −Σ k_w δ_w, F_k = −Σ k_axial δ_k;
// a row with clearance: its sides' law, BearingRows::elastic_load).
inline Eigen::Vector3d row_springs_force(const BearingSlides& b, const double* row) {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  for (BearingRowSpec r : b.rows) {
    r.index_x = b.x, r.index_y = b.y, r.index_axial = b.z;
    r.index_tilt_x = b.tilt_x, r.index_tilt_y = b.tilt_y;
    const BearingRows::Map map = BearingRows::map(r);
    double along[3] = {0.0, 0.0, 0.0};  // δ_k, δ_u, δ_w
    for (int j = 0; j < 3; ++j) {
      for (const BearingRows::Term& t : map[j]) along[j] += t.coefficient * row[t.index];
    }
    force += Eigen::Vector3d(BearingRows::elastic_load(r, 1, along[1]),
                             BearingRows::elastic_load(r, 2, along[2]),
                             BearingRows::elastic_load(r, 0, along[0]));
  }
  return force;
}

inline void bearing_slide_series(const double* angle, long samples, long angle_stride,
                                 const std::vector<BearingSlides>& slides, long bearings,
                                 double* displacement, double* elastic) {
  std::vector<std::vector<Eigen::Vector2d>> rollers;
  for (const BearingSlides& b : slides) {
    rollers.push_back(elastic != nullptr && b.spring.law == BearingLaw::roller_sum
                          ? BearingSprings::roller_directions(b.spring.rollers)
                          : std::vector<Eigen::Vector2d>());
  }
  for (long k = 0; k < samples; ++k) {
    const double* row = angle + k * angle_stride;
    for (size_t i = 0; i < slides.size(); ++i) {
      const BearingSlides& b = slides[i];
      const Eigen::Vector3d xyz(b.x >= 0 ? row[b.x] : 0.0, b.y >= 0 ? row[b.y] : 0.0,
                                b.z >= 0 ? row[b.z] : 0.0);
      const long at = 3 * (k * bearings + b.bearing);
      if (displacement != nullptr) {
        Eigen::Map<Eigen::Vector3d>(displacement + at) = b.axes.transpose() * xyz;
      }
      if (elastic == nullptr) continue;
      Eigen::Vector3d force(0.0, 0.0, -b.spring.axial_stiffness * xyz[2]);
      force.head<2>() = BearingSprings::radial_force(b.spring, rollers[i], xyz.head<2>());
      if (!b.rows.empty()) force = row_springs_force(b, row);
      Eigen::Map<Eigen::Vector3d>(elastic + at) = b.axes.transpose() * force;
    }
  }
}

// bearing_slide_series on a block's angle (samples, joints) into (samples, bearings, 3) arrays,
// either of them None (not computed): _native.bearing_slide_series.
using SlideAngles = nanobind::ndarray<const double, nanobind::ndim<2>, nanobind::device::cpu>;
using SlideRows = nanobind::ndarray<double, nanobind::ndim<3>, nanobind::c_contig,
                                    nanobind::device::cpu>;

inline void slide_series(const SlideAngles& angle, const std::vector<BearingSlides>& slides,
                         std::optional<SlideRows> displacement, std::optional<SlideRows> elastic) {
  const long samples = static_cast<long>(angle.shape(0)), joints = static_cast<long>(angle.shape(1));
  long bearings = -1;
  for (const std::optional<SlideRows>* out : {&displacement, &elastic}) {
    if (!*out) continue;
    const SlideRows& rows = **out;
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
        b.z >= joints || b.tilt_x >= joints || b.tilt_y >= joints) {
      throw std::invalid_argument("a bearing's column or slide is outside the arrays");
    }
  }
  nanobind::gil_scoped_release release;
  bearing_slide_series(angle.data(), samples, static_cast<long>(angle.stride(0)), slides,
                       bearings, displacement ? displacement->data() : nullptr,
                       elastic ? elastic->data() : nullptr);
}

// The kind (element_kind.hpp): StepperSpec.bearing_springs, the compliant bearings' and the
// support's springs (pinwind/dynamics/element_specs.py), one element for all of them.
struct BearingSpringsKind : KindBase {
  using Specs = std::vector<BearingSpringSpec>;
  using Built = Elements;
  static constexpr const char* field = "bearing_springs";

  static void check(const Specs& specs, const KindContext& c) {
    for (const auto& b : specs) {
      for (long i : {b.index_x, b.index_y, b.index_axial, b.index_tilt_x, b.index_tilt_y}) {
        if (i < -1 || i >= c.nv) throw std::invalid_argument("bad bearing spring joint index");
      }
      if ((b.index_x < 0) != (b.index_y < 0) || (b.index_tilt_x < 0) != (b.index_tilt_y < 0)) {
        throw std::invalid_argument("bearing spring: radial and tilt joints come in pairs");
      }
    }
  }

  static void add(const Specs& specs, const KindContext&, Elements& out) {
    if (!specs.empty()) out.push_back(std::make_unique<BearingSprings>(specs));
  }

  static void bind(nanobind::module_& m) {
    namespace nb = nanobind;
    using namespace nb::literals;
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
        .def_rw("tilt_x", &BearingSlides::tilt_x)
        .def_rw("tilt_y", &BearingSlides::tilt_y)
        .def_rw("rows", &BearingSlides::rows)
        .def_rw("axes", &BearingSlides::axes)
        .def_rw("spring", &BearingSlides::spring);

    m.def("bearing_slide_series", &slide_series, "angle"_a, "slides"_a, "displacement"_a.none(),
          "elastic"_a.none() = nb::none(),
          "Each bearing's displacement [m] and its springs' elastic force [N] (joint frame) from "
          "a block's joint coordinates, into (samples, bearings, 3) arrays (bearing_spring.hpp).");
  }
};

}  // namespace pinwind
