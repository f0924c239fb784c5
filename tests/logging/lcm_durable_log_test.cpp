// DurableLog end to end: records in, an LCM log file out, read back by EventLogReader, by
// LCM's own reader (lcm::LogFile) and replayed by lcm-logplayer onto loopback multicast.

#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/durable_log.hpp"
#include "sculpt/logging/event_log_reader.hpp"
#include "sculpt/logging/event_log_walk.hpp"
#include "sculpt/hal/lcm_messages.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt_lcm/collision_event_t.hpp"
#include "sculpt_lcm/glove_sample_t.hpp"
#include "sculpt_lcm/tick_stats_t.hpp"
#include "support/scratch_dir.hpp"
#include "support/file_contents.hpp"

namespace sculpt::logging {
namespace {

// This process's folder, removed when it exits.
std::string durable_log_path(const std::string& name) {
  static const test::ScratchDir kScratch("sculpt_durable_test_");
  return (kScratch.path() / name).string();
}

using test::file_contents;

// The events of `path` as the readers of a whole log see them: checked, the checks consumed
// (event_check.hpp). Any damage, and any event that fails its check, fails the test.
std::vector<LogEvent> checked_events(const std::string& path) {
  std::vector<LogEvent> events;
  const EventLogTotals totals = for_each_event(
      path, [&](const LogEvent& event) { events.push_back(event); },
      [](std::uint64_t, const std::string& what) { ADD_FAILURE() << what; });
  EXPECT_EQ(totals.corrupt, 0u);
  EXPECT_EQ(totals.failed_checks, 0u);
  return events;
}

// How many SCULPT_CHECK events `path` holds, read raw.
std::size_t raw_checks(const std::string& path) {
  EventLogReader reader(path);
  LogEvent event;
  std::size_t checks = 0;
  while (reader.next(event) == EventLogReader::Result::kEvent) checks += event.channel == kCheckChannel ? 1 : 0;
  return checks;
}

void record_ticks(DurableLog& log, std::int64_t first, std::int64_t count) {
  TickRecord tick;
  for (std::int64_t i = first; i < first + count; ++i) {
    tick.tick = i;
    ASSERT_TRUE(log.record(tick));
  }
}

CollisionRecord make_collision(std::int64_t i, std::int64_t utime) {
  CollisionRecord r;
  r.utime = utime;
  r.tick = i;
  r.time_s = 0.001 * static_cast<double>(i);
  r.hand = static_cast<std::uint8_t>(i % 2);
  r.finger = static_cast<std::uint8_t>(i % 5);
  r.mode = i % 3 == 0 ? CollisionMode::kPull : CollisionMode::kPush;
  const double x = static_cast<double>(i);
  r.probe = {x, -x, 0.5 * x};
  r.contact_index = static_cast<std::int32_t>(i * 7);
  r.contact = {x + 0.25, 1.0, -2.0};
  r.source = {x - 0.5, 2.0, 3.0};
  r.force = {0.125 * x, -0.5, 1e-3};
  r.weights = {1.0, 2.0 + x, 3.0};
  r.effective_force = {0.5, 0.25, x};
  r.bc_radius = 0.01 * x;
  r.region_kind = static_cast<RegionKind>(i % 3);
  r.region_centre = {1.0, 2.0, x};
  r.region_radius = 0.2;
  r.region_id = static_cast<std::int32_t>(i % 11) - 1;
  r.kernel = i % 2 == 0 ? KernelKind::kKelvin : KernelKind::kRegularized;
  r.kernel_eps = 1e-4;
  r.shear_modulus = 1000.0 + x;
  r.poisson_ratio = 0.3;
  r.form = i % 2 == 0 ? ForceForm::kScale : ForceForm::kForce;
  r.residual = 1e-9 * x;
  r.condition = 10.0 + x;
  r.frame_id = i / 2;
  r.frame_size = static_cast<std::uint8_t>(1 + i % 2);
  return r;
}

void expect_same(const CollisionRecord& a, const CollisionRecord& b) {
  EXPECT_EQ(a.utime, b.utime);
  EXPECT_EQ(a.tick, b.tick);
  EXPECT_EQ(a.time_s, b.time_s);
  EXPECT_EQ(a.hand, b.hand);
  EXPECT_EQ(a.finger, b.finger);
  EXPECT_EQ(a.mode, b.mode);
  EXPECT_EQ(a.probe, b.probe);
  EXPECT_EQ(a.contact_index, b.contact_index);
  EXPECT_EQ(a.contact, b.contact);
  EXPECT_EQ(a.source, b.source);
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(a.weights, b.weights);
  EXPECT_EQ(a.effective_force, b.effective_force);
  EXPECT_EQ(a.bc_radius, b.bc_radius);
  EXPECT_EQ(a.region_kind, b.region_kind);
  EXPECT_EQ(a.region_centre, b.region_centre);
  EXPECT_EQ(a.region_radius, b.region_radius);
  EXPECT_EQ(a.region_id, b.region_id);
  EXPECT_EQ(a.kernel, b.kernel);
  EXPECT_EQ(a.kernel_eps, b.kernel_eps);
  EXPECT_EQ(a.shear_modulus, b.shear_modulus);
  EXPECT_EQ(a.poisson_ratio, b.poisson_ratio);
  EXPECT_EQ(a.form, b.form);
  EXPECT_EQ(a.residual, b.residual);
  EXPECT_EQ(a.condition, b.condition);
  EXPECT_EQ(a.frame_id, b.frame_id);
  EXPECT_EQ(a.frame_size, b.frame_size);
}

hal::GloveSample make_glove(std::uint32_t sequence) {
  hal::GloveSample s;
  s.hand = static_cast<std::uint8_t>(sequence % 2);
  s.sequence = sequence;
  s.device_time_us = 1000u * sequence;
  for (std::size_t j = 0; j < hal::kJointPoints; ++j) {
    s.joints[j] = {static_cast<float>(j), static_cast<float>(sequence), -1.0f};
  }
  return s;
}

/// What a session records: ticks, with a collision every fifth, a glove sample every tenth,
/// a fingertip every 50th and a haptic command every 100th, in that order within a tick.
struct Session {
  std::vector<std::string> channels;  // expected order in the file
  std::vector<std::int64_t> utimes;
  std::vector<CollisionRecord> collisions;
};

Session record_session(DurableLog& log, std::int64_t ticks, std::int64_t base_utime, std::int64_t step_us) {
  Session session;
  auto add = [&](const char* channel, std::int64_t utime) {
    session.channels.emplace_back(channel);
    session.utimes.push_back(utime);
  };
  for (std::int64_t i = 0; i < ticks; ++i) {
    const std::int64_t utime = base_utime + i * step_us;
    if (i % 10 == 0) {
      EXPECT_TRUE(log.record(make_glove(static_cast<std::uint32_t>(i)), utime));
      add(kGloveChannel, utime);
    }
    if (i % 50 == 0) {
      FingertipRecord tip;
      tip.utime = utime;
      tip.tick = i;
      tip.finger = 1;
      EXPECT_TRUE(log.record(tip));
      add(kFingertipChannel, utime);
    }
    if (i % 5 == 0) {
      const CollisionRecord hit = make_collision(i, utime);
      EXPECT_TRUE(log.record(hit));
      session.collisions.push_back(hit);
      add(kCollisionChannel, utime);
    }
    TickRecord tick;
    tick.utime = utime;
    tick.tick = i;
    tick.collisions = i % 5 == 0 ? 1 : 0;
    EXPECT_TRUE(log.record(tick));
    add(kTickChannel, utime);
    if (i % 100 == 0) {
      hal::HapticCommand command;
      command.tick = static_cast<std::uint32_t>(i);
      command.active_mask = 1;
      EXPECT_TRUE(log.record(command, utime));
      add(kHapticChannel, utime);
    }
  }
  return session;
}

TEST(DurableLog, WritesEveryRecordInOrderAndRoundTripsCollisions) {
  const std::string path = durable_log_path("session/run.lcmlog");  // the folder does not exist yet
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
  DurableLogConfig config;
  config.path = path;
  config.flush_interval = std::chrono::milliseconds(5);
  Session session;
  DurableLog::Counters counters;
  {
    DurableLog log(config);
    log.start();
    session = record_session(log, 5000, 1'700'000'000'000'000, 1000);
    log.stop();
    counters = log.counters();
    EXPECT_EQ(counters[LogKind::kCollision].written, 1000u);
    EXPECT_EQ(counters[LogKind::kTick].written, 5000u);
    EXPECT_EQ(counters[LogKind::kGlove].written, 500u);
    EXPECT_EQ(counters[LogKind::kFingertip].written, 100u);
    EXPECT_EQ(counters[LogKind::kHaptic].written, 50u);
    EXPECT_EQ(counters.dropped(), 0u);
    EXPECT_EQ(counters.write_errors, 0u);
    EXPECT_GE(counters.flushes, 1u);
    log.stop();  // idempotent
  }

  std::map<std::string, std::size_t> per_channel;
  std::size_t n = 0, collision = 0;
  std::int64_t last_number = -1;
  const std::vector<LogEvent> events = checked_events(path);
  for (const LogEvent& event : events) {
    ASSERT_LT(n, session.channels.size());
    ASSERT_EQ(event.channel, session.channels[n]) << "event " << n;
    ASSERT_EQ(event.utime, session.utimes[n]) << "event " << n;
    EXPECT_GT(event.number, last_number) << "event " << n;  // the checks take numbers between
    last_number = event.number;
    ++per_channel[event.channel];
    std::string error;
    if (event.channel == kCollisionChannel) {
      sculpt_lcm::collision_event_t message{};
      ASSERT_TRUE(decode(event, message, error)) << error;
      CollisionRecord back;
      ASSERT_TRUE(from_lcm(message, back));
      expect_same(back, session.collisions[collision++]);
    } else if (event.channel == kGloveChannel) {
      sculpt_lcm::glove_sample_t message{};
      ASSERT_TRUE(decode(event, message, error)) << error;
      hal::GloveSample back;
      ASSERT_TRUE(from_lcm(message, back));
      EXPECT_EQ(back.sequence * 1000u, back.device_time_us);
    }
    ++n;
  }
  EXPECT_EQ(n, session.channels.size());
  // A check after the first event, then at each flush: the file's are the log's count.
  EXPECT_EQ(raw_checks(path), counters.checks);
  EXPECT_GE(counters.checks, 2u);
  EXPECT_EQ(last_number + 2, static_cast<std::int64_t>(n + counters.checks))
      << "a check closes the log, and the numbers run on through the checks";
  EXPECT_EQ(per_channel[kCollisionChannel], 1000u);
  EXPECT_EQ(per_channel[kTickChannel], 5000u);
  EXPECT_EQ(per_channel[kGloveChannel], 500u);
  EXPECT_EQ(per_channel[kFingertipChannel], 100u);
  EXPECT_EQ(per_channel[kHapticChannel], 50u);

  // LCM's own reader agrees, event for event (it sees the checks too, as any channel).
  lcm::LogFile lcm_log(path, "r");
  ASSERT_TRUE(lcm_log.good());
  std::size_t lcm_count = 0, lcm_checks = 0;
  while (const lcm::LogEvent* e = lcm_log.readNextEvent()) {
    if (e->channel == kCheckChannel) {
      ++lcm_checks;
      continue;
    }
    ASSERT_LT(lcm_count, session.channels.size());
    EXPECT_EQ(e->channel, session.channels[lcm_count]);
    EXPECT_EQ(e->timestamp, session.utimes[lcm_count]);
    ++lcm_count;
  }
  EXPECT_EQ(lcm_count, session.channels.size());
  EXPECT_EQ(lcm_checks, counters.checks);
}

TEST(DurableLog, FullQueueIsACountedDropAndStopWritesWhatWasQueued) {
  DurableLogConfig config;
  config.path = durable_log_path("full.lcmlog");
  config.queue_capacity = 4;
  DurableLog log(config);  // not started: nothing drains the queue
  TickRecord tick;
  int accepted = 0;
  for (int i = 0; i < 10; ++i) {
    tick.tick = i;
    tick.utime = 100 + i;
    accepted += log.record(tick) ? 1 : 0;
  }
  CollisionRecord hit;
  EXPECT_FALSE(log.record(hit));
  EXPECT_EQ(accepted, 4);
  auto counters = log.counters();
  EXPECT_EQ(counters[LogKind::kTick].dropped, 6u);
  EXPECT_EQ(counters[LogKind::kCollision].dropped, 1u);
  EXPECT_EQ(counters.written(), 0u);
  log.stop();  // never started: stop writes the queue itself
  counters = log.counters();
  EXPECT_EQ(counters[LogKind::kTick].written, 4u);
  EXPECT_FALSE(log.record(tick));  // closed
  EXPECT_EQ(log.counters()[LogKind::kTick].dropped, 7u);
  EXPECT_THROW(log.start(), std::runtime_error);

  const std::vector<LogEvent> events = checked_events(config.path);
  ASSERT_EQ(events.size(), 4u);
  for (std::int64_t i = 0; i < 4; ++i) EXPECT_EQ(events[static_cast<std::size_t>(i)].utime, 100 + i);
}

TEST(DurableLog, FlushNowMakesRecordsReadableWhileTheLogIsOpen) {
  DurableLogConfig config;
  config.path = durable_log_path("flush.lcmlog");
  config.flush_interval = std::chrono::hours(1);  // only flush_now flushes
  DurableLog log(config);
  log.start();
  EXPECT_THROW(log.start(), std::runtime_error);
  TickRecord tick;
  for (int i = 0; i < 3; ++i) {
    tick.tick = i;
    ASSERT_TRUE(log.record(tick));
  }
  log.flush_now();
  EXPECT_EQ(log.counters()[LogKind::kTick].written, 3u);
  EXPECT_GE(log.counters().flushes, 1u);
  EXPECT_EQ(checked_events(config.path).size(), 3u);
  EXPECT_EQ(raw_checks(config.path), 2u) << "after the first event, and at the flush";
  log.stop();
}

TEST(DurableLog, PeriodicFlushReachesTheFileWithoutStop) {
  DurableLogConfig config;
  config.path = durable_log_path("periodic.lcmlog");
  config.flush_interval = std::chrono::milliseconds(10);
  DurableLog log(config);
  log.start();
  TickRecord tick;
  ASSERT_TRUE(log.record(tick));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(2);
  std::uintmax_t size = 0;
  while (size == 0 && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    size = std::filesystem::file_size(config.path);
  }
  EXPECT_GT(size, 0u);
  log.stop();
}

TEST(DurableLog, TheSessionHeaderIsTheFirstEventOnDiskBeforeTheThreadStarts) {
  DurableLogConfig config;
  config.path = durable_log_path("header.lcmlog");
  config.flush_interval = std::chrono::hours(1);
  DurableLog log(config);
  sculpt_lcm::session_header_t header{};
  header.schema = sculpt_lcm::session_header_t::SCHEMA;
  header.version = "9.9.9";
  header.scene_text = std::string(5000, 'x');  // longer than any fixed-size record
  header.model_points = 3203;
  header.model_hash = -42;
  header.full_points = 3203;
  header.full_hash = -42;
  log.write_session_header(header);
  EXPECT_THROW(log.write_session_header(header), std::logic_error);  // only as the first event
  {
    // Readable before start(): a crash in the first tick still leaves a named log.
    EventLogReader reader(config.path);
    LogEvent event;
    ASSERT_EQ(reader.next(event), EventLogReader::Result::kEvent);
    EXPECT_EQ(event.channel, kSessionChannel);
    sculpt_lcm::session_header_t back;
    std::string error;
    ASSERT_TRUE(decode(event, back, error)) << error;
    EXPECT_EQ(back.version, "9.9.9");
    EXPECT_EQ(back.scene_text.size(), 5000u);
    EXPECT_EQ(back.model_hash, -42);
  }
  log.start();
  TickRecord tick;
  ASSERT_TRUE(log.record(tick));
  log.stop();
  std::vector<std::string> channels;
  for (const LogEvent& event : checked_events(config.path)) channels.push_back(event.channel);
  EXPECT_EQ(channels, (std::vector<std::string>{kSessionChannel, kTickChannel}));
}

TEST(DurableLog, UnwritablePathThrowsNamingIt) {
  const std::string blocker = durable_log_path("blocker");
  std::filesystem::create_directories(std::filesystem::path(blocker).parent_path());
  std::ofstream(blocker) << "a file, not a folder";
  DurableLogConfig config;
  config.path = blocker + "/sub/run.lcmlog";
  try {
    DurableLog log(config);
    FAIL() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(config.path), std::string::npos) << e.what();
  }
}

// A FIFO named as the log held the open until a reader came, so the station never started, and
// would keep nothing to recover or replay: refused at once, naming it. /dev/null, a session
// kept nowhere on purpose, still opens and takes a whole session, for two writers at once.
TEST(DurableLog, AFifoIsRefusedAtOnceAndDevNullTakesASession) {
  const std::string fifo = durable_log_path("fifo.lcmlog");
  std::filesystem::create_directories(std::filesystem::path(fifo).parent_path());
  std::filesystem::remove(fifo);
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  DurableLogConfig config;
  config.path = fifo;
  try {
    DurableLog log(config);
    ADD_FAILURE() << "no throw";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()),
              "DurableLog: '" + fifo + "' is a FIFO: a session's log is its edit history and must be a file");
  }
  EXPECT_TRUE(std::filesystem::is_fifo(fifo)) << "the FIFO is left as it was";
  std::filesystem::remove(fifo);

