// keel's OPRoS compatibility: OutputDataPort<T>. push() sends through keel's output data port
// of the same name and type: a value outside the profile's <validity> is a `range` fault of
// this component and is not sent, as for keel's own ports.
// Thread-safety: the owner's callbacks only.
#pragma once

#include <memory>
#include <string>

#include "OPRoSTypes.h"
#include "OutputDataPortInterface.h"
#include "ReturnType.h"
#include "keel/data_port.hpp"

template <class T>
class OutputDataPort : public OutputDataPortInterface {
 public:
  OutputDataPort() = default;
  explicit OutputDataPort(const std::string& name) : OutputDataPortInterface(name) {}

  ReturnType push(const T& data) {
    if (!keel_) return OPROS_PRECONDITION_NOT_MET;  // not loaded by keel: nothing to send to
    keel_->push(data);
    return OPROS_SUCCESS;
  }
  ReturnType push(opros_any& data) override {
    const T* v = opros_any_cast<T>(&data);
    if (!v) return OPROS_BAD_INPUT_PARAMETER;
    return push(*v);
  }
  void reset() override {}

  keel::detail::PortBase& keelBind(keel::Component& host) override {
    keel_ = std::make_unique<keel::OutputDataPort<T>>(&host, getName());
    return *keel_;
  }

 private:
  std::unique_ptr<keel::OutputDataPort<T>> keel_;
};
