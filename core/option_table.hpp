// An options struct declared once: a table of its fields (YAML name, where the value lives in the
// struct, the allowed range, a line of documentation) from which come
//   - Read(): parsing of a YAML map with file:line errors (unknown keys, wrong types, values out
//     of range, cross-field rules), over the defaults already in the struct;
//   - Check(): validation of every field of a struct built in code (the options' IsValid);
//   - Rows(): the documentation table (dotted name, default, range, description);
//   - NumericFields(): every numeric field with its range, so a test can try each one out of it.
// Sections nest another table under a key (e.g. `gnss:` -> MeasurementGateOptions).
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/yaml_node.hpp"

namespace statebench {

// A closed or open interval of finite numbers.
struct OptionRange {
  double min = -std::numeric_limits<double>::infinity();
  bool min_inclusive = true;
  double max = std::numeric_limits<double>::infinity();
  bool max_inclusive = true;

  static OptionRange Any() { return {}; }
  static OptionRange Positive() { return {0.0, false}; }
  static OptionRange NonNegative() { return {0.0, true}; }
  static OptionRange AtLeast(double v) { return {v, true}; }
  static OptionRange Closed(double lo, double hi) { return {lo, true, hi, true}; }

  bool Contains(double v) const {
    if (!std::isfinite(v)) return false;
    if (min_inclusive ? v < min : v <= min) return false;
    return max_inclusive ? v <= max : v < max;
  }
  // "> 0", ">= 1", "in [0, 1]", "any finite number".
  std::string Describe() const {
    std::ostringstream s;
    const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
    if (has_min && has_max) {
      s << "in " << (min_inclusive ? "[" : "(") << min << ", " << max
        << (max_inclusive ? "]" : ")");
    } else if (has_min) {
      s << (min_inclusive ? ">= " : "> ") << min;
    } else if (has_max) {
      s << (max_inclusive ? "<= " : "< ") << max;
    } else {
      s << "any finite number";
    }
    return s.str();
  }
  // A finite value outside the range (for tests); nullopt when every finite value is inside.
  std::optional<double> Outside() const {
    if (std::isfinite(min)) return min - 1.0;
    if (std::isfinite(max)) return max + 1.0;
    return std::nullopt;
  }
};

// The number at `node`, checked against `range`: InputError naming file:line and field when it is
// not a number or out of the range (NaN and infinities never pass).
inline double CheckedNumber(const YamlNode& node, const OptionRange& range) {
  const double v = node.As<double>();
  if (!range.Contains(v)) {
    std::ostringstream got;
    got << v;
    node.Fail("must be " + range.Describe() + ", got " + got.str());
  }
  return v;
}

// Sets *value from map[key] when the key is there and not null, checked against `range`.
inline void ReadOptionalNumber(const YamlNode& map, const std::string& key,
                               const OptionRange& range, double* value) {
  if (const auto child = map.Find(key); child && !child->IsNull()) {
    *value = CheckedNumber(*child, range);
  }
}

// One line of an options documentation table.
struct OptionRow {
  std::string name;  // dotted path, e.g. gnss.gate_chi2
  std::string default_value;
  std::string range;
  std::string doc;
};

// A numeric field reachable from the root of a table: its dotted path and range.
struct NumericOption {
  std::string path;
  OptionRange range;
  bool integer = false;
};

template <typename Options>
class OptionTable {
 public:
  template <typename T>
  using Access = std::function<T&(Options&)>;
  // A cross-field rule: nullopt if it holds, else (field name, message).
  using Rule = std::function<std::optional<std::pair<std::string, std::string>>(const Options&)>;

  explicit OptionTable(std::string what) : what_(std::move(what)) {}

  template <typename T>
  static Access<T> Member(T Options::*member) {
    return [member](Options& o) -> T& { return o.*member; };
  }

  OptionTable& Number(std::string name, Access<double> at, OptionRange range, std::string doc) {
    Field f = Named(std::move(name), std::move(doc));
    f.numeric = NumericOption{f.name, range, false};
    f.read = [at, range](const YamlNode& n, Options* o) { at(*o) = CheckedNumber(n, range); };
    f.check = [at, range, name = f.name](const Options& o) -> std::optional<std::string> {
      const double v = at(const_cast<Options&>(o));
      if (range.Contains(v)) return std::nullopt;
      return name + " must be " + range.Describe() + " (got " + Show(v) + ")";
    };
    f.show = [at](const Options& o) { return Show(at(const_cast<Options&>(o))); };
    f.range = range.Describe();
    fields_.push_back(std::move(f));
    return *this;
  }
  OptionTable& Number(std::string name, double Options::*m, OptionRange range, std::string doc) {
    return Number(std::move(name), Member(m), range, std::move(doc));
  }

