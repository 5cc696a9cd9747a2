// Field rules (field_rules.hpp): a path resolved against a message's table of fields, and each
// value checked by walking the table's visitors down the path, element by element, counting
// the elements of every array on the way so that a violation names where it is
// ("poses[2].position.x").
#include "runtime/field_rules.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <utility>

#include "runtime/clock.hpp"
#include "runtime/component_core.hpp"
#include "runtime/fault_detail.hpp"
#include "runtime/invoke.hpp"

namespace keel::runtime {
namespace {

using detail::FieldKind;
using detail::MessageField;

/// A message field's type without its array part: the ROS 2 name of the nested message.
std::string_view elementType(const MessageField& f) {
  const std::string_view t = f.type;
  return t.substr(0, t.find('['));
}

std::size_t editDistance(std::string_view a, std::string_view b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t above = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = above;
    }
  }
  return row[b.size()];
}

void collectNumeric(std::span<const MessageField> fields, const std::string& prefix, std::size_t depth,
                    std::vector<std::string>& out) {
  for (const MessageField& f : fields) {
    const std::string path = prefix.empty() ? f.name : prefix + "." + f.name;
    if (f.kind == FieldKind::Number) out.push_back(path);
    else if (f.kind == FieldKind::Message && depth + 1 < kMaxFieldDepth)
      collectNumeric(f.nested(), path, depth + 1, out);
  }
}

/// Up to `most` of `paths`, comma separated, "..." for the rest; "none" for none.
std::string listSome(const std::vector<std::string>& paths, std::size_t most = 12) {
  if (paths.empty()) return "none";
  std::string out;
  for (std::size_t i = 0; i < paths.size() && i < most; ++i) out += (i ? ", " : "") + paths[i];
  if (paths.size() > most) out += fmt::format(", ... ({} in all)", paths.size());
  return out;
}

std::string noSuchField(std::span<const MessageField> fields, std::string_view type, std::string_view prefix,
                        std::string_view name) {
  std::vector<std::string> names;
  const MessageField* nearest = nullptr;
  std::size_t best = 3;  // at most two edits away
  for (const MessageField& f : fields) {
    names.emplace_back(f.name);
    if (const std::size_t d = editDistance(name, f.name); d < best && d < std::max(name.size(), std::strlen(f.name))) {
      best = d;
      nearest = &f;
    }
  }
  const std::string in = prefix.empty() ? std::string() : fmt::format(" (the type of '{}')", prefix);
  std::string why = names.empty() ? fmt::format("{}{} has no field '{}': it has no fields", type, in, name)
                                  : fmt::format("{}{} has no field '{}': its fields are {}", type, in, name,
                                                fmt::join(names, ", "));
  if (nearest) why += fmt::format(" (did you mean '{}{}{}'?)", prefix, prefix.empty() ? "" : ".", nearest->name);
  return why;
}

}  // namespace

std::vector<std::string> numericFieldPaths(std::span<const MessageField> fields) {
  std::vector<std::string> out;
  collectNumeric(fields, "", 0, out);
  return out;
}

Result<std::vector<const MessageField*>> resolveFieldPath(std::span<const MessageField> fields, std::string_view type,
                                                          std::string_view path) {
  std::vector<const MessageField*> steps;
  std::string prefix;  // the names resolved so far, dotted
  std::span<const MessageField> here = fields;
  std::string_view here_type = type;
  for (std::size_t start = 0;;) {
    const std::size_t dot = std::min(path.find('.', start), path.size());
    const std::string_view name = path.substr(start, dot - start);
    const bool last = dot == path.size();
    if (steps.size() == kMaxFieldDepth) return fail(fmt::format("'{}' is deeper than {} fields", path, kMaxFieldDepth));
    const auto f = std::find_if(here.begin(), here.end(), [&](const MessageField& m) { return m.name == name; });
    if (f == here.end()) return fail(noSuchField(here, here_type, prefix, name));
    steps.push_back(&*f);
    const std::string reached = prefix.empty() ? std::string(name) : prefix + "." + std::string(name);
    if (f->kind == FieldKind::Message) {
      if (last) {
        std::vector<std::string> numbers;
        collectNumeric(f->nested(), reached, steps.size(), numbers);
        return fail(fmt::format("'{}' is a message ({}), not a number: name one of its numeric fields ({})", reached,
                                f->type, listSome(numbers)));
      }
      here = f->nested();
      here_type = elementType(*f);
    } else if (!last) {
      return fail(fmt::format("'{}' is a {}, which has no fields: '{}' names nothing", reached, f->type, path));
    } else if (f->kind != FieldKind::Number) {
      std::vector<std::string> numbers;
      collectNumeric(here, prefix, steps.size() - 1, numbers);
      return fail(
          fmt::format("'{}' is a {}: only numbers and arrays of numbers can be range-checked (the numeric "
                      "fields{}: {})",
                      reached, f->type, prefix.empty() ? "" : fmt::format(" of '{}'", prefix), listSome(numbers)));
    }
    if (last) return steps;
    prefix = reached;
    start = dot + 1;
  }
}

