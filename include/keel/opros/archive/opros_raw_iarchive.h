// opros_raw_iarchive.h — keel's own OPRoS-compatible raw input archive: reads raw_oarchive's
// untagged binary. A stream that ends early still throws; a mismatched type cannot be detected.
// One thread at a time.
#pragma once

#include "opros_binary_iarchive.h"

namespace opros {
namespace archive {

class raw_iarchive : public detail::basic_binary_iarchive<false> {
 public:
  using basic_binary_iarchive::basic_binary_iarchive;
};

}  // namespace archive
}  // namespace opros