  OptionTable& Integer(std::string name, Access<int> at, int min, std::string doc) {
    Field f = Named(std::move(name), std::move(doc));
    const OptionRange range = OptionRange::AtLeast(min);
    f.numeric = NumericOption{f.name, range, true};
    f.read = [at, min](const YamlNode& n, Options* o) {
      const int v = n.As<int>();
      if (v < min) n.Fail("must be at least " + std::to_string(min));
      at(*o) = v;
    };
    f.check = [at, min, name = f.name](const Options& o) -> std::optional<std::string> {
      const int v = at(const_cast<Options&>(o));
      if (v >= min) return std::nullopt;
      return name + " must be at least " + std::to_string(min) + " (got " + std::to_string(v) + ")";
    };
    f.show = [at](const Options& o) { return std::to_string(at(const_cast<Options&>(o))); };
    f.range = ">= " + std::to_string(min);
    fields_.push_back(std::move(f));
    return *this;
  }
  OptionTable& Integer(std::string name, int Options::*m, int min, std::string doc) {
    return Integer(std::move(name), Member(m), min, std::move(doc));
  }

  // true/on or false/off.
  OptionTable& Flag(std::string name, Access<bool> at, std::string doc) {
    Field f = Named(std::move(name), std::move(doc));
    f.read = [at](const YamlNode& n, Options* o) {
      const std::string v = n.As<std::string>();
      if (v == "true" || v == "on") {
        at(*o) = true;
      } else if (v == "false" || v == "off") {
        at(*o) = false;
      } else {
        n.Fail("expected true or false, got '" + v + "'");
      }
    };
    f.show = [at](const Options& o) {
      return std::string(at(const_cast<Options&>(o)) ? "true" : "false");
    };
    f.range = "true, false";
    fields_.push_back(std::move(f));
    return *this;
  }
  OptionTable& Flag(std::string name, bool Options::*m, std::string doc) {
    return Flag(std::move(name), Member(m), std::move(doc));
  }

  // One of named values (an enum), listed in `choices` in the order the docs give them.
  template <typename T>
  OptionTable& Choice(std::string name, T Options::*m,
                      std::vector<std::pair<std::string, T>> choices, std::string doc) {
    Field f = Named(std::move(name), std::move(doc));
    std::string expected, range;
    for (std::size_t i = 0; i < choices.size(); ++i) {
      const bool last = i + 1 == choices.size();
      expected += (i == 0 ? "" : last ? " or " : ", ") + choices[i].first;
      range += (i == 0 ? "" : ", ") + choices[i].first;
    }
    f.read = [m, choices, expected, leaf = f.name](const YamlNode& n, Options* o) {
      const std::string v = n.As<std::string>();
      for (const auto& [text, value] : choices) {
        if (v == text) {
          o->*m = value;
          return;
        }
      }
      n.Fail("unknown " + leaf + " '" + v + "' (expected " + expected + ")");
    };
    f.show = [m, choices](const Options& o) {
      for (const auto& [text, value] : choices) {
        if (o.*m == value) return text;
      }
      return std::string("?");
    };
    f.range = std::move(range);
    fields_.push_back(std::move(f));
    return *this;
  }

  // Any other value (an enum, an optional, a map): `read` parses and validates the node (and
  // fails on it), `show` prints the value for the docs, `range` says what is allowed.
  OptionTable& Custom(std::string name, std::function<void(const YamlNode&, Options*)> read,
                      std::function<std::string(const Options&)> show, std::string range,
                      std::string doc) {
    Field f = Named(std::move(name), std::move(doc));
    f.read = std::move(read);
    f.show = std::move(show);
    f.range = std::move(range);
    fields_.push_back(std::move(f));
    return *this;
  }

  // A nested map read with its own table.
  template <typename Sub>
  OptionTable& Section(std::string name, Access<Sub> at, const OptionTable<Sub>& table,
                       std::string doc) {
    Field f = Named(std::move(name), std::move(doc));
    f.read = [at, table](const YamlNode& n, Options* o) { table.Read(n, &at(*o)); };
    f.check = [at, table, name = f.name](const Options& o) -> std::optional<std::string> {
      const auto why = table.Check(at(const_cast<Options&>(o)));
      if (!why) return std::nullopt;
      return name + "." + *why;
    };
    f.rows = [at, table, name = f.name](const Options& o, std::vector<OptionRow>* rows) {
      for (OptionRow r : table.Rows(at(const_cast<Options&>(o)))) {
        r.name = name + "." + r.name;
        rows->push_back(std::move(r));
      }
    };
    for (NumericOption n : table.NumericFields()) {
      n.path = f.name + "." + n.path;
      f.nested.push_back(std::move(n));
    }
    fields_.push_back(std::move(f));
    return *this;
  }
  template <typename Sub>
  OptionTable& Section(std::string name, Sub Options::*m, const OptionTable<Sub>& table,
                       std::string doc) {
    return Section(std::move(name), Member(m), table, std::move(doc));
  }

