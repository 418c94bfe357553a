// Bearing rows: each rolling bearing (row) of a shaft's compliant bearing as its own linear
// spring-damper at its axial position (docs/model_format.md "Bearing rows"; pinwind/model/
// bearing_rows.py). A shaft held by a compliant bearing moves on its slides (bearing_spring.hpp's
// header): radial x, y along the bearing's radial axes u, w, axial z along its axis k and tilts
// θ_u, θ_w about u and w through the bearing centre (the joint's origin). A row at a [m] along k
// from the centre sees, to first order in the tilts (θ_u u × a k = −a θ_u w, θ_w w × a k = a θ_w u),
//
//     δ = (z,  x + a θ_w,  y − a θ_u,  θ_u,  θ_w) = B s,    s = (x, y, z, θ_u, θ_w),
//
// in the order of the model file's row stiffness (K_x axial, K_y along u, K_z along w, K_β about
// u, K_γ about w; Nejad et al. 2016 Table VI axes: x axial, (k, u, w) right-handed as (x, y, z)).
// Each component j is a linear spring k_j and damper c_j: the row's load on the shaft is
//
//     L_j = −k_j δ_j − c_j δ̇_j     (L = (F_k, F_u, F_w [N], M_u, M_w [N·m]))
//
// and its generalised force on the slides Bᵀ L, the gradient of U = ½ Σ_j k_j δ_j² and of the
// dissipation ½ Σ_j c_j δ̇_j². Like the torsional springs (torsional_spring.hpp) the forces are
// taken at the time step's weighted state s_n + ds₀ + κ_q ā, v_n + κ_v ā, linear in ā (W = Σ_j
// (κ_q k_j + κ_v c_j) b_j b_jᵀ, b_j row j of B): exact for a linear law, second order and, with
// ρ∞ = 1, energy-keeping. The rows need not sit about a stiffness centre: Σ k_j a couples the
// radial slides with the tilts through B. A slide the bearing lacks (no axial slide, no tilt
// hinges) is rigid: its terms drop out of B.
//
// A row with a radial clearance c [m] (has_clearance; the model file's radial_clearance_mm of
// the <row>, negative with preload="true": a preload) keeps its axial and tilt springs linear and
// holds each radial direction j (along u, along w) between two sides, each a one-sided linear
// contact of the row's stiffness k_j, the side s = ±1 touching while its overlap s δ_j − c > 0:
//
//     L_j = −k_j [max(δ_j − c, 0) − max(−δ_j − c, 0)],   U_j = ½ k_j Σ_s max(s δ_j − c, 0)²
//
// (compliant_mesh.hpp's two flanks, with the backlash 2c). With c > 0 it is the dead band
// −k_j sign(δ_j) max(|δ_j| − c, 0): no load until the shaft crosses c; with c < 0 both sides
// press by |c| at the centre, the row is 2 k_j stiff while |δ_j| < |c| and one side lets go
// beyond (a preloaded row); c = 0 is the linear spring. c is pinwind's radial clearance, the
// free travel from the centre to one side (Harris's diametral clearance P_d = 2c, as
// bearing_spring.hpp's and life/load_distribution.py's). The radial damper c_j acts while a side
// touches. Each side is an active set settled after each solve as the mesh's flanks are: a side
// whose overlap at the weighted state would be negative opens, a free one that would overlap
// closes, and the step is solved again; with ρ∞ = 1 the step keeps the energy to rounding but
// for the steps in which a side opens or closes (an O(h²) error: docs/simulation.md, the
// ledger). A static solve (Stepper::equilibrium) probes a direction whose sides are both open
// with the stiffness k_j and no force, to see which side the load pushes the shaft to, puts that
// side in contact and solves again; a side that then pulls opens, and the direction is left
// open (the row slack inside its clearance, the others holding the shaft).
//
// Each row writes its load of the settled step (the force the step used, so that the rows add
// up to the bearing's reaction) as two series of the row family (series.hpp): row_force (F_u,
// F_w, F_k) [N] and row_moment (M_u, M_w, 0) [N·m], on the shaft, along the bearing's u, w, k.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include <Eigen/Core>
#include <nanobind/eigen/dense.h>
#include <nanobind/nanobind.h>
#include <nanobind/stl/vector.h>

#include "element_kind.hpp"
#include "elements.hpp"

