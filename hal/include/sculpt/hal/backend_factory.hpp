#pragma once
// Builds the glove source and haptic sink a scene names, and nothing else.

#include <memory>

#include "sculpt/hal/backend_config.hpp"
#include "sculpt/hal/glove_source.hpp"
#include "sculpt/hal/haptic_sink.hpp"

namespace sculpt::hal {

/// Throws std::runtime_error when the backend was left out of this build
/// (SCULPT_WITH_USB/CAN/LCM off), naming the option that would bring it in.
std::unique_ptr<GloveSource> make_glove_source(const GloveConfig& config);
/// nullptr for SinkKind::kNone.
std::unique_ptr<HapticSink> make_haptic_sink(const HapticConfig& config);

}  // namespace sculpt::hal