  // Keys accepted and ignored (e.g. `name`, `description` of an options file).
  OptionTable& Ignored(std::string name) {
    ignored_.push_back(std::move(name));
    return *this;
  }

  OptionTable& AddRule(Rule rule) {
    rules_.push_back(std::move(rule));
    return *this;
  }

  // Reads the keys present in `node` over *o; throws InputError naming file:line and field.
  void Read(const YamlNode& node, Options* o) const {
    node.ExpectMap();
    for (const std::string& key : node.Keys()) {
      if (Find(key) == nullptr && !IsIgnored(key)) node[key].Fail(UnknownKey(key));
    }
    for (const Field& f : fields_) {
      if (const auto child = node.Find(f.name); child && !child->IsNull()) f.read(*child, o);
    }
    for (const Rule& rule : rules_) {
      if (const auto broken = rule(*o)) {
        if (const auto child = node.Find(broken->first)) child->Fail(broken->second);
        node.Fail(broken->first + " " + broken->second);
      }
    }
  }

  // The first field out of its range or rule broken: "gnss.gate_chi2 must be > 0 (got -1)".
  std::optional<std::string> Check(const Options& o) const {
    for (const Field& f : fields_) {
      if (!f.check) continue;
      if (auto why = f.check(o)) return why;
    }
    for (const Rule& rule : rules_) {
      if (const auto broken = rule(o)) return broken->first + " " + broken->second;
    }
    return std::nullopt;
  }
  // Check() with the table's name in front, in Ceres' IsValid style.
  bool IsValid(const Options& o, std::string* why) const {
    const auto broken = Check(o);
    if (broken && why != nullptr) *why = what_ + ": " + *broken;
    return !broken;
  }

  // Every field with its value in `defaults`, sections flattened to dotted names.
  std::vector<OptionRow> Rows(const Options& defaults) const {
    std::vector<OptionRow> rows;
    for (const Field& f : fields_) {
      if (f.rows) {
        f.rows(defaults, &rows);
      } else {
        rows.push_back({f.name, f.show ? f.show(defaults) : "", f.range, f.doc});
      }
    }
    return rows;
  }

  std::vector<NumericOption> NumericFields() const {
    std::vector<NumericOption> out;
    for (const Field& f : fields_) {
      if (f.numeric) out.push_back(*f.numeric);
      out.insert(out.end(), f.nested.begin(), f.nested.end());
    }
    return out;
  }

  const std::string& what() const { return what_; }

 private:
  struct Field {
    std::string name;
    std::string doc;
    std::function<void(const YamlNode&, Options*)> read;
    std::function<std::optional<std::string>(const Options&)> check;
    std::function<std::string(const Options&)> show;
    std::function<void(const Options&, std::vector<OptionRow>*)> rows;  // sections
    std::string range;
    std::optional<NumericOption> numeric;
    std::vector<NumericOption> nested;  // numeric fields of a section
  };

  static Field Named(std::string name, std::string doc) {
    Field f;
    f.name = std::move(name);
    f.doc = std::move(doc);
    return f;
  }
  static std::string Show(double v) {
    std::ostringstream s;
    s << v;
    return s.str();
  }
  const Field* Find(const std::string& key) const {
    for (const Field& f : fields_) {
      if (f.name == key) return &f;
    }
    return nullptr;
  }
  bool IsIgnored(const std::string& key) const {
    for (const std::string& k : ignored_) {
      if (k == key) return true;
    }
    return false;
  }
  std::string UnknownKey(const std::string& key) const {
    std::string known;
    for (const Field& f : fields_) known += (known.empty() ? "" : ", ") + f.name;
    return "unknown key '" + key + "' (known: " + known + ")";
  }

  std::string what_;
  std::vector<Field> fields_;
  std::vector<std::string> ignored_;
  std::vector<Rule> rules_;
};

}  // namespace statebench

namespace statebench {

// The rows as a Markdown table (option, default, allowed, meaning).
inline std::string OptionRowsMarkdown(const std::vector<OptionRow>& rows) {
  std::string out = "| option | default | allowed | meaning |\n|---|---|---|---|\n";
  for (const OptionRow& r : rows) {
    out += "| `" + r.name + "` | " + r.default_value + " | " + r.range + " | " + r.doc + " |\n";
  }
  return out;
}

}  // namespace statebench
