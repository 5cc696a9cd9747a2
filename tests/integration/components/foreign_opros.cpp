// A library as OPRoS's own build made them: it exports getComponent()/releaseComponent() but was
// not built with keel's OPRoS layer, so keel cannot host what it makes (opros_components_test).
extern "C" void* getComponent() { return nullptr; }
extern "C" void releaseComponent(void*) {}
