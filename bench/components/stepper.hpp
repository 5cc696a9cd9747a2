// The benchmark's trivial component: its onExecute only counts (the `recovered` moment of a
// recovery includes one step of it, so it must cost nothing). Registered under several names
// by the benchmark's component libraries: the victim and its alternatives.
#pragma once

#include <keel/component.hpp>

#include <cstdint>

namespace keel_bench {

class Stepper : public keel::Component {
 public:
  keel::ReturnCode onExecute() override {
    ++steps_;
    return keel::ReturnCode::Ok;
  }

 private:
  std::uint64_t steps_ = 0;
};

}  // namespace keel_bench
