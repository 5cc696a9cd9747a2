#include "engine/run_end.hpp"

#include "log/schema.hpp"

#include <fmt/format.h>

#include <variant>

namespace keel::engine {

bool RunEndLatch::request(RunEnd end) {
  {
    std::lock_guard lock(mutex_);
    if (end_) return false;  // the first request wins
    end_ = std::move(end);
    requested_.store(true, std::memory_order_release);
  }
  cv_.notify_all();
  return true;
}

std::optional<RunEnd> RunEndLatch::get() const {
  std::lock_guard lock(mutex_);
  return end_;
}

bool RunEndLatch::waitUntil(std::chrono::steady_clock::time_point until) const {
  std::unique_lock lock(mutex_);
  return cv_.wait_until(lock, until, [this] { return end_.has_value(); });
}

namespace {

/// The members of `fields` as a JSON object, or why they are not one.
std::variant<nlohmann::json, std::string> parseMembers(const std::string& fields) {
  try {
    nlohmann::json members = nlohmann::json::parse("{" + fields + "}");
    if (members.is_object()) return members;
    return std::string("not a JSON object");
  } catch (const nlohmann::json::exception& e) {
    return std::string(e.what());
  }
}

}  // namespace

nlohmann::json runEndRecord(const RunEnd& end, std::int64_t t_ns) {
  auto parsed = parseMembers(end.fields);
  nlohmann::json record = nlohmann::json::object();
  if (auto* members = std::get_if<nlohmann::json>(&parsed)) {
    record = std::move(*members);
  } else {
    record[log::schema::field::kFieldsError] = fmt::format("fields_json '{}' is not the members of a JSON object: {}",
                                                           end.fields, std::get<std::string>(parsed));
  }
  record[log::schema::field::kTime] = t_ns;
  record[log::schema::field::kEvent] = end.event;
  record[log::schema::field::kComponent] = end.component;
  return record;
}

}  // namespace keel::engine
