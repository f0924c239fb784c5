// libFuzzer target: any text as a scene file. parse_scene either returns a scene or throws
// SceneError naming the file; nothing else escapes.

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <string_view>

#include "sculpt/rt/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)sculpt::rt::parse_scene(text, "fuzz-input.toml", "/nonexistent");
  } catch (const sculpt::rt::SceneError& e) {
    if (std::string(e.what()).find("fuzz-input.toml") == std::string::npos) {
      std::fprintf(stderr, "scene_fuzz: an error that does not name its file: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
