// libFuzzer target: keel's OPRoS archive readers (include/keel/opros/archive), which an OPRoS
// component's data travel through when it reads what another process or a file wrote. The first
// byte picks the archive (binary, raw, string); the rest is read as a sequence of the values OPRoS
// components exchange (numbers, strings, containers, a user type with save/load, the device
// types) until the archive refuses. A refusal is an archive_exception; anything else escaping, a
// sanitizer report or an allocation beyond the input's size is a finding.
#include <ApiTypes.h>
#include <Property.h>
#include <archive/opros_binary_iarchive.h>
#include <archive/opros_raw_iarchive.h>
#include <archive/opros_string_iarchive.h>

#include <cstddef>
#include <cstdint>
#include <list>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "opros_person.hpp"

namespace {

void readAll(opros::archive::iarchive& ar) {
  for (int i = 0; i < 16; ++i) {
    int n = 0;
    double d = 0;
    std::string s;
    std::vector<double> v;
    std::map<std::string, int> m;
    std::list<std::string> l;
    Person p;
    OPRoS::Property property;
    OPRoS::Float64Array array;
    ar >> n >> d >> s >> v >> m >> l >> p >> property >> array;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  try {
    switch (data[0] % 3) {
      case 0: {
        opros::archive::binary_iarchive ar(&in);
        readAll(ar);
        break;
      }
      case 1: {
        opros::archive::raw_iarchive ar(&in);
        readAll(ar);
        break;
      }
      default: {
        opros::archive::string_iarchive ar(&in);
        readAll(ar);
        break;
      }
    }
  } catch (const opros::archive::archive_exception&) {
    // the reader refused the input: what it must do with bytes it cannot read
  }
  return 0;
}
