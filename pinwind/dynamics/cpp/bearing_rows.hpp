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
// Each row writes its load of the settled step (the force the step used, so that the rows add
// up to the bearing's reaction) as two series of the row family (series.hpp): row_force (F_u,
// F_w, F_k) [N] and row_moment (M_u, M_w, 0) [N·m], on the shaft, along the bearing's u, w, k.
#pragma once

#include <array>
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

  explicit BearingRows(std::vector<BearingRowSpec> specs) : specs_(std::move(specs)) {
    for (const BearingRowSpec& r : specs_) maps_.push_back(map(r));
    loads_.assign(specs_.size(), Eigen::Matrix<double, 5, 1>::Zero());
  }

  void add_implicit(const StepView& s, Eigen::MatrixXd& hessian, Eigen::VectorXd& force) override {
    const double kq = s.weights.position_gain, kv = s.weights.speed_gain;
    for (size_t r = 0; r < specs_.size(); ++r) {
      for (int j = 0; j < 5; ++j) {
        const std::vector<Term>& b = maps_[r][j];
        if (b.empty()) continue;
        const double k = specs_[r].stiffness[j], c = specs_[r].damping[j];
        const double w = kq * k + kv * c;
        const double load =
            -k * (along(b, s.q) + along(b, s.dq_free)) - c * along(b, s.v);
        for (const Term& t : b) {
          force[t.index] += t.coefficient * load;
          for (const Term& u : b) hessian(t.index, u.index) += w * t.coefficient * u.coefficient;
        }
      }
    }
  }

  bool settle(const StepView& s, const Eigen::VectorXd& a, bool) override {
    const double kq = s.weights.position_gain, kv = s.weights.speed_gain;
    elastic_.setZero(s.q.size());
    damping_.setZero(s.q.size());
    for (size_t r = 0; r < specs_.size(); ++r) {
      for (int j = 0; j < 5; ++j) {
        const std::vector<Term>& b = maps_[r][j];
        const double da = along(b, a);
        const double spring =
            -specs_[r].stiffness[j] * (along(b, s.q) + along(b, s.dq_free) + kq * da);
        const double damper = -specs_[r].damping[j] * (along(b, s.v) + kv * da);
        loads_[r][j] = spring + damper;
        for (const Term& t : b) {
          elastic_[t.index] += t.coefficient * spring;
          damping_[t.index] += t.coefficient * damper;
        }
      }
    }
    return false;
  }

  double potential(const StepView& s) const override {
    double energy = 0.0;
    for (size_t r = 0; r < specs_.size(); ++r) {
      for (int j = 0; j < 5; ++j) {
        const double d = along(maps_[r][j], s.q);
        energy += 0.5 * specs_[r].stiffness[j] * d * d;
      }
    }
    return energy;
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

 private:
  std::vector<BearingRowSpec> specs_;
  std::vector<Map> maps_;
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
        .def_rw("damping", &BearingRowSpec::damping);
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
