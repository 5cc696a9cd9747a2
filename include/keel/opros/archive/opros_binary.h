// opros_binary.h — keel's own OPRoS-compatible `opros::binary`: an owned block of bytes that an
// archive saves and loads as one opaque item (save_binary/load_binary). Not thread-safe: one
// owner at a time, like any value.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "opros_iarchive.h"
#include "opros_oarchive.h"

namespace opros {

class binary {
 public:
  binary() = default;
  virtual ~binary() = default;

  // Makes the block size bytes long, all zero (OPRoS also discarded the old contents).
  virtual void resize(unsigned long size) { bytes_.assign(size, 0); }
  virtual char* data() { return bytes_.empty() ? nullptr : bytes_.data(); }
  virtual unsigned long size() { return static_cast<unsigned long>(bytes_.size()); }

  const char* data() const { return bytes_.empty() ? nullptr : bytes_.data(); }
  unsigned long size() const { return static_cast<unsigned long>(bytes_.size()); }

  void save(archive::oarchive& ar, const unsigned int) {
    ar.save_binary(bytes_.data(), static_cast<long>(bytes_.size()));
  }

  void load(archive::iarchive& ar, const unsigned int) {
    char* block = nullptr;
    long length = 0;
    ar.load_binary(&block, length);
    const std::unique_ptr<char[]> owned(block);
    bytes_.assign(owned.get(), owned.get() + length);
  }

 private:
  std::vector<char> bytes_;
};

inline std::string typeName(binary*) { return "opros::binary"; }

}  // namespace opros
