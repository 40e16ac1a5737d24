// Checked access to YAML configuration files.
//
// YamlNode remembers the file it came from and the dotted path of the field, so every error
// reads "file:line:column: field 'vehicle.wheelbase_m': expected a number, got 'abc'". Errors
// are thrown as InputError; nothing here prints.
#pragma once

#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "core/eigen_types.hpp"

namespace statebench {

class YamlNode {
 public:
  // Parses a file; a syntax error names the file, line and column.
  static YamlNode LoadFile(const std::filesystem::path& path);
  // Parses text; `source_name` stands for the file name in messages.
  static YamlNode LoadString(const std::string& text, const std::string& source_name);

  bool IsMap() const { return node_.IsMap(); }
  bool IsSequence() const { return node_.IsSequence(); }
  bool IsScalar() const { return node_.IsScalar(); }
  bool IsNull() const { return !node_.IsDefined() || node_.IsNull(); }
  bool Has(const std::string& key) const;
  std::size_t size() const;

  // Child of a map; throws "missing field" when absent.
  YamlNode operator[](const std::string& key) const;
  std::optional<YamlNode> Find(const std::string& key) const;
  // Element of a sequence.
  YamlNode At(std::size_t index) const;
  std::vector<std::string> Keys() const;

  template <typename T>
  T As() const;
  template <typename T>
  T Get(const std::string& key) const {
    return (*this)[key].As<T>();
  }
  template <typename T>
  T Get(const std::string& key, const T& fallback) const {
    const auto child = Find(key);
    return child && !child->IsNull() ? child->As<T>() : fallback;
  }

  // Throws if the map has a key outside `allowed` (catches typos such as 'wheelbase_mm').
  void ExpectOnlyKeys(std::initializer_list<std::string_view> allowed) const;
  void ExpectMap() const;
  void ExpectSequence() const;

  // "file:line:column" of this node (line and column 1-based); "file" when unknown.
  std::string Where() const;
  const std::string& field() const { return field_; }
  const std::string& source() const { return source_; }
  // Directory of the source file, for resolving relative paths in it.
  std::filesystem::path Directory() const;
  std::filesystem::path ResolvePath(const std::string& relative) const;

  // Throws InputError "<where>: field '<field>': <what>".
  [[noreturn]] void Fail(const std::string& what) const;

  const YAML::Node& raw() const { return node_; }
  // The node as one line of flow-style YAML ({a: 1, b: [2, 3]}), its scalars as written: what a
  // file writing it back gets to read again.
  std::string FlowText() const;

 private:
  YamlNode(YAML::Node node, std::string source, std::string field, YAML::Mark mark)
      : node_(std::move(node)), source_(std::move(source)), field_(std::move(field)), mark_(mark) {}

  YAML::Node node_;
  std::string source_;
  std::string field_;
  YAML::Mark mark_;  // position of this node, or of its parent when the node is missing
};

template <>
double YamlNode::As<double>() const;
template <>
int YamlNode::As<int>() const;
template <>
std::int64_t YamlNode::As<std::int64_t>() const;
template <>
std::uint64_t YamlNode::As<std::uint64_t>() const;
template <>
bool YamlNode::As<bool>() const;
template <>
std::string YamlNode::As<std::string>() const;
template <>
Vec3 YamlNode::As<Vec3>() const;
template <>
std::vector<double> YamlNode::As<std::vector<double>>() const;
template <>
std::vector<std::string> YamlNode::As<std::vector<std::string>>() const;

}  // namespace statebench
