// The CiA 306 reader (drivers/canopen/eds/): the shipped EDS and vendor-like fixtures parse
// clean, values and $NODEID evaluate per node, and every malformed thing is reported at its line.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>

#include "cambio/canopen/eds/eds_file.hpp"

namespace cambio::canopen::eds {
namespace {

const std::string kShipped =
    std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/eds/cambio_virtual_drive.eds";
const std::string kFixtures = std::string(CAMBIO_SOURCE_DIR) + "/tests/drivers/canopen/eds/";

std::string issues_text(const EdsReadResult& result) {
  std::string text;
  for (const EdsIssue& issue : result.issues) text += issue.to_string() + "\n";
  return text;
}

/// Whether an issue at `line` says `what`.
bool has_issue(const EdsReadResult& result, int line, const std::string& what) {
  for (const EdsIssue& issue : result.issues) {
    if (issue.line == line && issue.message.find(what) != std::string::npos) return true;
  }
  return false;
}

/// A small well-formed EDS with `objects` appended and listed in [OptionalObjects] as `listed`.
std::string small_eds(const std::string& listed_count, const std::string& listed,
                      const std::string& objects) {
  return "[DeviceInfo]\nNrOfRXPDO=0\nNrOfTXPDO=0\n\n[MandatoryObjects]\nSupportedObjects=1\n"
         "1=0x1000\n\n[OptionalObjects]\nSupportedObjects=" +
         listed_count + "\n" + listed +
         "\n[1000]\nParameterName=Device type\nObjectType=0x7\nDataType=0x0007\nAccessType=ro\n"
         "DefaultValue=0x00020192\nPDOMapping=0\n\n" +
         objects;
}

TEST(EdsValue, NumbersAndNodeIdExpressions) {
  EXPECT_EQ(parse_integer("$NODEID+0x180")->evaluate(5), 0x185);
  EXPECT_EQ(parse_integer(" 0x80000200 + $nodeid ")->evaluate(127), 0x8000027F);
  EXPECT_EQ(parse_integer("-3")->evaluate(1), -3);
  EXPECT_EQ(parse_integer("017")->evaluate(1), 15);  // CiA 306: a leading 0 is octal.
  EXPECT_EQ(parse_integer("0xFFFFFFFFFFFFFFFF")->evaluate(1), -1);  // UNSIGNED64's bits.
  EXPECT_TRUE(parse_integer("$NODEID+0x180")->depends_on_node_id());
  for (const char* bad : {"", "abc", "$NODEID+", "0x", "1 2", "08", "1+0xFFFFFFFFFFFFFFFF",
                          "0x1FFFFFFFFFFFFFFFF", "--1", "$NODE"}) {
    EXPECT_FALSE(parse_integer(bad).has_value()) << bad;
  }
  EXPECT_EQ(parse_unsigned("0x1A"), 26u);
  EXPECT_FALSE(parse_unsigned("-1").has_value());
}

TEST(EdsDataType, CodesAreNamedWithTheirSizes) {
  EXPECT_EQ(find_data_type(0x0007)->name, "UNSIGNED32");
  EXPECT_EQ(find_data_type(0x0007)->bits, 32);
  EXPECT_EQ(find_data_type(0x0002)->name, "INTEGER8");
  EXPECT_EQ(find_data_type(0x0010)->bits, 24);
  EXPECT_EQ(find_data_type(0x001B)->name, "UNSIGNED64");
  EXPECT_EQ(find_data_type(0x000E), nullptr);  // Reserved.
  EXPECT_EQ(find_data_type(0x001C), nullptr);
  EXPECT_EQ(parse_access_type("RW"), AccessType::kRw);
  EXPECT_EQ(parse_access_type("Const"), AccessType::kConst);
  EXPECT_EQ(parse_access_type("rwr"), AccessType::kRwr);
  EXPECT_FALSE(parse_access_type("read").has_value());
  EXPECT_TRUE(writable(AccessType::kRww));
  EXPECT_FALSE(writable(AccessType::kConst));
  EXPECT_FALSE(readable(AccessType::kWo));
}

TEST(EdsFile, TheShippedEdsParsesClean) {
  const EdsReadResult result = read_eds_file(kShipped);
  ASSERT_TRUE(result.ok()) << issues_text(result);
  const EdsFile& eds = result.eds;
  // CiA 301's predefined connection set: four of each.
  EXPECT_EQ(eds.rx_pdos, 4);
  EXPECT_EQ(eds.tx_pdos, 4);
  EXPECT_EQ(eds.find(std::uint16_t{0x1018})->entries.size(), 5u);
  EXPECT_EQ(eds.find(ObjectAddress{0x1800, 1})->default_value->evaluate(5), 0x40000185);
  EXPECT_EQ(eds.find(ObjectAddress{0x6502, 0})->default_value->evaluate(1), 0x1A0);  // HM, CSP, CSV
  EXPECT_EQ(eds.find(ObjectAddress{0x60C2, 2})->data_type->name, "INTEGER8");
  EXPECT_EQ(eds.find(ObjectAddress{0x6041, 0})->access, AccessType::kRo);
  EXPECT_TRUE(eds.find(ObjectAddress{0x607A, 0})->pdo_mappable);
  EXPECT_EQ(eds.listed.at(0x1000), ObjectList::kMandatory);
}

// CRLF, comments, "Key = value", [1018Sub1], a CompactSubObj array, manufacturer objects.
TEST(EdsFile, AVendorFileWithItsQuirksParsesClean) {
  const EdsReadResult result = read_eds_file(kFixtures + "kinetra_kx40.eds");
  ASSERT_TRUE(result.ok()) << issues_text(result);
  const EdsFile& eds = result.eds;
  EXPECT_EQ(eds.rx_pdos, 1);
  EXPECT_EQ(eds.find(ObjectAddress{0x1018, 1})->name, "Vendor-ID");
  EXPECT_EQ(eds.find(ObjectAddress{0x1800, 1})->default_value->evaluate(3), 0x183);
  EXPECT_EQ(eds.find(ObjectAddress{0x1400, 1})->default_text, "$NODEID+0x200");
  EXPECT_EQ(eds.find(std::uint16_t{0x2100})->entries.size(), 4u);  // Sub 0 and 3 offsets.
  EXPECT_EQ(eds.find(ObjectAddress{0x2100, 3})->data_type->name, "INTEGER16");
  EXPECT_EQ(eds.listed.at(0x2000), ObjectList::kManufacturer);
  EXPECT_EQ(eds.find(ObjectAddress{0x6040, 0})->access, AccessType::kRww);
  EXPECT_EQ(eds.find(ObjectAddress{0x607F, 0})->high_limit->evaluate(1), 80000);
  EXPECT_EQ(eds.find(ObjectAddress{0x60C2, 2})->low_limit->evaluate(1), -4);
  EXPECT_EQ(eds.find(ObjectAddress{0x1A00, 0})->high_limit->evaluate(1), 4);
}

TEST(EdsFile, AMalformedFileReportsEveryProblemAtItsLine) {
  const EdsReadResult result = read_eds_file(kFixtures + "malformed.eds");
  const std::string all = issues_text(result);
  EXPECT_TRUE(has_issue(result, 25, "[1000] DataType 0x0030: unknown data type")) << all;
  EXPECT_TRUE(has_issue(result, 8, "NrOfRXPDO: expected a number")) << all;
  EXPECT_TRUE(has_issue(result, 20, "0x6060 is listed, but no [6060] section")) << all;
  EXPECT_TRUE(has_issue(result, 34, "AccessType: expected ro, wo, rw, rwr, rww or const")) << all;
  EXPECT_TRUE(has_issue(result, 41, "SubNumber: expected a number")) << all;
  EXPECT_TRUE(has_issue(result, 48, "DefaultValue: expected a number")) << all;
  EXPECT_TRUE(has_issue(result, 57, "expected 'key=value'")) << all;
  EXPECT_TRUE(has_issue(result, 59, "[6041sub1] under VAR object [6041]")) << all;
  EXPECT_TRUE(has_issue(result, 64, "[2001sub1] without its object [2001]")) << all;
  EXPECT_TRUE(has_issue(result, 69, "duplicate section [1001] (first at line 30)")) << all;
  EXPECT_EQ(result.issues.size(), 10u) << all;
  EXPECT_EQ(result.issues.front().to_string().rfind(kFixtures + "malformed.eds:8: ", 0), 0u);
}

TEST(EdsFile, ListsMustAgreeWithTheSections) {
  const EdsReadResult result =
      parse_eds(small_eds("2", "1=0x6041\n2=0x6041\n",
                          "[6040]\nParameterName=Controlword\nDataType=0x0006\nAccessType=rw\n"),
                "lists.eds");
  const std::string all = issues_text(result);
  EXPECT_TRUE(has_issue(result, 11, "0x6041 is listed, but no [6041] section")) << all;
  EXPECT_TRUE(has_issue(result, 12, "0x6041 is listed twice")) << all;
  EXPECT_TRUE(has_issue(result, 22, "object [6040] is in none of")) << all;
}

TEST(EdsFile, CountsAndValuesMustFit) {
  const EdsReadResult result = parse_eds(
      small_eds("2", "1=0x1400\n2=0x6060\n",
                "[1400]\nParameterName=RPDO1\nObjectType=0x9\nSubNumber=3\n\n"
                "[1400sub0]\nParameterName=Highest\nDataType=0x0005\nAccessType=const\n"
                "DefaultValue=2\n\n"
                "[6060]\nParameterName=Modes\nDataType=0x0002\nAccessType=rw\nDefaultValue=300\n"
                "LowLimit=5\nHighLimit=1\nDataType=0x0002\n"),
      "values.eds");
  const std::string all = issues_text(result);
  EXPECT_TRUE(has_issue(result, 2, "NrOfRXPDO=0 but 1 RPDO communication objects")) << all;
  EXPECT_TRUE(has_issue(result, 25, "SubNumber=3 but 1 sub-index sections")) << all;
  EXPECT_TRUE(has_issue(result, 37, "DefaultValue 300 does not fit INTEGER8 (-128..255)")) << all;
  EXPECT_TRUE(has_issue(result, 39, "HighLimit 1 is below LowLimit 5")) << all;
  EXPECT_TRUE(has_issue(result, 40, "duplicate key DataType (first at line 35)")) << all;
}

TEST(EdsFile, AnUnreadableFileIsOneIssue) {
  const EdsReadResult result = read_eds_file(kFixtures + "no_such_file.eds");
  ASSERT_EQ(result.issues.size(), 1u);
  EXPECT_NE(result.issues[0].message.find("cannot read"), std::string::npos);
  EXPECT_FALSE(read_eds_file(kFixtures).ok());  // A directory.
}

// The reader is fuzzed later; here every prefix of a real file and bytes of noise must give
// issues, never a throw or a read outside the text (the sanitizer build checks the latter).
TEST(EdsFile, TruncatedAndNoisyInputNeverThrows) {
  std::ifstream in(kFixtures + "kinetra_kx40.eds", std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string file = text.str();
  for (std::size_t size = 0; size < file.size(); size += 97) {
    EXPECT_NO_THROW((void)parse_eds(std::string_view(file).substr(0, size), "prefix.eds"));
  }
  std::uint32_t state = 12345;
  for (int round = 0; round < 200; ++round) {
    std::string noise(static_cast<std::size_t>(round * 7), '\0');
    for (char& c : noise) {
      state = state * 1664525u + 1013904223u;
      const char alphabet[] = "[]=;$+-x0123456789ABCDEFsubNODEID \r\n\t";
      c = alphabet[(state >> 24) % (sizeof alphabet - 1)];
    }
    EXPECT_NO_THROW((void)parse_eds(noise, "noise.eds"));
  }
}

}  // namespace
}  // namespace cambio::canopen::eds
