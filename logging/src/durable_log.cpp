#include "sculpt/logging/durable_log.hpp"

#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <system_error>
#include <type_traits>
#include <utility>
#include <vector>

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <lcm/lcm-cpp.hpp>

#include "sculpt/base/regular_file.hpp"
#include "sculpt/logging/channels.hpp"
#include "sculpt/logging/event_check.hpp"
#include "sculpt/hal/lcm_messages.hpp"

namespace sculpt::logging {
namespace {

std::size_t index(LogKind kind) noexcept { return static_cast<std::size_t>(kind); }

}  // namespace

std::uint64_t DurableLog::Counters::written() const noexcept {
  std::uint64_t sum = 0;
  for (const auto& kind : kinds) sum += kind.written;
  return sum;
}

std::uint64_t DurableLog::Counters::dropped() const noexcept {
  std::uint64_t sum = 0;
  for (const auto& kind : kinds) sum += kind.dropped;
  return sum;
}

DurableLog::DurableLog(DurableLogConfig config)
    : config_(std::move(config)),
      queue_(config_.queue_capacity),
      channels_{kGloveChannel, kFingertipChannel, kCollisionChannel, kTickChannel, kHapticChannel} {
  static_assert(std::is_trivially_copyable_v<Entry>, "entries cross threads through SpscQueue");
  static_assert(std::variant_size_v<Entry> == kLogKinds);
  if (config_.path.empty()) throw std::runtime_error("DurableLog: empty log path");
  const std::filesystem::path path(config_.path);
  if (path.has_parent_path()) {
    std::error_code error;
    std::filesystem::create_directories(path.parent_path(), error);
    if (error) {
      throw std::runtime_error("DurableLog: cannot create folder '" + path.parent_path().string() + "' for '" +
                               config_.path + "': " + error.message());
    }
  }
  lock_writer();
  event_ = std::make_unique<lcm::LogEvent>();
  // The check's arrays at their largest now (clear() keeps the capacity), so that the writer
  // thread never allocates.
  check_.count = static_cast<std::int32_t>(kMaxCheckedEvents);
  check_.crc.resize(kMaxCheckedEvents);
  check_buffer_.resize(static_cast<std::size_t>(check_.getEncodedSize()));
  check_.crc.clear();
  check_.count = 0;
}

DurableLog::~DurableLog() { stop(); }  // stop() closes the file and releases the lock

void DurableLog::open_file() {
  if (file_ != nullptr) return;
  errno = 0;
  file_ = std::make_unique<lcm::LogFile>(config_.path, "w");  // replaces an earlier log here, not before
  if (!file_->good()) {
    const int saved = errno;
    file_.reset();
    throw std::runtime_error("DurableLog: cannot open '" + config_.path + "' for writing" +
                             (saved != 0 ? std::string(": ") + std::strerror(saved) : std::string()));
  }
}

bool DurableLog::open_file_for_queued() noexcept {
  if (file_ != nullptr) return true;
  if (queue_.empty()) return false;
  try {
    open_file();
    return true;
  } catch (...) {
    write_errors_.fetch_add(1, std::memory_order_relaxed);  // the queued records stay unwritten
    return false;
  }
}

void DurableLog::lock_writer() {
  // One writer per log, for as long as it writes: two sessions started on the same log (a scene
  // run twice at once, a replay recording where a station writes) would otherwise both truncate
  // it and interleave their events. The lock is taken before the file is truncated, so the
  // refused session leaves the other's log as it is. flock is advisory and held by this open
  // file description, so readers (the viewer, sculpt replay) are not stopped.
  // A log is a file, or a device that takes every write (/dev/null, for a session kept
  // nowhere). A FIFO held the open until a reader came (the station never started), and
  // keeps nothing that a recovery or a replay could read back.
  const auto refuse_kind = [&](const std::string& kind) {
    throw std::runtime_error("DurableLog: '" + config_.path + "' is " + kind +
                             ": a session's log is its edit history and must be a file");
  };
  if (const std::string kind = base::non_regular_kind(config_.path); !kind.empty() && kind != base::kCharacterDevice) {
    refuse_kind(kind);
  }
  // O_NONBLOCK: a FIFO made after the check fails the open at once instead of waiting.
  // O_EXCL first, to know whether the file is this session's own (a session that never starts
  // removes it again) or an earlier log (left as it was until this session starts). The second
  // open keeps O_CREAT for a dangling symbolic link, whose target it creates as before.
  lock_fd_ = ::open(config_.path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC | O_NONBLOCK, 0644);
  created_file_ = lock_fd_ >= 0;
  if (lock_fd_ < 0 && errno == EEXIST) {
    lock_fd_ = ::open(config_.path.c_str(), O_WRONLY | O_CREAT | O_CLOEXEC | O_NONBLOCK, 0644);
  }
  if (lock_fd_ < 0) {
    throw std::runtime_error("DurableLog: cannot open '" + config_.path + "' for writing: " + std::strerror(errno));
  }
  struct stat info {};
  if (::fstat(lock_fd_, &info) == 0 && !S_ISREG(info.st_mode)) {
    if (!S_ISCHR(info.st_mode)) {
      release_writer_lock();
      refuse_kind("not a regular file");
    }
    return;  // a device keeps no session for another writer to spoil: two may share /dev/null
  }
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    const int saved = errno;
    release_writer_lock();
    if (saved == EWOULDBLOCK) {
      throw std::runtime_error("DurableLog: '" + config_.path +
                               "' is being written by another running session (a station or a replay "
                               "recording): its log is left as it is; stop that session or name another log");
    }
    throw std::runtime_error("DurableLog: cannot lock '" + config_.path + "' for writing: " + std::strerror(saved));
  }
}

