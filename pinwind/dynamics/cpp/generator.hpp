// Generator laws on one joint (the output shaft): the torque the generator puts on the shaft,
// τ = −T_gen, with T_gen > 0 when generating (pinwind/loads/generator.py documents each law):
//
//   constant         T_gen = T₀
//   linear_slip      T_gen = k (ω − ω_sync)
//   variable_speed   T_gen = K ω|ω| below rated speed, P_rated/|ω| (sign of ω) above; or,
//                    with a rated torque T_r (ROSCO's VS_ConstPower = 0), constant torque
//                    above rated speed ω_r, reached along Jonkman's region 2½ line from the
//                    K ω² curve (Jonkman et al. 2009 §7.2, DISCON's VS_SlPc):
//                      T_gen = min(max(K ω², T_r (ω − ω_s)/(ω_r − ω_s)), T_r),
//                      ω_s = ω_r/(1 + slip)   (ω ≥ 0; odd in ω)
//   induction        steady-state induction machine from its equivalent circuit (per phase:
//                    R_s + jX_ls in series with jX_m ∥ (R_r'/s + jX_lr')), motor convention
//                    τ = 3 |I_r'|² R_r' / (s ω_s),  s = (ω_s − ω)/ω_s,  ω_s = 2π f / p
//   induction_dq     Krause's dq model in the synchronous frame (IFToMM 2018),
//                    flux linkages λ = (λ_qs, λ_ds, λ'_qr, λ'_dr) as states:
//                      dλ/dt = u − R L⁻¹ λ − W(ω_r) λ,  u = (√2 V_ph, 0, 0, 0)
//                      τ = (3/2) p (λ_ds i_qs − λ_qs i_ds),  i = L⁻¹ λ,  ω_r = p ω
//                    integrated exactly over each step with the rotor speed frozen at its
//                    mid-step value (InductionMachineDq below): the flux ODE is linear, so
//                    λ_{k+1} = e^{Ah} λ_k + A⁻¹(e^{Ah} − I) u. The 60 Hz stator transient then
//                    keeps its frequency and decay at any step (no phase drift at the
//                    mechanics' 1 ms), the map is stable for every h (|eig e^{Ah}| < 1), and
//                    its fixed point −A⁻¹u is the exact steady state, so the torque settles on
//                    the equivalent circuit's.
// The torque of the first four is a law of the shaft speed, taken linearly implicit at the time
// step's weighted speed (joint_torque.hpp); the dq machine's is that of its fluxes at the
// weighted time, linear in the step's acceleration through the speed at mid-step, taken
// implicitly the same way.
#pragma once

#include <algorithm>
#include <cmath>
#include <complex>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <vector>

#include <Eigen/Dense>
#include <nanobind/nanobind.h>

#include "element_kind.hpp"
#include "joint_torque.hpp"

