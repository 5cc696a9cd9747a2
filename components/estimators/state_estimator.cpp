// Registers the state-estimation detector (state_estimator.hpp) in libkeel_stock, under the class
// name its profile StateEstimator.xml uses.
#include "state_estimator.hpp"

KEEL_REGISTER_COMPONENT_AS(keel::components::StateEstimator, "StateEstimator")
