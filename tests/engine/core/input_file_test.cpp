// Whole-file reads of input files: only regular files (a symlink to one is fine), never a
// device, a FIFO or a directory (each refused at once, never read or waited on), and a size
// cap checked before reading.
#include "engine/core/input_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

namespace acdr {
namespace {

namespace fs = std::filesystem;

class InputFile : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("acdr_input_file_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  std::string path(const std::string& name) const { return (dir_ / name).string(); }

  /// Reads `p` with a cap of `max` bytes and says how long it took.
  std::optional<std::string> read(const std::string& p, std::size_t max, std::string* error,
                                  double* seconds = nullptr) const {
    const auto t0 = std::chrono::steady_clock::now();
    auto out = read_input_file(p, max, "a test file", error);
    if (seconds) *seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    return out;
  }

  fs::path dir_;
};

TEST_F(InputFile, ReadsARegularFileAndASymlinkToOne) {
  std::ofstream(path("a.txt"), std::ios::binary) << "hello\n";
  fs::create_symlink(path("a.txt"), path("link.txt"));
  std::string error;
  EXPECT_EQ(read(path("a.txt"), 100, &error).value_or("?"), "hello\n") << error;
  EXPECT_EQ(read(path("link.txt"), 100, &error).value_or("?"), "hello\n") << error;
  std::ofstream(path("empty.txt"), std::ios::binary);
  EXPECT_EQ(read(path("empty.txt"), 100, &error).value_or("?"), "");
}

TEST_F(InputFile, RefusesDevicesBehindSymlinksAtOnce) {
  for (const char* device : {"/dev/zero", "/dev/urandom"}) {
    SCOPED_TRACE(device);
    fs::create_symlink(device, path("mesh.stl"));
    std::string error;
    double seconds = 0.0;
    EXPECT_FALSE(read(path("mesh.stl"), std::size_t{64} << 20, &error, &seconds));
    EXPECT_EQ(error, "not a regular file (got a character device, expected a test file)");
    EXPECT_LT(seconds, 1.0);
    fs::remove(path("mesh.stl"));
  }
}

TEST_F(InputFile, RefusesAFifoWithoutWaitingForAWriter) {
  ASSERT_EQ(::mkfifo(path("pipe").c_str(), 0600), 0);
  std::string error;
  double seconds = 0.0;
  EXPECT_FALSE(read(path("pipe"), 100, &error, &seconds));
  EXPECT_EQ(error, "not a regular file (got a FIFO, expected a test file)");
  EXPECT_LT(seconds, 1.0);
  fs::create_symlink(path("pipe"), path("pipe_link"));
  EXPECT_FALSE(read(path("pipe_link"), 100, &error));
  EXPECT_EQ(error, "not a regular file (got a FIFO, expected a test file)");
}

TEST_F(InputFile, RefusesADirectory) {
  std::string error;
  EXPECT_FALSE(read(dir_.string(), 100, &error));
  EXPECT_EQ(error, "not a regular file (got a directory, expected a test file)");
}

TEST_F(InputFile, RefusesAFileOverTheCapBeforeReadingIt) {
  std::ofstream(path("big.txt"), std::ios::binary) << std::string(101, 'x');
  std::string error;
  EXPECT_FALSE(read(path("big.txt"), 100, &error));
  EXPECT_EQ(error, "file too large (got 101 bytes, expected at most 100 for a test file)");
  EXPECT_EQ(read(path("big.txt"), 101, &error).value_or("").size(), 101u);
  // A sparse 1 TB file is refused from its size alone, without reading a byte.
  {
    std::ofstream(path("sparse.bin"), std::ios::binary);
  }
  fs::resize_file(path("sparse.bin"), std::uintmax_t{1} << 40);
  double seconds = 0.0;
  EXPECT_FALSE(read(path("sparse.bin"), kMaxMeshFileBytes, &error, &seconds));
  EXPECT_NE(error.find("file too large (got 1099511627776 bytes, expected at most 67108864"), std::string::npos)
      << error;
  EXPECT_LT(seconds, 1.0);
}

TEST_F(InputFile, SaysWhyAMissingFileCannotBeOpened) {
  std::string error;
  EXPECT_FALSE(read(path("none.txt"), 100, &error));
  EXPECT_EQ(error, "cannot open the file: No such file or directory (expected a test file)");
}

}  // namespace
}  // namespace acdr
