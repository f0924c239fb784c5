#pragma once
// The durable event log: the loop queues plain records, a thread of its own encodes them into
// sculpt_lcm messages and appends them to a file in LCM's log-file format, so lcm-logplayer,
// lcm-logger's readers and EventLogReader all read it. The log is the edit history
// (ARCHITECTURE.md): base model + this file = the sculpted model, so nothing queued is dropped
// on stop and the file is flushed often enough that a crash loses at most one flush interval.
// Each flush first writes the check of the events since the last one (event_check.hpp).

#include <array>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <variant>
#include <vector>

#include "sculpt/hal/glove_sample.hpp"
#include "sculpt/hal/haptic_sink.hpp"
#include "sculpt/base/spsc_queue.hpp"
#include "sculpt/logging/records.hpp"
#include "sculpt_lcm/log_check_t.hpp"
#include "sculpt_lcm/session_header_t.hpp"

namespace lcm {
class LogFile;
struct LogEvent;
}  // namespace lcm

namespace sculpt::logging {

struct DurableLogConfig {
  std::string path;  ///< the log file; parent folders are created, an existing file is replaced
                     ///< unless another DurableLog is writing it
  /// Records of all kinds between the loop and the thread. One record slot is the size of the
  /// largest record (a glove sample, ~400 bytes), so the default reserves about 25 MiB.
  std::size_t queue_capacity = 65536;
  /// How often written events are pushed from the C library's buffer to the kernel.
  std::chrono::milliseconds flush_interval{100};
  /// How long the thread sleeps when the queue was empty. The loop does not wake the thread
  /// (a wake-up would be a system call in the tick), so this bounds the write latency.
  std::chrono::microseconds poll_period{1000};
};

/// The record kinds, in the order of DurableLog::Counters::kinds.
enum class LogKind : std::uint8_t { kGlove = 0, kFingertip = 1, kCollision = 2, kTick = 3, kHaptic = 4 };
inline constexpr std::size_t kLogKinds = 5;

/// Thread-safety: every record() overload pushes into the same single-producer queue (one
/// queue keeps the file in exactly the order records were made), so all of them must be called
/// from one thread, the loop. start(), stop() and flush_now() belong to the owning thread;
/// counters() may be called from anywhere.
class DurableLog {
 public:
  struct KindCounters {
    std::uint64_t written = 0;  ///< appended to the file
    std::uint64_t dropped = 0;  ///< refused by record(): queue full, or the log already closed
  };
  struct Counters {
    std::array<KindCounters, kLogKinds> kinds{};  ///< indexed by LogKind
    std::uint64_t write_errors = 0;               ///< encode or write failures (the record is lost)
    std::uint64_t flushes = 0;                    ///< fflush calls made (periodic, flush_now and stop)
    std::uint64_t checks = 0;                     ///< SCULPT_CHECK events written (event_check.hpp)

    const KindCounters& operator[](LogKind kind) const noexcept { return kinds[static_cast<std::size_t>(kind)]; }
    std::uint64_t written() const noexcept;
    std::uint64_t dropped() const noexcept;
  };

  /// Creates the parent folders, takes the log's writer lock and reserves the queue. The lock
  /// is held until stop() has closed the file. The file itself is opened, and an earlier log at
  /// the path replaced, only by write_session_header() or start() (or by stop() and flush_now()
  /// when records are queued): a session that fails before it starts (its glove missing) leaves
  /// an earlier log as it was, and no file where there was none.
  /// @throw std::runtime_error naming the path when the folder or file cannot be created, or
  /// when another DurableLog (in any process) is writing it; that log is then left untouched.
  explicit DurableLog(DurableLogConfig config);
  /// Calls stop().
  ~DurableLog();
  DurableLog(const DurableLog&) = delete;
  DurableLog& operator=(const DurableLog&) = delete;

  /// Opens the file, writes the session header as the log's first event, on the calling
  /// thread, and pushes it to the disk: set-up time, before start() (it may allocate: its scene
  /// text has no bound).
  /// @throw std::logic_error when the thread was started, the log stopped or an event is already
  /// written; std::runtime_error naming the path when it cannot be opened, encoded or written.
  void write_session_header(const sculpt_lcm::session_header_t& header);

