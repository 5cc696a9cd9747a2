// opros_archive.h — keel's own OPRoS-compatible umbrella header: the archive interfaces and
// every concrete archive (binary, raw, string). Header-only.
#pragma once

#include "opros_access.h"
#include "opros_binary.h"
#include "opros_binary_iarchive.h"
#include "opros_binary_oarchive.h"
#include "opros_iarchive.h"
#include "opros_iarchive_stl.h"
#include "opros_oarchive.h"
#include "opros_oarchive_stl.h"
#include "opros_raw_iarchive.h"
#include "opros_raw_oarchive.h"
#include "opros_string_iarchive.h"
#include "opros_string_oarchive.h"
#include "opros_type_info.h"
#include "opros_type_traits.h"
