#ifndef _Odometry_PROVIDED_PORT_H
#define _Odometry_PROVIDED_PORT_H
/*
 *  The provided side of the service type Odometry (Odometry.xml), as OPRoS's generator writes it.
 */
#include <OPRoSTypes.h>
#include <ProvidedMethod.h>
#include <ProvidedServicePort.h>

#ifndef _IOdometry_CLASS_DEF
#define _IOdometry_CLASS_DEF
class IOdometry {
 public:
  virtual double total() = 0;
  virtual void zero() = 0;
};
#endif

class OdometryProvided : public ProvidedServicePort, public IOdometry {
 protected:
  IOdometry* pcom;
  typedef ProvidedMethod<double> totalFuncType;
  totalFuncType* totalFunc;
  typedef ProvidedMethod<void> zeroFuncType;
  zeroFuncType* zeroFunc;

 public:
  virtual double total() {
    opros_assert(totalFunc != NULL);
    return (*totalFunc)();
  }
  virtual void zero() {
    opros_assert(zeroFunc != NULL);
    (*zeroFunc)();
  }

  OdometryProvided(IOdometry* fn) {
    pcom = fn;
    totalFunc = NULL;
    zeroFunc = NULL;
    setup();
  }

  virtual void setup() {
    Method* ptr_method;
    ptr_method = makeProvidedMethod(&IOdometry::total, pcom, "total");
    opros_assert(ptr_method != NULL);
    addMethod("total", ptr_method);
    totalFunc = reinterpret_cast<totalFuncType*>(ptr_method);
    ptr_method = makeProvidedMethod(&IOdometry::zero, pcom, "zero");
    opros_assert(ptr_method != NULL);
    addMethod("zero", ptr_method);
    zeroFunc = reinterpret_cast<zeroFuncType*>(ptr_method);
  }
};
#endif
