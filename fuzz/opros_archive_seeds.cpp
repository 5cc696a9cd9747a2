// Not a fuzz target: writes opros_archive's seeds (fuzz/corpus/opros_archive/seed_0..2), one per
// archive (binary, raw, string), each the values fuzz/opros_archive_fuzz.cpp reads once, behind the
// byte that picks its archive. Built only when asked for (--target fuzz_opros_archive_seeds).
//   build-fuzz/fuzz/opros_archive_seeds fuzz/corpus/opros_archive
#include <ApiTypes.h>
#include <Property.h>
#include <archive/opros_binary_oarchive.h>
#include <archive/opros_raw_oarchive.h>
#include <archive/opros_string_oarchive.h>

#include <cstdio>
#include <fstream>
#include <list>
#include <map>
#include <sstream>

#include "opros_person.hpp"

void write(opros::archive::oarchive& ar) {
  int n = 7;
  double d = 2.5;
  std::string s = "hello";
  std::vector<double> v{1, 2, 3};
  std::map<std::string, int> m{{"a", 1}, {"b", 2}};
  std::list<std::string> l{"x", "y"};
  Person p(42, "Hong Gildong");
  OPRoS::Property property;
  property.SetValue("port", "COM1");
  OPRoS::Float64Array array;
  ar << n << d << s << v << m << l << p << property << array;
}
int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: opros_archive_seeds DIR\n");
    return 2;
  }
  for (int kind = 0; kind < 3; ++kind) {
    std::ostringstream os;
    if (kind == 0) {
      opros::archive::binary_oarchive ar(&os);
      write(ar);
    } else if (kind == 1) {
      opros::archive::raw_oarchive ar(&os);
      write(ar);
    } else {
      opros::archive::string_oarchive ar(&os);
      write(ar);
    }
    std::ofstream out(std::string(argv[1]) + "/seed_" + std::to_string(kind), std::ios::binary);
    out << static_cast<char>(kind) << os.str();
  }
}
