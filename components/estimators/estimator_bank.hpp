// keel::components::EstimatorBank: fault detection and isolation by state estimation. A Kalman
// filter over a linear model (x' = A x + B u + w, y = C x + D u + v, w ~ N(0, Q), v ~ N(0, R)) runs
// on every trusted measurement; beside it, a bank of filters each leaving one trusted measurement
// out. Each filter sums its normalised innovations squared (NIS) over a sliding window of
// samples: with the model right and the noise as stated, the sum is chi-square distributed with
// as many degrees of freedom as measurements were used, so a sum above the chi-square quantile
// 1 - false_alarm is an alarm at that false-alarm probability per test. On an alarm of the full
// filter:
//   - exactly one filter of the bank consistent (its sum under its threshold), the same one for
//     a window of samples: the measurement it leaves out is the faulty one (a sensor); it is
//     trusted no more, and the filter without it becomes the full filter;
//   - none consistent: every subset of measurements disagrees with the model's prediction from
//     the inputs, the measurements agree among themselves: the plant (the actuator) is faulty;
//   - more than one: undecided for up to two windows; then the actuator, said to be ambiguous.
// Pure: no I/O, no clock, no allocation after configure(). Used by StateEstimator
// (state_estimator.hpp); tests drive it with synthetic data. Thread-safety: none; one owner.
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>

namespace keel::components {

inline constexpr int kMaxStates = 8;        // n
inline constexpr int kMaxInputs = 4;        // p
inline constexpr int kMaxMeasurements = 8;  // m
inline constexpr int kMaxWindow = 64;

using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxMeasurements, kMaxMeasurements>;
using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxMeasurements, 1>;
static_assert(kMaxStates <= kMaxMeasurements && kMaxInputs <= kMaxMeasurements);

/// The model the integrator writes: n states, p inputs, m measurements.
struct LinearModel {
  Matrix A;   // n×n: the state's step
  Matrix B;   // n×p: the inputs' effect on it (p may be 0)
  Matrix C;   // m×n: what each measurement sees of the state
  Matrix D;   // m×p: what it sees of the inputs directly (p may be 0)
  Matrix Q;   // n×n: process noise covariance, symmetric positive semi-definite
  Matrix R;   // m×m: measurement noise covariance, symmetric positive definite
  Vector x0;  // n: the state at the start
  Matrix P0;  // n×n: its covariance, symmetric positive definite
  int states() const { return static_cast<int>(A.rows()); }
  int inputs() const { return static_cast<int>(B.cols()); }
  int measurements() const { return static_cast<int>(C.rows()); }
};

/// Why a model cannot be used ("" when it can): sizes, symmetry, definiteness.
inline std::string checkModel(const LinearModel& m) {
  const auto n = m.A.rows();
  if (n < 1 || n > kMaxStates || m.A.cols() != n) return "A must be square, 1 to 8 states";
  if (m.B.rows() != n && m.B.size() != 0) return "B must have a row per state";
  if (m.C.cols() != n || m.C.rows() < 1 || m.C.rows() > kMaxMeasurements) return "C must have a column per state";
  const auto k = m.C.rows();
  if (m.D.rows() != k || m.D.cols() != m.B.cols()) return "D must be m×p";
  if (m.Q.rows() != n || m.Q.cols() != n) return "Q must be n×n";
  if (m.R.rows() != k || m.R.cols() != k) return "R must be m×m";
  if (m.x0.size() != n) return "x0 must have a value per state";
  if (m.P0.rows() != n || m.P0.cols() != n) return "P0 must be n×n";
  if (!m.A.allFinite() || !m.B.allFinite() || !m.C.allFinite() || !m.D.allFinite() || !m.Q.allFinite() ||
      !m.R.allFinite() || !m.x0.allFinite() || !m.P0.allFinite())
    return "every value must be a finite number";
  return {};
}

/// Whether `s` is symmetric (to rounding) and positive definite (semi-definite when `semi`).
inline bool positiveDefinite(const Matrix& s, bool semi) {
  if (s.rows() != s.cols() || !s.isApprox(s.transpose(), 1e-9)) return false;
  if (s.size() == 0) return true;
  const Eigen::SelfAdjointEigenSolver<Matrix> eig(s, Eigen::EigenvaluesOnly);
  const double smallest = eig.eigenvalues().minCoeff();
  return semi ? smallest >= -1e-12 * std::max(1.0, eig.eigenvalues().maxCoeff()) : smallest > 0;
}

class EstimatorBank {
 public:
  /// What a step found.
  enum class Finding : std::uint8_t {
    None,
    Sensor,      // `measurement` is inconsistent with the others: it is trusted no more
    Actuator,    // the measurements agree with each other, not with the model
    Readmitted,  // `measurement`, excluded, was consistent for `readmit_after` samples: trusted again
  };
  struct Verdict {
    Finding finding = Finding::None;
    int measurement = -1;      // Sensor, Readmitted
    bool ambiguous = false;    // Actuator: more than one subset was consistent
    double statistic = 0;      // the full filter's windowed NIS sum at the finding
    double threshold = 0;      // its threshold
    int dof = 0;               // its degrees of freedom
    double best_left_out = 0;  // the smallest statistic / threshold of the bank (Sensor: the consistent one's)
  };

