// Registers the sliding-window process-model monitor (sliding_window_monitor.hpp) in
// libkeel_stock, under the class name its profile SlidingWindowMonitor.xml uses.
#include "sliding_window_monitor.hpp"

KEEL_REGISTER_COMPONENT_AS(keel::components::SlidingWindowMonitor, "SlidingWindowMonitor")
