#include "cambio/canopen/eds/eds_file.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "eds_reader.hpp"

namespace cambio::canopen::eds {

namespace {

/// An EDS larger than this is not a drive's data sheet (the largest real ones are ~1 MB).
constexpr std::streamoff kMaxFileBytes = 16 * 1024 * 1024;

/// How many PDOs of one direction the file describes: communication objects at `first`..+0x1FF.
int described_pdos(const EdsFile& eds, std::uint16_t first) {
  int count = 0;
  for (auto it = eds.objects.lower_bound(first);
       it != eds.objects.end() && it->first < first + 0x200; ++it) {
    ++count;
  }
  return count;
}

/// [DeviceInfo] NrOfRXPDO / NrOfTXPDO, which must agree with the PDO objects present.
void read_device_info(const IniDocument& document, EdsFile& eds, std::vector<EdsIssue>& issues) {
  const IniSection* section = document.find("deviceinfo");
  if (section == nullptr) {
    issues.push_back({eds.file, 0, "no [DeviceInfo] section"});
    return;
  }
  eds.device_info_line = section->line;
  const SectionReader reader(*section, eds.file, issues);
  struct Count {
    std::string_view key;
    std::optional<int>& value;
    std::uint16_t communication;
    std::string_view what;
  };
  for (const Count& count : {Count{"NrOfRXPDO", eds.rx_pdos, kRpdoCommunication, "RPDO"},
                             Count{"NrOfTXPDO", eds.tx_pdos, kTpdoCommunication, "TPDO"}}) {
    const IniKey* key = reader.optional(count.key);
    if (key == nullptr) continue;
    const auto value = reader.number(*key, count.key, 512);
    if (!value) continue;
    count.value = static_cast<int>(*value);
    const int described = described_pdos(eds, count.communication);
    if (described != *count.value) {
      reader.issue(key->line,
                   std::string(count.key) + "=" + key->value + " but " + std::to_string(described) +
                       " " + std::string(count.what) + " communication objects (" +
                       (count.communication == kRpdoCommunication ? "0x1400" : "0x1800") +
                       " onwards) are described");
    }
  }
}

}  // namespace

EdsReadResult parse_eds(std::string_view text, std::string file) {
  EdsReadResult result;
  result.eds.file = std::move(file);
  const IniDocument document = read_ini(text, result.eds.file, result.issues);
  read_objects(document, result.eds, result.issues);
  read_device_info(document, result.eds, result.issues);
  read_object_lists(document, result.eds, result.issues);
  std::stable_sort(result.issues.begin(), result.issues.end(),
                   [](const EdsIssue& a, const EdsIssue& b) { return a.line < b.line; });
  return result;
}

EdsReadResult read_eds_file(const std::string& path) {
  std::error_code error;
  std::ifstream in;
  if (std::filesystem::is_regular_file(path, error)) in.open(path, std::ios::binary);
  std::ostringstream text;
  if (in) {
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(0, std::ios::beg);
    if (size > kMaxFileBytes) {
      EdsReadResult result;
      result.eds.file = path;
      result.issues.push_back({path, 0, "larger than 16 MiB: not an electronic data sheet"});
      return result;
    }
    text << in.rdbuf();
  }
  if (!in) {
    EdsReadResult result;
    result.eds.file = path;
    result.issues.push_back({path, 0, "cannot read the file (not a readable regular file)"});
    return result;
  }
  return parse_eds(text.str(), path);
}

}  // namespace cambio::canopen::eds