  /// Takes a checked model (checkModel, the covariances' definiteness). `window` samples per
  /// test (1..kMaxWindow), false-alarm probability per test in (0, 1), `readmit_after` consistent
  /// samples before an excluded measurement is trusted again (0: never). Allocates.
  void configure(const LinearModel& model, int window, double false_alarm, int readmit_after) {
    model_ = model;
    window_ = window;
    readmit_after_ = readmit_after;
    const int most = window * model.measurements();
    thresholds_.assign(static_cast<std::size_t>(most) + 1, 0.0);
    for (int dof = 1; dof <= most; ++dof)
      thresholds_[static_cast<std::size_t>(dof)] = boost::math::quantile(
          boost::math::complement(boost::math::chi_squared(dof), false_alarm));
    reset();
  }

  /// Back to the model's start: every measurement trusted, no episode open.
  void reset() {
    last_u_ = Vector::Zero(model_.inputs());
    trusted_ = allOf(model_.measurements());
    full_ = fresh(trusted_);
    rebuildBank();
    for (auto& r : readmit_) r = Window{};
    readmit_run_.fill(0);
    in_episode_ = false;
    clear_run_ = 0;
    alarm_run_ = 0;
    candidate_ = -1;
    candidate_run_ = 0;
  }

  /// One sample: the inputs `u` (p values) and the measurements `y` (m values; bit i of `present`
  /// set when y[i] arrived this step). Every filter predicts and updates; then the verdict.
  Verdict step(const Vector& u, const Vector& y, std::uint32_t present) {
    const Vector b_u = model_.inputs() > 0 ? Vector(model_.B * u) : Vector(Vector::Zero(model_.states()));
    // The measurements less what they see of the inputs directly: C x is left to explain.
    const Vector z = model_.inputs() > 0 ? Vector(y - model_.D * u) : y;
    // An excluded measurement, against the full filter's prediction (before this update).
    Vector x_prior = model_.A * full_.x + b_u;
    Matrix p_prior = model_.A * full_.P * model_.A.transpose() + model_.Q;
    advance(full_, b_u, z, present);
    for (int b = 0; b < bank_size_; ++b) advance(bank_[static_cast<std::size_t>(b)], b_u, z, present);
    last_u_ = u;
    Verdict v = judge();
    if (v.finding == Finding::None) v = readmit(x_prior, p_prior, z, present);
    return v;
  }

  /// The full filter's state estimate and the measurements it predicts from it.
  const Vector& state() const { return full_.x; }
  double estimate(int measurement) const {
    const double direct = model_.inputs() > 0 ? model_.D.row(measurement).dot(last_u_) : 0.0;
    return model_.C.row(measurement).dot(full_.x) + direct;
  }
  double statistic() const { return full_.window.sum; }
  double threshold() const { return thresholdOf(full_.window.dof); }
  bool trusted(int measurement) const { return (trusted_ >> measurement) & 1U; }
  bool inEpisode() const { return in_episode_; }
  double thresholdOf(int dof) const {
    return dof <= 0
               ? 0.0
               : thresholds_[static_cast<std::size_t>(std::min<int>(dof, static_cast<int>(thresholds_.size()) - 1))];
  }

