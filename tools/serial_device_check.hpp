#pragma once
// Whether a path can be a glove's serial line, asked before a session starts. The serial
// backends retry a device that goes away, which is right for a glove unplugged mid-session but
// made a path that never was one (a typo, /dev/null, a regular file) run silently with 0
// samples, or wait for ever with nothing said when stderr was not a terminal.

#include <string>

namespace sculpt::tools {

/// Empty when `path` is a terminal (a serial port, a USB serial adapter, a pseudo-terminal);
/// otherwise why not: "no such device", "a regular file, not a serial device", "a character
/// device but not a terminal". A character device is opened (non-blocking, never as the
/// controlling terminal) and closed again to ask.
std::string serial_device_problem(const std::string& path);

}  // namespace sculpt::tools
