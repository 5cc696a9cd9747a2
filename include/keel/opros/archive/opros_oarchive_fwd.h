// opros_oarchive_fwd.h — keel's own OPRoS-compatible forward declaration of the output archive.
// Header-only.
#pragma once

namespace opros {
namespace archive {
class oarchive;
}  // namespace archive
}  // namespace opros
