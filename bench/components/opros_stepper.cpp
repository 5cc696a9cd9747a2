// The benchmark's trivial component written against the OPRoS API (keel_add_opros_component):
// the same work as keel_bench::Stepper (stepper.hpp), for `keel bench recovery`'s *_opros cells,
// which measure an OPRoS component's recovery beside a keel one's in the same run. One
// component per library, as OPRoS builds them; the victim and its alternative both load it.
#include <Component.h>

class OprosStepper : public Component {
 public:
  ReturnType onExecute() override {
    ++steps;
    return OPROS_SUCCESS;
  }

 private:
  unsigned long long steps{0};
};

extern "C" {
Component* getComponent();
void releaseComponent(Component* com);
}
Component* getComponent() { return new OprosStepper(); }
void releaseComponent(Component* com) { delete com; }
