#pragma once
// How every message prints a number: printf's %g, six significant digits. std::to_string and
// %f print 1e-9 as 0.000000 and the largest double as 309 digits; %g prints 1e-09 and
// 1.79769e+308, and 0.5 as 0.5. Header-only so that every library can use it without a link.

#include <cstdio>
#include <string>

namespace sculpt::base {

/// `value` as %g prints it: "0.5", "1e-09", "3e+07", "nan", "inf".
inline std::string number_text(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", value);
  return text;
}

}  // namespace sculpt::base
