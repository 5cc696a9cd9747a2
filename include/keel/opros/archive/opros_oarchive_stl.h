// opros_oarchive_stl.h — keel's own OPRoS-compatible version of OPRoS's STL output support.
// keel's oarchive saves the STL containers itself (opros_oarchive.h); this name is kept for the
// code that includes it. Header-only.
#pragma once

#include "opros_oarchive.h"
