// opros_iarchive_fwd.h — keel's own OPRoS-compatible forward declaration of the input archive.
// Header-only.
#pragma once

namespace opros {
namespace archive {
class iarchive;
}  // namespace archive
}  // namespace opros
