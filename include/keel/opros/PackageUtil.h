// keel's OPRoS compatibility: GetResourcePath(), the component's resource folder: its
// component profile's folder followed by "res/", with the trailing separator.
#pragma once

#include <string>

class Component;

/// The resource folder of `component` (set by keel when it loads the component).
std::string opros_package_getResPath(Component* component);

#define GetResourcePath() (opros_package_getResPath(this))