void DurableLog::release_writer_lock() noexcept {
  if (lock_fd_ < 0) return;
  ::close(lock_fd_);  // closing the last descriptor of the open file releases its flock
  lock_fd_ = -1;
}

void DurableLog::write_session_header(const sculpt_lcm::session_header_t& header) {
  if (thread_.joinable() || event_number_ != 0 || closed_.load(std::memory_order_acquire)) {
    throw std::logic_error("DurableLog: '" + config_.path +
                           "': the session header must be its first event, "
                           "written before start()");
  }
  open_file();
  const int size = header.getEncodedSize();
  std::vector<unsigned char> buffer(static_cast<std::size_t>(std::max(size, 0)));
  if (size <= 0 || header.encode(buffer.data(), 0, size) != size) {
    throw std::runtime_error("DurableLog: '" + config_.path + "': cannot encode the session header");
  }
  lcm::LogEvent event;
  event.eventnum = event_number_;
  event.timestamp = header.utime;
  event.channel = kSessionChannel;
  event.datalen = size;
  event.data = buffer.data();
  if (file_->writeEvent(&event) != 0) {
    throw std::runtime_error("DurableLog: '" + config_.path +
                             "': cannot write the session header: " + std::strerror(errno));
  }
  note_written(event_crc32(event.eventnum, event.timestamp, event.channel, buffer.data(), buffer.size()),
               event.eventnum, event.timestamp);
  ++event_number_;
  // On the disk before the first tick: a log cut at any later moment still names its session.
  flush(true);
}

void DurableLog::start() {
  if (thread_.joinable()) throw std::runtime_error("DurableLog: '" + config_.path + "' already started");
  if (closed_.load(std::memory_order_acquire)) {
    throw std::runtime_error("DurableLog: '" + config_.path + "' was stopped and is closed");
  }
  open_file();
  stop_requested_.store(false, std::memory_order_relaxed);
  thread_ = std::thread([this] { run(); });
}

void DurableLog::stop() {
  if (thread_.joinable()) {
    stop_requested_.store(true, std::memory_order_release);
    thread_.join();  // the thread drains the queue before it returns
  }
  if (closed_.exchange(true, std::memory_order_acq_rel)) return;
  if (file_ == nullptr && !open_file_for_queued()) {
    // Never opened and nothing to write: a session that did not start. An earlier log at the
    // path stays as it was (--replace-log replaces it only once the station runs); a file this
    // log created for its lock goes again.
    if (created_file_) ::unlink(config_.path.c_str());
    release_writer_lock();
    flushes_served_.store(UINT64_MAX, std::memory_order_release);
    return;
  }
  // Never started, or records slipped in after the thread's last drain: written here.
  while (drain(queue_.capacity()) > 0) {
  }
  close();
  // A flush_now() racing with stop() is served by the close above.
  flushes_served_.store(UINT64_MAX, std::memory_order_release);
}

bool DurableLog::push(const Entry& entry, LogKind kind) noexcept {
  if (!closed_.load(std::memory_order_relaxed) && queue_.push(entry)) return true;
  dropped_[index(kind)].fetch_add(1, std::memory_order_relaxed);
  return false;
}

