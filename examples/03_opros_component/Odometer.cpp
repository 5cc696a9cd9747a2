/*
 *  An OPRoS component, laid out as OPRoS's component generator writes one: it integrates the
 *  wheel speed it receives into the distance travelled, publishes it, and answers total() on
 *  its provided service port. Nothing in it knows keel, except critical(): Ahn et al. added it
 *  to OPRoS's Component, and keel's OPRoS Component has it (docs/opros.md).
 */
#include <Component.h>
#include <InputDataPort.h>
#include <OPRoSTypes.h>
#include <OutputDataPort.h>
#include <ServiceUtils.h>

#include "Odometer.h"

#include <cstdlib>
#include <iostream>

Odometer::Odometer() : wheelSpeed(OPROS_LAST, 1) { portSetup(); }

Odometer::Odometer(const std::string& name) : Component(name), wheelSpeed(OPROS_LAST, 1) { portSetup(); }

Odometer::~Odometer() = default;

void Odometer::portSetup() {
  // provided service port setup
  ProvidedServicePort* pa1;
  pa1 = new OdometryProvided(this);
  addPort("Odometry", pa1);
  // data port setup
  addPort("wheelSpeed", &wheelSpeed);
  addPort("distance", &distance);
  pose.travelled = 0;
  pose.cycles = 0;
  period = 0.02;
}

ReturnType Odometer::onInitialize() {
  // The profile's properties arrive as text, as in OPRoS.
  const std::string text = getProperty("period_s");
  char* end = nullptr;
  period = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != '\0' || period <= 0) return OPROS_BAD_INPUT_PARAMETER;
  critical(&pose, sizeof pose);  // keel backs it up and restores it after a fault
  return OPROS_SUCCESS;
}

ReturnType Odometer::onStart() { return OPROS_SUCCESS; }

ReturnType Odometer::onStop() {
  std::cout << getId() << ": travelled " << pose.travelled << " m in " << pose.cycles << " cycles" << std::endl;
  return OPROS_SUCCESS;
}

ReturnType Odometer::onReset() { return OPROS_SUCCESS; }

ReturnType Odometer::onError() {
  std::cout << getId() << ": error after " << pose.cycles << " cycles" << std::endl;
  return OPROS_SUCCESS;
}

ReturnType Odometer::onRecover() {
  std::cout << getId() << ": recovered at " << pose.travelled << " m, cycle " << pose.cycles << std::endl;
  return OPROS_SUCCESS;
}

ReturnType Odometer::onDestroy() { return OPROS_SUCCESS; }

ReturnType Odometer::onEvent(Event* /*evt*/) { return OPROS_SUCCESS; }

ReturnType Odometer::onExecute() {
  opros_any* pData = wheelSpeed.pop();
  if (pData != nullptr) {
    double speed = wheelSpeed.getContent(*pData);
    delete pData;
    pose.travelled += speed * period;
  }
  ++pose.cycles;
  distance.push(pose.travelled);
  return OPROS_SUCCESS;
}

ReturnType Odometer::onUpdated() { return OPROS_SUCCESS; }

ReturnType Odometer::onPeriodChanged() { return OPROS_SUCCESS; }

double Odometer::total() { return pose.travelled; }

void Odometer::zero() { pose.travelled = 0; }

#ifndef MAKE_STATIC_COMPONENT
extern "C" {
Component* getComponent();
void releaseComponent(Component* com);
}

Component* getComponent() { return new Odometer(); }

void releaseComponent(Component* com) { delete com; }
#endif
