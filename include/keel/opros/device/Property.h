// Property.h — keel's own, from-scratch OPRoS-compatible version of the device API's Property:
// a string-to-string parameter map with a status, passed to and returned by device services.
//
// One definition serves both OPRoS flavours (docs/opros.md): the 2014 `OPRoS::Property` (with its
// `ReturnType status`) is also the global `Property` of 2012 code, and this header makes
// std::vector, std::valarray, std::string and std::map usable unqualified, as 2012 code expects
// (through using-declarations, not `using namespace std`). A Property is a value; one object is
// not shared between threads without a lock.
#ifndef KEEL_OPROS_DEVICE_PROPERTY_H
#define KEEL_OPROS_DEVICE_PROPERTY_H

#include <cassert>
#include <map>
#include <string>
#include <valarray>
#include <vector>

#include "../ReturnType.h"
#include "../archive/opros_archive.h"

using std::map;
using std::string;
using std::valarray;
using std::vector;

namespace OPRoS {

class Property {
 public:
  Property() = default;

  ReturnType status = OPROS_SUCCESS;

  // Replaces all values, e.g. with a component's getPropertyMap().
  void SetProperty(const std::map<std::string, std::string>& values) { data = values; }
  std::map<std::string, std::string> GetProperty() const { return data; }

  void SetValue(const std::string& name, const std::string& value) { data[name] = value; }
  // The value of name, or "" when there is none (OPRoS also added the name then; keel does not).
  std::string GetValue(const std::string& name) const {
    const auto found = data.find(name);
    return found == data.end() ? std::string() : found->second;
  }
  bool FindName(const std::string& name) const { return data.find(name) != data.end(); }

  void save(opros::archive::oarchive& ar, const unsigned int) {
    ar << data;
    ar << status;
  }
  void load(opros::archive::iarchive& ar, const unsigned int) {
    ar >> data;
    ar >> status;
  }

 protected:
  friend class opros::archive::access;
  std::map<std::string, std::string> data;
};

inline std::string typeName(Property*) { return "Property"; }

}  // namespace OPRoS

using OPRoS::Property;

#endif  // KEEL_OPROS_DEVICE_PROPERTY_H
