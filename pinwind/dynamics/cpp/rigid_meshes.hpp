// Rigid gear meshes as constraint rows (constraints.hpp): the kind of StepperSpec.rigid_meshes.
#pragma once

#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nanobind/nanobind.h>

#include "constraints.hpp"
#include "element_kind.hpp"
#include "elements.hpp"
#include "mesh_path.hpp"
#include "mesh_rows.hpp"
#include "series.hpp"
#include "small_products.hpp"

namespace pinwind {

// Rigid gear meshes (mesh_rows.hpp; pinwind/dynamics/mesh.py): one row per mesh, the loaded
// flank's J = s cos α_w J_t + ε sin α_w J_r with its bias. λ is the tooth normal force F_n on
// gear B [N] along the line of action n of the loaded flank; −F_n n acts on gear A. A negative
// λ means the other flank carries the load: the row switches to it. Writes the mesh forces,
// transmission error (∫ J v dt along the loaded flank [m]), contact position, pairs and
// single-tooth force; its work joins work_constraints (zero but for the rows' drift).
class RigidMeshes final : public Constraint {
 public:
  // meshes: the indices of the rigid meshes in the model's mesh list, in row order.
  RigidMeshes(std::vector<long> meshes, const std::vector<MeshPathSpec>& paths)
      : meshes_(std::move(meshes)), paths_(&paths) {
    const auto n = static_cast<Eigen::Index>(meshes_.size());
    flank_.setOnes(n);
    te_.setZero(n);
    jv_.setZero(n);
    written_.setZero(n);
    hints_.resize(meshes_.size());
  }

  Eigen::Index size() const override { return flank_.size(); }

  bool reads_gear_motion() const override { return true; }

  // A fixed mesh's row (MeshRows::frame: J the same at every q, γ = 0) is written again only
  // when its flank has changed since it was last written into the step's J (the one J this is
  // called with; a saved state keeps that J and these flags together).
  void rows(const StepView& s, RowsBlock jac, ValuesBlock bias) const override {
    for (Eigen::Index r = 0; r < size(); ++r) {
      const Eigen::Index m = meshes_[r];
      const bool fixed = s.rows.fixed(m);
      if (fixed && written_[r] == flank_[r]) continue;
      flank_row(s.meshes, s.rows, m, flank_[r], jac.row(r), bias[r]);
      written_[r] = fixed ? flank_[r] : 0.0;
    }
  }

  void biases(const StepView& s, ValuesBlock bias) const override {
    for (Eigen::Index r = 0; r < size(); ++r) bias[r] = flank_bias(s.meshes, s.rows, meshes_[r], flank_[r]);
  }

  // With fixed axes the other flank's row is the opposite row and λ just flips sign;
  // otherwise solve again (a switch can move load between meshes).
  RowSwitch switch_rows(const StepView& s, ValuesBlock lambda) override {
    bool any = false, all_free = true;
    for (Eigen::Index r = 0; r < size(); ++r) {
      if (lambda[r] < 0.0) {
        any = true;
        all_free = all_free && flank_flip_is_free(s.rows, meshes_[r]);
      }
    }
    if (!any) return RowSwitch::none;
    for (Eigen::Index r = 0; r < size(); ++r) {
      if (lambda[r] < 0.0) flank_[r] = -flank_[r];
    }
    if (!all_free) return RowSwitch::solve;
    for (Eigen::Index r = 0; r < size(); ++r) {
      if (lambda[r] < 0.0) lambda[r] = -lambda[r];
    }
    return RowSwitch::free;
  }

  // The tooth forces at the pitch points: the reduced-coordinate form of
  // Saleh 2017 eqs. 16, 18, 23 and 26.
  void add_body_forces(const StepView& s, ConstValues lambda, BodyForces& out) const override {
    const auto& mc = s.meshes;
    for (Eigen::Index r = 0; r < size(); ++r) {
      const Eigen::Index m = meshes_[r];
      const Vec3 f = tooth_force_on_b(mc, s.rows, m, flank_[r], lambda[r]);
      const Vec3 p = s.rows.pitch_point.row(m).transpose();
      out.add(mc.joint_b[m], p, f);
      out.add(mc.joint_a[m], p, -f);
    }
  }