bool DurableLog::record(const hal::GloveSample& sample, std::int64_t utime) noexcept {
  return push(Entry(std::in_place_index<0>, StampedGlove{sample, utime}), LogKind::kGlove);
}

bool DurableLog::record(const FingertipRecord& record) noexcept {
  return push(Entry(std::in_place_index<1>, record), LogKind::kFingertip);
}

bool DurableLog::record(const CollisionRecord& record) noexcept {
  return push(Entry(std::in_place_index<2>, record), LogKind::kCollision);
}

bool DurableLog::record(const TickRecord& record) noexcept {
  return push(Entry(std::in_place_index<3>, record), LogKind::kTick);
}

bool DurableLog::record(const hal::HapticCommand& command, std::int64_t utime) noexcept {
  return push(Entry(std::in_place_index<4>, StampedHaptic{command, utime}), LogKind::kHaptic);
}

DurableLog::Counters DurableLog::counters() const noexcept {
  Counters out;
  for (std::size_t k = 0; k < kLogKinds; ++k) {
    out.kinds[k].written = written_[k].load(std::memory_order_relaxed);
    out.kinds[k].dropped = dropped_[k].load(std::memory_order_relaxed);
  }
  out.write_errors = write_errors_.load(std::memory_order_relaxed);
  out.flushes = flushes_.load(std::memory_order_relaxed);
  out.checks = checks_.load(std::memory_order_relaxed);
  return out;
}

void DurableLog::flush_now() {
  if (!thread_.joinable()) {
    // No thread owns the file: do the work here (after stop() there is nothing left to do).
    if (closed_.load(std::memory_order_acquire) || !open_file_for_queued()) return;
    while (drain(queue_.capacity()) > 0) {
    }
    flush(true);
    return;
  }
  const std::uint64_t ticket = flush_requests_.fetch_add(1, std::memory_order_acq_rel) + 1;
  // A short sleep rather than a condition variable: the writer serves requests within one
  // poll period anyway, and this keeps the writer free of locks.
  while (flushes_served_.load(std::memory_order_acquire) < ticket) {
    std::this_thread::sleep_for(config_.poll_period / 4 + std::chrono::microseconds(1));
  }
}

template <typename Message>
void DurableLog::write_message(LogKind kind, std::int64_t utime, const Message& message) noexcept {
  std::array<unsigned char, kMaxEncodedSize> buffer;
  const int size = message.getEncodedSize();
  const bool encoded =
      size > 0 && static_cast<std::size_t>(size) <= buffer.size() && message.encode(buffer.data(), 0, size) == size;
  if (!encoded || file_ == nullptr) {
    write_errors_.fetch_add(1, std::memory_order_relaxed);
    return;
  }
  lcm::LogEvent& event = *event_;
  event.eventnum = event_number_;
  event.timestamp = utime;
  event.channel = channels_[index(kind)];  // reuses the string's capacity: no allocation
  event.datalen = size;
  event.data = buffer.data();
  // writeEvent returns 0 on success; a short write (disk full) leaves a truncated event,
  // which EventLogReader reports and skips.
  const std::uint32_t crc =
      event_crc32(event.eventnum, utime, event.channel, buffer.data(), static_cast<std::size_t>(size));
  const int result = file_->writeEvent(&event);
  event.data = nullptr;
  if (result == 0) {
    note_written(crc, event_number_, utime);
    ++event_number_;
    dirty_ = true;
    written_[index(kind)].fetch_add(1, std::memory_order_relaxed);
  } else {
    write_errors_.fetch_add(1, std::memory_order_relaxed);
  }
}

void DurableLog::write(const Entry& entry) noexcept {
  switch (entry.index()) {
    case 0: {
      const auto& glove = *std::get_if<0>(&entry);
      sculpt_lcm::glove_sample_t message{};
      to_lcm(glove.sample, glove.utime, message);
      write_message(LogKind::kGlove, glove.utime, message);
      break;
    }
    case 1: {
      const auto& record = *std::get_if<1>(&entry);
      sculpt_lcm::fingertip_state_t message{};
      to_lcm(record, message);
      write_message(LogKind::kFingertip, record.utime, message);
      break;
    }
    case 2: {
      const auto& record = *std::get_if<2>(&entry);
      sculpt_lcm::collision_event_t message{};
      to_lcm(record, message);
      write_message(LogKind::kCollision, record.utime, message);
      break;
    }
    case 3: {
      const auto& record = *std::get_if<3>(&entry);
      sculpt_lcm::tick_stats_t message{};
      to_lcm(record, message);
      write_message(LogKind::kTick, record.utime, message);
      break;
    }
    case 4: {
      const auto& haptic = *std::get_if<4>(&entry);
      sculpt_lcm::haptic_command_t message{};
      to_lcm(haptic.command, haptic.utime, message);
      write_message(LogKind::kHaptic, haptic.utime, message);
      break;
    }
    default: write_errors_.fetch_add(1, std::memory_order_relaxed); break;
  }
}