 private:
  /// A sliding window of NIS values and their degrees of freedom.
  struct Window {
    std::array<double, kMaxWindow> nis{};
    std::array<int, kMaxWindow> dofs{};
    int head = 0;
    int filled = 0;
    double sum = 0;
    int dof = 0;
    void push(double value, int d, int window) {
      if (filled == window) {
        sum -= nis[static_cast<std::size_t>(head)];
        dof -= dofs[static_cast<std::size_t>(head)];
      } else {
        ++filled;
      }
      nis[static_cast<std::size_t>(head)] = value;
      dofs[static_cast<std::size_t>(head)] = d;
      sum += value;
      dof += d;
      head = (head + 1) % window;
      if (head == 0) {  // re-summed once a lap: no rounding drift over a long run
        sum = 0;
        for (int i = 0; i < filled; ++i) sum += nis[static_cast<std::size_t>(i)];
      }
    }
  };
  struct Filter {
    Vector x;
    Matrix P;
    std::uint32_t uses = 0;  // the measurements it updates on
    Window window;
    int left_out = -1;  // a bank filter's: the measurement it leaves out
  };

  static std::uint32_t allOf(int m) { return m >= 32 ? ~0U : (1U << m) - 1U; }

  Filter fresh(std::uint32_t uses) const {
    Filter f;
    f.x = model_.x0;
    f.P = model_.P0;
    f.uses = uses;
    return f;
  }

  void rebuildBank() {
    bank_size_ = 0;
    if (__builtin_popcount(trusted_) < 2) return;  // one measurement: nothing to compare it with
    for (int i = 0; i < model_.measurements(); ++i) {
      if (!trusted(i)) continue;
      Filter f = full_;
      f.uses = trusted_ & ~(1U << i);
      f.window = Window{};
      f.left_out = i;
      bank_[static_cast<std::size_t>(bank_size_++)] = f;
    }
  }

  // Predict, then update on the measurements `f` uses that arrived; its NIS into its window.
  void advance(Filter& f, const Vector& b_u, const Vector& y, std::uint32_t present) const {
    f.x = model_.A * f.x + b_u;
    f.P = model_.A * f.P * model_.A.transpose() + model_.Q;
    const std::uint32_t used = f.uses & present;
    const int k = __builtin_popcount(used);
    if (k == 0) return;
    std::array<int, kMaxMeasurements> rows{};
    int j = 0;
    for (int i = 0; i < model_.measurements(); ++i)
      if ((used >> i) & 1U) rows[static_cast<std::size_t>(j++)] = i;
    Matrix c(k, model_.states());
    Matrix r(k, k);
    Vector z(k);
    for (int a = 0; a < k; ++a) {
      const int ia = rows[static_cast<std::size_t>(a)];
      c.row(a) = model_.C.row(ia);
      z(a) = y(ia);
      for (int b = 0; b < k; ++b) r(a, b) = model_.R(ia, rows[static_cast<std::size_t>(b)]);
    }
    const Vector nu = z - c * f.x;
    const Matrix s = c * f.P * c.transpose() + r;
    const Eigen::LLT<Matrix> llt(s);
    const Matrix gain = llt.solve(c * f.P).transpose();  // P Cᵀ S⁻¹ (P, S symmetric)
    const Matrix i_kc = Matrix::Identity(model_.states(), model_.states()) - gain * c;
    f.x += gain * nu;
    f.P = i_kc * f.P * i_kc.transpose() + gain * r * gain.transpose();  // Joseph form: stays symmetric PSD
    f.window.push(nu.dot(llt.solve(nu)), k, window_);
  }

  bool alarmed(const Filter& f) const { return f.window.dof > 0 && f.window.sum > thresholdOf(f.window.dof); }

