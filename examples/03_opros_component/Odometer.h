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
  Odometer(const std::string& compId);
  virtual ~Odometer();
  virtual void portSetup();

 protected:
  virtual ReturnType onInitialize();
  virtual ReturnType onStart();
  virtual ReturnType onStop();
  virtual ReturnType onReset();
  virtual ReturnType onError();
  virtual ReturnType onRecover();
  virtual ReturnType onDestroy();

 public:
  virtual ReturnType onEvent(Event* evt);
  virtual ReturnType onExecute();
  virtual ReturnType onUpdated();
  virtual ReturnType onPeriodChanged();

  virtual double total();
  virtual void zero();
};

#endif
