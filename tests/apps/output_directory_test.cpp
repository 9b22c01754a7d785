// OutputDirectory against hostile contents of an --out directory: a manifest is untrusted input
// (names outside the directory, directories, FIFOs, huge files are refused before any work and
// nothing outside --out is touched), and a mount point as --out is written file by file.
#include "output_directory.hpp"

#include <sys/mount.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <future>
#include <iterator>
#include <string>

namespace cambio::app {
namespace {

namespace fs = std::filesystem;

fs::path fresh(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("cambio_output_directory_test_" + name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

void write_text(const fs::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  ASSERT_TRUE(file.good()) << path;
}

std::string read_text(const fs::path& path) {
  std::ifstream file(path);
  return {std::istreambuf_iterator<char>(file), {}};
}

/// Claims `out` and commits one file, as a run does.
void run_into(const fs::path& out) {
  OutputDirectory directory(out, "test");
  directory.stage("summary.json", std::string_view("{}\n"));
  directory.commit();
}

void expect_refused(const fs::path& out, const std::string& part) {
  try {
    OutputDirectory directory(out, "test");
    ADD_FAILURE() << "a hostile manifest was accepted in " << out;
  } catch (const OutputError& error) {
    EXPECT_NE(std::string(error.what()).find(part), std::string::npos) << error.what();
  }
}

TEST(OutputDirectoryTest, AManifestNamingAnythingButAPlainFileNameIsRefusedAndNothingIsTouched) {
  const fs::path root = fresh("escape");
  const fs::path victim = root / "victim";
  write_text(victim, "precious");
  const fs::path out = root / "out";
  fs::create_directories(out);
  for (const std::string& name :
       {victim.string(), std::string("../victim"), std::string(".."), std::string("a/../../victim"),
        std::string(""), std::string(".cambio-lock"), std::string(".cambio-staging-1")}) {
    write_text(out / OutputDirectory::kManifestName,
               "{\"files\": [\"summary.json\", \"" + name + "\"]}");
    expect_refused(out, "not a plain file name");
    EXPECT_EQ(read_text(victim), "precious") << name;
  }
  write_text(out / OutputDirectory::kManifestName, "{\"files\": [42]}");
  expect_refused(out, "not a plain file name");
  EXPECT_FALSE(fs::exists(out / "summary.json")) << "nothing was written";
}

TEST(OutputDirectoryTest, AManifestListingADirectoryIsRefusedAndTheDirectoryKept) {
  const fs::path out = fresh("listed_directory");
  fs::create_directories(out / "thesis");
  write_text(out / "thesis" / "chapter1.tex", "precious");
  write_text(out / OutputDirectory::kManifestName, R"({"files": ["thesis"]})");
  expect_refused(out, "not a regular file");
  EXPECT_EQ(read_text(out / "thesis" / "chapter1.tex"), "precious");
}

TEST(OutputDirectoryTest, AFifoOrAHugeFileAsTheManifestIsRefusedWithoutWaiting) {
  const fs::path out = fresh("fifo");
  ASSERT_EQ(::mkfifo((out / OutputDirectory::kManifestName).c_str(), 0644), 0);
  // Opening a FIFO for reading blocks until a writer comes: refused or this never returns.
  auto claim = std::async(std::launch::async, [&] { expect_refused(out, "not a regular file"); });
  ASSERT_EQ(claim.wait_for(std::chrono::seconds(30)), std::future_status::ready)
      << "the claim is waiting on the FIFO";
  claim.get();

  const fs::path big = fresh("huge_manifest");
  write_text(big / OutputDirectory::kManifestName,
             "{\"files\": [\"" + std::string(2 << 20, 'a') + "\"]}");
  expect_refused(big, "larger than a manifest can be");
}

TEST(OutputDirectoryTest, AMountPointAsOutIsWrittenFileByFile) {
  const fs::path out = fresh("mount_point");
  if (::geteuid() != 0 || ::unshare(CLONE_NEWNS) != 0 ||
      ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0 ||
      ::mount("cambio_test", out.c_str(), "tmpfs", 0, "size=1m") != 0) {
    GTEST_SKIP() << "mounting a tmpfs needs root and mount namespaces";
  }
  run_into(out);
  write_text(out / "stale.png", "from an earlier run");
  write_text(out / OutputDirectory::kManifestName,
             R"({"complete": true, "files": ["stale.png", "summary.json"]})");
  run_into(out);
  EXPECT_EQ(read_text(out / "summary.json"), "{}\n");
  EXPECT_FALSE(fs::exists(out / "stale.png")) << "the previous set was replaced";
  EXPECT_NE(read_text(out / OutputDirectory::kManifestName).find("\"complete\": true"),
            std::string::npos);
  for (const auto& entry : fs::directory_iterator(out)) {
    EXPECT_EQ(entry.path().filename().string().find(".cambio-staging-"), std::string::npos)
        << "a staging directory was left behind";
  }
  ::umount2(out.c_str(), MNT_DETACH);
}

}  // namespace
}  // namespace cambio::app