namespace pinwind {

// The generator laws (module comment), bound to Python as _native.GeneratorLaw.
enum class GeneratorLaw { constant, linear_slip, variable_speed, induction, induction_dq };

struct GeneratorSpec {
  long index = 0;             // velocity index of the generator joint
  GeneratorLaw law = GeneratorLaw::constant;
  double torque = 0.0;        // constant: T₀ [N·m]
  double slope = 0.0;         // linear_slip: k [N·m·s/rad]
  double sync_speed = 0.0;    // linear_slip: ω_sync [rad/s]
  double gain = 0.0;          // variable_speed: K [N·m·s²/rad²]
  double rated_power = 0.0;   // variable_speed: P_rated [W] (0: no limit)
  double rated_torque = 0.0;  // variable_speed: T_r [N·m] of constant-torque region 3 (0: none)
  double rated_speed = 0.0;   // variable_speed: ω_r [rad/s], where the torque reaches T_r
  double slip = 0.1;          // variable_speed: region 2½'s slip, ω_s = ω_r/(1 + slip)
  // Induction machine, per phase, referred to the stator.
  double stator_resistance = 0.0;  // R_s [Ω]
  double rotor_resistance = 0.0;   // R_r' [Ω]
  double stator_leakage = 0.0;     // L_ls [H]
  double rotor_leakage = 0.0;      // L_lr' [H]
  double magnetizing = 0.0;        // L_M [H]
  double voltage = 0.0;            // line-to-line RMS [V] (star connection)
  double frequency = 0.0;          // grid frequency f [Hz]
  long pole_pairs = 2;             // p
  double phases = 3.0;
  bool steady_start = false;       // induction_dq: start at the steady-state fluxes of ω(0)
};

// Steady-state torque of the induction machine on the shaft at speed ω [N·m], motor
// convention (positive below synchronous speed). Computed on the full circuit with the rotor
// branch multiplied by s, so that s = 0 gives exactly 0.
inline double induction_torque(const GeneratorSpec& g, double omega) {
  using C = std::complex<double>;
  const double we = 2.0 * M_PI * g.frequency;
  const double ws = we / static_cast<double>(g.pole_pairs);
  const double s = (ws - omega) / ws;
  const C zs(g.stator_resistance, we * g.stator_leakage);
  const C zm(0.0, we * g.magnetizing);
  const C zr_s(g.rotor_resistance, s * we * g.rotor_leakage);  // s · (R_r'/s + jX_lr')
  const C denominator = s * zm + zr_s;                           // s (Z_m + Z_r)
  const C parallel = zm * zr_s / denominator;                    // Z_m ∥ Z_r
  const double v_phase = g.voltage / std::sqrt(3.0);
  const C is = v_phase / (zs + parallel);
  // |I_r|² R_r'/s = |I_s|² |Z_m|² s R_r' / |s Z_m + s Z_r|²
  const double airgap = g.phases * std::norm(is) * std::norm(zm) * s * g.rotor_resistance /
                        std::norm(denominator);
  return airgap / ws;
}

// The laws of the shaft speed alone.
class ShaftSpeedGenerator : public JointTorqueElement {
 public:
  // slot: this generator's column in the per-generator outputs.
  ShaftSpeedGenerator(const GeneratorSpec& g, long slot)
      : JointTorqueElement(g.index), g_(g), slot_(slot) {}

  // Torque on the shaft τ(ω) [N·m].
  double operator()(double omega) const {
    switch (g_.law) {
      case GeneratorLaw::constant:
        return -g_.torque;
      case GeneratorLaw::linear_slip:
        return -g_.slope * (omega - g_.sync_speed);
      case GeneratorLaw::variable_speed: {
        const double w = std::abs(omega);
        double t = g_.gain * w * w;
        if (g_.rated_torque > 0.0) {
          const double sync = g_.rated_speed / (1.0 + g_.slip);
          const double ramp = g_.rated_torque * (w - sync) / (g_.rated_speed - sync);
          t = std::min(std::max(t, ramp), g_.rated_torque);
        } else if (g_.rated_power > 0.0 && t * w > g_.rated_power) {
          t = g_.rated_power / w;
        }
        return omega >= 0.0 ? -t : t;
      }
      case GeneratorLaw::induction:
        return induction_torque(g_, omega);
      default:
        return 0.0;
    }
  }

  TorqueSlope evaluate(const StepView& s, double accel) const override {
    const double scale = std::abs(g_.sync_speed) + 2.0 * M_PI * g_.frequency + 1.0;
    const double gain = s.weights.speed_gain;
    const TorqueSlope ts = torque_and_slope(*this, s.v[index_] + gain * accel, scale);
    return {ts.torque, ts.slope * gain};
  }

