// CartesianCoordinateData.h — keel's own OPRoS-compatible name for a device record that ApiTypes.h defines
// (OprosDeviceData.h); kept for the code that includes it by this name. Header-only.
#ifndef KEEL_OPROS_DEVICE_CARTESIAN_COORDINATE_DATA_H
#define KEEL_OPROS_DEVICE_CARTESIAN_COORDINATE_DATA_H

#include "ApiTypes.h"

#endif
