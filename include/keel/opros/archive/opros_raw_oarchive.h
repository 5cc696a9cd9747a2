// opros_raw_oarchive.h — keel's own OPRoS-compatible raw output archive: the binary format
// without type tags (opros_binary_format.h), for peers that know the layout. One thread at a time.
#pragma once

#include "opros_binary_oarchive.h"

namespace opros {
namespace archive {

class raw_oarchive : public detail::basic_binary_oarchive<false> {
 public:
  using basic_binary_oarchive::basic_binary_oarchive;
};

}  // namespace archive
}  // namespace opros
