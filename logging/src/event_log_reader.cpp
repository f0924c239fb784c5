#include "sculpt/logging/event_log_reader.hpp"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <utility>

#include <sys/stat.h>
#include <sys/types.h>
#include <unistd.h>

#include "sculpt/base/regular_file.hpp"

namespace sculpt::logging {
namespace {

// Resynchronisation reads the file in chunks this big; one chunk is enough for most gaps.
constexpr std::size_t kScanChunk = 64 * 1024;

std::uint32_t load_u32(const std::uint8_t* p) noexcept {
  return (std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) | (std::uint32_t{p[2]} << 8) | p[3];
}

std::uint64_t load_u64(const std::uint8_t* p) noexcept { return (std::uint64_t{load_u32(p)} << 32) | load_u32(p + 4); }

std::string hex32(std::uint32_t value) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08X", static_cast<unsigned>(value));
  return text;
}

}  // namespace

EventLogReader::EventLogReader(const std::string& path, std::uint64_t start) : path_(path), position_(start) {
  // Opened as base opens a model or a scene: a FIFO named as a log used to hold fopen until a
  // writer came (sculpt replay, render and report waited for ever), and a folder or a device is
  // named for what it is.
  int fd = -1;
  try {
    fd = base::open_regular_file(path);
  } catch (const base::FileReadError& e) {
    throw LogFileError(path + ": " + e.what());
  }
  struct stat info {};
  if (::fstat(fd, &info) != 0) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    throw LogFileError(path + ": cannot read its size: " + why);
  }
  file_ = ::fdopen(fd, "rb");
  if (file_ == nullptr) {
    const std::string why = std::strerror(errno);
    ::close(fd);
    throw LogFileError(path + ": cannot open: " + why);
  }
  size_ = static_cast<std::uint64_t>(info.st_size);
  if (start > size_) {
    std::fclose(file_);
    file_ = nullptr;
    throw LogFileError(path + ": byte offset " + std::to_string(start) + " is past the file's end (" +
                       std::to_string(size_) + " bytes)");
  }
}

EventLogReader::~EventLogReader() {
  if (file_ != nullptr) std::fclose(file_);
}

void EventLogReader::read_at(std::uint64_t offset, void* buffer, std::size_t size) {
  // Callers only ask for bytes inside size_, so a short read is an I/O error or a file that
  // shrank under us, not damage in the log.
  if (::fseeko(file_, static_cast<off_t>(offset), SEEK_SET) != 0 || std::fread(buffer, 1, size, file_) != size) {
    throw LogFileError(
        path_ + ": byte offset " + std::to_string(offset) + ": cannot read " + std::to_string(size) + " bytes" +
        (std::ferror(file_) != 0 ? std::string(": ") + std::strerror(errno) : std::string(" (file shrank?)")));
  }
}

EventLogReader::Header EventLogReader::read_header(std::uint64_t offset) {
  std::uint8_t bytes[kLogHeaderSize];
  read_at(offset, bytes, sizeof bytes);
  Header header;
  header.sync = load_u32(bytes);
  header.number = static_cast<std::int64_t>(load_u64(bytes + 4));
  header.utime = static_cast<std::int64_t>(load_u64(bytes + 12));
  header.channel_length = static_cast<std::int32_t>(load_u32(bytes + 20));
  header.data_length = static_cast<std::int32_t>(load_u32(bytes + 24));
  return header;
}

std::string EventLogReader::check(std::uint64_t offset, const Header& header, std::string& channel, bool& cut) {
  cut = false;
  if (header.sync != kLogSyncWord) {
    return "bad sync word " + hex32(header.sync) + " (expected " + hex32(kLogSyncWord) + ")";
  }
  if (header.channel_length <= 0 || header.channel_length > kMaxLogChannelLength) {
    return "channel length " + std::to_string(header.channel_length);
  }
  if (header.data_length < 0) return "data length " + std::to_string(header.data_length);
  // Checked against what is left before anything is allocated: a flipped bit in a length
  // must not ask for gigabytes.
  const std::uint64_t needs = kLogHeaderSize + static_cast<std::uint64_t>(header.channel_length) +
                              static_cast<std::uint64_t>(header.data_length);
  const std::uint64_t left = size_ - offset;
  if (needs > left) {
    cut = true;
    return "truncated event: needs " + std::to_string(needs) + " bytes, " + std::to_string(left) + " left";
  }
  channel.resize(static_cast<std::size_t>(header.channel_length));
  read_at(offset + kLogHeaderSize, channel.data(), channel.size());
  for (const char c : channel) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte < 0x20 || byte > 0x7E) {
      char text[64];
      std::snprintf(text, sizeof text, "channel name holds the non-printable byte 0x%02X", byte);
      return text;
    }
  }
  return {};
}

EventLogReader::Result EventLogReader::corrupt(const std::string& what, bool cut) {
  error_ = path_ + ": byte offset " + std::to_string(position_) + ": " + what;
  error_is_cut_ = cut;
  error_offset_ = position_;
  ++corrupt_events_;
  resync_pending_ = true;
  return Result::kCorrupt;
}

void EventLogReader::resynchronise() {
  // The event at position_ was rejected; its sync word (if any) is not trusted, so the scan
  // starts one byte later and accepts a candidate only when its whole header checks out.
  const std::uint64_t start = position_;
  if (scan_buffer_.empty()) scan_buffer_.resize(kScanChunk);
  std::string channel;
  std::uint64_t pos = start + 1;
  while (pos + 4 <= size_) {
    const auto n = static_cast<std::size_t>(std::min<std::uint64_t>(kScanChunk, size_ - pos));
    read_at(pos, scan_buffer_.data(), n);
    for (std::size_t i = 0; i + 4 <= n; ++i) {
      if (load_u32(scan_buffer_.data() + i) != kLogSyncWord) continue;
      const std::uint64_t candidate = pos + i;
      if (size_ - candidate < kLogHeaderSize) continue;
      bool cut = false;
      if (check(candidate, read_header(candidate), channel, cut).empty()) {
        skipped_bytes_ += candidate - start;
        position_ = candidate;
        return;
      }
    }
    pos += n - 3;  // n >= 4: a sync word across the chunk border is seen in the next chunk
  }
  skipped_bytes_ += size_ - start;
  position_ = size_;
}

EventLogReader::Result EventLogReader::next(LogEvent& out) {
  if (resync_pending_) {
    resync_pending_ = false;
    resynchronise();
  }
  if (position_ >= size_) return Result::kEnd;
  const std::uint64_t left = size_ - position_;
  if (left < kLogHeaderSize) {
    return corrupt(
        "truncated event header: needs " + std::to_string(kLogHeaderSize) + " bytes, " + std::to_string(left) + " left",
        /*cut=*/true);
  }
  const Header header = read_header(position_);
  bool cut = false;
  std::string why = check(position_, header, out.channel, cut);
  if (!why.empty()) return corrupt(std::move(why), cut);
  out.offset = position_;
  out.number = header.number;
  out.utime = header.utime;
  out.data.resize(static_cast<std::size_t>(header.data_length));
  if (!out.data.empty()) {
    read_at(position_ + kLogHeaderSize + out.channel.size(), out.data.data(), out.data.size());
  }
  position_ += kLogHeaderSize + out.channel.size() + out.data.size();
  return Result::kEvent;
}

}  // namespace sculpt::logging
