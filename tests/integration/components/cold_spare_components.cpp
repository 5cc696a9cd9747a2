// Tally's alternative alone in a library of its own (libkeel_test_cold_spare.so), for the
// cold-replacement scenario (tests/scenarios/handling_test.cpp): no profile of the scenario's
// package names this library but the alternative's, so it is not mapped until the fault manager
// loads it at fault time. It counts on from the checkpointed count, published on `count` like
// the tally it replaces (a tap downstream sees the count continue).
#include <keel/component.hpp>

namespace htest {

class TallyColdSpare : public keel::Component {
 public:
  keel::OutputDataPort<int> count{this, "count"};
  keel::ReturnCode onInitialize() override {
    critical(n_);  // the same critical memory layout as Tally's
    return keel::ReturnCode::Ok;
  }
  keel::ReturnCode onExecute() override {
    count.push(++n_);
    return keel::ReturnCode::Ok;
  }

 private:
  int n_ = 0;
};

}  // namespace htest

KEEL_REGISTER_COMPONENT_AS(htest::TallyColdSpare, "TallyColdSpare")
