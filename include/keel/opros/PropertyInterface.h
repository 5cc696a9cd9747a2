// keel's OPRoS compatibility: PropertyInterface, a component's properties as text. keel sets
// them from the profile (after subcomponent overrides and `keel run --set`) before
// onInitialize.
#pragma once

#include <map>
#include <string>

class PropertyInterface {
 public:
  virtual ~PropertyInterface() = default;
  virtual void setProperty(const std::string& name, const std::string& value) = 0;
  /// The value of `name`, or an empty string when the component has no such property.
  virtual std::string& getProperty(const std::string& name) = 0;
  virtual std::map<std::string, std::string>& getPropertyMap() = 0;
};