  // Also T_gen = −τ over the step, the generator's own output.
  void record(const StepView& s, long k, const Outputs& out) const override {
    JointTorqueElement::record(s, k, out);
    out.at(Series::generator_torque, out.entry(Family::generator, k, slot_)) = -applied();
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override {
    return copy_of<ShaftSpeedGenerator, Element>(*this);
  }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  GeneratorSpec g_;
  long slot_;
};

// Krause's dq induction machine with its flux linkages as states.
//
// In complex form, Λ_s = λ_qs + j λ_ds and Λ_r = λ'_qr + j λ'_dr, the four real equations are
// two complex ones (Krause, Analysis of Electric Machinery, §4.5, in the synchronous frame):
//
//     d/dt (Λ_s, Λ_r) = A (Λ_s, Λ_r) + (U, 0),
//     A = −diag(R_s, R_r') L⁻¹ + j diag(ω_e, ω_e − ω_r),   L = [[L_s, L_M], [L_M, L_r']]
//
// with ω_r frozen over the step, A is a constant 2 × 2 complex matrix and the step is exact:
// with μ = tr A / 2 and δ² = ((a₁₁ − a₂₂)/2)² + a₁₂ a₂₁ (eigenvalues μ ± δ),
//
//     Φ = e^{Ah} = ½(e₊ + e₋) I + (e₊ − e₋)/(2δ) (A − μI),   e± = e^{(μ±δ)h}
//     Λ_{k+1} = Φ Λ_k + A⁻¹ (Φ − I) (U, 0)
//
// (the Cayley–Hamilton form of the exponential of a 2 × 2 matrix). Two complex exponentials
// and one square root per evaluation, no allocation.
class InductionMachineDq : public JointTorqueElement {
 public:
  using C = std::complex<double>;
  // Λ_s and Λ_r [V·s].
  struct Flux {
    C stator, rotor;
  };

  // slot: this generator's column in the per-generator outputs.
  InductionMachineDq(const GeneratorSpec& g, long slot)
      : JointTorqueElement(g.index), g_(g), slot_(slot) {
    ls_ = g.stator_leakage + g.magnetizing;
    lr_ = g.rotor_leakage + g.magnetizing;
    lm_ = g.magnetizing;
    det_ = ls_ * lr_ - lm_ * lm_;
    we_ = 2.0 * M_PI * g.frequency;
    pole_pairs_ = static_cast<double>(g.pole_pairs);
    voltage_ = std::sqrt(2.0) * g.voltage / std::sqrt(3.0);
    // The entries of A that do not depend on the rotor speed.
    a11_ = C(-g.stator_resistance * lr_ / det_, we_);
    a12_ = g.stator_resistance * lm_ / det_;
    a21_ = g.rotor_resistance * lm_ / det_;
    a22_real_ = -g.rotor_resistance * ls_ / det_;
  }

  // Electromagnetic torque of the fluxes [N·m], motor convention:
  // τ = (3/2) p (λ_ds i_qs − λ_qs i_ds) = −(3/2) p Im(conj(Λ_s) I_s).
  double torque(const Flux& f) const {
    const C is = (lr_ * f.stator - lm_ * f.rotor) / det_;
    return -1.5 * pole_pairs_ * std::imag(std::conj(f.stator) * is);
  }

  void prepare(const StepView& s) override {
    if (first_ && g_.steady_start) flux_ = steady(s.v[index_]);
    first_ = false;
    JointTorqueElement::prepare(s);
  }

  // The torque over the step is the fluxes' at the time step's weighted time,
  // (1 − αf) τ(λ_{n+1}) + αf τ(λ_n) (time_step.hpp; the mid-step mean for ρ∞ = 1), with
  // λ_{n+1} from a step at ω_mid = ω_n + (h/2) ā: linear in ā through dτ/dω_mid, taken
  // implicitly like the laws of the shaft speed. Explicit in the fluxes, a machine whose slip
  // stiffness is large next to its shaft's inertia (many poles, a light shaft) would be
  // unstable at the mechanical step.
  TorqueSlope evaluate(const StepView& s, double accel) const override {
    const double w = s.v[index_] + 0.5 * s.dt * accel;
    const double d = 1e-6 * (std::abs(w) + we_ / pole_pairs_);
    const double t0 = torque(step(w, s.dt));
    const double t1 = torque(step(w + d, s.dt));
    const double end = s.weights.force_new;
    return {end * t0 + (1.0 - end) * torque(flux_), end * 0.5 * s.dt * (t1 - t0) / d};
  }

  bool damps_unresolved() const override { return false; }

  // Also T_gen = −τ over the step (the electromagnetic torque at the weighted time).
  void record(const StepView& s, long k, const Outputs& out) const override {
    JointTorqueElement::record(s, k, out);
    out.at(Series::generator_torque, out.entry(Family::generator, k, slot_)) = -applied();
  }

  void advance(const StepView& s, const Eigen::VectorXd& v_next) override {
    JointTorqueElement::advance(s, v_next);
    flux_ = step(0.5 * (s.v[index_] + v_next[index_]), s.dt);
  }

