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
  using getFuncType = ProvidedMethod<int>;
  getFuncType* getFunc = nullptr;
  using addFuncType = ProvidedMethod<int>;
  addFuncType* addFunc = nullptr;

 public:
  int get() override {
    opros_assert(getFunc != nullptr);
    return (*getFunc)();
  }
  int add(int amount) override {
    opros_assert(addFunc != nullptr);
    return (*addFunc)(amount);
  }
  CounterProvided(ICounter* fn) : pcom(fn) { setup(); }
  virtual void setup() {
    Method* ptr_method;
    ptr_method = makeProvidedMethod(&ICounter::get, pcom, "get");
    opros_assert(ptr_method != nullptr);
    addMethod("get", ptr_method);
    getFunc = reinterpret_cast<getFuncType*>(ptr_method);
    ptr_method = makeProvidedMethod(&ICounter::add, pcom, "add");
    opros_assert(ptr_method != nullptr);
    addMethod("add", ptr_method);
    addFunc = reinterpret_cast<addFuncType*>(ptr_method);
  }
};

class CounterRequired : public RequiredServicePort {
 protected:
  using getFuncType = RequiredMethod<int>;
  getFuncType* getFunc = nullptr;
  using addFuncType = RequiredMethod<int>;
  addFuncType* addFunc = nullptr;

 public:
  CounterRequired() { setup(); }
  int get() {
    opros_assert(getFunc != nullptr);
    return (*getFunc)();
  }
  int add(int amount) {
    opros_assert(addFunc != nullptr);
    return (*addFunc)(amount);
  }
  virtual void setup() {
    Method* ptr_method;
    ptr_method = makeRequiredMethod(&CounterRequired::get, "get");
    opros_assert(ptr_method != nullptr);
    addMethod("get", ptr_method);
    getFunc = reinterpret_cast<getFuncType*>(ptr_method);
    ptr_method = makeRequiredMethod(&CounterRequired::add, "add");
    opros_assert(ptr_method != nullptr);
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
  ~OprosCounter() override = default;
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
  int get() override { return state.executions; }
  int add(int amount) override {
    state.received += amount;
    return state.received;
  }

 protected:
  ReturnType onInitialize() override {
    critical(&state, sizeof state);
    return OPROS_SUCCESS;
  }
  ReturnType onStart() override { return OPROS_SUCCESS; }
  ReturnType onStop() override {
    if (!getProperty("trace").empty()) {
      std::ofstream out(getProperty("trace").c_str());
      out << state.executions << ' ' << state.received << ' ' << events << '\n';
    }
    return OPROS_SUCCESS;
  }
  ReturnType onReset() override { return OPROS_SUCCESS; }
  ReturnType onError() override { return OPROS_SUCCESS; }
  ReturnType onRecover() override { return OPROS_SUCCESS; }
  ReturnType onDestroy() override { return OPROS_SUCCESS; }

 public:
  ReturnType onEvent(Event* evt) override {
    if (evt->getId() == "tick") ++events;
    return OPROS_SUCCESS;
  }
  ReturnType onExecute() override {
    ++state.executions;
    opros_any* p = in.pop();
    if (p != nullptr) {
      state.received += in.getContent(*p);
      delete p;
    }
    if (!faulted && std::strtol(getProperty("fault_at").c_str(), nullptr, 10) == state.executions) {
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
  ReturnType onUpdated() override { return OPROS_SUCCESS; }
  ReturnType onPeriodChanged() override { return OPROS_SUCCESS; }
};

extern "C" {
Component* getComponent();
void releaseComponent(Component* com);
}
Component* getComponent() { return new OprosCounter(); }
void releaseComponent(Component* com) { delete com; }
