#pragma once
// The --lcm options' check: an LCM URL is refused by CLI11 with its problem named, before any
// work, as a scene's lcm.url is refused by the scene reader.

#include <CLI/CLI.hpp>

#include <string>

#include "sculpt/rt/transport_url.hpp"

namespace sculpt::tools {

inline CLI::Validator lcm_url_check() {
  return CLI::Validator([](std::string& url) { return rt::lcm_url_problem(url); }, "LCM URL");
}

}  // namespace sculpt::tools
