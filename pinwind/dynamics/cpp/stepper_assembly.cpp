// A Stepper's start, with its elements and constraints from their kinds' factories
// (element_kinds.hpp), and the assembly the tests check against Pinocchio (stepper.hpp).
#include <algorithm>
#include <atomic>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <utility>

#include "joint_algorithms.hpp"
#include "mesh_path.hpp"
#include "stepper.hpp"

namespace pinwind {

Elements Stepper::build_elements() const {
  Elements out;
  const KindContext c = context();
  for (const auto& add : s_.elements) add(c, out);
  return out;
}

Constraints Stepper::build_constraints() const {
  Constraints out;
  const KindContext c = context();
  for (const auto& add : s_.constraints) add(c, out);
  return out;
}

namespace {

Eigen::Index total_rows(const Constraints& constraints) {
  Eigen::Index rows = 0;
  for (const auto& c : constraints) rows += c->size();
  return rows;
}

bool reads_gear_motion(const Constraints& constraints) {
  return std::any_of(constraints.begin(), constraints.end(),
                     [](const auto& c) { return c->reads_gear_motion(); });
}

// The joints on the path from joint j up to the world, j first (the world, 0, left out).
std::vector<long> joints_above(const pinocchio::Model& model, long j) {
  std::vector<long> out;
  for (; j > 0; j = static_cast<long>(model.parents[static_cast<size_t>(j)])) out.push_back(j);
  return out;
}

// MeshRows::angle_terms and angle_offset of the fixed meshes (rows.frame set, rows' geometry
// evaluated at q, data's placements and J at q). All rotations about one direction k commute, so
// when every joint from the world to gear A turns about ±k (or does not turn), A's rotation is
// Rot(k, Σ_j s_j q_j) times its rotation at q = 0, s_j = a_j·k = ±1 for the joint's world axis
// a_j; the frame's likewise. The centre line turns with the frame, so ψ_A = Σ over A's joints
// of s_j q_j less the same over the frame's, plus a constant taken from gear_a_angle at q. A
// configuration that is not the joints' angles (nq ≠ nv) or any other joint leaves the mesh
// to gear_a_angle.
void fixed_mesh_angles(const pinocchio::Model& model, const pinocchio::Data& data,
                       const MeshConstants& mc, const std::vector<MeshPathSpec>& paths,
                       const Eigen::VectorXd& q, MeshRows& rows) {
  const auto count = static_cast<size_t>(mc.count());
  rows.angle_terms.assign(count, {});
  rows.angle_offset.assign(count, std::numeric_limits<double>::quiet_NaN());
  if (!is_vector_space(model) || paths.size() != count) return;
  for (size_t m = 0; m < count; ++m) {
    const auto index = static_cast<Eigen::Index>(m);
    if (!rows.fixed(index)) continue;
    const Vec3 k = rows.axis.row(index).transpose();
    Eigen::VectorXd weight = Eigen::VectorXd::Zero(model.nv);
    bool affine = true;
    const auto add = [&](long joint, double sign) {
      for (const long j : joints_above(model, joint)) {
        const std::string kind = model.joints[static_cast<size_t>(j)].shortname();
        const int column = model.idx_vs[static_cast<size_t>(j)];
        if (kind == "JointModelPX" || kind == "JointModelPY" || kind == "JointModelPZ" ||
            kind == "JointModelPrismaticUnaligned") {
          continue;
        }
        const Vec3 axis = data.J.col(column).tail<3>();
        const double along = axis.dot(k);
        const bool revolute = kind == "JointModelRX" || kind == "JointModelRY" ||
                              kind == "JointModelRZ" || kind == "JointModelRevoluteUnaligned";
        if (!revolute || (axis - along * k).norm() > 1e-12 ||
            std::abs(std::abs(along) - 1.0) > 1e-12) {
          affine = false;
          return;
        }
        weight[column] += sign * (along > 0.0 ? 1.0 : -1.0);
      }
    };
    add(mc.joint_a[index], 1.0);
    add(rows.frame[m], -1.0);
    if (!affine) continue;
    double sum = 0.0;
    for (Eigen::Index j = 0; j < model.nv; ++j) {
      if (weight[j] == 0.0) continue;
      rows.angle_terms[m].emplace_back(j, weight[j]);
      sum += weight[j] * q[j];  // nq = nv: q's index is the column's
    }
    const auto& rot_a = data.oMi[static_cast<size_t>(mc.joint_a[index])].rotation();
    const double psi = gear_a_angle(mc, rows, paths[m], rot_a, index);
    rows.angle_offset[m] = psi - sum;
  }
}

// For each mesh, the joint whose frame carries its geometry when the mesh is fixed (its rows J
// the same at every q, so γ = J̇ v = 0: MeshRows::frame), else -1; data holds the placements and
// J at any q (kinematics()). Only the joints on the paths from the gears' common ancestor to
// each gear move one gear and not the other (the row's nonzero columns). If every one of them
// is revolute about the mesh's axis k, the row's entry for joint c is ± the moment arm of c's
// axis about the line of action, and the line of action, the pitch point and the gear centres
// follow from the centres; so the row is constant when the plane figure of the points on these
// paths (each joint's axis, each gear's centre) turns as one body whatever the angles. Turning
// joint d moves the points below it (its subtree's axes and gear centre) about its axis and
// leaves the others: rigid if the moved points lie on d's axis (d moves nothing) or the others
// do (d carries the figure). With no carrying joint the figure is fixed in the common
// ancestor's frame; with one, in the carrier's (sun and planet on a carrier: the sun's axis is
// the carrier's; a ring on the ground about the carrier's axis); two or more, or any other
// joint, and the mesh is evaluated in full. The test holds at every q if it holds at one: each
// joint's turn then moves the figure rigidly, so the relations stay. A gear on a crank that
// swings about another axis (the centre distance varies) fails it. Distances below 64 ε times
// the model's largest length count as zero (rounding), as in mass_is_constant.
std::vector<long> fixed_mesh_frames(const pinocchio::Model& model, const pinocchio::Data& data,
                                    const MeshConstants& mc,
                                    const std::vector<int>& slide_axes) {
  const auto nj = static_cast<long>(model.njoints);
  double length = 1.0;
  for (long i = 1; i < nj; ++i) length = std::max(length, data.oMi[i].translation().norm());
  const double tol = 64.0 * std::numeric_limits<double>::epsilon() * length;
  std::vector<long> out(static_cast<size_t>(mc.count()), -1);
  for (Eigen::Index m = 0; m < mc.count(); ++m) {
    const long ja = mc.joint_a[m], jb = mc.joint_b[m];
    const Vec3 k = (data.oMi[ja].rotation() * mc.axis_a.row(m).transpose()).normalized();
    const auto above_a = joints_above(model, ja), above_b = joints_above(model, jb);
    const auto has = [](const std::vector<long>& list, long j) {
      return std::find(list.begin(), list.end(), j) != list.end();
    };
    std::vector<long> path;  // the path joints
    for (long j : above_a) {
      if (!has(above_b, j)) path.push_back(j);
    }
    for (long j : above_b) {
      if (!has(above_a, j)) path.push_back(j);
    }
    long common = 0;
    for (long j : above_a) {
      if (has(above_b, j)) {
        common = j;
        break;
      }
    }
    // The figure's points, each with the joint it hangs from (a path joint's axis point, its
    // origin, hangs from its parent; a gear's centre from the gear's joint).
    std::vector<std::pair<Vec3, long>> points;
    points.emplace_back(data.oMi[ja].act(Vec3(mc.centre_a.row(m).transpose())), ja);
    points.emplace_back(data.oMi[jb].act(Vec3(mc.centre_b.row(m).transpose())), jb);
    bool fixed = true;
    for (const long j : path) {
      const std::string kind = model.joints[static_cast<size_t>(j)].shortname();
      const bool revolute = kind == "JointModelRX" || kind == "JointModelRY" ||
                            kind == "JointModelRZ" || kind == "JointModelRevoluteUnaligned";
      const Vec3 axis = data.J.col(model.idx_vs[static_cast<size_t>(j)]).tail<3>();
      if (!revolute || slide_axes[static_cast<size_t>(j)] >= 0 || axis.cross(k).norm() > tol) {
        fixed = false;
        break;
      }
      points.emplace_back(data.oMi[j].translation(),
                          static_cast<long>(model.parents[static_cast<size_t>(j)]));
    }
    if (!fixed) continue;
    long carrier = -1;
    int carriers = 0;
    for (const long d : path) {
      const Vec3& o = data.oMi[d].translation();
      const auto on_axis = [&](const Vec3& x) {
        const Vec3 r = x - o;
        return (r - r.dot(k) * k).norm() <= tol;
      };
      bool moved_on_axis = true, others_on_axis = true;
      for (const auto& point : points) {
        const long hangs = point.second;
        const bool moved = hangs > 0 && has(joints_above(model, hangs), d);
        if (on_axis(point.first)) continue;
        if (moved) {
          moved_on_axis = false;
        } else {
          others_on_axis = false;
        }
      }
      if (moved_on_axis) continue;
      if (!others_on_axis) {
        fixed = false;
        break;
      }
      carrier = d;
      ++carriers;
    }
    if (!fixed || carriers > 1) continue;
    out[static_cast<size_t>(m)] = carriers == 1 ? carrier : common;
  }
  return out;
}

// Per joint, whether its body's inertia in world axes (world_inertias) is the same at every q:
// the joint is revolute with the world as its parent (its axis and origin fixed in the world),
// the body's centre of mass lies on the axis a and its inertia about it is μ 1 + (λ − μ) a aᵀ
// in the joint's frame (turning about a leaves it unchanged: a gear, a carrier with its pins at
// equal angles). data holds the placements and J at any q. Offsets below 64 ε times the
// model's largest length, and inertia entries below 64 ε times the largest, count as zero.
std::vector<bool> fixed_inertias(const pinocchio::Model& model, const pinocchio::Data& data,
                                 const std::vector<int>& slide_axes) {
  const auto nj = static_cast<long>(model.njoints);
  double length = 1.0;
  for (long i = 1; i < nj; ++i) length = std::max(length, data.oMi[i].translation().norm());
  const double eps = 64.0 * std::numeric_limits<double>::epsilon();
  std::vector<bool> out(static_cast<size_t>(nj), false);
  for (long i = 1; i < nj; ++i) {
    const auto j = static_cast<size_t>(i);
    const std::string kind = model.joints[j].shortname();
    const bool revolute = kind == "JointModelRX" || kind == "JointModelRY" ||
                          kind == "JointModelRZ" || kind == "JointModelRevoluteUnaligned";
    if (!revolute || slide_axes[j] >= 0 || model.parents[j] != 0) continue;
    // The axis in the joint's frame (a turn about it leaves it in place).
    const Vec3 a = (data.oMi[j].rotation().transpose() *
                    Vec3(data.J.col(model.idx_vs[j]).tail<3>())).normalized();
    const pinocchio::Inertia& body = model.inertias[j];
    const Vec3 c = body.lever();
    if ((c - c.dot(a) * a).norm() > eps * length) continue;
    const Eigen::Matrix3d inertia = body.inertia().matrix();
    const double along = a.dot(inertia * a), across = 0.5 * (inertia.trace() - along);
    const Eigen::Matrix3d symmetric =
        across * Eigen::Matrix3d::Identity() + (along - across) * a * a.transpose();
    out[j] = (inertia - symmetric).cwiseAbs().maxCoeff() <= eps * inertia.cwiseAbs().maxCoeff();
  }
  return out;
}

// A number for each stepper of the process, never reused (StepperState::run).
unsigned long long next_stepper_id() {
  static std::atomic<unsigned long long> next{1};
  return next++;
}

// The copy of each of items (Element::copy), checked to be whole: a kind that keeps no copy, or
// a class that inherits its base's copy (which would slice it), makes the state unsaveable.
template <class List>
List copies(const List& items) {
  List out;
  out.reserve(items.size());
  for (const auto& item : items) {
    auto copy = item->copy();
    if (!copy || typeid(*copy) != typeid(*item)) {
      throw std::logic_error(std::string("the run's state cannot be saved: its element ") +
                             typeid(*item).name() + " keeps no copy of its state (copy())");
    }
    out.push_back(std::move(copy));
  }
  return out;
}

template <class List>
bool all_copy(const List& items) {
  return std::all_of(items.begin(), items.end(), [](const auto& item) {
    const auto copy = item->copy();
    return copy && typeid(*copy) == typeid(*item);
  });
}

}  // namespace

bool Stepper::saves_state() const { return all_copy(elements_) && all_copy(constraints_); }

std::unique_ptr<StepperState> Stepper::save() const {
  auto st = std::make_unique<StepperState>();
  st->run = id_;
  st->q = q_;
  st->v = v_;
  st->accel_memory = accel_memory_;
  st->nle_last = nle_last_;
  st->gravity_last = gravity_last_;
  st->a = a_;
  st->lam = lam_;
  st->bias = bias_;
  st->mass = mass_;
  st->jac = jac_;
  st->first_step = first_step_;
  st->ledger = ledger_;
  st->elements = copies(elements_);
  st->constraints = copies(constraints_);
  st->qp = std::make_unique<ConstrainedQp>(qp_);
  return st;
}

void Stepper::restore(const StepperState& st) {
  if (st.run != id_) {
    throw std::invalid_argument(
        "the state was saved from another run (another model or session); a run takes back "
        "only the states its own save() gave");
  }
  q_ = st.q;
  v_ = st.v;
  accel_memory_ = st.accel_memory;
  nle_last_ = st.nle_last;
  gravity_last_ = st.gravity_last;
  a_ = st.a;
  lam_ = st.lam;
  bias_ = st.bias;
  mass_ = st.mass;
  jac_ = st.jac;
  first_step_ = st.first_step;
  ledger_ = st.ledger;
  for (size_t i = 0; i < elements_.size(); ++i) elements_[i]->restore(*st.elements[i]);
  for (size_t c = 0; c < constraints_.size(); ++c) constraints_[c]->restore(*st.constraints[c]);
  qp_ = *st.qp;
}

Stepper::Stepper(StepperSetup setup, const Eigen::VectorXd& q0, const Eigen::VectorXd& v0,
                 long samples)
    : s_(std::move(setup)),
      id_(next_stepper_id()),
      data_(s_.model),
      samples_(samples),
      nv_(s_.model.nv),
      nm_(s_.meshes.count()),
      elements_(build_elements()),
      constraints_(build_constraints()),
      rows_(total_rows(constraints_)),
      gear_motion_(reads_gear_motion(constraints_)),
      qp_(nv_, rows_, s_.solver),
      method_(s_.rho_infinity),
      q_(q0),
      q_next_(q0),
      v_(v0) {
  rows_data_.resize(nm_, nv_);
  origin_.resize(s_.meshes.joint_ids.size());
  rot_.resize(s_.meshes.joint_ids.size());
  fext_.of_joint.assign(s_.model.njoints, pinocchio::Force::Zero());
  slide_axes_ = slide_axes(s_.model);
  rows_data_.translation.assign(static_cast<size_t>(nv_), 0);
  for (size_t i = 1; i < slide_axes_.size(); ++i) {
    if (slide_axes_[i] >= 0) rows_data_.translation[s_.model.idx_vs[i]] = 1;
  }
  constant_mass_ = mass_is_constant(s_.model, slide_axes_);
  if (nm_) {
    // Every mesh in full at q0 (frame empty), then the fixed ones' rows kept and their geometry
    // in their frames' axes (MeshRows::frame).
    joint_jacobians(s_.model, data_, q_, slide_axes_);
    for (size_t i = 0; i < s_.meshes.joint_ids.size(); ++i) {
      origin_[i] = data_.oMi[s_.meshes.joint_ids[i]].translation();
      rot_[i] = data_.oMi[s_.meshes.joint_ids[i]].rotation();
    }
    evaluate_mesh_geometry(s_.meshes, data_.J, origin_, rot_, rows_data_);
    const std::vector<long> frames = fixed_mesh_frames(s_.model, data_, s_.meshes, slide_axes_);
    auto& r = rows_data_;
    for (auto* local : {&r.local_tangent, &r.local_radial, &r.local_pitch_point, &r.local_axis,
                        &r.local_centre_a, &r.local_centre_b}) {
      local->setZero(nm_, 3);
    }
    for (Eigen::Index m = 0; m < nm_; ++m) {
      const long f = frames[static_cast<size_t>(m)];
      if (f < 0) continue;
      const pinocchio::SE3& frame = data_.oMi[static_cast<size_t>(f)];
      const auto direction = [&](const Rows3& world, Rows3& local) {
        local.row(m) = (frame.rotation().transpose() * world.row(m).transpose()).transpose();
      };
      const auto point = [&](const Rows3& world, Rows3& local) {
        local.row(m) = frame.actInv(Vec3(world.row(m).transpose())).transpose();
      };
      direction(r.tangent, r.local_tangent);
      direction(r.radial, r.local_radial);
      direction(r.axis, r.local_axis);
      point(r.pitch_point, r.local_pitch_point);
      point(r.centre_a, r.local_centre_a);
      point(r.centre_b, r.local_centre_b);
    }
    r.frame = frames;
    fixed_mesh_angles(s_.model, data_, s_.meshes, s_.paths, q_, r);
    // The fixed meshes' bias is 0: the gears' motion is needed only for the others'.
    if (std::all_of(frames.begin(), frames.end(), [](long f) { return f >= 0; })) {
      gear_motion_ = false;
    }
  }
  vector_space_ = is_vector_space(s_.model);
  for (const auto& placement : s_.frame_placement) {
    frame_at_joint_.push_back(placement.rotation().isIdentity(0.0) &&
                              placement.translation().isZero(0.0));
  }
  for (const auto& inertia : s_.model.inertias) {
    massless_.push_back(inertia.mass() == 0.0 && inertia.inertia().data().isZero(0.0));
  }
  {
    // The bodies whose world inertia is fixed, taken at q0 (world_inertias keeps them).
    joint_jacobians(s_.model, data_, q_, slide_axes_);
    fixed_inertia_ = fixed_inertias(s_.model, data_, slide_axes_);
    const auto nj = static_cast<size_t>(s_.model.njoints);
    body_.assign(nj, pinocchio::Inertia::Zero());
    for (size_t i = 1; i < nj; ++i) {
      if (fixed_inertia_[i] && !massless_[i]) body_[i] = data_.oMi[i].act(s_.model.inertias[i]);
    }
  }
  Eigen::Index offset = 0;
  for (const auto& c : constraints_) {
    offset_.push_back(offset);
    size_.push_back(c->size());
    offset += c->size();
  }
  jac_.setZero(rows_, nv_);
  bias_.setZero(rows_);
  const StepView sv = view();
  for (size_t c = 0; c < constraints_.size(); ++c) {
    if (constraints_[c]->constant_rows()) {
      constraints_[c]->rows(sv, rows_of(jac_, c), rows_of(bias_, c));
    } else {
      varying_.push_back(c);
    }
  }
  jv_.setZero(rows_);
  mv_.setZero(nv_);
  dq_free_.setZero(nv_);
  accel_memory_.setZero(nv_);
}

Assembly Stepper::assemble(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  const Eigen::VectorXd q_run = q_, v_run = v_;
  q_ = q;
  v_ = v;
  assemble_positions();
  assemble_velocities();
  Assembly out{mass_, nle_, jac_, bias_};
  q_ = q_run;
  v_ = v_run;
  return out;
}

ElementForces Stepper::element_forces(const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  const Eigen::VectorXd q_run = q_, v_run = v_;
  q_ = q;
  v_ = v;
  assemble_positions();
  assemble_velocities();
  const Eigen::VectorXd held = Eigen::VectorXd::Zero(nv_);  // dq₀ = 0: the force at q itself
  ElementForces out{Eigen::VectorXd::Zero(nv_), Eigen::MatrixXd::Zero(nv_, nv_),
                    Eigen::MatrixXd::Zero(nv_, nv_), 0.0};
  // With κ_q = κ_v = 0 an implicit element's force b − W ā is its force at (q, v); with one gain
  // at 1, W is its derivative along q or v.
  StepWeights at_state, along_q, along_v;
  along_q.position_gain = 1.0;
  along_v.speed_gain = 1.0;
  Eigen::VectorXd unused = Eigen::VectorXd::Zero(nv_);
  for (const StepWeights* w : {&at_state, &along_q, &along_v}) {
    const StepView view{q_,  v_,      s_.dt,   data_,   s_.meshes, rows_data_, *w,
                        held, time_, nullptr, nullptr, nullptr,   &mass_};
    Eigen::MatrixXd& tangent = w == &along_v ? out.damping : out.stiffness;
    Eigen::MatrixXd scratch = Eigen::MatrixXd::Zero(nv_, nv_);
    for (auto& element : build_elements()) {
      element->prepare(view);
      if (w == &at_state) {
        element->add_force(view, out.force);
        element->add_implicit(view, scratch, out.force);
        out.potential += element->potential(view);
      } else {
        element->add_implicit(view, tangent, unused);
      }
    }
  }
  // The elements fill the lower triangle only (Element::add_implicit).
  out.stiffness.triangularView<Eigen::StrictlyUpper>() = out.stiffness.transpose();
  out.damping.triangularView<Eigen::StrictlyUpper>() = out.damping.transpose();
  q_ = q_run;
  v_ = v_run;
  assemble_positions();
  assemble_velocities();
  return out;
}

}  // namespace pinwind
