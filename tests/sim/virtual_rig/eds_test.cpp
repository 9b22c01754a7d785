// The shipped EDS (firmware_config/eds/cambio_virtual_drive.eds) and the emulated drive agree:
// every object the EDS lists is read over SDO with raw CiA 301 frames, its length, value and
// access checked against what the EDS says, and every entry of the drive is in the EDS.
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "drive_test_support.hpp"

namespace cambio::virtual_rig::test {
namespace {

/// A CiA 306 file: sections of key=value lines, ';' starts a comment. Keys are case-insensitive
/// in CiA 306; the shipped file uses one spelling, which this reads as written.
using Ini = std::map<std::string, std::map<std::string, std::string>>;

Ini read_ini(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << path;
  Ini ini;
  std::string line;
  std::string section;
  while (std::getline(in, line)) {
    if (const auto semicolon = line.find(';'); semicolon != std::string::npos)
      line.erase(semicolon);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ')) line.pop_back();
    if (line.empty()) continue;
    if (line.front() == '[') {
      section = line.substr(1, line.find(']') - 1);
      ini[section];
      continue;
    }
    const auto equals = line.find('=');
    EXPECT_NE(equals, std::string::npos) << line;
    ini[section][line.substr(0, equals)] = line.substr(equals + 1);
  }
  return ini;
}

long long number(const std::string& text) {
  return std::stoll(text, nullptr, 0);
}

/// A DefaultValue: a number, or $NODEID plus a number (CiA 306 §4.6.3).
long long default_value(std::string text, int node_id) {
  long long value = 0;
  if (const auto at = text.find("$NODEID"); at != std::string::npos) {
    value += node_id;
    text.erase(at, 7);
    if (!text.empty() && text.front() == '+') text.erase(0, 1);
    if (!text.empty() && text.back() == '+') text.pop_back();
    if (text.empty()) return value;
  }
  return value + number(text);
}

std::size_t type_bytes(int data_type) {
  switch (data_type) {
    case 0x1:
    case 0x2:
    case 0x5:
      return 1;
    case 0x3:
    case 0x6:
      return 2;
    case 0x4:
    case 0x7:
      return 4;
  }
  return 0;
}

/// Reads an object with raw SDO frames (expedited or segmented). Returns the abort code or 0.
std::uint32_t upload(DriveBench& bench, canopen::ObjectAddress a, std::vector<std::uint8_t>& data) {
  data.clear();
  const auto r =
      bench.sdo({0x40, DriveBench::lo(a.index), DriveBench::hi(a.index), a.subindex, 0, 0, 0, 0});
  if (r.data[0] == 0x80) return static_cast<std::uint32_t>(le_i32(r, 4));
  if ((r.data[0] & 0x02) != 0) {  // Expedited, size indicated.
    const std::size_t bytes = 4 - ((r.data[0] >> 2) & 3);
    data.assign(r.data.begin() + 4, r.data.begin() + 4 + static_cast<long>(bytes));
    return 0;
  }
  const auto size = static_cast<std::size_t>(le_i32(r, 4));
  std::uint8_t toggle = 0;
  while (data.size() < size) {
    const auto s = bench.sdo({static_cast<std::uint8_t>(0x60 | toggle << 4), 0, 0, 0, 0, 0, 0, 0});
    if (s.data[0] == 0x80) return static_cast<std::uint32_t>(le_i32(s, 4));
    const std::size_t bytes = 7 - ((s.data[0] >> 1) & 7);
    data.insert(data.end(), s.data.begin() + 1, s.data.begin() + 1 + static_cast<long>(bytes));
    toggle ^= 1;
    if (s.data[0] & 1) break;
  }
  return 0;
}

std::string access_name(Access access) {
  switch (access) {
    case Access::kReadOnly:
      return "ro";
    case Access::kReadWrite:
      return "rw";
    case Access::kWriteOnly:
      return "wo";
    case Access::kConst:
      return "const";
  }
  return "?";
}

TEST(Eds, EveryObjectReadsOverSdoAsTheEdsSays) {
  const Ini eds =
      read_ini(std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/eds/cambio_virtual_drive.eds");
  ASSERT_EQ(eds.at("FileInfo").at("EDSVersion"), "4.0");
  const int node_id = 5;
  DriveBench bench(pan_drive(node_id));
  bench.power_on();

  std::size_t entries_checked = 0;
  for (const char* list : {"MandatoryObjects", "OptionalObjects", "ManufacturerObjects"}) {
    const auto& objects = eds.at(list);
    const long long count = number(objects.at("SupportedObjects"));
    for (long long k = 1; k <= count; ++k) {
      const auto index = static_cast<std::uint16_t>(number(objects.at(std::to_string(k))));
      char name[8];
      std::snprintf(name, sizeof name, "%04X", index);
      ASSERT_TRUE(eds.count(name)) << "no section for listed object " << name;
      const auto& object = eds.at(name);
      std::vector<std::pair<std::uint8_t, const std::map<std::string, std::string>*>> subs;
      if (object.count("SubNumber")) {
        for (int sub = 0; sub < 256; ++sub) {
          char sub_name[16];
          std::snprintf(sub_name, sizeof sub_name, "%04Xsub%X", index, sub);
          if (eds.count(sub_name))
            subs.emplace_back(static_cast<std::uint8_t>(sub), &eds.at(sub_name));
        }
        EXPECT_EQ(static_cast<long long>(subs.size()), number(object.at("SubNumber"))) << name;
      } else {
        subs.emplace_back(0, &object);
      }
      for (const auto& [sub, entry] : subs) {
        const canopen::ObjectAddress address{index, sub};
        const std::string where = std::string(name) + "sub" + std::to_string(sub);
        const int data_type = static_cast<int>(number(entry->at("DataType")));
        const std::string access = entry->at("AccessType");
        const ObjectEntry* emulated = bench.drive().dictionary().find(address);
        ASSERT_NE(emulated, nullptr) << where << " is in the EDS, not in the drive";
        EXPECT_EQ(static_cast<int>(emulated->type), data_type) << where;
        EXPECT_EQ(access_name(emulated->access), access) << where;
        EXPECT_EQ(emulated->pdo_mappable, number(entry->at("PDOMapping")) != 0) << where;
        ++entries_checked;
        if (access == "wo") continue;

        std::vector<std::uint8_t> data;
        ASSERT_EQ(upload(bench, address, data), 0u) << where;
        if (data_type == 0x9) {
          const std::string text(data.begin(), data.end());
          if (entry->count("DefaultValue")) {
            EXPECT_EQ(text, entry->at("DefaultValue")) << where;
          }
          continue;
        }
        ASSERT_EQ(data.size(), type_bytes(data_type)) << where;
        std::uint32_t raw = 0;
        for (std::size_t i = 0; i < data.size(); ++i)
          raw |= static_cast<std::uint32_t>(data[i]) << (8 * i);
        const bool is_signed_type = data_type >= 0x2 && data_type <= 0x4;
        const long long value = is_signed_type
                                    ? static_cast<long long>(canopen::sign_extend(raw, data.size()))
                                    : static_cast<long long>(raw);
        if (entry->count("DefaultValue")) {
          EXPECT_EQ(value, default_value(entry->at("DefaultValue"), node_id)) << where;
        }
        if (access == "ro" || access == "const") {
          // The bus says so too: writing it back is refused as read only.
          const auto r = bench.download(index, sub, raw, static_cast<int>(data.size()));
          EXPECT_TRUE(r.abort()) << where;
          EXPECT_EQ(r.value, 0x06010002u) << where;
        }
      }
    }
  }
  EXPECT_EQ(entries_checked, bench.drive().dictionary().entries().size())
      << "every entry of the drive is described in the EDS";
}

TEST(Eds, DeviceInfoMatchesTheIdentityObject) {
  const Ini eds =
      read_ini(std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/eds/cambio_virtual_drive.eds");
  DriveBench bench;
  bench.power_on();
  const auto& info = eds.at("DeviceInfo");
  EXPECT_EQ(number(info.at("VendorNumber")), bench.upload(0x1018, 1).value);
  EXPECT_EQ(number(info.at("ProductNumber")), bench.upload(0x1018, 2).value);
  EXPECT_EQ(number(info.at("RevisionNumber")), bench.upload(0x1018, 3).value);
  EXPECT_EQ(number(info.at("NrOfRXPDO")), EmulatedDrive::kPdoCount);
  EXPECT_EQ(number(info.at("NrOfTXPDO")), EmulatedDrive::kPdoCount);
}

// CiA 306: a const object's value is the data sheet's, so it must say it (0x6076 said none).
TEST(Eds, EveryConstObjectGivesItsValue) {
  const Ini eds =
      read_ini(std::string(CAMBIO_SOURCE_DIR) + "/firmware_config/eds/cambio_virtual_drive.eds");
  int consts = 0;
  for (const auto& [section, keys] : eds) {
    const auto access = keys.find("AccessType");
    if (access == keys.end() || access->second != "const") continue;
    ++consts;
    EXPECT_TRUE(keys.count("DefaultValue")) << "[" << section << "] is const without DefaultValue";
  }
  EXPECT_GT(consts, 3);
}

}  // namespace
}  // namespace cambio::virtual_rig::test
