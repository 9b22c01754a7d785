#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <limits>
#include <sstream>
#include <system_error>

#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/eventhandler.h>

#include "cambio/config/map_reader.hpp"
#include "format.hpp"

namespace cambio::config {

namespace {

ConfigIssue issue_at(const std::string& file, const YAML::Mark& mark, std::string message) {
  const bool known = !mark.is_null() && mark.line >= 0;
  return ConfigIssue{file, known ? mark.line + 1 : 0, known ? mark.column + 1 : 0, "",
                     std::move(message)};
}

/// The list index `text` names, if it is one; an index too large for size_t is past any end.
std::optional<std::size_t> parse_index(std::string_view text) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string_view::npos) {
    return std::nullopt;
  }
  std::size_t index = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), index);
  return error == std::errc{} ? index : std::numeric_limits<std::size_t>::max();
}

std::string describe_kind(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Scalar:
      return "the value " + in_quotes(node.Scalar());
    case YAML::NodeType::Sequence:
      return "a list";
    default:
      return "empty";
  }
}

/// The end of "cannot read the file: ..." for a failed stat() or open().
std::string describe_errno(int error) {
  switch (error) {
    case ENOENT:
      return "it does not exist";
    case EACCES:
    case EPERM:
      return "permission denied";
    case ENAMETOOLONG:
      return "the name is too long";
    case ELOOP:
      return "too many levels of symbolic links (a link that leads back to itself?)";
    case ENOTDIR:
      return "a folder on its path is not a folder";
    default:
      return std::generic_category().message(error);
  }
}

/// The end of "cannot read the file: ..." for what is not a regular file.
std::string describe_not_regular(mode_t mode) {
  if (S_ISDIR(mode)) return "it is a directory, expected a YAML file";
  std::string kind = "a special file";
  if (S_ISCHR(mode)) kind = "a character device (such as /dev/zero)";
  if (S_ISBLK(mode)) kind = "a block device";
  if (S_ISFIFO(mode)) kind = "a FIFO (named pipe)";
  if (S_ISSOCK(mode)) kind = "a socket";
  return "it is " + kind + ", expected a regular file";
}

std::string describe_too_large(std::string_view what, std::uintmax_t bytes) {
  return std::string(what) + " " + std::to_string(bytes) +
         " bytes, more than a config file's most of " + std::to_string(kMaxConfigFileBytes) +
         " (1 MiB)";
}

/// Closes a file descriptor when it goes out of scope.
class FileDescriptor {
 public:
  FileDescriptor() = default;
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  int get() const { return fd_; }
  void reset(int fd) { fd_ = fd; }

 private:
  int fd_ = -1;
};

/// Opens `path` for reading if it is a regular file of at most kMaxConfigFileBytes; else why not.
std::optional<std::string> open_config_file(const std::string& path, FileDescriptor& file,
                                            std::uintmax_t max_bytes = kMaxConfigFileBytes) {
  // stat() first: opening a device or a FIFO can block or act on it.
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) return describe_errno(errno);
  if (!S_ISREG(info.st_mode)) return describe_not_regular(info.st_mode);
  if (static_cast<std::uintmax_t>(info.st_size) > max_bytes) {
    return describe_too_large("it holds", static_cast<std::uintmax_t>(info.st_size));
  }
  // O_NONBLOCK: should the path have become a FIFO since stat(), open() does not wait for it.
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK);
  if (fd < 0) return describe_errno(errno);
  file.reset(fd);
  if (::fstat(fd, &info) != 0) return describe_errno(errno);
  if (!S_ISREG(info.st_mode)) return describe_not_regular(info.st_mode);
  return std::nullopt;
}

[[noreturn]] void throw_unreadable(const std::string& path, const std::string& problem) {
  throw ConfigError({ConfigIssue{path, 0, 0, "", "cannot read the file: " + problem}});
}

/// Where each document of a YAML stream starts, and nothing else of it.
class DocumentStarts final : public YAML::EventHandler {
 public:
  void OnDocumentStart(const YAML::Mark& mark) override { start_ = mark; }
  void OnDocumentEnd() override {}
  void OnNull(const YAML::Mark&, YAML::anchor_t) override {}
  void OnAlias(const YAML::Mark&, YAML::anchor_t) override {}
  void OnScalar(const YAML::Mark&, const std::string&, YAML::anchor_t,
                const std::string&) override {}
  void OnSequenceStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                       YAML::EmitterStyle::value) override {}
  void OnSequenceEnd() override {}
  void OnMapStart(const YAML::Mark&, const std::string&, YAML::anchor_t,
                  YAML::EmitterStyle::value) override {}
  void OnMapEnd() override {}
  const YAML::Mark& start() const { return start_; }

 private:
  YAML::Mark start_ = YAML::Mark::null_mark();
};

