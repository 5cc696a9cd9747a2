// The monitor's web page (src/monitor/page/index.html), embedded in the keel command at build
// time: the page keel serves at `/`.
#pragma once

#include <string_view>

namespace keel::monitor {

/// The page's HTML, with its script and style inline (no other resource, no internet).
std::string_view pageHtml();

}  // namespace keel::monitor
