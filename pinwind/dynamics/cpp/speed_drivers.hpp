// Speed drivers and locked bearings as constraint rows (constraints.hpp): the kind of
// StepperSpec.driver_index.
#pragma once

#include <memory>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nanobind/nanobind.h>

#include "constraints.hpp"
#include "element_kind.hpp"
#include "elements.hpp"
#include "series.hpp"

namespace pinwind {

// Speed drivers and locked bearings: row e_i on velocity i, J v = w(t), w the driver's speed
// [rad/s] (0 for a lock), bias 0. λ is the torque the driver puts on its joint [N·m]; it joins
// the joint's recorded torque, and its work joins work_drivers.
class SpeedDrivers final : public Constraint {
 public:
  // index: velocity index of each driver and lock, in row order.
  SpeedDrivers(std::vector<long> index, Eigen::Index nv) : index_(std::move(index)) {
    torque_.setZero(nv);
  }

  Eigen::Index size() const override { return static_cast<Eigen::Index>(index_.size()); }

  void rows(const StepView&, RowsBlock jac, ValuesBlock bias) const override {
    jac.setZero();
    for (Eigen::Index i = 0; i < size(); ++i) jac(i, index_[i]) = 1.0;
    bias.setZero();
  }

  void biases(const StepView&, ValuesBlock bias) const override { bias.setZero(); }

  bool constant_rows() const override { return true; }

  void targets(const StepView& s, ValuesBlock now, ValuesBlock next) const override {
    if (!size()) return;
    now = Eigen::Map<const Eigen::VectorXd>(s.target_now, size());
    next = Eigen::Map<const Eigen::VectorXd>(s.target_next, size());
  }

  void record(const StepView&, long k, ConstValues lambda, const Outputs& out) const override {
    for (Eigen::Index i = 0; i < size(); ++i) {
      out.at(Series::torque, out.entry(Family::joint, k, index_[i])) += lambda[i];
    }
  }

  void work(const StepView&, ConstRows, ConstValues lambda, const Eigen::VectorXd& dq,
            EnergyLedger& ledger) const override {
    torque_.setZero();
    for (Eigen::Index i = 0; i < size(); ++i) torque_[index_[i]] += lambda[i];
    ledger.drivers += torque_.dot(dq);
  }

  // A copy for a saved state of the run, and its states taken back (Constraint::copy).
  std::unique_ptr<Constraint> copy() const override {
    return copy_of<SpeedDrivers, Constraint>(*this);
  }
  void restore(const Constraint& saved) override { restore_from(*this, saved); }

 private:
  std::vector<long> index_;
  mutable Eigen::VectorXd torque_;  // Σ λ_i e_i [N·m]
};

// The kind (element_kind.hpp): StepperSpec.driver_index, the velocity index of each driver and
// lock in row order (the speeds come per sample: Stepper::run's target). Nothing to bind of its
// own.
struct SpeedDriversKind : KindBase {
  using Specs = std::vector<long>;
  using Built = Constraints;
  static constexpr const char* field = "driver_index";

  static void check(const Specs&, const KindContext&) {}

  static void add(const Specs& index, const KindContext& c, Constraints& out) {
    if (!index.empty()) out.push_back(std::make_unique<SpeedDrivers>(index, c.nv));
  }

  static void bind(nanobind::module_&) {}
};

}  // namespace pinwind