/// The one YAML document of `text` (a null node for none); throws ConfigError (in `name`) for
/// a syntax error, nesting deeper than the parser takes, or a second document.
YAML::Node parse_one_document(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
    // YAML::LoadAll would say how many documents follow, but a ',' where a document starts
    // makes yaml-cpp return an empty document there again and again, without end (LoadAll
    // grows without bound); one more document is all that needs seeing.
    std::istringstream stream(text);
    YAML::Parser parser(stream);
    DocumentStarts documents;
    if (parser.HandleNextDocument(documents) && parser.HandleNextDocument(documents)) {
      const YAML::Mark& at = documents.start();
      const bool stray_comma = at.pos >= 0 && static_cast<std::size_t>(at.pos) < text.size() &&
                               text[static_cast<std::size_t>(at.pos)] == ',';
      throw ConfigError({issue_at(name, at,
                                  stray_comma ? "invalid YAML: a ',' outside any list or map"
                                              : "expected one YAML document, found a second "
                                                "(a line '---' starts it)")});
    }
  } catch (const YAML::DeepRecursion& error) {
    // yaml-cpp's own message for it says "bad file", and its column is where the scanner had
    // got to (the line's end): the line alone is given.
    ConfigIssue issue = issue_at(name, error.mark,
                                 "invalid YAML: nested " + std::to_string(error.depth()) +
                                     " levels deep, more than the YAML parser takes (config "
                                     "files nest a few levels)");
    issue.column = 0;
    throw ConfigError({std::move(issue)});
  } catch (const YAML::Exception& error) {
    throw ConfigError({issue_at(name, error.mark, "invalid YAML: " + error.msg)});
  }
  return root;
}

std::string joined(const std::vector<std::string>& names) {
  std::string path;
  for (const std::string& name : names) path += (path.empty() ? "" : ".") + name;
  return path;
}

/// The key paths `names` stands for in `node`: a `*` is each key of the map (each item of the
/// list) the document holds at that place, so one `--set` reaches every camera or every joint.
/// Names after the last `*` are kept as given (the override may create them). Returns what is
/// wrong when a `*` matches nothing.
std::optional<std::string> expand_wildcards(const YAML::Node& node,
                                            const std::vector<std::string>& names, std::size_t i,
                                            std::vector<std::string>& prefix,
                                            std::vector<std::vector<std::string>>& paths) {
  const auto star = std::find(names.begin() + static_cast<std::ptrdiff_t>(i), names.end(), "*");
  if (star == names.end()) {
    std::vector<std::string> path = prefix;
    path.insert(path.end(), names.begin() + static_cast<std::ptrdiff_t>(i), names.end());
    paths.push_back(std::move(path));
    return std::nullopt;
  }
  const std::size_t before = prefix.size();
  const auto restore = [&] { prefix.resize(before); };
  YAML::Node current;
  current.reset(node);
  for (; names.begin() + static_cast<std::ptrdiff_t>(i) != star; ++i) {
    const std::string& name = names[i];
    const auto index = parse_index(name);
    // A missing key reads as an invalid node, which assignment and reset() refuse: copied, then
    // tested, before it is walked into.
    const YAML::Node& view = current;
    const auto lookup = [&]() -> YAML::Node {
      if (current.IsMap()) return view[name];
      if (current.IsSequence() && index && *index < current.size()) return view[*index];
      return YAML::Node(YAML::NodeType::Undefined);
    };
    const YAML::Node child = lookup();
    prefix.push_back(name);
    if (!child.IsDefined() || child.IsNull()) {
      std::string problem = "'*' matches nothing: the document has no " + joined(prefix);
      restore();
      return problem;
    }
    current.reset(child);
  }
  if (current.size() == 0 || !(current.IsMap() || current.IsSequence())) {
    std::string problem =
        "'*' matches nothing: " + (prefix.empty() ? "the document" : joined(prefix)) + " is " +
        (current.IsMap() || current.IsSequence() ? "empty" : describe_kind(current)) +
        ", not a map or list with entries";
    restore();
    return problem;
  }
  std::size_t item = 0;
  for (auto it = current.begin(); it != current.end(); ++it, ++item) {
    const bool in_map = current.IsMap();
    if (in_map && !it->first.IsScalar()) continue;
    prefix.push_back(in_map ? it->first.Scalar() : std::to_string(item));
    const YAML::Node child = in_map ? it->second : *it;
    const auto problem = expand_wildcards(child, names, i + 1, prefix, paths);
    prefix.pop_back();
    if (problem) {
      restore();
      return problem;
    }
  }
  restore();
  return std::nullopt;
}

}  // namespace

std::optional<std::string> config_file_problem(const std::string& path) {
  FileDescriptor file;
  return open_config_file(path, file);
}

std::optional<std::string> readable_file_problem(const std::string& path) {
  FileDescriptor file;
  return open_config_file(path, file, std::numeric_limits<std::uintmax_t>::max());
}

ConfigDocument::ConfigDocument(YAML::Node root, std::string file)
    : root_(root), file_(std::move(file)), issues_(std::make_shared<IssueList>()) {}

