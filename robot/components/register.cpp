// Registers the test robot's components in libkeel_robot, under the class names their profiles
// in robot/components/profiles use.
#include "robot/components/actuator_control.hpp"
#include "robot/components/camera_sensor.hpp"
#include "robot/components/mission_referee.hpp"
#include "robot/components/obstacle_avoidance.hpp"
#include "robot/components/obstacle_guard.hpp"
#include "robot/components/path_planner.hpp"
#include "robot/components/range_message.hpp"
#include "robot/components/sonar_frame_latch.hpp"
#include "robot/components/twist_command.hpp"
#include "robot/components/ultrasonic_sensor.hpp"
#include "robot/components/vision/color_blob_detector.hpp"
#include "robot/components/wheel_encoder.hpp"
#include "robot/components/wheel_reference_model.hpp"

KEEL_REGISTER_COMPONENT_AS(keel::robot::ActuatorControl, "ActuatorControl")
KEEL_REGISTER_COMPONENT_AS(keel::robot::CameraSensor, "Camera")
KEEL_REGISTER_COMPONENT_AS(keel::robot::ColorBlobDetector, "ColorBlobDetector")
KEEL_REGISTER_COMPONENT_AS(keel::robot::PathPlanner, "PathPlanner")
KEEL_REGISTER_COMPONENT_AS(keel::robot::SonarFrameLatch, "SonarFrameLatch")
KEEL_REGISTER_COMPONENT_AS(keel::robot::UltrasonicSensor, "UltrasonicSensor")
KEEL_REGISTER_COMPONENT_AS(keel::robot::ObstacleAvoidance, "ObstacleAvoidance")
KEEL_REGISTER_COMPONENT_AS(keel::robot::ObstacleAvoidanceSecondary, "ObstacleAvoidanceSecondary")
KEEL_REGISTER_COMPONENT_AS(keel::robot::WheelReferenceModel, "WheelReferenceModel")
KEEL_REGISTER_COMPONENT_AS(keel::robot::MissionReferee, "MissionReferee")
KEEL_REGISTER_COMPONENT_AS(keel::robot::TwistCommand, "TwistCommand")
KEEL_REGISTER_COMPONENT_AS(keel::robot::ObstacleGuard, "ObstacleGuard")
KEEL_REGISTER_COMPONENT_AS(keel::robot::RangeMessage, "RangeMessage")
KEEL_REGISTER_COMPONENT_AS(keel::robot::WheelEncoder, "WheelEncoder")
KEEL_REGISTER_COMPONENT_AS(keel::robot::RateGyro, "RateGyro")
