// CameraSensor ("Camera" in profiles): the test robot's vision sensor (paper Fig. 5). What a real
// camera gets from the world the simulated one renders from the simulation's ground truth
// (robot/sim/truth.hpp, published by the motion board the actuator started): each execution, one
// frame from the true pose (robot/world/camera.hpp). Until the truth exists it sends nothing.
// Thread-safety: a component.
#pragma once

#include <unistd.h>

#include <optional>
#include <string>

#include <keel/component.hpp>

#include "robot/components/robot_types.hpp"
#include "robot/sim/sim_host.hpp"
#include "robot/sim/truth.hpp"

namespace keel::robot {

class CameraSensor : public Component {
 public:
  OutputDataPort<Image> image{this, "image"};

  ReturnCode onInitialize() override {
    const auto world_name = property<std::string>("world", "paper");
    world_ = worldByName(world_name);
    if (!world_) rejectProperty("world", "names unknown world '" + world_name + "' (worlds: " + worldNames() + ")");
    CameraConfig c;
    c.seed = static_cast<std::uint64_t>(property<std::int64_t>("seed", 1));
    c.noise_sigma = property<double>("noise_sigma", 0.0);
    camera_.emplace(c);
    truth_.emplace(truthPath(property<std::string>("sim", "robot"), getpid()));
    return ReturnCode::Ok;
  }

  ReturnCode onExecute() override {
    const std::optional<TruthSample> t = truth_->read();
    if (!t) return ReturnCode::Ok;  // the board has not started yet
    image.push(camera_->render(*world_, Pose{t->x_m, t->y_m, t->heading_rad}));
    return ReturnCode::Ok;
  }

 private:
  std::optional<World> world_;
  std::optional<Camera> camera_;
  std::optional<TruthReader> truth_;
};

}  // namespace keel::robot