ConfigDocument ConfigDocument::load_file(const std::string& path,
                                         const std::vector<ConfigOverride>& overrides) {
  FileDescriptor file;
  if (const auto problem = open_config_file(path, file)) throw_unreadable(path, *problem);
  // Read one byte past the limit: a file that grew since fstat() is refused, not cut.
  std::string text;
  std::array<char, 64 * 1024> buffer{};
  while (text.size() <= kMaxConfigFileBytes) {
    const ssize_t n = ::read(file.get(), buffer.data(), buffer.size());
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw_unreadable(path, describe_errno(errno));
    if (n == 0) break;
    text.append(buffer.data(), static_cast<std::size_t>(n));
  }
  if (text.size() > kMaxConfigFileBytes) {
    throw_unreadable(path, describe_too_large("it grew past", text.size()));
  }
  return parse(text, path, overrides);
}

ConfigDocument ConfigDocument::from_string(const std::string& text, const std::string& name,
                                           const std::vector<ConfigOverride>& overrides) {
  if (text.size() > kMaxConfigFileBytes) {
    throw_unreadable(name, describe_too_large("it holds", text.size()));
  }
  return parse(text, name, overrides);
}

ConfigDocument ConfigDocument::parse(const std::string& text, const std::string& name,
                                     const std::vector<ConfigOverride>& overrides) {
  ConfigDocument document(parse_one_document(text, name), name);
  for (const auto& override_value : overrides) document.apply(override_value);
  return document;
}

// A `*` in the key path is each key (list item) the document holds there (expand_wildcards).
void ConfigDocument::apply(const ConfigOverride& override_value) {
  const auto fail = [&](std::string message) {
    issues_->add(ConfigIssue{"--set", 0, 0, override_value.key_path, std::move(message)});
  };
  if (override_value.value.size() > kMaxOverrideValueBytes) {
    fail("expected a value of at most " + std::to_string(kMaxOverrideValueBytes) +
         " bytes (a number, a list, a map of a few keys), found " +
         std::to_string(override_value.value.size()) + " bytes");
    return;
  }
  YAML::Node value;
  try {
    value = parse_one_document(override_value.value, "--set");
  } catch (const ConfigError& error) {
    // "invalid YAML: ..." or "expected one YAML document, found 2 ..." (a value holding "---"
    // would otherwise set only what precedes it).
    fail("expected a YAML value, found " + in_quotes(override_value.value) + " (" +
         error.issues().front().message + ")");
    return;
  }
  if (!root_.IsDefined() || root_.IsNull()) root_.reset(YAML::Node(YAML::NodeType::Map));
  if (!root_.IsMap()) {
    fail("cannot set a key: the document is not a map");
    return;
  }

  std::vector<std::string> names;
  for (std::size_t start = 0;;) {
    const std::size_t dot = override_value.key_path.find('.', start);
    names.push_back(override_value.key_path.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }

  std::vector<std::vector<std::string>> paths;
  std::vector<std::string> prefix;
  if (const auto problem = expand_wildcards(root_, names, 0, prefix, paths)) {
    fail(*problem);
    return;
  }
  // Walk with reset(): assigning one yaml-cpp Node to another would overwrite the tree.
  const auto set_at = [&](const std::vector<std::string>& path_names,
                          const YAML::Node& path_value) {
    YAML::Node current;
    current.reset(root_);
    std::string path;
    bool created = false;  // Whether a map on the path is one this override made up.
    for (std::size_t i = 0; i < path_names.size(); ++i) {
      const std::string& name = path_names[i];
      const bool last = i + 1 == path_names.size();
      const auto index = parse_index(name);
      if (current.IsSequence() && index) {
        if (*index >= current.size()) {
          fail("cannot set item " + echoed(name) + " of " + path + ": the list has " +
               std::to_string(current.size()) + " items");
          return false;
        }
        path += "[" + name + "]";
        if (last) {
          current[*index] = path_value;
        } else {
          YAML::Node next = current[*index];
          current.reset(next);
        }
        continue;
      }
      if (!current.IsMap()) {
        fail("cannot set " + echoed(name) + " under " + path + ": " + path + " is " +
             describe_kind(current) + ", not a map");
        return false;
      }
      path += (path.empty() ? "" : ".") + name;
      if (last) {
        current[name] = path_value;
        continue;
      }
      YAML::Node next = current[name];
      if (!next.IsDefined() || next.IsNull()) {
        if (!next.IsDefined() && !created) {
          std::vector<std::string> file_keys;
          for (auto it = current.begin(); it != current.end(); ++it) {
            if (it->first.IsScalar()) file_keys.push_back(it->first.Scalar());
          }
          issues_->mark_created(path, std::move(file_keys));
          created = true;
        }
        current[name] = YAML::Node(YAML::NodeType::Map);
        next.reset(current[name]);
      }
      current.reset(next);
    }
    issues_->mark_overridden(path);
    return true;
  };
  // A copy per path: yaml-cpp nodes are shared by reference, and a later `--set` of one camera's
  // key must not change the others'.
  for (const auto& path_names : paths) {
    if (!set_at(path_names, YAML::Clone(value))) return;
  }
}

MapReader ConfigDocument::root() {
  return MapReader(root_, "", file_, issues_);
}

}  // namespace cambio::config
