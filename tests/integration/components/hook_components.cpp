// Components for the tests of the runtime's hooks for a robot run: a Finisher that ends the run
// (Component::endRun) after a number of executions or from its onStop. Built into the test
// component library with the others.
#include <keel/component.hpp>

#include <string>

namespace itest {

/// Ends the run after `end_after` executions (0: never), or from onStop with `end_on_stop`.
/// The end's record is `event` with the members `fields` and "executions":N (when `fields` is
/// not empty). A second call right after the first shows that only the first counts.
class Finisher : public keel::Component {
 public:
  keel::ReturnCode onInitialize() override {
    end_after_ = property<int>("end_after", 0);
    end_on_stop_ = property<bool>("end_on_stop", false);
    event_ = property<std::string>("event", "");
    fields_ = property<std::string>("fields", "");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    if (++n_ != end_after_) return keel::ReturnCode::Ok;
    endRun("done after " + std::to_string(n_) + " executions", event_, fields());
    endRun("a second call", "ignored", "\"ignored\":true");
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onStop() override {
    if (end_on_stop_) endRun("stopped after " + std::to_string(n_) + " executions", event_, fields());
    return keel::ReturnCode::Ok;
  }

 private:
  std::string fields() const {
    return fields_.empty() ? fields_ : fields_ + ",\"executions\":" + std::to_string(n_);
  }
  int n_ = 0;
  int end_after_ = 0;
  bool end_on_stop_ = false;
  std::string event_;
  std::string fields_;
};

}  // namespace itest

KEEL_REGISTER_COMPONENT_AS(itest::Finisher, "Finisher")
