#pragma once
// The --lcm and --channel options' checks: an LCM URL or channel name is refused by CLI11 with
// its problem named, before any work, as a scene's lcm.url and channel are by the scene reader.

#include <CLI/CLI.hpp>

#include <string>

#include "sculpt/rt/transport_url.hpp"

namespace sculpt::tools {

inline CLI::Validator lcm_url_check() {
  return CLI::Validator([](std::string& url) { return rt::lcm_url_problem(url); }, "LCM URL");
}

inline CLI::Validator lcm_channel_check() {
  return CLI::Validator([](std::string& channel) { return rt::lcm_channel_problem(channel); }, "LCM channel");
}

}  // namespace sculpt::tools