  /// Opens the file (unless the header did) and starts the writer thread.
  /// @throw std::runtime_error when already started or already stopped (the file is closed), or
  /// naming the path when the file cannot be opened.
  void start();
  /// Writes everything still queued, flushes, syncs and closes the file, then stops the
  /// thread. Works whether or not start() was called. Idempotent. The loop must have stopped
  /// recording first: records made after stop() are refused and counted as dropped.
  void stop();

  /// Queue a record for the file. Real-time safe: noexcept, wait-free, no allocation, no
  /// system call. False when the queue is full or the log is closed (counted as dropped).
  /// `utime` stamps samples and commands that carry no wall-clock time of their own
  /// (microseconds since the Unix epoch, e.g. wall_time_us()).
  bool record(const hal::GloveSample& sample, std::int64_t utime) noexcept;
  bool record(const FingertipRecord& record) noexcept;
  bool record(const CollisionRecord& record) noexcept;
  bool record(const TickRecord& record) noexcept;
  bool record(const hal::HapticCommand& command, std::int64_t utime) noexcept;

  Counters counters() const noexcept;

  /// Writes what was queued before the call and flushes it to the kernel (and to disk), then
  /// returns; for SIGINT and crash-handling paths. Blocks the caller, so never call it from the
  /// loop. Before start() or after stop() it does the work on the calling thread.
  void flush_now();

  const std::string& path() const noexcept { return config_.path; }

 private:
  struct StampedGlove {
    hal::GloveSample sample;
    std::int64_t utime;
  };
  struct StampedHaptic {
    hal::HapticCommand command;
    std::int64_t utime;
  };
  // Alternatives in LogKind order, so index() is the kind.
  using Entry = std::variant<StampedGlove, FingertipRecord, CollisionRecord, TickRecord, StampedHaptic>;

  bool push(const Entry& entry, LogKind kind) noexcept;
  void run() noexcept;
  std::size_t drain(std::size_t limit) noexcept;
  void write(const Entry& entry) noexcept;
  template <typename Message>
  void write_message(LogKind kind, std::int64_t utime, const Message& message) noexcept;
  // Adds a written event's CRC-32 to the next check; writes the check after the log's first
  // event (so that a reader knows the log is checked) and when it is full.
  void note_written(std::uint32_t crc, std::int64_t number, std::int64_t utime) noexcept;
  // Writes the check of the events since the last one, if any (before every flush).
  void write_check() noexcept;
  void flush(bool sync) noexcept;
  void close() noexcept;
  // Opens the log and takes its writer lock (flock), or throws naming the path.
  void lock_writer();
  // Opens file_ for writing (truncating the path), unless open; throws naming the path.
  void open_file();
  // For stop() and flush_now(): opens file_ when records wait to be written; false when it stays
  // closed (nothing queued, or the open failed: counted as a write error).
  bool open_file_for_queued() noexcept;
  void release_writer_lock() noexcept;

  DurableLogConfig config_;
  std::unique_ptr<lcm::LogFile> file_;  // owned by the thread while it runs
  int lock_fd_ = -1;                    // holds the writer lock until the file is closed
  bool created_file_ = false;           // the path held no file before this log
  base::SpscQueue<Entry> queue_;
  std::array<std::string, kLogKinds> channels_;  // made once so writes need not build names
  std::unique_ptr<lcm::LogEvent> event_;         // reused by every write, like its channel string
  Entry scratch_;                                // the entry being written; a member because glove samples are large
  std::int64_t event_number_ = 0;
  sculpt_lcm::log_check_t check_{};          // the events written since the last check
  std::vector<unsigned char> check_buffer_;  // its encoding: both reserved once, for the largest
  std::int64_t last_utime_ = 0;              // the newest event's timestamp, the check's own
  bool dirty_ = false;                       // written since the last flush
  std::array<std::atomic<std::uint64_t>, kLogKinds> written_{};
  std::array<std::atomic<std::uint64_t>, kLogKinds> dropped_{};
  std::atomic<std::uint64_t> write_errors_{0};
  std::atomic<std::uint64_t> flushes_{0};
  std::atomic<std::uint64_t> checks_{0};
  std::atomic<std::uint64_t> flush_requests_{0};
  std::atomic<std::uint64_t> flushes_served_{0};
  std::atomic<bool> closed_{false};
  std::atomic<bool> stop_requested_{false};
  std::thread thread_;
};

}  // namespace sculpt::logging
