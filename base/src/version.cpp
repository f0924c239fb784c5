#include "sculpt/base/version.hpp"

#ifndef SCULPT_VERSION
#error "SCULPT_VERSION is defined by base/CMakeLists.txt from PROJECT_VERSION"
#endif

namespace sculpt::base {

const char* project_version() noexcept { return SCULPT_VERSION; }

}  // namespace sculpt::base