namespace pinwind {

// One row of a compliant bearing: its slides, position and five springs and dampers.
struct BearingRowSpec {
  long index_x = -1, index_y = -1;            // velocity indices of the radial slides (u, w)
  long index_axial = -1;                      // the axial slide (−1: none, axially rigid)
  long index_tilt_x = -1, index_tilt_y = -1;  // the tilt hinges about u and w (−1: none)
  double position = 0.0;                      // a [m] along the bearing axis from its centre
  // (k_axial, k_u, k_w [N/m], k_tilt_u, k_tilt_w [N·m/rad]): the model file's K_x..K_γ.
  Eigen::Matrix<double, 5, 1> stiffness = Eigen::Matrix<double, 5, 1>::Zero();
  // (c_axial, c_u, c_w [N·s/m], c_tilt_u, c_tilt_w [N·m·s/rad]).
  Eigen::Matrix<double, 5, 1> damping = Eigen::Matrix<double, 5, 1>::Zero();
  bool has_clearance = false;  // radial law with sides (the header's comment); false: linear
  double clearance = 0.0;      // c [m] from the centre to a side (negative: a preload)
};

class BearingRows : public Element {
 public:
  // One term of a row's δ_j: coefficient × the coordinate of velocity index.
  struct Term {
    long index;
    double coefficient;
  };
  // Row j of B for a row (the header's comment): at most two terms, the absent slides left out.
  using Map = std::array<std::vector<Term>, 5>;

  static Map map(const BearingRowSpec& r) {
    Map b;
    auto put = [&](int j, long index, double coefficient) {
      if (index >= 0 && coefficient != 0.0) b[j].push_back({index, coefficient});
    };
    put(0, r.index_axial, 1.0);
    put(1, r.index_x, 1.0);
    put(1, r.index_tilt_y, r.position);
    put(2, r.index_y, 1.0);
    put(2, r.index_tilt_x, -r.position);
    put(3, r.index_tilt_x, 1.0);
    put(4, r.index_tilt_y, 1.0);
    return b;
  }

  // b_j · x for a vector x over the velocities.
  static double along(const std::vector<Term>& b, const Eigen::VectorXd& x) {
    double out = 0.0;
    for (const Term& t : b) out += t.coefficient * x[t.index];
    return out;
  }

  // Component j of row r has sides (the header's comment): a radial one of a row with clearance.
  static bool sided(const BearingRowSpec& r, int j) {
    return r.has_clearance && (j == 1 || j == 2);
  }

  // The overlap s δ − c [m] of side (0: s = +1, 1: s = −1) at the deflection δ.
  static double overlap(const BearingRowSpec& r, int side, double delta) {
    return (side == 0 ? delta : -delta) - r.clearance;
  }

  // L_j [N or N·m] of component j of row r at its deflection δ_j: −k δ, or the sides' law.
  static double elastic_load(const BearingRowSpec& r, int j, double delta) {
    const double k = r.stiffness[j];
    if (!sided(r, j)) return -k * delta;
    return -k * (std::max(overlap(r, 0, delta), 0.0) - std::max(overlap(r, 1, delta), 0.0));
  }

  // U_j [J] of component j of row r at its deflection δ_j: ½ k δ², or the sides' ½ k Σ overlap₊².
  static double energy(const BearingRowSpec& r, int j, double delta) {
    const double k = r.stiffness[j];
    if (!sided(r, j)) return 0.5 * k * delta * delta;
    double out = 0.0;
    for (int side = 0; side < 2; ++side) {
      const double o = std::max(overlap(r, side, delta), 0.0);
      out += 0.5 * k * o * o;
    }
    return out;
  }

  explicit BearingRows(std::vector<BearingRowSpec> specs) : specs_(std::move(specs)) {
    for (const BearingRowSpec& r : specs_) maps_.push_back(map(r));
    loads_.assign(specs_.size(), Eigen::Matrix<double, 5, 1>::Zero());
    touch_.assign(specs_.size(), Sides{});
    open_.assign(specs_.size(), {false, false});
  }

  // The sides touch where the shaft is at the first state (a run or a check from a displaced
  // state, a preloaded row at the centre: both).
  void prepare(const StepView& s) override {
    if (started_) return;
    started_ = true;
    for (size_t r = 0; r < specs_.size(); ++r) {
      for (int j = 1; j <= 2; ++j) {
        if (!sided(specs_[r], j)) continue;
        const double delta = along(maps_[r][j], s.q);
        for (int side = 0; side < 2; ++side) {
          touch_[r][j - 1][side] = overlap(specs_[r], side, delta) > 0.0;
        }
      }
    }
  }

