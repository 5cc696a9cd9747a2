// A component written against the OPRoS API, in an outside author's project: built with
// keel_add_opros_component against the installed keel's OPRoS headers, it prints what the
// Greeter (a keel component) sends it.
#include <OPRoSInclude.h>

#include <iostream>

class Shouter : public Component {
 public:
  Shouter() : greetings(OPROS_LAST, 1) { addPort("greetings", &greetings); }
  virtual ReturnType onExecute() {
    opros_any* p = greetings.pop();
    if (p != NULL) {
      std::cout << getId() << " heard " << greetings.getContent(*p) << std::endl;
      delete p;
    }
    return OPROS_SUCCESS;
  }

 protected:
  InputDataPort<std::string> greetings;
};

extern "C" {
Component* getComponent();
void releaseComponent(Component* com);
}
Component* getComponent() { return new Shouter(); }
void releaseComponent(Component* com) { delete com; }