  // The fluxes after a step h [s] from the current ones at shaft speed ω [rad/s] (exact for
  // ω held over the step; class comment).
  Flux step(double omega, double h) const {
    const C a22(a22_real_, we_ - pole_pairs_ * omega);
    const C mu = 0.5 * (a11_ + a22), half = 0.5 * (a11_ - a22);
    const C delta = principal_sqrt(half * half + a12_ * a21_);
    const C ep = std::exp((mu + delta) * h), em = std::exp((mu - delta) * h);
    const C c0 = 0.5 * (ep + em);
    // (e₊ − e₋)/(2δ) = e^{μh} sinh(δh)/δ, by its series where δh is small.
    const C dh = delta * h;
    const C c1 = std::abs(dh) > 1e-4 ? (ep - em) * reciprocal(2.0 * delta)
                                     : std::exp(mu * h) * h * (1.0 + dh * dh / 6.0);
    const C p11 = c0 + c1 * half, p22 = c0 - c1 * half, p12 = c1 * a12_, p21 = c1 * a21_;
    // A⁻¹ (Φ − I) (U, 0), A⁻¹ = [[a₂₂, −a₁₂], [−a₂₁, a₁₁]] / det A.
    const C inv_det = reciprocal(a11_ * a22 - a12_ * a21_);
    const C g1 = (p11 - 1.0) * voltage_, g2 = p21 * voltage_;
    const C forced_s = (a22 * g1 - a12_ * g2) * inv_det;
    const C forced_r = (a11_ * g2 - a21_ * g1) * inv_det;
    return {p11 * flux_.stator + p12 * flux_.rotor + forced_s,
            p21 * flux_.stator + p22 * flux_.rotor + forced_r};
  }

  // The steady-state fluxes at shaft speed ω: −A⁻¹ (U, 0).
  Flux steady(double omega) const {
    const C a22(a22_real_, we_ - pole_pairs_ * omega);
    const C inv_det = reciprocal(a11_ * a22 - a12_ * a21_);
    return {-a22 * voltage_ * inv_det, a21_ * voltage_ * inv_det};
  }

  // 1/z and the principal √z of finite, moderate numbers, without the library's handling of
  // infinities and overflow (__divdc3, csqrt and hypot took most of a step's dq time).
  static C reciprocal(const C& z) {
    const double n = z.real() * z.real() + z.imag() * z.imag();
    return {z.real() / n, -z.imag() / n};
  }
  static C principal_sqrt(const C& z) {
    const double r = std::sqrt(z.real() * z.real() + z.imag() * z.imag());
    const double re = std::sqrt(0.5 * (r + z.real()));
    const double im = std::sqrt(0.5 * std::max(r - z.real(), 0.0));
    return {re, std::signbit(z.imag()) ? -im : im};
  }

  // A copy for a saved state of the run, and its states taken back (Element::copy).
  std::unique_ptr<Element> copy() const override {
    return copy_of<InductionMachineDq, Element>(*this);
  }
  void restore(const Element& saved) override { restore_from(*this, saved); }

 private:
  GeneratorSpec g_;
  long slot_;
  double ls_ = 0.0, lr_ = 0.0, lm_ = 0.0, det_ = 0.0, we_ = 0.0, pole_pairs_ = 2.0;
  double voltage_ = 0.0, a12_ = 0.0, a21_ = 0.0, a22_real_ = 0.0;
  C a11_;
  Flux flux_{};
  bool first_ = true;
};

// The element of each generator law, indexed by GeneratorLaw.
using GeneratorFactory = std::unique_ptr<Element> (*)(const GeneratorSpec&, long slot);

template <class Law>
std::unique_ptr<Element> make_generator(const GeneratorSpec& g, long slot) {
  return std::make_unique<Law>(g, slot);
}

inline constexpr GeneratorFactory kGeneratorElements[] = {
    make_generator<ShaftSpeedGenerator>,  // constant
    make_generator<ShaftSpeedGenerator>,  // linear_slip
    make_generator<ShaftSpeedGenerator>,  // variable_speed
    make_generator<ShaftSpeedGenerator>,  // induction
    make_generator<InductionMachineDq>,   // induction_dq
};
static_assert(std::size(kGeneratorElements) ==
              static_cast<size_t>(GeneratorLaw::induction_dq) + 1);

// The kind (element_kind.hpp): StepperSpec.generators, an element each (its law's), its column
// of the generator series its place in the list.
struct GeneratorsKind : KindBase {
  using Specs = std::vector<GeneratorSpec>;
  using Built = Elements;
  static constexpr const char* field = "generators";