std::size_t DurableLog::drain(std::size_t limit) noexcept {
  std::size_t count = 0;
  while (count < limit && queue_.pop(scratch_)) {
    write(scratch_);
    ++count;
  }
  return count;
}

void DurableLog::note_written(std::uint32_t crc, std::int64_t number, std::int64_t utime) noexcept {
  if (check_.count == 0) check_.first_event = number;
  check_.crc.push_back(static_cast<std::int32_t>(crc));  // within the reserve: no allocation
  ++check_.count;
  last_utime_ = utime;
  if (number == 0 || check_.crc.size() >= kMaxCheckedEvents) write_check();
}

void DurableLog::write_check() noexcept {
  if (check_.count == 0 || file_ == nullptr) return;
  const int size = check_.getEncodedSize();
  const bool encoded = size > 0 && static_cast<std::size_t>(size) <= check_buffer_.size() &&
                       check_.encode(check_buffer_.data(), 0, size) == size;
  lcm::LogEvent& event = *event_;
  event.eventnum = event_number_;
  event.timestamp = last_utime_;
  event.channel = kCheckChannel;  // short enough for the string's own buffer: no allocation
  event.datalen = size;
  event.data = check_buffer_.data();
  // A check that cannot be written leaves its events unchecked, as a crash's tail is: a reader
  // hands them on as they are.
  if (encoded && file_->writeEvent(&event) == 0) {
    ++event_number_;
    checks_.fetch_add(1, std::memory_order_relaxed);
  } else {
    write_errors_.fetch_add(1, std::memory_order_relaxed);
  }
  event.data = nullptr;
  check_.crc.clear();
  check_.count = 0;
}

void DurableLog::flush(bool sync) noexcept {
  if (file_ == nullptr) return;
  write_check();
  std::FILE* f = file_->getFilePtr();
  if (std::fflush(f) != 0) write_errors_.fetch_add(1, std::memory_order_relaxed);
  // fsync only on explicit requests and at close: it can take milliseconds on a busy disk,
  // and the periodic flush already survives a crash of this process (not of the machine).
  if (sync && ::fsync(::fileno(f)) != 0 && errno != EINVAL && errno != EROFS) {
    write_errors_.fetch_add(1, std::memory_order_relaxed);
  }
  dirty_ = false;
  flushes_.fetch_add(1, std::memory_order_relaxed);
}

void DurableLog::close() noexcept {
  if (file_ == nullptr) return;
  flush(true);
  file_.reset();          // lcm_eventlog_destroy closes the FILE
  release_writer_lock();  // after the last write: the next writer finds the log complete
}

void DurableLog::run() noexcept {
  auto last_flush = std::chrono::steady_clock::now();
  // Drain in batches so a producer faster than the disk cannot starve flushes and requests.
  const std::size_t batch = queue_.capacity();
  for (;;) {
    const bool stopping = stop_requested_.load(std::memory_order_acquire);
    const std::uint64_t requested = flush_requests_.load(std::memory_order_acquire);
    const std::size_t written = drain(batch);
    if (requested > flushes_served_.load(std::memory_order_relaxed)) {
      // Everything queued before the request is in front of what drain() may have left.
      while (drain(batch) > 0) {
      }
      flush(true);
      last_flush = std::chrono::steady_clock::now();
      flushes_served_.store(requested, std::memory_order_release);
    }
    const auto now = std::chrono::steady_clock::now();
    if (dirty_ && now - last_flush >= config_.flush_interval) {
      flush(false);
      last_flush = now;
    }
    if (stopping) break;
    if (written == 0) std::this_thread::sleep_for(config_.poll_period);
  }
  // What the loop queued before stop() is written: stop() closes the file after the join.
  while (drain(batch) > 0) {
  }
}

}  // namespace sculpt::logging
