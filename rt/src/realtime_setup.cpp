#include "sculpt/rt/realtime_setup.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/prctl.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace sculpt::rt {
namespace {

std::string reason(int error) {
  std::string text = std::strerror(error);
  if (error == EPERM) text += " (needs root, CAP_SYS_NICE / CAP_IPC_LOCK, or an rtprio/memlock limit)";
  return text;
}

}  // namespace

std::vector<std::string> apply_realtime(const RealtimeOptions& options) {
  const int lowest = sched_get_priority_min(SCHED_FIFO);
  const int highest = sched_get_priority_max(SCHED_FIFO);
  if (options.fifo && (options.priority < lowest || options.priority > highest)) {
    throw std::invalid_argument("realtime: SCHED_FIFO priority must be " + std::to_string(lowest) + " to " +
                                std::to_string(highest) + ", got " + std::to_string(options.priority));
  }
  if (options.cpu < -1 || options.cpu >= CPU_SETSIZE) {
    throw std::invalid_argument("realtime: cpu must be -1 (any) or 0 to " + std::to_string(CPU_SETSIZE - 1) + ", got " +
                                std::to_string(options.cpu));
  }

  std::vector<std::string> warnings;
  if (options.fifo) {
    sched_param param{};
    param.sched_priority = options.priority;
    // pthread_setschedparam returns the error rather than setting errno.
    if (const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param); error != 0) {
      warnings.push_back("realtime: SCHED_FIFO priority " + std::to_string(options.priority) +
                         " refused: " + reason(error) + "; running with normal scheduling");
    }
  }
  if (options.lock_memory) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) != 0) {
      const int error = errno;
      warnings.push_back("realtime: mlockall refused: " + reason(error) + "; pages may fault in the loop");
    }
  }
  if (options.cpu >= 0) {
    cpu_set_t set;
    CPU_ZERO(&set);
    CPU_SET(options.cpu, &set);
    if (const int error = pthread_setaffinity_np(pthread_self(), sizeof(set), &set); error != 0) {
      warnings.push_back("realtime: pinning to CPU " + std::to_string(options.cpu) + " refused: " + reason(error) +
                         "; the thread may migrate");
    }
  }
  if (options.tight_timer_slack) {
    // 1, not 0: a slack of 0 means "back to the default".
    if (prctl(PR_SET_TIMERSLACK, 1UL, 0UL, 0UL, 0UL) != 0) {
      const int error = errno;
      warnings.push_back("realtime: timer slack 1 ns refused: " + reason(error) + "; wake-ups may be up to 50 us late");
    }
  }
  return warnings;
}

std::string required_refusal(const std::vector<std::string>& warnings) {
  for (const std::string& w : warnings) {
    if (w.rfind("realtime: SCHED_FIFO", 0) == 0 || w.rfind("realtime: mlockall", 0) == 0) return w;
  }
  return {};
}

}  // namespace sculpt::rt
