// LCM URLs checked where they enter: the forms LCM 1.3's providers take pass (the installed
// liblcm has udpm, mpudpm, tcpq, memq and the log-file provider), and each refusal names what
// is wrong. That LCM opens what passes is shown where the HIL and LCM tests open their URLs.
#include "sculpt/rt/transport_url.hpp"

#include <gtest/gtest.h>

#include <string>

namespace sculpt::rt {
namespace {

TEST(LcmUrl, TheFormsLcmOpensPass) {
  for (const char* url : {"udpm://239.255.76.67:7667?ttl=0", "udpm://", "udpm://239.255.76.67",
                          "udpm://224.0.0.1:1?ttl=255&recv_buf_size=2097152", "mpudpm://239.255.76.67:7667?nports=4",
                          "memq://", "file:///tmp/session.lcmlog?mode=r&speed=2", "tcpq://localhost:7700"}) {
    EXPECT_EQ(lcm_url_problem(url), "") << url;
  }
}

TEST(LcmUrl, EachRefusalSaysWhatIsWrong) {
  const std::pair<const char*, const char*> cases[] = {
      {"239.255.76.67:7667", "'239.255.76.67:7667' is not an LCM URL (provider://address"},
      {"udp://239.255.76.67", "'udp://239.255.76.67' names no LCM provider"},
      {"udpm://999.1.1.1:7667", "'999.1.1.1' is not an IPv4 address"},
      {"udpm://localhost:7667", "'localhost' is not an IPv4 address"},
      {"udpm://127.0.0.1:7667", "'127.0.0.1' is not a multicast address"},
      {"udpm://240.0.0.1:7667", "'240.0.0.1' is not a multicast address"},
      {"udpm://239.255.76.67:0", "port '0' is not in 1..65535"},
      {"udpm://239.255.76.67:7667x", "port '7667x' is not in 1..65535"},
      {"udpm://239.255.76.67:7667?ttl=256", "ttl '256' is not in 0..255"},
      {"udpm://239.255.76.67:7667?ttl", "option 'ttl' is not key=value"},
      {"udpm://239.255.76.67:7667?recv_buf_size=-1", "recv_buf_size '-1' is not a positive byte count"},
      {"file://?mode=r", "names no file"},
      // LCM's provider would wait on a FIFO (or read a folder) for ever.
      {"file:///tmp?mode=r", "'/tmp' is a directory, not a log file"},
      {"file:///dev/zero", "'/dev/zero' is a character device, not a log file"},
  };
  for (const auto& [url, expected] : cases) {
    const std::string problem = lcm_url_problem(url);
    EXPECT_NE(problem.find(expected), std::string::npos) << url << ": " << problem;
  }
}

TEST(LcmChannel, LcmsLimitsAreNamed) {
  EXPECT_EQ(lcm_channel_problem("SCULPT_GLOVE"), "");
  EXPECT_EQ(lcm_channel_problem(std::string(63, 'C')), "");  // LCM_MAX_CHANNEL_NAME_LENGTH
  EXPECT_EQ(lcm_channel_problem(std::string(64, 'C')), "is 64 bytes long; LCM takes at most 63");
  EXPECT_EQ(lcm_channel_problem(""), "must not be empty");
  EXPECT_EQ(lcm_channel_problem(std::string("GLOVE\0B", 7)), "holds a NUL byte");
}

}  // namespace
}  // namespace sculpt::rt
