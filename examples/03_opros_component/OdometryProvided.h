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
  using totalFuncType = ProvidedMethod<double>;
  totalFuncType* totalFunc;
  using zeroFuncType = ProvidedMethod<void>;
  zeroFuncType* zeroFunc;

 public:
  double total() override {
    opros_assert(totalFunc != nullptr);
    return (*totalFunc)();
  }
  void zero() override {
    opros_assert(zeroFunc != nullptr);
    (*zeroFunc)();
  }

  OdometryProvided(IOdometry* fn) : pcom(fn), totalFunc(nullptr), zeroFunc(nullptr) { setup(); }

  virtual void setup() {
    Method* ptr_method;
    ptr_method = makeProvidedMethod(&IOdometry::total, pcom, "total");
    opros_assert(ptr_method != nullptr);
    addMethod("total", ptr_method);
    totalFunc = reinterpret_cast<totalFuncType*>(ptr_method);
    ptr_method = makeProvidedMethod(&IOdometry::zero, pcom, "zero");
    opros_assert(ptr_method != nullptr);
    addMethod("zero", ptr_method);
    zeroFunc = reinterpret_cast<zeroFuncType*>(ptr_method);
  }
};
#endif
