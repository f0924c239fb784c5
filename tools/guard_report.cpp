#include "guard_report.hpp"

#include <nlohmann/json.hpp>

namespace sculpt::tools {

std::string acted_guards(const deform::GuardCounts& guards, char separator) {
  std::string text;
  deform::for_each_guard(guards, [&](const char* name, std::uint32_t count) {
    if (count == 0) return;
    text += ' ';
    text += name;
    text += separator;
    text += std::to_string(count);
  });
  return text;
}

nlohmann::json guards_json(const deform::GuardCounts& guards) {
  nlohmann::json json = nlohmann::json::object();
  deform::for_each_guard(guards, [&](const char* name, std::uint32_t count) { json[name] = count; });
  return json;
}

}  // namespace sculpt::tools
