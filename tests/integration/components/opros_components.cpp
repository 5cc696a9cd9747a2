// A component written against the OPRoS API as OPRoS's code generator lays one out, for keel's
// tests of OPRoS components (tests/integration/opros_components_test.cpp). OPRoS's convention:
// one component per library, exported through getComponent()/releaseComponent().
//
// OprosCounter counts its cycles in memory registered with critical() and pushes the count on
// `count`; it adds what arrives on `in` (LAST, 1, as generated code writes it); its provided
// service `Counter` answers `get()` and `add(int)`. Its property `fault_at` (an execution
// number) and `fault` (segv, throw, error, hang) make it fail there, once per process, after
// scribbling over its critical state (a reset that restores the checkpoint undoes it). At stop
// it writes "<executions> <received> <events>" to the file its property `trace` names.
#include <OPRoSInclude.h>

#include <csignal>
#include <cstdlib>
#include <fstream>
#include <thread>

class ICounter {
 public:
  virtual ~ICounter() = default;
  virtual int get() = 0;
  virtual int add(int amount) = 0;
};

class CounterProvided : public ProvidedServicePort, public ICounter {
 protected:
  ICounter* pcom;
  typedef ProvidedMethod<int> getFuncType;
  getFuncType* getFunc;
  typedef ProvidedMethod<int> addFuncType;
  addFuncType* addFunc;

 public:
  virtual int get() {
    opros_assert(getFunc != NULL);
    return (*getFunc)();
  }
  virtual int add(int amount) {
    opros_assert(addFunc != NULL);
    return (*addFunc)(amount);
  }
  CounterProvided(ICounter* fn) {
    pcom = fn;
    getFunc = NULL;
    addFunc = NULL;
    setup();
  }
  virtual void setup() {
    Method* ptr_method;
    ptr_method = makeProvidedMethod(&ICounter::get, pcom, "get");
    opros_assert(ptr_method != NULL);
    addMethod("get", ptr_method);
    getFunc = reinterpret_cast<getFuncType*>(ptr_method);
    ptr_method = makeProvidedMethod(&ICounter::add, pcom, "add");
    opros_assert(ptr_method != NULL);
    addMethod("add", ptr_method);
    addFunc = reinterpret_cast<addFuncType*>(ptr_method);
  }
};

class CounterRequired : public RequiredServicePort {
 protected:
  typedef RequiredMethod<int> getFuncType;
  getFuncType* getFunc;
  typedef RequiredMethod<int> addFuncType;
  addFuncType* addFunc;

 public:
  CounterRequired() {
    getFunc = NULL;
    addFunc = NULL;
    setup();
  }
  int get() {
    opros_assert(getFunc != NULL);
    return (*getFunc)();
  }
  int add(int amount) {
    opros_assert(addFunc != NULL);
    return (*addFunc)(amount);
  }
  virtual void setup() {
    Method* ptr_method;
    ptr_method = makeRequiredMethod(&CounterRequired::get, "get");
    opros_assert(ptr_method != NULL);
    addMethod("get", ptr_method);
    getFunc = reinterpret_cast<getFuncType*>(ptr_method);
    ptr_method = makeRequiredMethod(&CounterRequired::add, "add");
    opros_assert(ptr_method != NULL);
    addMethod("add", ptr_method);
    addFunc = reinterpret_cast<addFuncType*>(ptr_method);
  }
};

class OprosCounter : public Component, public ICounter {
 protected:
  OutputDataPort<int> count;
  InputDataPort<int> in;
  OutputEventPort<std::string> tick;
  InputEventPort<std::string> ticks;
  CounterRequired* peer;
  struct State {
    int executions;
    int received;
  } state;
  int events;
  bool faulted;

 public:
  OprosCounter() : in(OPROS_LAST, 1) { portSetup(); }
  virtual ~OprosCounter() {}
  virtual void portSetup() {
    addPort("count", &count);
    addPort("in", &in);
    addPort("tick", &tick);
    addPort("ticks", &ticks);
    ticks.setOwner(this);
    ProvidedServicePort* pa1 = new CounterProvided(this);
    addPort("Counter", pa1);
    peer = new CounterRequired();
    addPort("Peer", peer);
    state.executions = 0;
    state.received = 0;
    events = 0;
    faulted = false;
  }
  virtual int get() { return state.executions; }
  virtual int add(int amount) {
    state.received += amount;
    return state.received;
  }

 protected:
  virtual ReturnType onInitialize() {
    critical(&state, sizeof state);
    return OPROS_SUCCESS;
  }
  virtual ReturnType onStart() { return OPROS_SUCCESS; }
  virtual ReturnType onStop() {
    if (!getProperty("trace").empty()) {
      std::ofstream out(getProperty("trace").c_str());
      out << state.executions << ' ' << state.received << ' ' << events << '\n';
    }
    return OPROS_SUCCESS;
  }
  virtual ReturnType onReset() { return OPROS_SUCCESS; }
  virtual ReturnType onError() { return OPROS_SUCCESS; }
  virtual ReturnType onRecover() { return OPROS_SUCCESS; }
  virtual ReturnType onDestroy() { return OPROS_SUCCESS; }

 public:
  virtual ReturnType onEvent(Event* evt) {
    if (evt->getId() == "tick") ++events;
    return OPROS_SUCCESS;
  }
  virtual ReturnType onExecute() {
    ++state.executions;
    opros_any* p = in.pop();
    if (p != NULL) {
      state.received += in.getContent(*p);
      delete p;
    }
    if (!faulted && atoi(getProperty("fault_at").c_str()) == state.executions) {
      faulted = true;
      state.executions = -1000000;  // what a fault may leave behind
      const std::string& fault = getProperty("fault");
      if (fault == "segv") std::raise(SIGSEGV);
      if (fault == "throw") throw std::runtime_error("OprosCounter: thrown on purpose");
      if (fault == "error") return OPROS_INTERNAL_FAULT;
      if (fault == "hang")
        for (;;) std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (getProperty("call_peer") == "true") state.received = peer->add(1);
    count.push(state.executions);
    EventData<std::string> e;
    e.setId("tick");
    e.setContentData(getId());
    tick.push(&e);
    return OPROS_SUCCESS;
  }
  virtual ReturnType onUpdated() { return OPROS_SUCCESS; }
  virtual ReturnType onPeriodChanged() { return OPROS_SUCCESS; }
};

extern "C" {
Component* getComponent();
void releaseComponent(Component* com);
}
Component* getComponent() { return new OprosCounter(); }
void releaseComponent(Component* com) { delete com; }
