#include "core/yaml_node.hpp"

#include <charconv>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/error.hpp"

namespace statebench {
namespace {

std::string JoinField(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

std::string Describe(const YAML::Node& node) {
  if (!node.IsDefined() || node.IsNull()) return "nothing";
  if (node.IsMap()) return "a map";
  if (node.IsSequence()) return "a list";
  return "'" + node.Scalar() + "'";
}

// Every map key must be a plain scalar (a list or map used as a key, e.g. `{[a, b]: 1}`, is YAML
// but never a field name): checked once at load, so every reader may take keys as strings.
// Depth-limited like the documents people write; deeper nesting is refused the same way.
void CheckKeys(const YAML::Node& node, const std::string& source, int depth = 0) {
  const auto fail = [&source](const YAML::Mark& mark, const std::string& what) {
    std::ostringstream os;
    os << source << ":" << mark.line + 1 << ":" << mark.column + 1 << ": " << what;
    throw InputError(os.str());
  };
  if (depth > 64) fail(node.Mark(), "nested more than 64 levels deep");
  if (node.IsMap()) {
    for (const auto& kv : node) {
      if (!kv.first.IsScalar()) fail(kv.first.Mark(), "a map key must be a plain name");
      CheckKeys(kv.second, source, depth + 1);
    }
  } else if (node.IsSequence()) {
    for (const auto& child : node) CheckKeys(child, source, depth + 1);
  }
}

}  // namespace

YamlNode YamlNode::LoadFile(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) {
    throw InputError(path.string() + ": file not found");
  }
  YAML::Node root;
  try {
    root = YAML::LoadFile(path.string());
  } catch (const YAML::Exception& e) {
    std::ostringstream os;
    os << path.string() << ":" << e.mark.line + 1 << ":" << e.mark.column + 1
       << ": YAML syntax error: " << e.msg;
    throw InputError(os.str());
  }
  CheckKeys(root, path.string());
  return YamlNode(root, path.string(), "", root.Mark());
}

YamlNode YamlNode::LoadString(const std::string& text, const std::string& source_name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& e) {
    std::ostringstream os;
    os << source_name << ":" << e.mark.line + 1 << ":" << e.mark.column + 1
       << ": YAML syntax error: " << e.msg;
    throw InputError(os.str());
  }
  CheckKeys(root, source_name);
  return YamlNode(root, source_name, "", root.Mark());
}

bool YamlNode::Has(const std::string& key) const {
  return node_.IsMap() && node_[key].IsDefined();
}

std::size_t YamlNode::size() const { return node_.size(); }

YamlNode YamlNode::operator[](const std::string& key) const {
  ExpectMap();
  const YAML::Node child = node_[key];
  const std::string field = JoinField(field_, key);
  if (!child.IsDefined()) {
    YamlNode(child, source_, field, mark_).Fail("missing field");
  }
  return YamlNode(child, source_, field, child.Mark().is_null() ? mark_ : child.Mark());
}

std::optional<YamlNode> YamlNode::Find(const std::string& key) const {
  if (IsNull()) return std::nullopt;
  ExpectMap();
  const YAML::Node child = node_[key];
  if (!child.IsDefined()) return std::nullopt;
  return YamlNode(child, source_, JoinField(field_, key),
                  child.Mark().is_null() ? mark_ : child.Mark());
}

YamlNode YamlNode::At(std::size_t index) const {
  ExpectSequence();
  const std::string field = field_ + "[" + std::to_string(index) + "]";
  if (index >= node_.size()) {
    YamlNode(YAML::Node(), source_, field, mark_).Fail("index out of range");
  }
  const YAML::Node child = node_[index];
  return YamlNode(child, source_, field, child.Mark().is_null() ? mark_ : child.Mark());
}

std::vector<std::string> YamlNode::Keys() const {
  ExpectMap();
  std::vector<std::string> keys;
  for (const auto& kv : node_) keys.push_back(kv.first.as<std::string>());
  return keys;
}

