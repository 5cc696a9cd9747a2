// The user data type opros_archive's target reads and its seeds write: one as OPRoS's generator
// writes them (OneComp's PersonData: save/load for opros::archive, reached as a friend).
#pragma once

#include <archive/opros_access.h>
#include <archive/opros_iarchive.h>
#include <archive/opros_oarchive.h>

#include <string>
#include <utility>

class Person {
 public:
  Person() = default;
  Person(int age, std::string name) : age_(age), name_(std::move(name)) {}
  void save(opros::archive::oarchive& ar, const unsigned int) {
    ar << age_;
    ar << name_;
  }
  void load(opros::archive::iarchive& ar, const unsigned int) {
    ar >> age_;
    ar >> name_;
  }

 private:
  friend class opros::archive::access;
  int age_ = 0;
  std::string name_;
};
