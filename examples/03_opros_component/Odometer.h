#ifndef _Odometer_COMPONENT_H
#define _Odometer_COMPONENT_H
/*
 *  An OPRoS component, laid out as OPRoS's component generator writes one, built unchanged
 *  against keel's OPRoS headers (examples/03_opros_component, docs/opros.md).
 */
#include <Component.h>
#include <InputDataPort.h>
#include <OPRoSTypes.h>
#include <OutputDataPort.h>

#include "OdometryProvided.h"

class Odometer : public Component, public IOdometry {
 protected:
  // data
  InputDataPort<double> wheelSpeed;  // m/s, from the wheel driver
  OutputDataPort<double> distance;   // m travelled
                                     // state kept across a reset: checkpointed by keel (critical() in onInitialize)
  struct Pose {
    double travelled;
    long cycles;
  } pose;
  double period;

 public:
  Odometer();
  Odometer(const std::string& name);
  ~Odometer() override;
  virtual void portSetup();

 protected:
  ReturnType onInitialize() override;
  ReturnType onStart() override;
  ReturnType onStop() override;
  ReturnType onReset() override;
  ReturnType onError() override;
  ReturnType onRecover() override;
  ReturnType onDestroy() override;

 public:
  ReturnType onEvent(Event* evt) override;
  ReturnType onExecute() override;
  ReturnType onUpdated() override;
  ReturnType onPeriodChanged() override;

  double total() override;
  void zero() override;
};

#endif
