// keel's OPRoS compatibility: the umbrella header of OPRoS 2014 component sources.
#pragma once

#include "Component.h"
#include "EventCallBack.h"
#include "EventData.h"
#include "InputDataPort.h"
#include "InputEventPort.h"
#include "OPRoSTypes.h"
#include "OutputDataPort.h"
#include "OutputEventPort.h"
#include "ProvidedMethod.h"
#include "ProvidedServicePort.h"
#include "RequiredMethod.h"
#include "RequiredServicePort.h"
#include "ServiceUtils.h"
#include "ext/EventPortX.h"
