#pragma once
// --bad-normals, shared by the commands that load a model file (deform, replay, render): the option,
// the check it asks for, the stderr line and the JSON entry, so both say the same thing.

#include <nlohmann/json_fwd.hpp>

#include <string>

#include "sculpt/deform/normal_check.hpp"
#include "sculpt/deform/point_model.hpp"

namespace CLI {  // NOLINT(readability-identifier-naming): CLI11's own
class App;
class Option;
}  // namespace CLI

namespace sculpt::tools {

class BadNormalsOption {
 public:
  BadNormalsOption() = default;
  // CLI11 writes the choice into this object, so it must stay where it was registered.
  BadNormalsOption(const BadNormalsOption&) = delete;
  BadNormalsOption& operator=(const BadNormalsOption&) = delete;

  /// Adds --bad-normals reestimate|refuse (default reestimate) to the subcommand.
  void add_to(CLI::App& sub);

  deform::NormalPolicy policy() const;
  /// True when the user gave the option (so it overrides a scene's model.bad_normals).
  bool given() const;

  /// check_normals() on a model just read from `path`; prints "<path>: <what it did>" on stderr
  /// when it changed anything. Throws deform::ModelFileError when the policy refuses the file.
  deform::NormalReport check(deform::PointModel& model, const std::string& path) const;

  /// {"policy", "zero_or_nonfinite", "renormalised"} for a command's JSON summary.
  nlohmann::json to_json(const deform::NormalReport& report) const;

 private:
  std::string choice_ = "reestimate";
  const CLI::Option* option_ = nullptr;
};

}  // namespace sculpt::tools
