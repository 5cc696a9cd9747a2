// MissionReferee; see mission_referee.hpp.
#include "robot/components/mission_referee.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>

#include <fmt/format.h>

namespace keel::robot {
namespace {

constexpr double kAtRestRpm = 1.0;  // both wheels slower than this: at rest
constexpr double kMovingRpm = 5.0;  // either wheel faster than this: the robot has moved

}  // namespace

ReturnCode MissionReferee::onInitialize() {
  const auto world_name = property<std::string>("world", "paper");
  world_ = worldByName(world_name);
  if (!world_) rejectProperty("world", "names unknown world '" + world_name + "' (worlds: " + worldNames() + ")");
  if (world_->boxes().size() > kWorldBoxes)
    rejectProperty("world", fmt::format("names world '{}' of {} boxes; the `world` port carries {} at most", world_name,
                                        world_->boxes().size(), kWorldBoxes));
  truth_.emplace(truthPath(property<std::string>("sim", "robot"), getpid()));
  goal_radius_m_ = property<double>("goal_radius_m", goal_radius_m_);
  settle_s_ = property<double>("settle_s", settle_s_);
  stopped_after_s_ = property<double>("stopped_after_s", stopped_after_s_);
  const auto trace = property<std::string>("trace", "");
  if (!trace.empty()) {
    trace_ = std::fopen(trace.c_str(), "w");
    if (trace_ == nullptr) rejectProperty("trace", "names a file that cannot be written: " + trace);
    std::fputs(
        "t_s,x_m,y_m,heading_rad,rpm_left,rpm_right,measured_left,measured_right,reference_left,reference_right,"
        "clearance_m,collisions\n",
        trace_);
    writeWorld(trace + ".world.json");
  }
  return ReturnCode::Ok;
}

ReturnCode MissionReferee::onExecute() {
  InputDataPort<double>* ports[4] = {&measured_left, &measured_right, &reference_left, &reference_right};
  for (int i = 0; i < 4; ++i)
    while (std::optional<double> v = ports[i]->pop()) signals_[i] = *v;
  if (!world_sent_) {
    world.push(worldValues());
    world_sent_ = true;
  }
  const std::optional<TruthSample> t = truth_->read();
  if (!t || finished_) return ReturnCode::Ok;
  last_ = t;
  if (first_t_s_ < 0) first_t_s_ = t->t_s;
  truth.push({t->t_s, t->x_m, t->y_m, t->heading_rad, t->rpm_left, t->rpm_right, t->clearance_m, t->collisions});
  writeTrace(*t);
  const bool at_rest = std::fabs(t->rpm_left) < kAtRestRpm && std::fabs(t->rpm_right) < kAtRestRpm;
  moved_ = moved_ || std::fabs(t->rpm_left) > kMovingRpm || std::fabs(t->rpm_right) > kMovingRpm;
  if (!at_rest || !moved_) {
    at_rest_since_s_ = -1.0;
    return ReturnCode::Ok;
  }
  if (at_rest_since_s_ < 0) at_rest_since_s_ = t->t_s;
  const double rest_s = t->t_s - at_rest_since_s_;
  const Target& target = world_->target();
  const bool near = std::hypot(t->x_m - target.x_m, t->y_m - target.y_m) <= goal_radius_m_;
  if (near && rest_s >= settle_s_) finish("goal");
  else if (rest_s >= stopped_after_s_) finish("stopped");
  return ReturnCode::Ok;
}

void MissionReferee::finish(const char* how) {
  if (finished_) return;
  finished_ = true;
  const TruthSample t = last_.value_or(TruthSample{});
  const Target& target = world_->target();
  const double distance = std::hypot(t.x_m - target.x_m, t.y_m - target.y_m);
  const bool goal = std::string_view(how) == "goal";
  const double clearance_cm = std::isfinite(t.min_clearance_m) ? 100.0 * t.min_clearance_m : -1.0;
  const double duration = first_t_s_ < 0 ? 0.0 : t.t_s - first_t_s_;
  // What put the motors in neutral for this final rest, first: a stop command of the main board
  // (the actuator's onStop or onEmergencyStop, the planner at the goal), or the board's deadman
  // when the main board stopped sending (a safety net, not a stop keel made).
  const bool by_command = t.neutral_since_s >= 0 && (t.deadman_since_s < 0 || t.neutral_since_s <= t.deadman_since_s);
  const char* held_by = by_command ? "command" : t.deadman_since_s >= 0 ? "deadman" : "none";
  const std::string fields = fmt::format(
      R"("goal_reached":{},"collisions":{},"min_clearance_cm":{:.1f},"duration_s":{:.2f},"ended":"{}","distance_to_target_m":{:.2f},"x_m":{:.3f},"y_m":{:.3f},"neutral_by":"{}")",
      goal, static_cast<int>(t.collisions), clearance_cm, duration, how, distance, t.x_m, t.y_m, held_by);
  const std::string summary =
      fmt::format("mission {} — goal {}, {} collision{}, min clearance {:.1f} cm, {:.1f} s, {:.2f} m from the target",
                  how, goal ? "reached" : "not reached", static_cast<int>(t.collisions), t.collisions == 1 ? "" : "s",
                  clearance_cm, duration, distance);
  endRun(summary, "mission", fields);
}

ReturnCode MissionReferee::onStop() {
  finish("shutdown");  // the run ends for another reason (duration, signal): say how far it got
  return ReturnCode::Ok;
}

ReturnCode MissionReferee::onDestroy() {
  if (trace_ != nullptr) std::fclose(trace_);
  trace_ = nullptr;
  return ReturnCode::Ok;
}

void MissionReferee::writeTrace(const TruthSample& t) {
  if (trace_ == nullptr) return;
  std::fprintf(trace_, "%.3f,%.4f,%.4f,%.4f,%.2f,%.2f,%.2f,%.2f,%.2f,%.2f,%.4f,%d\n", t.t_s, t.x_m, t.y_m,
               t.heading_rad, t.rpm_left, t.rpm_right, signals_[0], signals_[1], signals_[2], signals_[3],
               t.clearance_m, static_cast<int>(t.collisions));
  std::fflush(trace_);
}

std::array<double, kWorldValues> MissionReferee::worldValues() const {
  std::array<double, kWorldValues> v;
  v.fill(std::numeric_limits<double>::quiet_NaN());
  const Target& t = world_->target();
  const Pose& s = world_->start();
  const double head[6] = {t.x_m, t.y_m, t.radius_m, s.x_m, s.y_m, s.heading_rad};
  std::copy(std::begin(head), std::end(head), v.begin());
  std::size_t i = 6;
  for (const Box& b : world_->boxes())
    for (const double c : {b.min_x, b.min_y, b.max_x, b.max_y}) v[i++] = c;
  return v;
}

void MissionReferee::writeWorld(const std::string& path) const {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) return;
  std::string boxes;
  for (const Box& b : world_->boxes())
    boxes += fmt::format("{}[{},{},{},{}]", boxes.empty() ? "" : ",", b.min_x, b.min_y, b.max_x, b.max_y);
  const Target& t = world_->target();
  const Pose& s = world_->start();
  std::fprintf(
      f, "{\"boxes\":[%s],\"target\":{\"x\":%g,\"y\":%g,\"r\":%g},\"start\":{\"x\":%g,\"y\":%g,\"heading\":%g}}\n",
      boxes.c_str(), t.x_m, t.y_m, t.radius_m, s.x_m, s.y_m, s.heading_rad);
  std::fclose(f);
}

}  // namespace keel::robot