  Verdict judge() {
    Verdict v;
    v.statistic = full_.window.sum;
    v.threshold = thresholdOf(full_.window.dof);
    v.dof = full_.window.dof;
    const bool alarm = alarmed(full_);
    if (in_episode_) {  // an actuator fault reported: closed after a window without alarm
      clear_run_ = alarm ? 0 : clear_run_ + 1;
      if (clear_run_ >= window_) in_episode_ = false;
      return v;
    }
    if (!alarm) {
      alarm_run_ = 0;
      candidate_ = -1;
      candidate_run_ = 0;
      return v;
    }
    ++alarm_run_;
    int consistent = -1;
    int count = 0;
    double best = -1;
    for (int b = 0; b < bank_size_; ++b) {
      const Filter& f = bank_[static_cast<std::size_t>(b)];
      const double ratio = f.window.dof > 0 ? f.window.sum / thresholdOf(f.window.dof) : 0.0;
      if (best < 0 || ratio < best) best = ratio;
      if (!alarmed(f)) {
        ++count;
        consistent = b;
      }
    }
    v.best_left_out = best;
    if (count == 1) {
      // A sensor, once the same one stands out for a window: a fault of the plant can single
      // out its most precise sensor for a few samples before every subset disagrees.
      candidate_run_ = candidate_ == consistent ? candidate_run_ + 1 : 1;
      candidate_ = consistent;
      if (candidate_run_ < window_) return v;
      Filter& f = bank_[static_cast<std::size_t>(consistent)];
      v.finding = Finding::Sensor;
      v.measurement = f.left_out;
      readmit_[static_cast<std::size_t>(f.left_out)] = Window{};
      readmit_run_[static_cast<std::size_t>(f.left_out)] = 0;
      trusted_ = f.uses;
      full_ = f;
      full_.left_out = -1;
      rebuildBank();
      alarm_run_ = 0;
      candidate_ = -1;
      candidate_run_ = 0;
      return v;
    }
    candidate_ = -1;
    candidate_run_ = 0;
    // More than one subset consistent: more samples may tell them apart, for two windows.
    if (count > 1 && alarm_run_ < 2 * window_) return v;
    v.finding = Finding::Actuator;
    v.ambiguous = count > 1;
    in_episode_ = true;
    clear_run_ = 0;
    alarm_run_ = 0;
    return v;
  }

  Verdict readmit(const Vector& x_prior, const Matrix& p_prior, const Vector& y, std::uint32_t present) {
    Verdict v;
    if (readmit_after_ <= 0) return v;
    for (int i = 0; i < model_.measurements(); ++i) {
      auto& run = readmit_run_[static_cast<std::size_t>(i)];
      if (trusted(i)) {
        run = 0;
        continue;
      }
      if (!((present >> i) & 1U)) continue;
      const double nu = y(i) - model_.C.row(i).dot(x_prior);
      const double s = model_.C.row(i) * p_prior * model_.C.row(i).transpose() + model_.R(i, i);
      Window& w = readmit_[static_cast<std::size_t>(i)];
      w.push(nu * nu / s, 1, window_);
      run = w.sum > thresholdOf(w.dof) ? 0 : run + 1;
      if (run < readmit_after_) continue;
      run = 0;
      w = Window{};
      trusted_ |= 1U << i;
      full_.uses = trusted_;
      full_.window = Window{};
      rebuildBank();
      v.finding = Finding::Readmitted;
      v.measurement = i;
      return v;
    }
    return v;
  }

  LinearModel model_;
  Vector last_u_;  // the inputs of the last step (the estimates' D u)
  int window_ = 1;
  int readmit_after_ = 0;
  std::vector<double> thresholds_;  // by degrees of freedom
  std::uint32_t trusted_ = 0;
  Filter full_;
  std::array<Filter, kMaxMeasurements> bank_{};
  int bank_size_ = 0;
  std::array<Window, kMaxMeasurements> readmit_{};
  std::array<int, kMaxMeasurements> readmit_run_{};
  bool in_episode_ = false;
  int clear_run_ = 0;      // samples without alarm in an episode
  int alarm_run_ = 0;      // samples alarmed in a row, undecided
  int candidate_ = -1;     // the bank filter alone consistent, of late
  int candidate_run_ = 0;  // samples it has been so in a row
};

}  // namespace keel::components
