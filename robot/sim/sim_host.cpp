// The simulated robot in its world: board physics, then what the world makes of the new pose.
#include "robot/sim/sim_host.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace keel::robot {
namespace {

SimulatorConfig simulatorConfig(const SimHostConfig& config, const World& world) {
  SimulatorConfig sim;
  sim.seed = config.seed;
  sim.deadman_ms = config.deadman_ms;
  sim.start = world.start();
  sim.ray_cast = sonarRayCast(world);
  return sim;
}

World requireWorld(const std::string& name) {
  auto world = worldByName(name);
  if (!world) throw std::invalid_argument("unknown world '" + name + "' (worlds: " + worldNames() + ")");
  return *world;
}

}  // namespace

std::string worldNames() { return "paper"; }

std::optional<World> worldByName(const std::string& name) {
  if (name == "paper") return World::paperArena();
  return std::nullopt;
}

SimHost::SimHost(const SimHostConfig& config)
    : world_(requireWorld(config.world)), board_(simulatorConfig(config, world_)) {
  if (config.sonar_noise_cm > 0) {
    const auto mm = static_cast<std::uint16_t>(std::lround(std::min(config.sonar_noise_cm * 10, 65535.0)));
    board_.applyFault(FaultCommand{FaultKind::Noise, 0, mm});
  }
  if (!config.truth_path.empty()) writer_ = std::make_unique<TruthWriter>(config.truth_path);
  truth_.min_clearance_m = std::numeric_limits<double>::infinity();
  observe();
}

std::vector<std::uint8_t> SimHost::step(double dt_s) {
  std::vector<std::uint8_t> frame = board_.step(dt_s);
  observe();
  return frame;
}

void SimHost::observe() {
  const Simulator& sim = board_.simulator();
  const Pose& p = sim.pose();
  truth_.t_s = sim.timeS();
  truth_.x_m = p.x_m;
  truth_.y_m = p.y_m;
  truth_.heading_rad = p.heading_rad;
  truth_.rpm_left = sim.wheelRpm(Wheel::Left);
  truth_.rpm_right = sim.wheelRpm(Wheel::Right);
  truth_.clearance_m = world_.clearance(p.x_m, p.y_m, p.heading_rad);
  truth_.min_clearance_m = std::min(truth_.min_clearance_m, truth_.clearance_m);
  const bool colliding = world_.collides(p.x_m, p.y_m, p.heading_rad);
  if (colliding && !in_collision_) truth_.collisions += 1;
  in_collision_ = colliding;
  truth_.deadman = sim.deadmanTripped() ? 1.0 : 0.0;
  truth_.neutral_since_s = sim.neutralSinceS();
  truth_.deadman_since_s = sim.deadmanSinceS();
  truth_.powered_left = sim.motorPowered(Wheel::Left) ? 1.0 : 0.0;
  truth_.powered_right = sim.motorPowered(Wheel::Right) ? 1.0 : 0.0;
  truth_.steps += 1;
  if (writer_) writer_->publish(truth_);
}

}  // namespace keel::robot
