// opros_iarchive_stl.h — keel's own OPRoS-compatible version of OPRoS's STL input support.
// keel's iarchive loads the STL containers itself (opros_iarchive.h); this name is kept for the
// code that includes it. Header-only.
#pragma once

#include "opros_iarchive.h"