  static void check(const Specs& specs, const KindContext& c) {
    for (const auto& g : specs) {
      if (g.index < 0 || g.index >= c.nv) throw std::invalid_argument("bad generator joint index");
      const bool induction =
          g.law == GeneratorLaw::induction || g.law == GeneratorLaw::induction_dq;
      if (induction && (g.pole_pairs < 1 || !(g.frequency > 0.0))) {
        throw std::invalid_argument("induction machine: pole_pairs ≥ 1 and frequency > 0");
      }
      if (g.law == GeneratorLaw::variable_speed && g.rated_torque > 0.0 &&
          !(g.rated_speed > 0.0 && g.slip > 0.0)) {
        throw std::invalid_argument("variable speed at rated torque: rated_speed, slip > 0");
      }
    }
  }

  static void add(const Specs& specs, const KindContext&, Elements& out) {
    for (size_t i = 0; i < specs.size(); ++i) {
      const GeneratorSpec& g = specs[i];
      out.push_back(kGeneratorElements[static_cast<size_t>(g.law)](g, static_cast<long>(i)));
    }
  }

  static void count(const Specs& specs, FamilyCounts& counts) {
    counts[static_cast<size_t>(Family::generator)] = static_cast<long>(specs.size());
  }

  static void bind(nanobind::module_& m) {
    namespace nb = nanobind;
    using namespace nb::literals;
    nb::enum_<GeneratorLaw>(m, "GeneratorLaw")
        .value("constant", GeneratorLaw::constant)
        .value("linear_slip", GeneratorLaw::linear_slip)
        .value("variable_speed", GeneratorLaw::variable_speed)
        .value("induction", GeneratorLaw::induction)
        .value("induction_dq", GeneratorLaw::induction_dq);

    nb::class_<GeneratorSpec>(m, "GeneratorSpec")
        .def(nb::init<>())
        .def_rw("index", &GeneratorSpec::index)
        .def_rw("law", &GeneratorSpec::law)
        .def_rw("torque", &GeneratorSpec::torque)
        .def_rw("slope", &GeneratorSpec::slope)
        .def_rw("sync_speed", &GeneratorSpec::sync_speed)
        .def_rw("gain", &GeneratorSpec::gain)
        .def_rw("rated_power", &GeneratorSpec::rated_power)
        .def_rw("rated_torque", &GeneratorSpec::rated_torque)
        .def_rw("rated_speed", &GeneratorSpec::rated_speed)
        .def_rw("slip", &GeneratorSpec::slip)
        .def_rw("stator_resistance", &GeneratorSpec::stator_resistance)
        .def_rw("rotor_resistance", &GeneratorSpec::rotor_resistance)
        .def_rw("stator_leakage", &GeneratorSpec::stator_leakage)
        .def_rw("rotor_leakage", &GeneratorSpec::rotor_leakage)
        .def_rw("magnetizing", &GeneratorSpec::magnetizing)
        .def_rw("voltage", &GeneratorSpec::voltage)
        .def_rw("frequency", &GeneratorSpec::frequency)
        .def_rw("pole_pairs", &GeneratorSpec::pole_pairs)
        .def_rw("phases", &GeneratorSpec::phases)
        .def_rw("steady_start", &GeneratorSpec::steady_start);

    m.def(
        "shaft_speed_torque",
        [](const GeneratorSpec& g, double speed) {
          if (g.law == GeneratorLaw::induction_dq) {
            throw std::invalid_argument("the dq machine's torque is not a law of the speed");
          }
          return ShaftSpeedGenerator(g, 0)(speed);
        },
        "generator"_a, "speed"_a,
        "Torque on the shaft τ(ω) [N·m] of a law of the shaft speed (−T_gen).");
    m.def("induction_torque", &induction_torque, "generator"_a, "speed"_a,
          "Steady-state induction machine torque on the shaft at speed [rad/s] (motor "
          "convention).");
  }
};

}  // namespace pinwind
