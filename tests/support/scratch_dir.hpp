#pragma once
// A temporary folder owned by one test. Its name joins the test's label, the process id and a
// random suffix because several suites run on one machine at the same time (ctest -j, and each
// developer's worktree): fixed /tmp names let one suite overwrite or delete another's files.
// The folder and everything in it is removed when the ScratchDir goes out of scope. Tests only.
#include <unistd.h>

#include <filesystem>
#include <random>
#include <string>
#include <string_view>
#include <system_error>

namespace labo::test {

class ScratchDir {
 public:
  explicit ScratchDir(std::string_view label) : path_(unique_path(label)) {
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ignored;  // a test that failed half way must not throw from a destructor
    std::filesystem::remove_all(path_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  ScratchDir(ScratchDir&&) = delete;
  ScratchDir& operator=(ScratchDir&&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::filesystem::path& name) const { return path_ / name; }
  operator const std::filesystem::path&() const { return path_; }  // NOLINT: reads like a path

 private:
  static std::filesystem::path unique_path(std::string_view label) {
    std::random_device entropy;
    const auto suffix = std::to_string(entropy()) + std::to_string(entropy() & 0xffffu);
    return std::filesystem::temp_directory_path() /
           ("labo_" + std::string(label) + "_" + std::to_string(::getpid()) + "_" + suffix);
  }

  std::filesystem::path path_;
};

}  // namespace labo::test