  // The forces from the loaded flanks' multipliers, with where the teeth are along the path of
  // contact.
  void record(const StepView& s, long k, ConstValues lambda, const Outputs& out) const override {
    const auto& mc = s.meshes;
    for (Eigen::Index r = 0; r < size(); ++r) {
      const Eigen::Index m = meshes_[r];
      const auto& path = (*paths_)[static_cast<size_t>(m)];
      // ψ_A from q where it is affine in q (no atan2), else from gear A's rotation
      const double angle =
          s.rows.angle_affine(m)
              ? affine_angle(s.rows, m, s.q)
              : gear_a_angle(mc, s.rows, path, s.data.oMi[mc.joint_a[m]].rotation(), m);
      // the affine angle differs from gear_a_angle's by rounding already: its roll is wrapped
      // by wrap_positive_near, the other's by fmod as before
      const PathState p = path_state(path, angle, flank_[r], 0.0, &hints_[static_cast<size_t>(r)],
                                     s.rows.angle_affine(m));
      record_mesh_force(out, mc, s.rows, k, m, lambda[r], flank_[r]);
      const long e = out.entry(Family::mesh, k, m);
      out.at(Series::transmission_error, e) = te_[r];
      out.at(Series::mesh_deflection, e) = 0.0;
      out.at(Series::mesh_contact_position, e) = path.roll_start + p.entering;
      out.at(Series::mesh_pairs, e) = p.pairs;
      out.at(Series::mesh_single_tooth_force, e) = lambda[r] * p.share;
    }
  }

  void work(const StepView&, ConstRows jac, ConstValues lambda, const Eigen::VectorXd& dq,
            EnergyLedger& ledger) const override {
    if (!size()) return;
    small_product(jac, dq, jv_);
    ledger.constraints += lambda.dot(jv_);
  }

  void advance(const StepView&, ConstRows jac, const Eigen::VectorXd& dq) override {
    // Σ_c J_rc dq_c in column order, as Eigen's dot of the strided row sums it, for all rows at
    // once by columns (small_product: each row's sum from 0.0, the same value; te_ is never
    // −0.0, which alone could tell a +0.0 sum from a −0.0 one).
    if (!size()) return;
    small_product<Accumulate::add>(jac, dq, te_);
  }

  // A copy for a saved state of the run, and its states taken back (Constraint::copy).
  std::unique_ptr<Constraint> copy() const override {
    return copy_of<RigidMeshes, Constraint>(*this);
  }
  void restore(const Constraint& saved) override { restore_from(*this, saved); }

 private:
  // Whether mesh m's other flank has the opposite row (fixed axes): λ just changes sign. When
  // the radial part of the row vanishes in joint space it vanishes at every state (the axes
  // cannot move apart), so its bias, the time derivative, vanishes too.
  static bool flank_flip_is_free(const MeshRows& rows, Eigen::Index m) {
    const double scale = rows.jac_t.row(m).cwiseAbs().maxCoeff() + 1e-300;
    return rows.jac_r.row(m).cwiseAbs().maxCoeff() <= 1e-12 * scale;
  }

  std::vector<long> meshes_;
  const std::vector<MeshPathSpec>* paths_;  // the setup's (a pointer: copies assign)
  Eigen::VectorXd flank_, te_;  // loaded flank s (±1) and transmission error [m] of each row
  mutable Eigen::VectorXd jv_;
  // The flank of each fixed mesh's row as rows() last wrote it into J (0: not written, or not
  // fixed): a state of the step's J, saved and taken back with it.
  mutable Eigen::VectorXd written_;
  mutable std::vector<PathHint> hints_;  // each row's table look-ups (path_state; speed only)
};

// The kind (element_kind.hpp): StepperSpec.rigid_meshes, the indices of the meshes that are
// rows, in row order; their paths of contact are the KindContext's. The spec is a list of
// indices: nothing to bind of its own.
struct RigidMeshesKind : KindBase {
  using Specs = std::vector<long>;
  using Built = Constraints;
  static constexpr const char* field = "rigid_meshes";

  static void check(const Specs& meshes, const KindContext& c) {
    for (long m : meshes) {
      if (m < 0 || m >= c.meshes.count()) throw std::invalid_argument("bad rigid mesh");
    }
  }

  static void add(const Specs& meshes, const KindContext& c, Constraints& out) {
    if (!meshes.empty()) out.push_back(std::make_unique<RigidMeshes>(meshes, c.paths));
  }

  static void bind(nanobind::module_&) {}
};

}  // namespace pinwind
