// write_file_atomically: the target is the old file or the new one, never a mix, and no
// temporary file outlives a failed write. Failures are real ones (a file size limit that stops
// write() half way, a missing folder, a name too long), not mocks.

#include <gtest/gtest.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "sculpt/deform/atomic_file.hpp"
#include "sculpt/deform/generators.hpp"
#include "sculpt/deform/model_io.hpp"

namespace sculpt::deform {
namespace {

namespace fs = std::filesystem;

// A fresh, empty folder per test, so "nothing else is there" can be checked exactly.
class AtomicFile : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = fs::path(::testing::TempDir()) / (std::string("atomic_") + info->name());
    fs::remove_all(folder_);
    fs::create_directories(folder_);
  }
  void TearDown() override {
    fs::permissions(folder_, fs::perms::owner_all, fs::perm_options::add);
    fs::remove_all(folder_);
  }

  std::string at(const std::string& name) const { return (folder_ / name).string(); }

  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(folder_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }

  fs::path folder_;
};

std::string contents(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void put(const std::string& path, const std::string& bytes) { std::ofstream(path, std::ios::binary) << bytes; }

// RLIMIT_FSIZE makes write() fail with EFBIG once a file would grow past the limit: a disk
// that fills up in the middle of the write. SIGXFSZ is ignored so the process survives it.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &saved_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limit = saved_;
    limit.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &limit);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit saved_{};
  void (*old_handler_)(int) = nullptr;
};

// Expects `write` to throw ModelFileError about `path` whose message contains `reason`.
template <typename Write>
void expect_refused(Write write, const std::string& path, const std::string& reason) {
  try {
    write();
    ADD_FAILURE() << "the write to " << path << " succeeded";
  } catch (const ModelFileError& e) {
    EXPECT_EQ(e.path(), path);
    EXPECT_NE(std::string(e.what()).find(reason), std::string::npos) << e.what();
  }
}

TEST_F(AtomicFile, CreatesTheFileAndLeavesNothingElse) {
  write_file_atomically(at("new.txt"), "hello\n");
  EXPECT_EQ(contents(at("new.txt")), "hello\n");
  EXPECT_EQ(entries(), std::vector<std::string>{"new.txt"});
}

TEST_F(AtomicFile, ReplacesAnExistingFileWhole) {
  put(at("old.txt"), std::string(10000, 'o'));
  write_file_atomically(at("old.txt"), "short");
  EXPECT_EQ(contents(at("old.txt")), "short");
  EXPECT_EQ(entries(), std::vector<std::string>{"old.txt"});
}

TEST_F(AtomicFile, ARelativePathIsWrittenInTheCurrentFolder) {
  const fs::path before = fs::current_path();
  fs::current_path(folder_);
  write_file_atomically("relative.txt", "r");
  fs::current_path(before);
  EXPECT_EQ(contents(at("relative.txt")), "r");
  EXPECT_EQ(entries(), std::vector<std::string>{"relative.txt"});
}

TEST_F(AtomicFile, AWriteThatFailsHalfWayLeavesTheOldFileAndNoTemporary) {
  const std::string old_bytes = "the old model\n";
  put(at("model.ply"), old_bytes);
  {
    const FileSizeLimit limit(4096);
    expect_refused([&] { write_file_atomically(at("model.ply"), std::string(100000, 'n')); }, at("model.ply"),
                   "cannot write (File too large)");
  }
  EXPECT_EQ(contents(at("model.ply")), old_bytes);
  EXPECT_EQ(entries(), std::vector<std::string>{"model.ply"});
}

TEST_F(AtomicFile, WritePlyThatFailsHalfWayLeavesTheOldFile) {
  const PointModel small = make_sphere(10);
  write_ply(at("sphere.ply"), small);
  const std::string old_bytes = contents(at("sphere.ply"));
  {
    const FileSizeLimit limit(old_bytes.size() + 100);
    expect_refused([&] { write_ply(at("sphere.ply"), make_sphere(5000)); }, at("sphere.ply"), "cannot write");
  }
  EXPECT_EQ(contents(at("sphere.ply")), old_bytes);
  EXPECT_EQ(entries(), std::vector<std::string>{"sphere.ply"});
}

