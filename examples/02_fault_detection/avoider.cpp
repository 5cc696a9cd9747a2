// Fuses the sonars it hears from; raises a user fault when it has heard nothing for a while,
// which is how a component reports a problem it noticed itself.
#include <keel/component.hpp>

#include <string>

class Avoider : public keel::Component {
 public:
  keel::InputDataPort<double> left{this, "left"};
  keel::InputDataPort<double> right{this, "right"};

  keel::ReturnCode onExecute() override {
    check(left.pop(), silent_left_, "left");
    check(right.pop(), silent_right_, "right");
    return keel::ReturnCode::Ok;
  }

 private:
  void check(std::optional<double> v, int& silent, const char* side) {
    if (v) {
      silent = 0;
      return;
    }
    if (++silent == 20) raiseFault(std::string("no reading from the ") + side + " sonar for 20 cycles");
  }
  int silent_left_ = 0;
  int silent_right_ = 0;
};

KEEL_REGISTER_COMPONENT(Avoider)