  void add_implicit(const StepView& s, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    const double kq = s.weights.position_gain, kv = s.weights.speed_gain;
    for (size_t r = 0; r < specs_.size(); ++r) {
      for (int j = 0; j < 5; ++j) {
        const std::vector<Term>& b = maps_[r][j];
        if (b.empty()) continue;
        const double k = specs_[r].stiffness[j], c = specs_[r].damping[j];
        double w = kq * k + kv * c;
        double load = -k * (along(b, s.q) + along(b, s.dq_free)) - c * along(b, s.v);
        if (sided(specs_[r], j)) {
          // The sides that touch: each −k (δ − s c); none: a static solve's probe (no force).
          const std::array<bool, 2>& t = touch_[r][j - 1];
          const double delta = along(b, s.q) + along(b, s.dq_free);
          const double damper = (t[0] || t[1]) ? c : 0.0;
          double stiff = 0.0;
          load = -damper * along(b, s.v);
          for (int side = 0; side < 2; ++side) {
            if (!t[side]) continue;
            stiff += k;
            load -= k * (delta - (side == 0 ? 1.0 : -1.0) * specs_[r].clearance);
          }
          const bool probe = s.weights.statics && !t[0] && !t[1] && !open_[r][j - 1];
          w = kq * (probe ? k : stiff) + kv * damper;
        }
        for (const Term& t : b) {
          force[t.index] += t.coefficient * load;
          for (const Term& u : b) hessian(t.index, u.index) += w * t.coefficient * u.coefficient;
        }
      }
    }
  }

  bool settle(const StepView& s, const Eigen::VectorXd& a, bool last) override {
    const double kq = s.weights.position_gain, kv = s.weights.speed_gain;
    bool changed = false;
    elastic_.setZero(s.q.size());
    damping_.setZero(s.q.size());
    for (size_t r = 0; r < specs_.size(); ++r) {
      for (int j = 0; j < 5; ++j) {
        const std::vector<Term>& b = maps_[r][j];
        const double da = along(b, a);
        double spring =
            -specs_[r].stiffness[j] * (along(b, s.q) + along(b, s.dq_free) + kq * da);
        double damper = -specs_[r].damping[j] * (along(b, s.v) + kv * da);
        if (sided(specs_[r], j)) {
          const double delta = along(b, s.q) + along(b, s.dq_free) + kq * da;
          if (!last) changed = switch_sides(r, j, delta, kq * da, s.weights.statics) || changed;
          const std::array<bool, 2>& t = touch_[r][j - 1];
          spring = 0.0;  // −s k (s δ − c) per touching side: the force the step used
          for (int side = 0; side < 2; ++side) {
            const double sign = side == 0 ? 1.0 : -1.0;
            if (t[side]) spring -= sign * specs_[r].stiffness[j] * overlap(specs_[r], side, delta);
          }
          if (!t[0] && !t[1]) damper = 0.0;
        }
        loads_[r][j] = spring + damper;
        for (const Term& t : b) {
          elastic_[t.index] += t.coefficient * spring;
          damping_[t.index] += t.coefficient * damper;
        }
      }
    }
    return changed;
  }

  double potential(const StepView& s) const override {
    double out = 0.0;
    for (size_t r = 0; r < specs_.size(); ++r) {
      for (int j = 0; j < 5; ++j) out += energy(specs_[r], j, along(maps_[r][j], s.q));
    }
    return out;
  }

  StepWork work(const StepView& s, const Eigen::VectorXd&,
                const Eigen::VectorXd& v_mid) const override {
    return {elastic_.dot(v_mid) * s.dt, -damping_.dot(v_mid) * s.dt, 0.0};
  }

  void record(const StepView&, long k, const Outputs& out) const override {
    for (size_t r = 0; r < specs_.size(); ++r) {
      const long e = out.entry(Family::row, k, static_cast<long>(r));
      const Eigen::Matrix<double, 5, 1>& l = loads_[r];
      out.at(Series::row_force, e, 0) = l[1];
      out.at(Series::row_force, e, 1) = l[2];
      out.at(Series::row_force, e, 2) = l[0];
      out.at(Series::row_moment, e, 0) = l[3];
      out.at(Series::row_moment, e, 1) = l[4];
      out.at(Series::row_moment, e, 2) = 0.0;
    }
  }

