#include "recording_check.hpp"

#include <cstdio>

namespace sculpt::tools {

bool log_is_complete(const rt::RecordingCounts& counts, const std::string& model) {
  if (!counts.logging || (counts.log_dropped == 0 && counts.write_errors == 0)) return true;
  std::fprintf(stderr,
               "log      %s is incomplete: %llu events dropped (the logger fell behind), %llu writes failed (a full "
               "disk, a file size limit, a device gone): the base model and this log no longer give %s\n",
               counts.log_path.c_str(), static_cast<unsigned long long>(counts.log_dropped),
               static_cast<unsigned long long>(counts.write_errors), model.c_str());
  return false;
}

}  // namespace sculpt::tools
