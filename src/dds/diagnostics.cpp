// /diagnostics (diagnostics.hpp).
#include "dds/diagnostics.hpp"

namespace keel::dds {

keel::msg::diagnostic_msgs::DiagnosticArray diagnosticArray(const std::vector<Health>& health, std::int64_t wall_ns) {
  keel::msg::diagnostic_msgs::DiagnosticArray array;
  array.header.stamp.sec = static_cast<std::int32_t>(wall_ns / 1'000'000'000);
  array.header.stamp.nanosec = static_cast<std::uint32_t>(wall_ns % 1'000'000'000);
  for (const Health& h : health) {
    keel::msg::diagnostic_msgs::DiagnosticStatus s;
    s.level = h.level;
    s.name = h.name;
    s.message = h.message;
    s.hardware_id = "keel";
    s.values = {{"state", h.state}, {"faults", std::to_string(h.faults)}, {"last_fault", h.last_fault}};
    array.status.push_back(std::move(s));
  }
  return array;
}

DiagnosticsWriter::DiagnosticsWriter(Snapshot snapshot, Publish publish, std::chrono::milliseconds period)
    : snapshot_(std::move(snapshot)), publish_(std::move(publish)), period_(period) {
  thread_ = std::thread([this] { run(); });
}

DiagnosticsWriter::~DiagnosticsWriter() { stop(); }

void DiagnosticsWriter::poke() {
  {
    std::lock_guard lock(mutex_);
    poked_ = true;
  }
  cv_.notify_one();
}

void DiagnosticsWriter::stop() {
  {
    std::lock_guard lock(mutex_);
    if (stopping_) return;
    stopping_ = true;
  }
  cv_.notify_one();
  if (thread_.joinable()) thread_.join();
}

void DiagnosticsWriter::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    poked_ = false;
    lock.unlock();
    write();
    lock.lock();
    if (stopping_) return;
    cv_.wait_for(lock, period_, [this] { return poked_ || stopping_; });
  }
}

void DiagnosticsWriter::write() {
  const auto now = std::chrono::system_clock::now().time_since_epoch();  // ROS time is the wall clock
  publish_(diagnosticArray(snapshot_(), std::chrono::duration_cast<std::chrono::nanoseconds>(now).count()));
}

}  // namespace keel::dds