  config.path = "/dev/null";
  DurableLog log(config);
  DurableLog beside(config);  // a device keeps no session, so two stations may both send theirs there
  log.start();
  for (std::int64_t t = 0; t < 100; ++t) ASSERT_TRUE(log.record(TickRecord{.utime = t}));
  log.stop();
  EXPECT_EQ(log.counters()[LogKind::kTick].written, 100u);
  EXPECT_EQ(log.counters().write_errors, 0u);
}

// Two sessions on one log (a scene run twice at once) would both truncate it and interleave
// their events. The second writer is refused before it truncates, naming the log, and the first
// session's bytes stay as they were; once the first has stopped, the log can be replaced.
TEST(DurableLog, ASecondWriterIsRefusedAndTheFirstSessionsLogStaysAsItWas) {
  DurableLogConfig config;
  config.path = durable_log_path("two_writers.lcmlog");
  DurableLog first(config);
  first.start();
  record_ticks(first, 0, 50);
  first.flush_now();
  const std::string before = file_contents(config.path);
  ASSERT_FALSE(before.empty());
  try {
    DurableLog second(config);
    FAIL() << "a second writer was let in";
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("'" + config.path + "' is being written by another running session"), std::string::npos)
        << message;
  }
  EXPECT_EQ(file_contents(config.path), before);
  record_ticks(first, 50, 50);  // the first session goes on writing where it was
  first.stop();
  const std::string complete = file_contents(config.path);
  EXPECT_GT(complete.size(), before.size());
  EXPECT_EQ(complete.compare(0, before.size(), before), 0);
  {
    EventLogReader reader(config.path);
    LogEvent event;
    std::size_t ticks = 0;
    while (reader.next(event) == EventLogReader::Result::kEvent) ticks += event.channel == kTickChannel ? 1 : 0;
    EXPECT_EQ(ticks, 100u);
    EXPECT_EQ(reader.corrupt_events(), 0u);
  }
  DurableLog next(config);  // stopped: the lock is released, and a new session replaces the log
  next.start();
  next.stop();
  EXPECT_EQ(std::filesystem::file_size(config.path), 0u);
}

