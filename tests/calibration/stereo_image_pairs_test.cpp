// The pairing rule of `calibrate stereo --images`: leftID.* with rightID.*, every image without
// its partner and every view given twice named.
#include "stereo_image_pairs.hpp"

#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

namespace cambio::app {
namespace {

class ImageFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = std::filesystem::temp_directory_path() /
                 ("cambio_pairs_" + std::to_string(::getpid()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(directory_);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }
  void touch(const std::string& name) const { std::ofstream(directory_ / name) << "x"; }
  std::string refusal() const {
    try {
      (void)find_stereo_image_pairs(directory_);
    } catch (const CalibrationInputError& error) {
      return error.what();
    }
    return "(accepted)";
  }

  std::filesystem::path directory_;
};

TEST_F(ImageFolder, PairsByIdInOrderAcrossExtensionsAndIgnoresOtherFiles) {
  for (const char* name : {"right02.png", "left02.png", "left01.jpg", "right01.JPG", "notes.txt",
                           "board.png", "left03.txt"}) {
    touch(name);
  }
  const auto pairs = find_stereo_image_pairs(directory_);
  ASSERT_EQ(pairs.size(), 2U);
  EXPECT_EQ(pairs[0].view_id, "01");
  EXPECT_EQ(pairs[0].left.filename(), "left01.jpg");
  EXPECT_EQ(pairs[0].right.filename(), "right01.JPG");
  EXPECT_EQ(pairs[1].view_id, "02");
  EXPECT_EQ(pairs[1].right.filename(), "right02.png");
}

TEST_F(ImageFolder, NamesEveryUnpairedImage) {
  for (const char* name : {"left01.png", "right01.png", "left02.png", "right03.png"}) touch(name);
  const std::string message = refusal();
  EXPECT_NE(message.find("left02.png has no right02.*"), std::string::npos) << message;
  EXPECT_NE(message.find("right03.png has no left03.*"), std::string::npos) << message;
}

TEST_F(ImageFolder, NamesAViewGivenTwice) {
  for (const char* name : {"left01.png", "left01.jpg", "right01.png"}) touch(name);
  const std::string message = refusal();
  EXPECT_NE(message.find("left01.jpg, left01.png are one view given twice"), std::string::npos)
      << message;
}

TEST_F(ImageFolder, RefusesAFolderWithoutPairsAndAMissingFolder) {
  touch("board.png");
  EXPECT_NE(refusal().find("holds no image pair"), std::string::npos) << refusal();
  std::filesystem::remove_all(directory_);
  EXPECT_NE(refusal().find("is not a directory"), std::string::npos) << refusal();
}

}  // namespace
}  // namespace cambio::app