void YamlNode::ExpectOnlyKeys(std::initializer_list<std::string_view> allowed) const {
  ExpectMap();
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    bool ok = false;
    for (const auto& a : allowed) ok = ok || (a == key);
    if (!ok) {
      std::string list;
      for (const auto& a : allowed) list += (list.empty() ? "" : ", ") + std::string(a);
      YamlNode(kv.second, source_, JoinField(field_, key), kv.first.Mark())
          .Fail("unknown field (expected one of: " + list + ")");
    }
  }
}

void YamlNode::ExpectMap() const {
  if (!node_.IsMap()) Fail("expected a map, got " + Describe(node_));
}

void YamlNode::ExpectSequence() const {
  if (!node_.IsSequence()) Fail("expected a list, got " + Describe(node_));
}

std::string YamlNode::Where() const {
  std::ostringstream os;
  os << source_;
  if (!mark_.is_null()) os << ":" << mark_.line + 1 << ":" << mark_.column + 1;
  return os.str();
}

std::string YamlNode::FlowText() const {
  YAML::Emitter out;
  out.SetMapFormat(YAML::Flow);
  out.SetSeqFormat(YAML::Flow);
  out << node_;
  return out.c_str();
}

std::filesystem::path YamlNode::Directory() const {
  return std::filesystem::path(source_).parent_path();
}

std::filesystem::path YamlNode::ResolvePath(const std::string& relative) const {
  const std::filesystem::path p(relative);
  return p.is_absolute() ? p : Directory() / p;
}

void YamlNode::Fail(const std::string& what) const {
  throw InputError(Where() + ": field '" + (field_.empty() ? "<root>" : field_) + "': " + what);
}

template <>
double YamlNode::As<double>() const {
  if (!node_.IsScalar()) Fail("expected a number, got " + Describe(node_));
  const std::string& s = node_.Scalar();
  double value = 0.0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size()) {
    Fail("expected a number, got " + Describe(node_));
  }
  if (!std::isfinite(value)) Fail("expected a finite number, got " + Describe(node_));
  return value;
}

template <>
std::int64_t YamlNode::As<std::int64_t>() const {
  if (!node_.IsScalar()) Fail("expected an integer, got " + Describe(node_));
  const std::string& s = node_.Scalar();
  std::int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
  if (ec != std::errc() || ptr != s.data() + s.size()) {
    Fail("expected an integer, got " + Describe(node_));
  }
  return value;
}

template <>
std::uint64_t YamlNode::As<std::uint64_t>() const {
  const std::int64_t v = As<std::int64_t>();
  if (v < 0) Fail("expected a non-negative integer, got " + Describe(node_));
  return static_cast<std::uint64_t>(v);
}

template <>
int YamlNode::As<int>() const {
  const std::int64_t v = As<std::int64_t>();
  if (v < std::numeric_limits<int>::min() || v > std::numeric_limits<int>::max()) {
    Fail("integer out of range: " + Describe(node_));
  }
  return static_cast<int>(v);
}

template <>
bool YamlNode::As<bool>() const {
  if (!node_.IsScalar()) Fail("expected true or false, got " + Describe(node_));
  const std::string& s = node_.Scalar();
  if (s == "true" || s == "True" || s == "yes") return true;
  if (s == "false" || s == "False" || s == "no") return false;
  Fail("expected true or false, got " + Describe(node_));
}

template <>
std::string YamlNode::As<std::string>() const {
  if (!node_.IsScalar()) Fail("expected a string, got " + Describe(node_));
  return node_.Scalar();
}

template <>
std::vector<double> YamlNode::As<std::vector<double>>() const {
  ExpectSequence();
  std::vector<double> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(At(i).As<double>());
  return out;
}

template <>
std::vector<std::string> YamlNode::As<std::vector<std::string>>() const {
  ExpectSequence();
  std::vector<std::string> out;
  for (std::size_t i = 0; i < node_.size(); ++i) out.push_back(At(i).As<std::string>());
  return out;
}

template <>
Vec3 YamlNode::As<Vec3>() const {
  ExpectSequence();
  if (node_.size() != 3) Fail("expected a list of 3 numbers, got " + std::to_string(size()));
  return Vec3(At(0).As<double>(), At(1).As<double>(), At(2).As<double>());
}

}  // namespace statebench
