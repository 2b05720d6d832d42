// io::StreamedFile: a file written while it is formatted (the ASCII frames) holds what the
// same text formatted whole holds, and a failed write in the middle leaves no file behind.
#include <gtest/gtest.h>
#include <sys/resource.h>

#include <csignal>
#include <filesystem>

#include "support/cli.hpp"
#include "tc/core/error.hpp"
#include "tc/io/files/files.hpp"

using namespace tc;
namespace fs = std::filesystem;

namespace {

/// Prints lines of numbers into `out` until about `bytes` are formatted: several of
/// StreamedFile's 1 MiB chunks, so that writes happen inside print() and not only in finish().
template <class Out>
void numbers(Out& out, size_t bytes) {
  for (size_t i = 0, n = 0; n < bytes; ++i) {
    const double x = 1.0 / static_cast<double>(i + 3);
    out.print("{} {}\n", i, x);
    n += fmt::formatted_size("{} {}\n", i, x);
  }
}

/// RLIMIT_FSIZE lowered for one scope (SIGXFSZ ignored, so a write beyond it fails with
/// EFBIG as one on a full disk fails with ENOSPC), restored after.
class FileSizeLimit {
 public:
  explicit FileSizeLimit(rlim_t bytes) {
    getrlimit(RLIMIT_FSIZE, &old_);
    old_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit lowered = old_;
    lowered.rlim_cur = bytes;
    setrlimit(RLIMIT_FSIZE, &lowered);
  }
  ~FileSizeLimit() {
    setrlimit(RLIMIT_FSIZE, &old_);
    std::signal(SIGXFSZ, old_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

 private:
  rlimit old_{};
  void (*old_handler_)(int) = nullptr;
};

TEST(StreamedFile, HoldsWhatTheWholeTextHolds) {
  const auto dir = test::fresh_dir("streamed-file");
  constexpr size_t bytes = 3'500'000;  // three whole chunks and a part
  io::TextBuffer whole;
  numbers(whole, bytes);
  io::StreamedFile streamed(dir / "streamed.txt");
  numbers(streamed, bytes);
  streamed.finish();
  EXPECT_EQ(test::read_file(dir / "streamed.txt"), std::string(whole.view()));
}

TEST(StreamedFile, AFailedWriteInTheMiddleLeavesNoFileAndNamesIt) {
  const auto dir = test::fresh_dir("streamed-file-limit");
  const auto file = dir / "frame.vtu";
  try {
    const FileSizeLimit limit(1'500'000);  // the second chunk's write fails
    io::StreamedFile out(file);
    numbers(out, 3'500'000);
    out.finish();
    ADD_FAILURE() << "a write beyond the file-size limit succeeded";
  } catch (const OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot write " + file.string() + ": File too large"),
              std::string::npos)
        << e.what();
  }
  EXPECT_FALSE(fs::exists(file)) << "the partial file was left";
}

TEST(StreamedFile, AFileNotFinishedIsRemoved) {
  // An exception while the frame is formatted (the caller's) must not leave half a frame that
  // a reader would take for a written one.
  const auto dir = test::fresh_dir("streamed-file-unfinished");
  const auto file = dir / "frame.vtu";
  {
    io::StreamedFile out(file);
    numbers(out, 2'500'000);
    EXPECT_TRUE(fs::exists(file));
  }
  EXPECT_FALSE(fs::exists(file));
}

}  // namespace