// The file used to be opened, truncating an earlier log, when the log was made, before the
// station's glove started: a glove that failed to start cost the session `--replace-log` was
// about to replace, and left a header-only log behind. Until the header or start() the path is
// locked but untouched; a log that never opened removes the file it made for its lock.
TEST(DurableLog, AnEarlierLogStaysUntilTheNewSessionOpensIt) {
  DurableLogConfig config;
  config.path = durable_log_path("earlier.lcmlog");
  std::filesystem::create_directories(std::filesystem::path(config.path).parent_path());
  std::ofstream(config.path, std::ios::binary) << "an earlier session";
  {
    DurableLog unstarted(config);
    EXPECT_THROW(DurableLog{config}, std::runtime_error) << "the path is locked from the start";
    EXPECT_EQ(file_contents(config.path), "an earlier session");
    unstarted.flush_now();  // nothing queued: nothing to open
    EXPECT_EQ(file_contents(config.path), "an earlier session");
  }  // stopped without a start
  EXPECT_EQ(file_contents(config.path), "an earlier session");

  {
    DurableLog replacing(config);
    sculpt_lcm::session_header_t header{};
    header.schema = sculpt_lcm::session_header_t::SCHEMA;
    replacing.write_session_header(header);  // the session begins: the earlier log goes
    const std::vector<LogEvent> events = checked_events(config.path);
    ASSERT_EQ(events.size(), 1u);
    EXPECT_EQ(events[0].channel, kSessionChannel);
  }

  config.path = durable_log_path("never-started.lcmlog");
  { DurableLog never(config); }
  EXPECT_FALSE(std::filesystem::exists(config.path)) << "a session that never started left a file";
  {
    DurableLog queued(config);  // records queued without a thread are written at stop
    record_ticks(queued, 0, 3);
  }
  EXPECT_EQ(checked_events(config.path).size(), 3u);
}

