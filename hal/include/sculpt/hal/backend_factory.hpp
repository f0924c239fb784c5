#pragma once
// Builds the glove source and haptic sink a scene names, and nothing else. The backends'
// classes (their I/O threads, queues and devices) are private to hal (hal/src): code outside
// hal sees only the GloveSource and HapticSink interfaces it gets from here.

#include <memory>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/glove_source.hpp"
#include "sculpt/hal/haptic_sink.hpp"

#if SCULPT_HAS_LCM
namespace lcm {
class LCM;
}  // namespace lcm
#endif

namespace sculpt::hal {

/// Throws std::runtime_error when the backend was left out of this build
/// (SCULPT_WITH_USB/CAN/LCM off), naming the option that would bring it in.
std::unique_ptr<GloveSource> make_glove_source(const GloveConfig& config);
/// nullptr for SinkKind::kNone.
std::unique_ptr<HapticSink> make_haptic_sink(const HapticConfig& config);

#if SCULPT_HAS_LCM
/// An LCM glove source listening on an LCM instance the caller owns (not owned; it must outlive
/// the source), e.g. memq://, which delivers only within one instance: a test publishes on it.
std::unique_ptr<GloveSource> make_lcm_glove_source(lcm::LCM& bus, const LcmConfig& config, std::size_t queue_capacity);
#endif

}  // namespace sculpt::hal
