// keel::components::MedianVoterN<N>: the paper's voting component (§5.1.4), median of N
// redundant inputs (N odd: 3, 5, ...). Each execution takes the latest value of every input,
// outputs their median, masks inputs that stray from it by more than the tolerance and reports
// each such outlier once as a `vote` fault about the component that produced it (`sources`).
// Registered as "MedianVoter" (N = 3) and "MedianVoter5" (N = 5) in libkeel_stock; the contract
// is in docs/stock_components.md. Thread-safety: a component; its callbacks are serialised.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>

#include <keel/component.hpp>

namespace keel::components {

template <std::size_t N>
class MedianVoterN : public Component {
  static_assert(N >= 3 && N % 2 == 1, "a median voter needs an odd number (>= 3) of inputs");

 public:
  static constexpr std::size_t kInputs = N;
  static constexpr std::size_t kMajority = N / 2 + 1;

  /// in0 .. in{N-1}: the redundant versions (queue policy LAST: only the latest counts).
  std::array<InputDataPort<double>, N> in = makeInputs(this, std::make_index_sequence<N>{});
  /// The median of the inputs present, when a majority of them agree.
  OutputDataPort<double> output{this, "output"};
  /// How many inputs are within tolerance of the median (pushed with every vote).
  OutputDataPort<int> agreeing{this, "agreeing"};

  /// Reads and checks the properties. A bad value throws keel::PropertyError naming it.
  ReturnCode onInitialize() override {
    tolerance_ = property<double>("tolerance", 10.0);
    tolerance_ratio_ = property<double>("tolerance_ratio", 0.0);
    const auto stale_after = property<std::int64_t>("stale_after", 0);
    const auto sources = property<std::string>("sources", "");
    if (!std::isfinite(tolerance_) || tolerance_ < 0)
      rejectProperty("tolerance", "must be >= 0 (got " + std::to_string(tolerance_) + ")");
    if (!std::isfinite(tolerance_ratio_) || tolerance_ratio_ < 0)
      rejectProperty("tolerance_ratio", "must be >= 0 (got " + std::to_string(tolerance_ratio_) + ")");
    if (stale_after < 0) rejectProperty("stale_after", "must be >= 0 (got " + std::to_string(stale_after) + ")");
    stale_after_ = static_cast<std::uint64_t>(stale_after);
    parseSources(sources);
    forget();
    return ReturnCode::Ok;
  }

  /// Takes the latest value of each input, then votes.
  ReturnCode onExecute() override {
    for (std::size_t i = 0; i < N; ++i) {
      Slot& s = slots_[i];
      bool fresh = false;
      while (std::optional<double> v = in[i].pop()) {  // any policy: keep the newest
        s.value = *v;
        fresh = true;
      }
      if (fresh) {
        s.seen = true;
        s.age = 0;
      } else if (s.seen) {
        ++s.age;
      }
    }
    vote();
    return ReturnCode::Ok;
  }

  /// A reset forgets every input and every open fault episode.
  ReturnCode onReset() override {
    forget();
    return ReturnCode::Ok;
  }

 private:
  struct Slot {
    double value = 0.0;
    bool seen = false;      // delivered at least once
    std::uint64_t age = 0;  // executions since the last delivery
    bool reported = false;  // an outlier fault is open for this input
  };

  template <std::size_t... I>
  static std::array<InputDataPort<double>, N> makeInputs(Component* self, std::index_sequence<I...>) {
    return {{InputDataPort<double>(self, "in" + std::to_string(I))...}};
  }

  bool present(const Slot& s) const { return s.seen && (stale_after_ == 0 || s.age < stale_after_); }

