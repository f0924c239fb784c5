#include "sculpt/rt/transport_url.hpp"

#include <arpa/inet.h>

#include <array>
#include <charconv>
#include <cstdint>
#include <string>

#include "sculpt/base/regular_file.hpp"

namespace sculpt::rt {
namespace {

constexpr std::array<std::string_view, 5> kProviders = {"udpm", "mpudpm", "tcpq", "memq", "file"};

// 'text', built by appending: GCC 12 warns (-Wrestrict, a known false positive) on
// "'" + std::string(text) + "'" chains.
std::string quote(std::string_view text) {
  std::string quoted;
  quoted.reserve(text.size() + 2);
  quoted.push_back('\'');
  quoted.append(text);
  quoted.push_back('\'');
  return quoted;
}

// A decimal integer in [lo, hi], the whole text.
bool integer_in(std::string_view text, long lo, long hi) {
  long value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  return error == std::errc() && end == text.data() + text.size() && value >= lo && value <= hi;
}

std::string multicast_problem(std::string_view network) {
  if (network.empty()) return "";  // LCM's default group and port
  const std::size_t colon = network.rfind(':');
  const std::string address(network.substr(0, colon));
  in_addr parsed{};
  if (::inet_pton(AF_INET, address.c_str(), &parsed) != 1) {
    return quote(address).append(" is not an IPv4 address (udpm needs a multicast group, e.g. 239.255.76.67)");
  }
  const std::uint32_t first_octet = ntohl(parsed.s_addr) >> 24;
  if (first_octet < 224 || first_octet > 239) {
    return quote(address).append(" is not a multicast address (224.0.0.0 to 239.255.255.255)");
  }
  if (colon != std::string_view::npos && !integer_in(network.substr(colon + 1), 1, 65535)) {
    return "port " + quote(network.substr(colon + 1)).append(" is not in 1..65535");
  }
  return "";
}

std::string options_problem(std::string_view options) {
  while (!options.empty()) {
    const std::size_t amp = options.find('&');
    const std::string_view option = options.substr(0, amp);
    options = amp == std::string_view::npos ? std::string_view() : options.substr(amp + 1);
    const std::size_t eq = option.find('=');
    if (eq == std::string_view::npos || eq == 0) {
      return "option " + quote(option).append(" is not key=value");
    }
    const std::string_view key = option.substr(0, eq), value = option.substr(eq + 1);
    if (key == "ttl" && !integer_in(value, 0, 255)) return "ttl " + quote(value).append(" is not in 0..255");
    if (key == "recv_buf_size" && !integer_in(value, 1, 1L << 30)) {
      return "recv_buf_size " + quote(value).append(" is not a positive byte count");
    }
  }
  return "";
}

}  // namespace

std::string lcm_url_problem(std::string_view url) {
  const std::string quoted = quote(url).append(" ");
  const std::size_t scheme_end = url.find("://");
  if (scheme_end == std::string_view::npos) {
    return quoted + "is not an LCM URL (provider://address, e.g. udpm://239.255.76.67:7667)";
  }
  const std::string_view provider = url.substr(0, scheme_end);
  bool known = false;
  for (const std::string_view p : kProviders) known = known || p == provider;
  if (!known) return quoted + "names no LCM provider (udpm, mpudpm, tcpq, memq or file)";
  const std::string_view rest = url.substr(scheme_end + 3);
  const std::size_t question = rest.find('?');
  const std::string_view network = rest.substr(0, question);
  const std::string_view options = question == std::string_view::npos ? std::string_view() : rest.substr(question + 1);
  std::string problem;
  if (provider == "udpm" || provider == "mpudpm") problem = multicast_problem(network);
  if (provider == "file" && network.empty()) problem = "names no file";
  // LCM's log-file provider opens with fopen, which waits for a FIFO's other end for ever.
  if (provider == "file" && problem.empty()) {
    if (const std::string kind = base::non_regular_kind(std::string(network)); !kind.empty()) {
      problem = quote(network).append(" is ").append(kind).append(", not a log file");
    }
  }
  if (problem.empty()) problem = options_problem(options);
  return problem.empty() ? "" : quoted + "is not a usable LCM URL: " + problem;
}

std::string lcm_channel_problem(std::string_view channel) {
  if (channel.empty()) return "must not be empty";
  if (channel.find('\0') != std::string_view::npos) return "holds a NUL byte";
  if (channel.size() > kMaxLcmChannelLength) {
    return "is " + std::to_string(channel.size()) + " bytes long; LCM takes at most " +
           std::to_string(kMaxLcmChannelLength);
  }
  return {};
}

}  // namespace sculpt::rt
