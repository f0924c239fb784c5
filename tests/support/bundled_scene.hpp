#pragma once
// A bundled scene copied for a test: the tests run the scenes users run, but never write into
// the checkout (a scene's outputs point at its out/, which holds a user's sessions; test.sh
// fails a pass that touches it). SCULPT_SOURCE_DIR is the checkout, defined by tests/CMakeLists.

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

namespace sculpt::test {

/// Every `from` in `text` replaced by `to`, left to right, never inside what was put in.
inline void replace_every(std::string& text, const std::string& from, const std::string& to) {
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
    text.replace(at, from.size(), to);
  }
}

/// scenes/<name>.toml written into `dir` as <name>.toml: each `edits` pair's first text replaced
/// by its second, then the model path made absolute and the outputs put in `dir`, and `extra`
/// appended (a second table of a name the scene has is a TOML error, so `extra` brings tables
/// the scene does not have). Returns the copy's path.
inline std::filesystem::path copy_bundled_scene(const std::filesystem::path& dir, const std::string& name,
                                                const std::string& extra = "",
                                                const std::vector<std::pair<std::string, std::string>>& edits = {}) {
  std::ifstream in(std::filesystem::path(SCULPT_SOURCE_DIR) / "scenes" / (name + ".toml"));
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  for (const auto& [from, to] : edits) replace_every(text, from, to);
  replace_every(text, "../data/", std::string(SCULPT_SOURCE_DIR) + "/data/");
  replace_every(text, "../out/", dir.string() + "/");
  const std::filesystem::path copy = dir / (name + ".toml");
  std::ofstream(copy) << text << "\n" << extra << "\n";
  return copy;
}

}  // namespace sculpt::test