  void vote() {
    std::array<double, N> values{};
    std::size_t m = 0;
    for (std::size_t i = 0; i < N; ++i) {
      const Slot& s = slots_[i];
      if (!present(s)) continue;
      if (std::isfinite(s.value)) values[m++] = s.value;
      else flagOutlier(i, 0.0, 0.0);  // NaN/inf never votes
    }
    if (m < kMajority) return;  // too few inputs to outvote one bad one: no output
    std::sort(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(m));
    const double median = m % 2 ? values[m / 2] : (values[m / 2 - 1] + values[m / 2]) / 2;
    const double tol = tolerance_ratio_ > 0 ? tolerance_ratio_ * std::fabs(median) : tolerance_;
    std::size_t agree = 0;
    for (std::size_t k = 0; k < m; ++k) agree += std::fabs(values[k] - median) <= tol;
    agreeing.push(static_cast<int>(agree));
    if (agree < kMajority) {  // no majority agrees: nothing can be masked or blamed
      if (!no_majority_reported_) reportNoMajority(agree, median, tol);
      no_majority_reported_ = true;
      return;
    }
    no_majority_reported_ = false;
    output.push(median);
    for (std::size_t i = 0; i < N; ++i) {
      Slot& s = slots_[i];
      if (!present(s) || !std::isfinite(s.value)) continue;
      if (std::fabs(s.value - median) > tol) flagOutlier(i, median, tol);
      else s.reported = false;  // agrees again: re-armed
    }
  }

  void flagOutlier(std::size_t i, double median, double tol) {
    Slot& s = slots_[i];
    if (s.reported) return;
    s.reported = true;
    char detail[192];  // formatted on the stack: no allocation on the fault path
    if (!std::isfinite(s.value)) std::snprintf(detail, sizeof detail, "in%zu = %g is not a finite number", i, s.value);
    else if (tolerance_ratio_ > 0)
      std::snprintf(detail, sizeof detail,
                    "in%zu = %.4g deviates from median %.4g by %.4g (tolerance %.4g = %g "
                    "\u00d7 median)",
                    i, s.value, median, std::fabs(s.value - median), tol, tolerance_ratio_);
    else
      std::snprintf(detail, sizeof detail, "in%zu = %.4g deviates from median %.4g by %.4g (tolerance %g)", i, s.value,
                    median, std::fabs(s.value - median), tol);
    reportFault(FaultEvent(FaultKind::Vote, sources_[i], detail));
  }

  void reportNoMajority(std::size_t agree, double median, double tol) {
    char detail[192];
    int n = std::snprintf(detail, sizeof detail, "no majority: %zu of %zu inputs within %.4g of median %.4g:", agree, N,
                          tol, median);
    for (std::size_t i = 0; i < N && n > 0 && static_cast<std::size_t>(n) < sizeof detail; ++i) {
      const std::size_t room = sizeof detail - static_cast<std::size_t>(n);
      if (present(slots_[i])) n += std::snprintf(detail + n, room, " in%zu=%.4g", i, slots_[i].value);
      else n += std::snprintf(detail + n, room, " in%zu=missing", i);
    }
    reportFault(FaultEvent(FaultKind::Vote, "", detail));  // about the voter itself
  }

  void parseSources(const std::string& text) {
    std::istringstream words(text);
    std::array<std::string, N> names{};
    std::size_t n = 0;
    for (std::string w; words >> w; ++n) {
      if (n < N) names[n] = w;
      if (w.size() >= FaultEvent{}.component.size())
        rejectProperty("sources", "names '" + w + "', longer than a fault event can name (" +
                                      std::to_string(FaultEvent{}.component.size() - 1) + " characters)");
    }
    if (n != 0 && n != N)
      rejectProperty("sources", "must name " + std::to_string(N) + " components, one per input in order (got " +
                                    std::to_string(n) + ": '" + text + "')");
    sources_ = std::move(names);  // empty names: faults are about the voter itself
  }

  void forget() {
    for (Slot& s : slots_) s = Slot{};
    no_majority_reported_ = false;
  }

  // configuration (onInitialize)
  double tolerance_ = 10.0;
  double tolerance_ratio_ = 0.0;   // > 0: tolerance relative to |median| instead
  std::uint64_t stale_after_ = 0;  // > 0: an input silent this many executions is missing
  std::array<std::string, N> sources_{};
  // state
  std::array<Slot, N> slots_{};
  bool no_majority_reported_ = false;
};

using MedianVoter = MedianVoterN<3>;
using MedianVoter5 = MedianVoterN<5>;

}  // namespace keel::components
