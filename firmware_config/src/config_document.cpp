#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cambio/config/map_reader.hpp"
#include "format.hpp"

namespace cambio::config {

namespace {

ConfigIssue issue_at(const std::string& file, const YAML::Mark& mark, std::string message) {
  const bool known = !mark.is_null() && mark.line >= 0;
  return ConfigIssue{file, known ? mark.line + 1 : 0, known ? mark.column + 1 : 0, "",
                     std::move(message)};
}

bool is_index(std::string_view text) {
  return !text.empty() && text.find_first_not_of("0123456789") == std::string_view::npos;
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

}  // namespace

ConfigDocument::ConfigDocument(YAML::Node root, std::string file)
    : root_(root), file_(std::move(file)), issues_(std::make_shared<IssueList>()) {}

ConfigDocument ConfigDocument::load_file(const std::string& path,
                                         const std::vector<ConfigOverride>& overrides) {
  std::error_code error;
  if (!std::filesystem::exists(path, error)) {
    throw ConfigError({ConfigIssue{path, 0, 0, "", "cannot read the file: it does not exist"}});
  }
  if (std::filesystem::is_directory(path, error)) {
    throw ConfigError({ConfigIssue{
        path, 0, 0, "", "cannot read the file: it is a directory, expected a YAML file"}});
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw ConfigError({ConfigIssue{path, 0, 0, "",
                                   std::string("cannot read the file: ") + std::strerror(errno)}});
  }
  std::ostringstream text;
  text << in.rdbuf();
  return parse(text.str(), path, overrides);
}

ConfigDocument ConfigDocument::from_string(const std::string& text, const std::string& name,
                                           const std::vector<ConfigOverride>& overrides) {
  return parse(text, name, overrides);
}

ConfigDocument ConfigDocument::parse(const std::string& text, const std::string& name,
                                     const std::vector<ConfigOverride>& overrides) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw ConfigError({issue_at(name, error.mark, "invalid YAML: " + error.msg)});
  }
  ConfigDocument document(root, name);
  for (const auto& override_value : overrides) document.apply(override_value);
  return document;
}

void ConfigDocument::apply(const ConfigOverride& override_value) {
  const auto fail = [&](std::string message) {
    issues_->add(ConfigIssue{"--set", 0, 0, override_value.key_path, std::move(message)});
  };
  YAML::Node value;
  try {
    value = YAML::Load(override_value.value);
  } catch (const YAML::Exception& error) {
    fail("expected a YAML value, found " + in_quotes(override_value.value) + " (" + error.msg +
         ")");
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

  // Walk with reset(): assigning one yaml-cpp Node to another would overwrite the tree.
  YAML::Node current;
  current.reset(root_);
  std::string path;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    const bool last = i + 1 == names.size();
    if (current.IsSequence() && is_index(name)) {
      const std::size_t index = std::stoul(name);
      if (index >= current.size()) {
        fail("cannot set item " + name + " of " + path + ": the list has " +
             std::to_string(current.size()) + " items");
        return;
      }
      path += "[" + name + "]";
      if (last) {
        current[index] = value;
      } else {
        YAML::Node next = current[index];
        current.reset(next);
      }
      continue;
    }
    if (!current.IsMap()) {
      fail("cannot set " + name + " under " + path + ": " + path + " is " + describe_kind(current) +
           ", not a map");
      return;
    }
    path += (path.empty() ? "" : ".") + name;
    if (last) {
      current[name] = value;
      continue;
    }
    YAML::Node next = current[name];
    if (!next.IsDefined() || next.IsNull()) {
      current[name] = YAML::Node(YAML::NodeType::Map);
      next.reset(current[name]);
    }
    current.reset(next);
  }
  issues_->mark_overridden(path);
}

MapReader ConfigDocument::root() {
  return MapReader(root_, "", file_, issues_);
}

}  // namespace cambio::config
