#include "sculpt/hal/backend_factory.hpp"

#include <stdexcept>

#include "serial_glove_source.hpp"
#include "serial_haptic_sink.hpp"
#include "sim_glove_source.hpp"
#if SCULPT_HAS_USB
#include "usb_glove_source.hpp"
#include "usb_haptic_sink.hpp"
#endif
#if SCULPT_HAS_CAN
#include "can_glove_source.hpp"
#include "can_haptic_sink.hpp"
#endif
#if SCULPT_HAS_LCM
#include "lcm_glove_source.hpp"
#include "lcm_haptic_sink.hpp"
#endif

namespace sculpt::hal {
namespace {

[[noreturn, maybe_unused]] void left_out(const char* what, const char* option) {
  throw std::runtime_error(std::string(what) + " was left out of this build; reconfigure with -D" + option + "=ON");
}

}  // namespace

std::unique_ptr<GloveSource> make_glove_source(const GloveConfig& c) {
  switch (c.backend) {
    case Backend::kSim: return std::make_unique<SimGloveSource>(c.sim, c.queue_capacity);
    case Backend::kSerial: return std::make_unique<SerialGloveSource>(c.serial, c.queue_capacity);
    case Backend::kUsb:
#if SCULPT_HAS_USB
      return std::make_unique<UsbGloveSource>(c.usb, c.queue_capacity);
#else
      left_out("the usb glove backend", "SCULPT_WITH_USB");
#endif
    case Backend::kLcm:
#if SCULPT_HAS_LCM
      return std::make_unique<LcmGloveSource>(c.lcm, c.queue_capacity);
#else
      left_out("the lcm glove backend", "SCULPT_WITH_LCM");
#endif
    case Backend::kSocketCan:
#if SCULPT_HAS_CAN
      return std::make_unique<CanGloveSource>(c.can, c.queue_capacity);
#else
      left_out("the socketcan glove backend", "SCULPT_WITH_CAN");
#endif
  }
  throw std::invalid_argument("unknown glove backend");
}

std::unique_ptr<HapticSink> make_haptic_sink(const HapticConfig& c) {
  switch (c.sink) {
    case SinkKind::kNone: return nullptr;
    case SinkKind::kSerial: return std::make_unique<SerialHapticSink>(c.serial, c.queue_capacity);
    case SinkKind::kLcm:
#if SCULPT_HAS_LCM
      return std::make_unique<LcmHapticSink>(c.lcm, c.queue_capacity);
#else
      left_out("the lcm haptic sink", "SCULPT_WITH_LCM");
#endif
    case SinkKind::kCan:
#if SCULPT_HAS_CAN
      return std::make_unique<CanHapticSink>(c.can, c.queue_capacity);
#else
      left_out("the can haptic sink", "SCULPT_WITH_CAN");
#endif
    case SinkKind::kUsb:
#if SCULPT_HAS_USB
      return std::make_unique<UsbHapticSink>(c.usb, static_cast<float>(c.max_force), c.queue_capacity);
#else
      left_out("the usb haptic sink", "SCULPT_WITH_USB");
#endif
  }
  throw std::invalid_argument("unknown haptic sink");
}

#if SCULPT_HAS_LCM
std::unique_ptr<GloveSource> make_lcm_glove_source(lcm::LCM& bus, const LcmConfig& config, std::size_t queue_capacity) {
  return std::make_unique<LcmGloveSource>(bus, config, queue_capacity);
}
#endif

}  // namespace sculpt::hal
