#pragma once
// Line and token walking over text held in memory: the shared front end of the PLY header,
// PLY ascii, OFF and XYZ parsers. Nothing is copied; lines and tokens are views into the text.

#include <cstddef>
#include <cstring>
#include <string>
#include <string_view>

namespace sculpt::deform {

/// Whitespace between tokens. '\r' counts so that "\r\n" files need no special casing.
inline bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

/// "line N", the <where> of text errors.
inline std::string line_where(std::size_t line_number) { return "line " + std::to_string(line_number); }

/// A token quoted for an error message: at most 40 characters, non-printable bytes as '?', so
/// a binary file misread as text cannot produce a megabyte-long message.
inline std::string quoted(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  std::string out = "'";
  for (std::size_t i = 0; i < token.size() && i < kMaxShown; ++i) {
    const auto c = static_cast<unsigned char>(token[i]);
    out += (c >= 0x20 && c < 0x7f) ? static_cast<char>(c) : '?';
  }
  if (token.size() > kMaxShown) out += "...";
  return out + "'";
}

/// The part of a line before a '#' comment.
inline std::string_view strip_comment(std::string_view line) {
  const std::size_t hash = line.find('#');
  return hash == std::string_view::npos ? line : line.substr(0, hash);
}

/// True when the line holds only whitespace.
inline bool is_blank_line(std::string_view line) {
  for (char c : line) {
    if (!is_blank(c)) return false;
  }
  return true;
}

/// Hands out the lines of a text one by one, counting them from 1.
class TextScanner {
 public:
  /// Starts at byte `offset` of `text`; the first line returned gets number `first_line`.
  explicit TextScanner(std::string_view text, std::size_t offset = 0, std::size_t first_line = 1)
      : text_(text), pos_(offset), next_line_number_(first_line) {}

  /// The next line without its "\n" or "\r\n"; false when the text is used up.
  bool next_line(std::string_view& line) {
    if (pos_ >= text_.size()) return false;
    const char* begin = text_.data() + pos_;
    const std::size_t left = text_.size() - pos_;
    const void* newline = std::memchr(begin, '\n', left);
    const std::size_t length =
        newline != nullptr ? static_cast<std::size_t>(static_cast<const char*>(newline) - begin) : left;
    pos_ += newline != nullptr ? length + 1 : length;
    line = std::string_view(begin, length);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    line_number_ = next_line_number_++;
    return true;
  }

  /// Number of the line last returned by next_line.
  std::size_t line_number() const { return line_number_; }
  /// Number the next line will get: where to point errors about text that is missing.
  std::size_t next_line_number() const { return next_line_number_; }
  /// Byte offset of the first character not yet returned.
  std::size_t offset() const { return pos_; }
  /// Bytes not yet returned.
  std::size_t remaining() const { return pos_ < text_.size() ? text_.size() - pos_ : 0; }

 private:
  std::string_view text_;
  std::size_t pos_;
  std::size_t next_line_number_;
  std::size_t line_number_ = 0;
};

/// Splits one line into whitespace-separated tokens.
class TokenCursor {
 public:
  explicit TokenCursor(std::string_view line) : rest_(line) {}

  /// The next token; false when only whitespace is left.
  bool next(std::string_view& token) {
    std::size_t i = 0;
    while (i < rest_.size() && is_blank(rest_[i])) ++i;
    if (i == rest_.size()) {
      rest_ = {};
      return false;
    }
    std::size_t j = i;
    while (j < rest_.size() && !is_blank(rest_[j])) ++j;
    token = rest_.substr(i, j - i);
    rest_.remove_prefix(j);
    return true;
  }

  /// True when no token is left.
  bool at_end() const { return is_blank_line(rest_); }

 private:
  std::string_view rest_;
};

}  // namespace sculpt::deform
