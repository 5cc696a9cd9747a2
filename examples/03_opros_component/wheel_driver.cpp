// A keel component beside the OPRoS one: it plays the wheel driver, publishing the wheel's
// speed (m/s) each cycle. An OPRoS InputDataPort<double> and a keel OutputDataPort<double> are
// the same port type to keel, so the two connect like any others.
#include <keel/component.hpp>

class WheelDriver : public keel::Component {
 public:
  keel::OutputDataPort<double> speed{this, "speed"};

  keel::ReturnCode onInitialize() override {
    speed_ = property<double>("speed_mps");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    speed.push(speed_);
    return keel::ReturnCode::Ok;
  }

 private:
  double speed_ = 0;
};

KEEL_REGISTER_COMPONENT(WheelDriver)