  // The rows' forces of the settled step, (F_u, F_w, F_k) as row_force records them.
  void row_forces(std::vector<Eigen::Vector3d>& rows) const override {
    if (rows.size() < specs_.size()) rows.resize(specs_.size(), Eigen::Vector3d::Zero());
    for (size_t r = 0; r < specs_.size(); ++r) {
      rows[r] = Eigen::Vector3d(loads_[r][1], loads_[r][2], loads_[r][0]);
    }
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override { return copy_of<BearingRows, Element>(*this); }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  using Sides = std::array<std::array<bool, 2>, 2>;  // [direction u, w][side +, −]: touching

  // Side changes of component j of row r at the deflection δ of the solved step, whose own
  // change was step (the header's comment); true when the step must be solved again. A static
  // solve that probed a direction puts the side the probe moved it towards in contact (the
  // shaft is free inside its clearance, so any load carries it across; a move of rounding,
  // below 1e-9 of the clearance, is no load: the direction stays open); a side that then pulls
  // opens and the direction stays open, unprobed: the row is slack in the equilibrium.
  bool switch_sides(size_t r, int j, double delta, double step, bool statics) {
    std::array<bool, 2>& t = touch_[r][j - 1];
    bool& open = open_[r][j - 1];
    if (statics && !t[0] && !t[1] && !open) {
      if (std::abs(step) > 1e-9 * std::abs(specs_[r].clearance)) {
        t[step > 0.0 ? 0 : 1] = true;
      } else {
        open = true;
      }
      return true;
    }
    bool changed = false;
    for (int side = 0; side < 2; ++side) {
      const double o = overlap(specs_[r], side, delta);
      if (t[side] ? o < 0.0 : o > 0.0) {
        t[side] = !t[side];
        changed = true;
      }
    }
    if (changed) open = !t[0] && !t[1];
    return changed;
  }

  std::vector<BearingRowSpec> specs_;
  std::vector<Map> maps_;
  std::vector<Sides> touch_;                    // each row's touching sides
  std::vector<std::array<bool, 2>> open_;       // a static solve found the direction free
  bool started_ = false;                        // touch_ set from the first state prepared
  std::vector<Eigen::Matrix<double, 5, 1>> loads_;  // L of the settled step, per row
  Eigen::VectorXd elastic_, damping_;  // the settled spring and damper forces on the slides
};

// The kind (element_kind.hpp): StepperSpec.bearing_rows, one spec per row in the order of the
// row family's columns (pinwind/dynamics/element_specs.py), one element for all of them.
struct BearingRowsKind : KindBase {
  using Specs = std::vector<BearingRowSpec>;
  using Built = Elements;
  static constexpr const char* field = "bearing_rows";

  static void check(const Specs& specs, const KindContext& c) {
    for (const auto& r : specs) {
      for (long i : {r.index_x, r.index_y, r.index_axial, r.index_tilt_x, r.index_tilt_y}) {
        if (i < -1 || i >= c.nv) throw std::invalid_argument("bad bearing row joint index");
      }
      if ((r.index_x < 0) != (r.index_y < 0) || (r.index_tilt_x < 0) != (r.index_tilt_y < 0)) {
        throw std::invalid_argument("bearing row: radial and tilt joints come in pairs");
      }
      if (!(r.stiffness.allFinite() && r.damping.allFinite() && r.stiffness.minCoeff() >= 0.0 &&
            r.damping.minCoeff() >= 0.0)) {
        throw std::invalid_argument("bearing row: stiffness and damping must be finite, >= 0");
      }
      if (!std::isfinite(r.clearance)) {
        throw std::invalid_argument("bearing row: clearance must be finite");
      }
    }
  }

  static void count(const Specs& specs, FamilyCounts& counts) {
    counts[static_cast<size_t>(Family::row)] = static_cast<long>(specs.size());
  }

  static void add(const Specs& specs, const KindContext&, Elements& out) {
    if (!specs.empty()) out.push_back(std::make_unique<BearingRows>(specs));
  }

  static void bind(nanobind::module_& m) {
    nanobind::class_<BearingRowSpec>(m, "BearingRowSpec")
        .def(nanobind::init<>())
        .def_rw("index_x", &BearingRowSpec::index_x)
        .def_rw("index_y", &BearingRowSpec::index_y)
        .def_rw("index_axial", &BearingRowSpec::index_axial)
        .def_rw("index_tilt_x", &BearingRowSpec::index_tilt_x)
        .def_rw("index_tilt_y", &BearingRowSpec::index_tilt_y)
        .def_rw("position", &BearingRowSpec::position)
        .def_rw("stiffness", &BearingRowSpec::stiffness)
        .def_rw("damping", &BearingRowSpec::damping)
        .def_rw("has_clearance", &BearingRowSpec::has_clearance)
        .def_rw("clearance", &BearingRowSpec::clearance);
    m.def(
        "bearing_row_map",
        [](const BearingRowSpec& r, long nv) {
          for (long i : {r.index_x, r.index_y, r.index_axial, r.index_tilt_x, r.index_tilt_y}) {
            if (i < -1 || i >= nv) throw std::invalid_argument("bad bearing row joint index");
          }
          Eigen::MatrixXd b = Eigen::MatrixXd::Zero(5, nv);
          const BearingRows::Map map = BearingRows::map(r);
          for (int j = 0; j < 5; ++j) {
            for (const BearingRows::Term& t : map[j]) b(j, t.index) += t.coefficient;
          }
          return b;
        },
        nanobind::arg("row"), nanobind::arg("nv"),
        "B (5, nv): the row's deflections δ = B q (axial, along u, along w, about u, about w) "
        "from the velocity coordinates (bearing_rows.hpp), for the linear model.");
  }
};

}  // namespace pinwind
