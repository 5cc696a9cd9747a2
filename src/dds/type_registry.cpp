// The registry of DDS message types (type_registry.hpp), and the write the generated outlets
// call (keel/detail/dds_type.hpp).
#include "dds/type_registry.hpp"

#include <dds/dds.h>

#include <algorithm>
#include <map>
#include <mutex>

namespace keel::dds {
namespace {

struct Registry {
  std::mutex mutex;
  std::map<std::string, detail::DdsType, std::less<>> by_name;
};

Registry& registry() {
  static Registry r;  // constructed on first use: registrations run in static initialisers
  return r;
}

}  // namespace

const detail::DdsType* findType(std::string_view ros_name) {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  const auto it = r.by_name.find(ros_name);
  return it == r.by_name.end() ? nullptr : &it->second;  // nodes of a std::map do not move
}

std::vector<std::string> typeNames() {
  Registry& r = registry();
  std::lock_guard lock(r.mutex);
  std::vector<std::string> out;
  for (const auto& [name, type] : r.by_name) out.push_back(name);
  return out;
}

}  // namespace keel::dds

namespace keel::detail {

void registerDdsType(const DdsType& type) {
  keel::dds::Registry& r = keel::dds::registry();
  std::lock_guard lock(r.mutex);
  r.by_name.try_emplace(type.ros_name, type);
}

bool ddsWrite(std::int32_t writer, const void* sample) { return dds_write(writer, sample) == DDS_RETCODE_OK; }

}  // namespace keel::detail