// lcm-logplayer replays the file onto loopback multicast; a raw subscriber counts what arrives.
TEST(DurableLog, LcmLogplayerReplaysTheFile) {
  if (std::system("command -v lcm-logplayer > /dev/null 2>&1") != 0) GTEST_SKIP() << "lcm-logplayer not installed";
  DurableLogConfig config;
  config.path = durable_log_path("replay.lcmlog");
  Session session;
  {
    DurableLog log(config);
    log.start();
    // 200 ticks 1 ms apart: about 0.2 s of playback, slow enough that loopback drops nothing.
    session = record_session(log, 200, 1'700'000'000'000'000, 1000);
    log.stop();
  }
  const std::string url = "udpm://239.255.76.67:" + std::to_string(20000 + ::getpid() % 20000) + "?ttl=0";
  lcm::LCM lcm(url);
  if (!lcm.good()) GTEST_SKIP() << "cannot open " << url;
  struct Counts {
    std::map<std::string, std::size_t> by_channel;
    std::size_t total = 0;
  } counts;
  lcm.subscribeFunction(
      "SCULPT_(GLOVE|FINGERTIP|COLLISION|TICK|HAPTIC)",
      +[](const lcm::ReceiveBuffer*, const std::string& channel, Counts* c) {
        ++c->by_channel[channel];
        ++c->total;
      },
      &counts);
  // Probe: does multicast loop back here at all?
  bool probed = false;
  lcm.subscribeFunction(
      "SCULPT_PROBE", +[](const lcm::ReceiveBuffer*, const std::string&, bool* seen) { *seen = true; }, &probed);
  const std::uint8_t probe_byte = 0;
  for (int i = 0; i < 10 && !probed; ++i) {
    lcm.publish("SCULPT_PROBE", &probe_byte, 1);
    lcm.handleTimeout(50);
  }
  if (!probed) GTEST_SKIP() << "multicast on " << url << " does not loop back here";

  // Loopback UDP under a loaded CI machine may still drop a datagram (the durable log never
  // depends on UDP for that reason), so one of three replays must arrive whole.
  const std::string command = "lcm-logplayer -l '" + url + "' '" + config.path + "' > /dev/null 2>&1";
  for (int attempt = 0; attempt < 3; ++attempt) {
    counts = Counts{};
    std::thread player([&] { EXPECT_EQ(std::system(command.c_str()), 0); });
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (counts.total < session.channels.size() && std::chrono::steady_clock::now() < deadline) lcm.handleTimeout(20);
    player.join();
    while (lcm.handleTimeout(50) > 0) {
    }
    if (counts.total == session.channels.size()) break;
    std::printf("replay %d: %zu of %zu messages arrived; replaying again\n", attempt + 1, counts.total,
                session.channels.size());
  }
  EXPECT_EQ(counts.total, session.channels.size());
  EXPECT_EQ(counts.by_channel[kTickChannel], 200u);
  EXPECT_EQ(counts.by_channel[kCollisionChannel], 40u);
  EXPECT_EQ(counts.by_channel[kGloveChannel], 20u);
  EXPECT_EQ(counts.by_channel[kFingertipChannel], 4u);
  EXPECT_EQ(counts.by_channel[kHapticChannel], 2u);
}

}  // namespace
}  // namespace sculpt::logging