TEST_F(AtomicFile, AModelThatFailsValidationNeverTouchesTheTarget) {
  put(at("model.ply"), "old");
  PointModel broken = make_sphere(10);
  broken.triangles = {0, 1, 99};
  EXPECT_THROW(write_model(at("model.ply"), broken), std::invalid_argument);
  EXPECT_EQ(contents(at("model.ply")), "old");
  EXPECT_EQ(entries(), std::vector<std::string>{"model.ply"});
}

TEST_F(AtomicFile, AMissingFolderIsRefusedAndNothingIsCreated) {
  const std::string path = at("missing/out.ply");
  expect_refused([&] { write_file_atomically(path, "x"); }, path, "No such file or directory");
  EXPECT_TRUE(entries().empty());
}

TEST_F(AtomicFile, AFileInPlaceOfTheFolderIsRefused) {
  put(at("plain"), "p");
  const std::string path = at("plain/out.ply");
  expect_refused([&] { write_file_atomically(path, "x"); }, path, "Not a directory");
  EXPECT_EQ(contents(at("plain")), "p");
  EXPECT_EQ(entries(), std::vector<std::string>{"plain"});
}

TEST_F(AtomicFile, ANameTooLongIsRefusedAndLeavesNoTemporary) {
  const std::string path = at(std::string(300, 'n') + ".ply");
  expect_refused([&] { write_file_atomically(path, "x"); }, path, "File name too long");
  EXPECT_TRUE(entries().empty());
}

TEST_F(AtomicFile, ANameAtTheLimitStillGetsATemporaryBesideIt) {
  // 255 bytes is the longest name; the temporary's name must not be longer.
  const std::string name = std::string(251, 'n') + ".ply";
  write_file_atomically(at(name), "x");
  EXPECT_EQ(entries(), std::vector<std::string>{name});
}

TEST_F(AtomicFile, AReadOnlyFolderIsRefusedAndTheFileKept) {
  if (::geteuid() == 0) GTEST_SKIP() << "root writes into read-only folders";
  put(at("kept.txt"), "kept");
  fs::permissions(folder_, fs::perms::owner_read | fs::perms::owner_exec);
  expect_refused([&] { write_file_atomically(at("kept.txt"), "new"); }, at("kept.txt"), "Permission denied");
  fs::permissions(folder_, fs::perms::owner_all);
  EXPECT_EQ(contents(at("kept.txt")), "kept");
  EXPECT_EQ(entries(), std::vector<std::string>{"kept.txt"});
}

TEST_F(AtomicFile, ADirectoryOrFifoAtThePathIsRefusedAndLeftAsItIs) {
  fs::create_directory(at("dir.ply"));
  expect_refused([&] { write_file_atomically(at("dir.ply"), "x"); }, at("dir.ply"), "is a directory");
  EXPECT_TRUE(fs::is_directory(at("dir.ply")));
  ASSERT_EQ(::mkfifo(at("pipe.ply").c_str(), 0600), 0);
  expect_refused([&] { write_file_atomically(at("pipe.ply"), "x"); }, at("pipe.ply"), "not a regular file");
  EXPECT_TRUE(fs::is_fifo(at("pipe.ply")));
  EXPECT_EQ(entries(), (std::vector<std::string>{"dir.ply", "pipe.ply"}));
}

TEST_F(AtomicFile, AnExistingFileKeepsItsPermissions) {
  put(at("shared.txt"), "old");
  fs::permissions(at("shared.txt"), fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
  write_file_atomically(at("shared.txt"), "new");
  EXPECT_EQ(fs::status(at("shared.txt")).permissions(),
            fs::perms::owner_read | fs::perms::owner_write | fs::perms::group_read);
}

TEST_F(AtomicFile, ANewFileGetsTheUmasksPermissions) {
  const mode_t saved = ::umask(027);
  write_file_atomically(at("new.txt"), "x");
  ::umask(saved);
  struct stat info {};
  ASSERT_EQ(::stat(at("new.txt").c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 0777, 0640u);
}

TEST_F(AtomicFile, ASymbolicLinkIsWrittenThrough) {
  put(at("real.ply"), "old");
  fs::create_symlink("real.ply", at("link.ply"));
  write_file_atomically(at("link.ply"), "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(at("link.ply"))));
  EXPECT_EQ(contents(at("real.ply")), "new");
  EXPECT_EQ(entries(), (std::vector<std::string>{"link.ply", "real.ply"}));
}

}  // namespace
}  // namespace sculpt::deform
