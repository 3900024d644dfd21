// A fresh temporary directory per test, removed afterwards: the fixture of every test that writes
// real files (tests/<module>/ include it as "support/temp_dir_test.hpp"). The directory is named
// after the process and the test, so that tests run in parallel by ctest never share one.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <utility>

namespace ricochet::test {

class TempDirTest : public ::testing::Test {
 protected:
  /// `prefix` names the module in the directory's name, e.g. "ricochet-impact".
  explicit TempDirTest(std::string prefix = "ricochet-test") : prefix_(std::move(prefix)) {}
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           (prefix_ + "-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  /// A file named `name` in the directory.
  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::filesystem::path dir_;

 private:
  std::string prefix_;
};

}  // namespace ricochet::test
