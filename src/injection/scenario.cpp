#include "injection/scenario.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include "profile/values.hpp"
#include "profile/xml_reader.hpp"

namespace keel::injection {
namespace {

using profile::Diagnostic;
using profile::Diagnostics;

constexpr const char* kKinds =
    "segfault, divide_by_zero, abort, throw, error_code, hang, stall_heartbeat, out_of_range, kill; "
    "hardware: sensor_unplugged, sensor_stuck, sensor_ok, motor_power_off, motor_power_on, noise, encoder_dead, "
    "encoder_ok, gyro_dead, gyro_ok";
constexpr std::string_view kHardwareKinds[] = {"sensor_unplugged", "sensor_stuck", "sensor_ok",    "motor_power_off",
                                               "motor_power_on",   "noise",        "encoder_dead", "encoder_ok",
                                               "gyro_dead",        "gyro_ok"};

// Bounds that keep the injector's arithmetic in range: times in ms up to about 11.6 days (in ns
// they fit an int64 many times over), and a million repetitions of one fault.
constexpr double kMaxMs = 1e9;
constexpr double kMaxRepeat = 1e6;

class FaultReader {
 public:
  FaultReader(const profile::detail::XmlFile& file, Diagnostics& diags) : file_(file), diags_(diags) {}

  std::optional<ScheduledFault> read(pugi::xml_node n) {
    ScheduledFault f;
    f.where = file_.where(n);
    const std::size_t before = diags_.size();
    for (pugi::xml_attribute a : n.attributes()) {
      std::string_view name = a.name();
      if (name == "at") f.at_ms = number(n, a, 0, false, kMaxMs);
      else if (name == "component") f.component = a.value();
      else if (name == "kind") f.kind_name = a.value();
      else if (name == "port") f.port = a.value();
      else if (name == "value") f.value = number(n, a, -std::numeric_limits<double>::infinity(), true);
      else if (name == "duration") f.duration_ms = number(n, a, 0, false, kMaxMs);
      else if (name == "repeat") f.repeat = count(n, a);
      else if (name == "every") f.every_ms = number(n, a, 0, false, kMaxMs);
      else if (name == "args") f.args = profile::detail::trim(a.value());
      else
        error(n, fmt::format("<fault>: unknown attribute '{}' (known: at, component, kind, port, value, "
                             "duration, repeat, every, args)",
                             name));
    }
    if (n.attribute("at").empty()) error(n, "<fault>: attribute 'at' (ms) is required");
    if (f.component.empty()) error(n, "<fault>: attribute 'component' is required");
    readKind(n, f);
    if (n.attribute("value").empty()) f.value = std::numeric_limits<double>::quiet_NaN();
    if (f.repeat > 1 && f.every_ms <= 0) error(n, "<fault>: repeat needs every (ms) > 0");
    if (diags_.size() != before) return std::nullopt;
    return f;
  }

  void error(pugi::xml_node n, std::string message) {
    diags_.push_back(Diagnostic{file_.where(n), std::move(message)});
  }

 private:
  /// The kind, and the attributes that go with it: `args` with the hardware kinds only; `port`,
  /// `value` and `duration` with the software ones.
  void readKind(pugi::xml_node n, ScheduledFault& f) {
    f.hardware = isHardwareKind(f.kind_name);
    if (f.hardware) {
      for (const char* a : {"port", "value", "duration"}) {
        if (n.attribute(a).empty()) continue;
        error(n, fmt::format("<fault>: attribute '{}' is not for hardware kind '{}' (it takes args)", a, f.kind_name));
      }
      return;
    }
    if (auto k = runtime::parseInjectKind(f.kind_name)) {
      f.kind = *k;
      if (!n.attribute("args").empty())
        error(n, fmt::format("<fault>: attribute 'args' is for the hardware kinds; '{}' takes none", f.kind_name));
      return;
    }
    error(n, fmt::format("<fault>: unknown kind '{}' (kinds: {})", f.kind_name, kKinds));
  }

  double number(pugi::xml_node n, pugi::xml_attribute a, double min, bool allow_nan = false,
                double max = std::numeric_limits<double>::infinity()) {
    std::string_view text = a.value();
    if (allow_nan && (text == "nan" || text == "NaN")) return std::numeric_limits<double>::quiet_NaN();
    auto v = profile::detail::parseDouble(text, allow_nan);
    if (!v || *v < min || *v > max) {
      error(n, fmt::format("<fault>: attribute '{}' must be a number{}{}, got '{}'", a.name(),
                           std::isfinite(min) ? fmt::format(" >= {}", min) : "",
                           std::isfinite(max) ? fmt::format(" and <= {}", max) : "", text));
      return min;
    }
    return *v;
  }
  /// `repeat`: a whole number in [1, kMaxRepeat].
  int count(pugi::xml_node n, pugi::xml_attribute a) {
    const double v = number(n, a, 1, false, kMaxRepeat);
    if (v == std::floor(v)) return static_cast<int>(v);
    error(n, fmt::format("<fault>: attribute 'repeat' must be a whole number, got '{}'", a.value()));
    return 1;
  }
  const profile::detail::XmlFile& file_;
  Diagnostics& diags_;
};

}  // namespace

bool isHardwareKind(std::string_view kind) {
  return std::find(std::begin(kHardwareKinds), std::end(kHardwareKinds), kind) != std::end(kHardwareKinds);
}

Result<Scenario, Diagnostics> loadScenario(const std::string& path) {
  Diagnostics diags;
  std::string open_error;
  Diagnostic syntax;
  auto file = profile::detail::XmlFile::read(path, path, open_error, syntax);
  if (!file) {
    if (open_error.empty()) {
      diags.push_back(std::move(syntax));
    } else {
      // Built in place member by member: GCC 12 at -O3 warns (-Wmaybe-uninitialized) about the
      // temporary of a brace-initialised Diagnostic here.
      Diagnostic& d = diags.emplace_back();
      d.where.file = path;
      d.message = fmt::format("cannot open scenario: {}", open_error);
    }
    return diags;
  }
  pugi::xml_node root = file->root();
  if (std::string_view(root.name()) != "fault_scenario") {
    diags.push_back(
        Diagnostic{file->where(root), fmt::format("root element must be <fault_scenario>, got <{}>", root.name())});
    return diags;
  }
  Scenario s;
  s.file = path;
  FaultReader reader(*file, diags);
  for (pugi::xml_node n : root.children()) {
    if (n.type() != pugi::node_element) continue;
    if (std::string_view(n.name()) == "description") continue;
    if (std::string_view(n.name()) != "fault") {
      reader.error(n, fmt::format("unknown element <{}> in <fault_scenario> (expected <fault>)", n.name()));
      continue;
    }
    if (auto f = reader.read(n)) s.faults.push_back(std::move(*f));
  }
  if (!diags.empty()) return diags;
  std::stable_sort(s.faults.begin(), s.faults.end(), [](const auto& a, const auto& b) { return a.at_ms < b.at_ms; });
  return s;
}

}  // namespace keel::injection
