// keel::components::StateEstimator: diagnosis by state estimation, as a stock detector. The
// integrator writes a linear model in the profile's properties (its states, its inputs, its
// measurements each named with the component and port it comes from, the matrices and the
// noise); the component runs EstimatorBank (estimator_bank.hpp) on every sample and reports a
// `model` fault of the component whose measurement is inconsistent with the others (the fault
// names the measurement), or of `actuator` when the measurements agree with each other but not
// with the model. It publishes each measurement as the trusted ones estimate it, which a profile
// can route a consumer to in place of a sensor it lost. Registered as "StateEstimator" in
// libkeel_stock; the contract is in docs/stock_components.md. Thread-safety: a component; its
// callbacks are serialised.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <keel/component.hpp>

#include "estimator_bank.hpp"

namespace keel::components {

/// A matrix written in a property: rows separated by ';', values by spaces or commas
/// ("1 0; 0 1"). nullopt with `why` set when a value is not a number or the rows differ.
inline std::optional<Matrix> parseMatrix(std::string_view text, std::string& why) {
  std::vector<std::vector<double>> rows(1);
  std::string cell;
  auto flush = [&]() -> bool {
    if (cell.empty()) return true;
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (end == cell.c_str() || *end != '\0' || !std::isfinite(v)) {
      why = "'" + cell + "' is not a finite number";
      return false;
    }
    rows.back().push_back(v);
    cell.clear();
    return true;
  };
  for (char ch : text) {
    if (ch == ';') {
      if (!flush()) return std::nullopt;
      rows.emplace_back();
    } else if (ch == ' ' || ch == ',' || ch == '\t' || ch == '\n' || ch == '\r') {
      if (!flush()) return std::nullopt;
    } else {
      cell.push_back(ch);
    }
  }
  if (!flush()) return std::nullopt;
  while (!rows.empty() && rows.back().empty()) rows.pop_back();  // a trailing ';'
  if (rows.empty()) return Matrix(0, 0);
  const std::size_t cols = rows.front().size();
  for (std::size_t r = 0; r < rows.size(); ++r)
    if (rows[r].size() != cols) {
      why = "row " + std::to_string(r + 1) + " has " + std::to_string(rows[r].size()) + " values, row 1 has " +
            std::to_string(cols);
      return std::nullopt;
    }
  if (rows.size() > kMaxMeasurements || cols > kMaxMeasurements) {
    why = "is larger than 8×8";
    return std::nullopt;
  }
  Matrix m(static_cast<Eigen::Index>(rows.size()), static_cast<Eigen::Index>(cols));
  for (std::size_t r = 0; r < rows.size(); ++r)
    for (std::size_t c = 0; c < cols; ++c) m(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = rows[r][c];
  return m;
}

/// "2 rows of 3": a matrix's shape in words.
inline std::string shapeOf(const Matrix& m) {
  return std::to_string(m.rows()) + (m.rows() == 1 ? " row of " : " rows of ") + std::to_string(m.cols());
}

class StateEstimator : public Component {
 public:
  /// u0 .. u3: the model's inputs, in the order of property `inputs` (FIFO: every sample).
  std::array<InputDataPort<double>, kMaxInputs> u = makeInputs<kMaxInputs>(this, "u");
  /// y0 .. y7: the measurements, in the order of property `measurements` (FIFO).
  std::array<InputDataPort<double>, kMaxMeasurements> y = makeInputs<kMaxMeasurements>(this, "y");
  /// estimate0 .. estimate7: each measurement as the trusted measurements and the model estimate
  /// it (C x̂), one per sample; an accused sensor's is its estimate from the others.
  std::array<OutputDataPort<double>, kMaxMeasurements> estimate = makeOutputs(this);
  /// The full filter's test statistic (its normalised innovations squared summed over the
  /// window) and the threshold it is compared with, one each per sample.
  OutputDataPort<double> statistic{this, "statistic"};
  OutputDataPort<double> threshold{this, "threshold"};

  ReturnCode onInitialize() override {
    const auto states = words(property<std::string>("states", ""));
    const auto inputs = words(property<std::string>("inputs", ""));
    const auto measurements = words(property<std::string>("measurements", ""));
    if (states.empty() || states.size() > kMaxStates)
      rejectProperty("states", "must name 1 to 8 state variables (got " + std::to_string(states.size()) + ")");
    if (inputs.size() > kMaxInputs)
      rejectProperty("inputs", "must name at most 4 inputs (got " + std::to_string(inputs.size()) + ")");
    if (measurements.empty() || measurements.size() > kMaxMeasurements)
      rejectProperty("measurements", "must name 1 to 8 measurements (got " + std::to_string(measurements.size()) + ")");
    names_.clear();
    components_.clear();
    for (const auto& m : measurements) {
      // "name=component.port", or "component.port" named after its component.
      const auto eq = m.find('=');
      const std::string source = eq == std::string::npos ? m : m.substr(eq + 1);
      const auto dot = source.find('.');
      if (dot == std::string::npos || dot == 0 || dot + 1 == source.size() || eq == 0)
        rejectProperty("measurements", "'" + m + "' is not [name=]component.port");
      const std::string component = source.substr(0, dot);
      const std::string name = eq == std::string::npos ? component : m.substr(0, eq);
      if (std::find(names_.begin(), names_.end(), name) != names_.end())
        rejectProperty("measurements", "names '" + name + "' twice (name one of them: name=" + source + ")");
      if (name.size() >= FaultEvent{}.measurement.size())
        rejectProperty("measurements", "'" + name + "' is longer than a fault event can name");
      names_.push_back(name);
      components_.push_back(component);
    }
    const auto n = static_cast<Eigen::Index>(states.size());
    const auto p = static_cast<Eigen::Index>(inputs.size());
    const auto k = static_cast<Eigen::Index>(measurements.size());
    const std::string per_state = "a row per state: " + joined(states);
    const std::string per_measurement = "a row per measurement: " + joined(names_);
    LinearModel model;
    model.A = matrix("A", n, n, per_state, false);
    model.B = p == 0 ? Matrix(n, 0) : matrix("B", n, p, per_state + "; a column per input: " + joined(inputs), false);
    model.C = matrix("C", k, n, per_measurement + "; a column per state", false);
    // D: zero unless given (most measurements see the inputs only through the state).
    model.D = p == 0 || property<std::string>("D", "").empty()
                  ? Matrix(Matrix::Zero(k, p))
                  : matrix("D", k, p, per_measurement + "; a column per input", false);
    model.Q = matrix("Q", n, n, per_state, true);
    model.R = matrix("R", k, k, per_measurement, true);
    model.x0 = property<std::string>("x0", "").empty()
                   ? Vector(Vector::Zero(n))
                   : Vector(matrix("x0", 1, n, "a value per state", false).transpose());
    // Without P0: the start is as uncertain as a unit per state, plus a step's process noise.
    model.P0 = property<std::string>("P0", "").empty() ? Matrix(model.Q + Matrix::Identity(n, n))
                                                       : matrix("P0", n, n, per_state, true);
    if (!positiveDefinite(model.Q, /*semi=*/true))
      rejectProperty("Q", "is not a covariance: it must be symmetric and positive semi-definite");
    if (!positiveDefinite(model.R, /*semi=*/false))
      rejectProperty("R", "is not a covariance: it must be symmetric and positive definite");
    if (!positiveDefinite(model.P0, /*semi=*/false))
      rejectProperty("P0", "is not a covariance: it must be symmetric and positive definite");

    const auto window = property<std::int64_t>("window", 5);
    if (window < 1 || window > kMaxWindow)
      rejectProperty("window",
                     "must be between 1 and " + std::to_string(kMaxWindow) + " (got " + std::to_string(window) + ")");
    const double false_alarm = property<double>("false_alarm", 1e-6);
    if (!(false_alarm > 0 && false_alarm < 1))
      rejectProperty("false_alarm",
                     "is a probability per test and must be in (0, 1) (got " + number(false_alarm) + ")");
    const auto readmit_after = property<std::int64_t>("readmit_after", 0);
    if (readmit_after < 0) rejectProperty("readmit_after", "must be >= 0 (got " + std::to_string(readmit_after) + ")");
    actuator_ = property<std::string>("actuator", "");
    if (actuator_.empty()) rejectProperty("actuator", "must name the component accused when the model is wrong");
    bank_.configure(model, static_cast<int>(window), false_alarm, static_cast<int>(readmit_after));
    readmit_after_ = static_cast<int>(readmit_after);
    inputs_ = static_cast<int>(p);
    measurements_ = static_cast<int>(k);
    last_u_ = Vector::Zero(p);
    return ReturnCode::Ok;
  }

  /// Steps once per complete sample: every input port and every measurement port it waits for
  /// has one, the samples of one step being each port's oldest. It runs when samples arrive,
  /// possibly while its producers are still pushing theirs (a late cycle pushes several frames
  /// at once), so a port running ahead is no sign of another's loss. A measurement it no longer
  /// trusts is not waited for (its samples are dropped, unless it may be readmitted). A port
  /// kStalled samples ahead of an empty one means that one's producer stopped: the step goes on
  /// without it (a measurement unused, an input held at its last value).
  ReturnCode onExecute() override {
    while (ready()) {
      Vector uk = last_u_;
      for (int i = 0; i < inputs_; ++i)
        if (auto v = u[static_cast<std::size_t>(i)].pop(); v && std::isfinite(*v)) uk(i) = *v;
      last_u_ = uk;
      Vector yk = Vector::Zero(measurements_);
      std::uint32_t present = 0;
      for (int i = 0; i < measurements_; ++i) {
        auto& port = y[static_cast<std::size_t>(i)];
        if (!waitsFor(i)) {
          while (port.pop()) {}
          continue;
        }
        if (auto v = port.pop(); v && std::isfinite(*v)) {
          yk(i) = *v;
          present |= 1U << i;
        }
      }
      const EstimatorBank::Verdict v = bank_.step(uk, yk, present);
      for (int i = 0; i < measurements_; ++i) estimate[static_cast<std::size_t>(i)].push(bank_.estimate(i));
      statistic.push(bank_.statistic());
      threshold.push(bank_.threshold());
      if (v.finding != EstimatorBank::Finding::None) report(v);
    }
    return ReturnCode::Ok;
  }

  ReturnCode onReset() override {
    bank_.reset();
    last_u_ = Vector::Zero(inputs_);
    return ReturnCode::Ok;
  }

  /// For tests and benchmarks: the bank itself.
  const EstimatorBank& bank() const { return bank_; }

 private:
  template <std::size_t N>
  static std::array<InputDataPort<double>, N> makeInputs(Component* self, const char* prefix) {
    return makeInputsOf(self, prefix, std::make_index_sequence<N>{});
  }
  template <std::size_t... I>
  static std::array<InputDataPort<double>, sizeof...(I)> makeInputsOf(Component* self, const char* prefix,
                                                                      std::index_sequence<I...>) {
    return {{InputDataPort<double>(self, prefix + std::to_string(I))...}};
  }
  static std::array<OutputDataPort<double>, kMaxMeasurements> makeOutputs(Component* self) {
    return makeOutputsOf(self, std::make_index_sequence<kMaxMeasurements>{});
  }
  template <std::size_t... I>
  static std::array<OutputDataPort<double>, sizeof...(I)> makeOutputsOf(Component* self, std::index_sequence<I...>) {
    return {{OutputDataPort<double>(self, "estimate" + std::to_string(I))...}};
  }

  static std::vector<std::string> words(const std::string& text) {
    std::istringstream in(text);
    std::vector<std::string> out;
    for (std::string w; in >> w;) out.push_back(w);
    return out;
  }
  static std::string joined(const std::vector<std::string>& words) {
    std::string out;
    for (const auto& w : words) out += (out.empty() ? "" : " ") + w;
    return out;
  }
  static std::string number(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
  }

  // Property `name` as a rows×cols matrix; `diagonal`: one row of `rows` values is the diagonal
  // of a square one. `rows_are` says what each row stands for, in an error ("a row per state:
  // left right").
  Matrix matrix(const char* name, Eigen::Index rows, Eigen::Index cols, const std::string& rows_are,
                bool diagonal) const {
    std::string why;
    auto m = parseMatrix(property<std::string>(name, ""), why);
    if (!m) rejectProperty(name, why);
    if (diagonal && m->rows() == 1 && rows == cols && m->cols() == rows) return Matrix(m->row(0).asDiagonal());
    if (m->rows() != rows || m->cols() != cols)
      rejectProperty(name, "has " + shapeOf(*m) + ", the model needs " + std::to_string(rows) + "×" +
                               std::to_string(cols) + (rows_are.empty() ? "" : " (" + rows_are + ")") +
                               (diagonal ? ", or its diagonal as one row" : ""));
    return *m;
  }

  // Whether a step waits for measurement i: trusted, or excluded but watched for readmission.
  bool waitsFor(int i) const { return bank_.trusted(i) || readmit_after_ > 0; }

  bool ready() const {
    bool all = true;
    bool stalled = false;
    bool any = false;
    auto look = [&](const InputDataPort<double>& port, bool waited) {
      const std::size_t queued = port.size();
      if (waited) all = all && queued > 0;
      any = any || queued > 0;
      stalled = stalled || queued >= kStalled;
    };
    for (int i = 0; i < inputs_; ++i) look(u[static_cast<std::size_t>(i)], true);
    for (int i = 0; i < measurements_; ++i) look(y[static_cast<std::size_t>(i)], waitsFor(i));
    return any && (all || stalled);
  }

  void report(const EstimatorBank::Verdict& v) {
    char detail[160];
    FaultEvent ev;
    ev.kind = FaultKind::Model;
    switch (v.finding) {
      case EstimatorBank::Finding::Sensor: {
        const auto i = static_cast<std::size_t>(v.measurement);
        std::snprintf(detail, sizeof detail,
                      "measurement '%s' disagrees with the others: statistic %.4g > %.4g (%d dof); without it %.2f "
                      "of its threshold",
                      names_[i].c_str(), v.statistic, v.threshold, v.dof, v.best_left_out);
        FaultEvent::copyInto(ev.component, components_[i]);
        FaultEvent::copyInto(ev.measurement, names_[i]);
        break;
      }
      case EstimatorBank::Finding::Actuator:
        std::snprintf(detail, sizeof detail,
                      "%s: statistic %.4g > %.4g (%d dof); without any one measurement still %.2f of its threshold",
                      v.ambiguous ? "the measurements do not single one out" : "the measurements agree, not the model",
                      v.statistic, v.threshold, v.dof, v.best_left_out);
        FaultEvent::copyInto(ev.component, actuator_);
        break;
      case EstimatorBank::Finding::Readmitted:
      case EstimatorBank::Finding::None: return;  // trusted again: no fault
    }
    FaultEvent::copyInto(ev.detail, detail);
    reportFault(ev);
  }

  // Samples a port may run ahead of an empty one before that one counts as stopped: half a
  // second of 20 ms samples (the queues hold 64).
  static constexpr std::size_t kStalled = 25;

  EstimatorBank bank_;
  std::vector<std::string> names_;       // each measurement's name
  std::vector<std::string> components_;  // the component each comes from (the one accused)
  std::string actuator_;
  int inputs_ = 0;
  int measurements_ = 0;
  int readmit_after_ = 0;
  Vector last_u_;
};

}  // namespace keel::components
