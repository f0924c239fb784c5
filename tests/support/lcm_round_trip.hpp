#pragma once
// A value through LCM's wire format and back, for the tests of every to_lcm / from_lcm pair
// (hal's glove and haptic messages, logging's records): the round trip must go through the
// encoded bytes, since only they show that a field's width, sign and order survive.

#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

namespace sculpt::test {

/// The message's wire bytes; a failure is added when encode() does not fill them exactly.
template <typename Message>
std::vector<std::uint8_t> lcm_encode(const Message& message) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(message.getEncodedSize()));
  EXPECT_EQ(message.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  return bytes;
}

/// Encodes `message`, decodes the bytes into a fresh message and converts that with from_lcm
/// (found by argument-dependent lookup in the value's namespace) into `received`. Fails, saying
/// which step, when decode does not take every byte or from_lcm refuses.
template <typename Message, typename Value>
::testing::AssertionResult lcm_round_trip(const Message& message, Value& received) {
  const std::vector<std::uint8_t> bytes = lcm_encode(message);
  Message decoded{};
  const int used = decoded.decode(bytes.data(), 0, static_cast<int>(bytes.size()));
  if (used != static_cast<int>(bytes.size())) {
    return ::testing::AssertionFailure() << "decode took " << used << " of " << bytes.size() << " bytes";
  }
  if (!from_lcm(decoded, received)) return ::testing::AssertionFailure() << "from_lcm refused the decoded message";
  return ::testing::AssertionSuccess();
}

}  // namespace sculpt::test