Result<std::vector<const MessageField*>> resolveFieldTap(std::span<const MessageField> fields, std::string_view type,
                                                         std::string_view path) {
  auto steps = resolveFieldPath(fields, type, path);
  if (!steps) return steps;
  std::string reached;
  for (const MessageField* f : *steps) {
    reached += (reached.empty() ? "" : ".") + std::string(f->name);
    if (f->array)
      return fail(
          fmt::format("'{}' is an array ({}): a connection carries one number of each message", reached, f->type));
  }
  return steps;
}

}  // namespace keel::runtime

namespace keel::detail {
namespace {

using runtime::FieldRule;
using runtime::kMaxFieldDepth;

/// One value's walk down one rule's path.
struct Walk {
  Walk(const FieldRule& rule, std::size_t elements) : r(rule), want(elements) {}
  const FieldRule& r;
  std::size_t want;       // element-wise bounds: the number of elements the field must have; 0: any
  std::size_t level = 0;  // the step being visited
  std::size_t count = 0;  // numbers seen
  std::array<std::size_t, kMaxFieldDepth> seen{};  // elements seen at each level, in the current parent
  std::array<std::size_t, kMaxFieldDepth> at{};    // `seen` when the violation was found
  bool bad = false;
  Violation v;
};

bool visitLevel(Walk& w, const void* message);

bool onNumber(void* context, double x) {
  Walk& w = *static_cast<Walk*>(context);
  const std::size_t i = w.count++;
  ++w.seen[w.level];
  if (w.bad || (w.want != 0 && i >= w.want)) return true;  // counted for the size check
  const double lo = w.r.rule.minAt(i), hi = w.r.rule.maxAt(i);
  if (std::isfinite(x) && x >= lo && x <= hi) return true;
  w.bad = true;
  w.v = Violation{i, x, lo, hi, 0, 0, true};
  w.at = w.seen;
  return w.want != 0;  // element-wise: count on, a wrong size is said first
}

bool onMessage(void* context, const void* message) {
  Walk& w = *static_cast<Walk*>(context);
  ++w.seen[w.level];
  ++w.level;
  const bool go = visitLevel(w, message);
  --w.level;
  return go;
}

bool visitLevel(Walk& w, const void* message) {
  const MessageField& f = *w.r.steps[w.level];
  w.seen[w.level] = 0;
  return f.kind == FieldKind::Number ? f.numbers(message, &w, onNumber) : f.messages(message, &w, onMessage);
}

/// The path with the index of each array's element where the violation is: "poses[2].position.x".
/// In `out`, cut to fit, terminated; allocates nothing.
template <std::size_t N>
void indexedPath(const Walk& w, std::array<char, N>& out) {
  char* p = out.data();
  char* const end = out.data() + N - 1;
  for (std::size_t l = 0; l < w.r.steps.size() && p < end; ++l) {
    const MessageField& f = *w.r.steps[l];
    const auto left = static_cast<std::size_t>(end - p);
    p = f.array ? fmt::format_to_n(p, left, "{}{}[{}]", l ? "." : "", f.name, w.at[l] - 1).out
                : fmt::format_to_n(p, left, "{}{}", l ? "." : "", f.name).out;
  }
  *std::min(p, end) = '\0';
}

void report(Component& owner, const std::string& port, const Walk& w, bool wrong_size, bool on_delivery) {
  FaultEvent ev;
  ev.kind = FaultKind::Range;
  ev.t_ns = runtime::steadyNs();
  FaultEvent::copyInto(ev.component, runtime::coreOf(owner).instance_name);
  const char* where = on_delivery ? "received on" : "pushed on";
  if (wrong_size) {
    runtime::formatDetail(ev, "{} port '{}' field '{}': {} elements, validity expects {}", where, port, w.r.path,
                          w.count, w.want);
  } else {
    std::array<char, 160> path;
    indexedPath(w, path);
    runtime::formatDetail(ev, "value {} {} port '{}' field '{}' outside [{}, {}]", w.v.value, where, port, path.data(),
                          w.v.min, w.v.max);
  }
  runtime::reportFault(owner, ev);
}

}  // namespace

bool checkFields(const FieldRules& rules, const void* value, Component& owner, const std::string& port,
                 bool on_delivery) {
  for (const FieldRule& r : rules.rules) {
    Walk w(r, r.rule.elementWise());
    visitLevel(w, value);
    const bool wrong_size = w.want != 0 && w.count != w.want;
    if (!w.bad && !wrong_size) continue;
    report(owner, port, w, wrong_size, on_delivery);
    return false;
  }
  for (const FieldTap& t : rules.taps) sendField(t, value);
  return true;
}

void sendField(const FieldTap& tap, const void* message) {
  // Down the path, no array on the way (resolveFieldTap): one message per level, one number.
  const void* at = message;
  for (std::size_t i = 0; i + 1 < tap.steps.size(); ++i) {
    const void* next = nullptr;
    tap.steps[i]->messages(at, &next, [](void* context, const void* m) {
      *static_cast<const void**>(context) = m;
      return false;
    });
    if (next == nullptr) return;
    at = next;
  }
  double x = 0;
  bool found = false;
  std::pair<double*, bool*> into{&x, &found};
  tap.steps.back()->numbers(at, &into, [](void* context, double v) {
    auto& [to, seen] = *static_cast<std::pair<double*, bool*>*>(context);
    *to = v;
    *seen = true;
    return false;
  });
  if (found) tap.out->push(x);
}

}  // namespace keel::detail
