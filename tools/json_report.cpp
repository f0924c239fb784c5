#include "json_report.hpp"

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "sculpt/base/version.hpp"
#include "output_paths.hpp"
#include "sculpt/deform/atomic_file.hpp"

namespace sculpt::tools {
namespace {

int g_json_fd = STDOUT_FILENO;  // where `--json -` writes: the real stdout

}  // namespace

void stamp_summary(nlohmann::json& summary) {
  summary["schema"] = kJsonSchema;
  summary["version"] = base::project_version();
}

void reserve_stdout_for_json() {
  if (g_json_fd != STDOUT_FILENO) return;
  std::fflush(stdout);
  std::cout.flush();
  const int saved = ::dup(STDOUT_FILENO);
  if (saved < 0 || ::dup2(STDERR_FILENO, STDOUT_FILENO) < 0) return;  // then text and JSON share stdout
  g_json_fd = saved;
}

std::string json_text(const nlohmann::json& summary) {
  return summary.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
}

void write_json(const std::string& path, const nlohmann::json& summary) {
  const std::string text = json_text(summary);
  if (path != "-") {
    create_parent_folders(path);
    deform::write_file_atomically(path, text);
    return;
  }
  std::fflush(stdout);
  std::cout.flush();
  for (std::size_t done = 0; done < text.size();) {
    const ssize_t n = ::write(g_json_fd, text.data() + done, text.size() - done);
    if (n <= 0) throw std::runtime_error("--json -: cannot write to stdout");
    done += static_cast<std::size_t>(n);
  }
}

}  // namespace sculpt::tools
