#include "sculpt/hal/glove_source.hpp"

namespace sculpt::hal {

SourceCounters AtomicSourceCounters::snapshot() const noexcept {
  // Relaxed: each counter is independently monotonic; readers want recent values, not a
  // consistent cut across counters (that would need a lock the I/O thread shares).
  constexpr auto kOrder = std::memory_order_relaxed;
  SourceCounters c;
  c.samples = samples.load(kOrder);
  c.crc_errors = crc_errors.load(kOrder);
  c.framing_errors = framing_errors.load(kOrder);
  c.sequence_gaps = sequence_gaps.load(kOrder);
  c.overflows = overflows.load(kOrder);
  c.reconnects = reconnects.load(kOrder);
  c.disconnects = disconnects.load(kOrder);
  c.error_frames = error_frames.load(kOrder);
  c.bus_off = bus_off.load(kOrder);
  return c;
}

}  // namespace sculpt::hal
