// Tests of firmware_config/src/config_document.cpp: which files are read as config (regular
// files of a sane size only, every failure named), and what YAML text becomes a document.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <filesystem>
#include <string>

#include "cambio/config/map_reader.hpp"
#include "file_test_support.hpp"

namespace cambio::config {
namespace {

using test::ScratchFolder;

/// What loading `path` reports ("file: message"), or "loaded" if it loads.
std::string load_problem(const std::string& path) {
  try {
    ConfigDocument::load_file(path);
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "loaded";
}

std::string parse_problem(const std::string& text) {
  try {
    ConfigDocument::from_string(text, "doc.yaml");
  } catch (const ConfigError& error) {
    return error.what();
  }
  return "loaded";
}

// ---------------------------------------------------------------------------------------------
// Only regular files of at most kMaxConfigFileBytes are read, and every failure is named.

TEST(ConfigFile, RefusesWhatIsNotARegularFile) {
  // /dev/zero would be read forever and a FIFO would block the open: both are refused first.
  EXPECT_EQ(load_problem("/dev/zero"),
            "/dev/zero: cannot read the file: it is a character device (such as /dev/zero), "
            "expected a regular file");
  ScratchFolder folder("cambio_config_file_test");
  const std::string fifo = folder.path("fifo.yaml");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  EXPECT_EQ(load_problem(fifo),
            fifo + ": cannot read the file: it is a FIFO (named pipe), expected a regular file");
  EXPECT_EQ(load_problem(folder.path("")),
            folder.path("") + ": cannot read the file: it is a directory, expected a YAML file");
}

TEST(ConfigFile, RefusesAFileAboveTheSizeLimit) {
  ScratchFolder folder("cambio_config_file_test");
  // Valid YAML, a comment past the limit: refused by size before it is parsed.
  const std::string path =
      folder.write("big.yaml", "rig: {name: big}\n# " + std::string(kMaxConfigFileBytes, 'x'));
  EXPECT_EQ(load_problem(path), path + ": cannot read the file: it holds " +
                                    std::to_string(kMaxConfigFileBytes + 19) +
                                    " bytes, more than a config file's most of 1048576 (1 MiB)");
  // At the limit it is read.
  const std::string at_limit =
      folder.write("at_limit.yaml", "a: 1\n#" + std::string(kMaxConfigFileBytes - 6, 'x'));
  EXPECT_EQ(load_problem(at_limit), "loaded");
  EXPECT_NE(parse_problem(std::string(kMaxConfigFileBytes + 1, ' ')).find("1048577 bytes"),
            std::string::npos);
}

TEST(ConfigFile, NamesEachPathError) {
  ScratchFolder folder("cambio_config_file_test");
  const std::string long_name = folder.path(std::string(300, 'a') + ".yaml");
  EXPECT_EQ(load_problem(long_name), long_name + ": cannot read the file: the name is too long");
  const std::string loop = folder.path("loop_a.yaml");
  std::filesystem::create_symlink(folder.path("loop_b.yaml"), loop);
  std::filesystem::create_symlink(loop, folder.path("loop_b.yaml"));
  EXPECT_EQ(load_problem(loop),
            loop +
                ": cannot read the file: too many levels of symbolic links (a link that "
                "leads back to itself?)");
  const std::string under_a_file = folder.write("file.yaml", "a: 1\n") + "/rig.yaml";
  EXPECT_EQ(load_problem(under_a_file),
            under_a_file + ": cannot read the file: a folder on its path is not a folder");
  EXPECT_EQ(load_problem(folder.path("missing.yaml")),
            folder.path("missing.yaml") + ": cannot read the file: it does not exist");
}

TEST(ConfigFile, APermissionProblemIsReportedAsSuch) {
  ScratchFolder folder("cambio_config_file_test");
  const std::string closed_file = folder.write("closed.yaml", "a: 1\n");
  std::filesystem::permissions(closed_file, std::filesystem::perms::none);
  std::filesystem::create_directories(folder.path("closed"));
  const std::string in_closed_folder = folder.write("closed/rig.yaml", "a: 1\n");
  std::filesystem::permissions(folder.path("closed"), std::filesystem::perms::none);

  EXPECT_EQ(test::run_unprivileged([&] { return load_problem(closed_file); }),
            closed_file + ": cannot read the file: permission denied");
  // Not "it does not exist": the file may well be there.
  EXPECT_EQ(test::run_unprivileged([&] { return load_problem(in_closed_folder); }),
            in_closed_folder + ": cannot read the file: permission denied");
  EXPECT_EQ(test::run_unprivileged(
                [&] { return config_file_problem(in_closed_folder).value_or("readable"); }),
            "permission denied");
}

TEST(ConfigFile, AReadableFileHasNoProblem) {
  ScratchFolder folder("cambio_config_file_test");
  EXPECT_EQ(config_file_problem(folder.write("ok.yaml", "a: 1\n")), std::nullopt);
  EXPECT_EQ(config_file_problem("/dev/zero").value_or(""),
            "it is a character device (such as /dev/zero), expected a regular file");
}

// ---------------------------------------------------------------------------------------------
// The text: exactly one YAML document, nested within the parser's limit.

TEST(ConfigText, NestingBeyondTheParsersDepthIsNamed) {
  // yaml-cpp's own message for it is "bad file".
  const std::string deep = "rig: " + std::string(3000, '[') + std::string(3000, ']') + "\n";
  const std::string problem = parse_problem(deep);
  EXPECT_TRUE(problem.starts_with("doc.yaml:1: invalid YAML: nested ")) << problem;
  EXPECT_NE(problem.find(" levels deep, more than the YAML parser takes (config files nest a few "
                         "levels)"),
            std::string::npos)
      << problem;
  EXPECT_EQ(problem.find("bad file"), std::string::npos) << problem;
}

TEST(ConfigText, ASecondDocumentIsRefused) {
  // Only the first would be read, silently.
  EXPECT_EQ(parse_problem("rig: {name: a}\n---\nrig: {name: b}\n"),
            "doc.yaml:2:1: expected one YAML document, found a second (a line '---' starts it)");
  EXPECT_EQ(parse_problem("---\nrig: {name: a}\n"), "loaded");
  EXPECT_EQ(parse_problem(""), "loaded");
}

TEST(ConfigText, AStrayCommaWhereADocumentStartsIsRefused) {
  // Found by fuzz_experiment: yaml-cpp reads a ',' where a document starts as an empty document,
  // YAML::Load dropped the rest of the file, and YAML::LoadAll returned that empty document
  // again and again until memory ran out.
  EXPECT_EQ(parse_problem(", e.yaml\n  executor: lockstep\n"),
            "doc.yaml:1:1: invalid YAML: a ',' outside any list or map");
  EXPECT_EQ(parse_problem("a: 1\n...\n,\n"),
            "doc.yaml:3:1: invalid YAML: a ',' outside any list or map");
}

}  // namespace
}  // namespace cambio::config
