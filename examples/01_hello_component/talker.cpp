// A periodic component: counts, and publishes the count on a data port. Its counter is
// registered with critical(), so the framework can checkpoint and restore it.
#include <keel/component.hpp>

class Talker : public keel::Component {
 public:
  keel::OutputDataPort<int> count{this, "count"};
  keel::OutputEventPort<keel::Event> news{this, "news"};

  keel::ReturnCode onInitialize() override {
    every_ = property<int>("announce_every");
    critical(n_);  // checkpointed state
    return keel::ReturnCode::Ok;
  }

  keel::ReturnCode onExecute() override {
    count.push(++n_);
    if (n_ % every_ == 0) news.send(keel::Event{"milestone", n_, 0.0});
    return keel::ReturnCode::Ok;
  }

 private:
  int n_ = 0;
  int every_ = 10;
};

KEEL_REGISTER_COMPONENT(Talker)
