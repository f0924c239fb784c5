#pragma once
// The project's version (CMake's PROJECT_VERSION), for `sculpt --version`, every JSON summary
// and the session header. A function rather than a macro in every target, so a version bump
// recompiles one file.

namespace sculpt::base {

/// "MAJOR.MINOR.PATCH", as the top-level CMakeLists.txt's project() declares it.
const char* project_version() noexcept;

}  // namespace sculpt::base
