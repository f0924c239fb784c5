// PNGs are written whole or not at all, and read back as written.
#include "render/png_reader.cpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "sculpt/render/png_file.hpp"

namespace sculpt::test {
namespace {

namespace fs = std::filesystem;

fs::path fresh_folder(const std::string& name) {
  const fs::path folder = fs::temp_directory_path() / ("sculpt_render_" + name + "_" + std::to_string(getpid()));
  fs::remove_all(folder);
  fs::create_directories(folder);
  return folder;
}

TEST(PngFile, ReadsBackAsWrittenAndLeavesNoTemporaryFile) {
  const fs::path folder = fresh_folder("png");
  render::Image image(7, 5, {0.1, 0.5, 0.9});
  image.set(3, 2, {1.0, 0.0, 0.0});
  const std::string path = (folder / "picture.png").string();
  render::write_png(path, image);
  render::write_png(path, image);  // replacing an existing picture
  const render::Image back = read_png(path);
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.pixels, image.pixels);
  EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 1);
  EXPECT_EQ(fs::status(path).permissions() & fs::perms::others_read, fs::perms::others_read);
  fs::remove_all(folder);
}

TEST(PngFile, AFolderThatIsNotThereIsAnErrorNamingThePath) {
  const std::string path = "/nonexistent-folder/picture.png";
  try {
    render::write_png(path, render::Image(2, 2, {}));
    FAIL() << "wrote into a missing folder";
  } catch (const render::PngFileError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
  }
}

}  // namespace
}  // namespace sculpt::test
