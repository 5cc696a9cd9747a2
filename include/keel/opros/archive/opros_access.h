// opros_access.h — keel's own OPRoS-compatible version of the header a serialisable user type
// includes. It declares `opros::archive::access` (which the type befriends) and, unlike OPRoS's
// forward declarations only, the full oarchive/iarchive, so that the type's inline save/load
// members (`ar << m_age;`) compile with this include alone. Header-only.
#pragma once

#include "opros_archive_common.h"
#include "opros_iarchive.h"
#include "opros_oarchive.h"
