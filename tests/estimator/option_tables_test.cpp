// The option tables of the estimators (core/option_table.hpp): every numeric option of every
// estimator, set out of its range in a YAML file, is refused with file:line and its name; the
// option tables of docs/estimator-config.md are the ones the code generates.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "core/error.hpp"
#include "estimator/ekf_options.hpp"
#include "estimator/estimator_config.hpp"
#include "estimator/factor_graph_option_table.hpp"

namespace statebench::est {
namespace {

// "a.b.c" with value v as nested YAML maps, the value on the last line.
std::string NestedYaml(const std::string& path, const std::string& value, int* value_line) {
  std::string yaml, indent;
  std::stringstream parts(path);
  std::string part;
  std::vector<std::string> keys;
  while (std::getline(parts, part, '.')) keys.push_back(part);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    yaml += indent + keys[i] + ":" + (i + 1 == keys.size() ? " " + value : "") + "\n";
    indent += "  ";
  }
  *value_line = static_cast<int>(keys.size());
  return yaml;
}

std::string Leaf(const std::string& path) { return path.substr(path.rfind('.') + 1); }

template <typename Options>
void ExpectEveryNumericOptionChecked(const OptionTable<Options>& table,
                                     const std::function<void(const YamlNode&)>& parse) {
  const std::vector<NumericOption> fields = table.NumericFields();
  ASSERT_FALSE(fields.empty());
  for (const NumericOption& f : fields) {
    const std::optional<double> outside = f.range.Outside();
    if (!outside) continue;  // any finite value allowed
    std::ostringstream value;
    value << *outside;
    int line = 0;
    const std::string yaml = NestedYaml(f.path, value.str(), &line);
    try {
      parse(YamlNode::LoadString(yaml, "options.yaml"));
      ADD_FAILURE() << f.path << " = " << *outside << " was accepted";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("options.yaml:" + std::to_string(line) + ":"), std::string::npos)
          << f.path << ": " << what;
      EXPECT_NE(what.find(Leaf(f.path)), std::string::npos) << f.path << ": " << what;
    }
  }
}

TEST(OptionTables, EveryNumericFactorGraphOptionOutOfRangeIsAFileLineError) {
  ExpectEveryNumericOptionChecked(FactorGraphOptionTable(),
                                  [](const YamlNode& n) { ParseFactorGraphOptions(n); });
  EXPECT_GT(FactorGraphOptionTable().NumericFields().size(), 50u);
}

TEST(OptionTables, EveryNumericEkfOptionOutOfRangeIsAFileLineError) {
  ExpectEveryNumericOptionChecked(EkfOptionTable(), [](const YamlNode& n) { ParseEkfOptions(n); });
}

TEST(OptionTables, SensorOverridesOfTheSetupAreCheckedToo) {
  const auto setup = [](const std::string& estimator_block) {
    return "sensors:\n"
           "  - {type: imu, id: imu, T_body_sensor: {translation: [0, 0, 0]},\n"
           "     estimator: " +
           estimator_block + "}\n";
  };
  for (const NumericOption& f : ImuNoiseOptionTable().NumericFields()) {
    std::ostringstream block;
    block << "{" << f.path << ": " << *f.range.Outside() << "}";
    try {
      ParseEstimatorSensorSetup(YamlNode::LoadString(setup(block.str()), "setup.yaml"));
      ADD_FAILURE() << f.path << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("setup.yaml:3:"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(f.path), std::string::npos) << e.what();
    }
  }
}

TEST(OptionTables, OptionsBuiltInCodeAreValidatedField) {
  FactorGraphOptions o;
  o.zero_velocity.max_encoder_speed_mps = -1.0;
  std::string why;
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("zero_velocity.max_encoder_speed_mps"), std::string::npos) << why;
  o = FactorGraphOptions{};
  o.lidar.odometry.max_range_m = 0.5;  // below min_range_m
  EXPECT_FALSE(o.IsValid(&why));
  EXPECT_NE(why.find("max_range_m"), std::string::npos) << why;
  EkfOptions e;
  e.vehicle.mass_kg = 0.0;
  EXPECT_FALSE(e.IsValid(&why));
  EXPECT_NE(why.find("mass_kg"), std::string::npos) << why;
}

// The block between the markers of docs/estimator-config.md; STATEBENCH_UPDATE_DOCS=1 rewrites it.
void ExpectDocsBlock(const std::string& name, const std::string& generated) {
  const char* dir = std::getenv("STATEBENCH_SOURCE_DIR");  // set by ctest
  const std::filesystem::path docs =
      std::filesystem::path(dir != nullptr ? dir : ".") / "docs/estimator-config.md";
  std::ifstream in(docs);
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string text = buffer.str();
  const std::string begin = "<!-- options:" + name + ":begin (generated: option_tables_test) -->\n";
  const std::string end = "<!-- options:" + name + ":end -->";
  const std::size_t a = text.find(begin), b = text.find(end);
  ASSERT_TRUE(a != std::string::npos && b != std::string::npos) << "markers of " << name;
  const std::string current = text.substr(a + begin.size(), b - a - begin.size());
  if (current != generated && std::getenv("STATEBENCH_UPDATE_DOCS") != nullptr) {
    text.replace(a + begin.size(), b - a - begin.size(), generated);
    std::ofstream(docs) << text;
    return;
  }
  EXPECT_EQ(current, generated) << "docs/estimator-config.md is out of date: run this test with "
                                   "STATEBENCH_UPDATE_DOCS=1";
}

TEST(OptionTables, DocsTablesAreTheGeneratedOnes) {
  ExpectDocsBlock("factor_graph",
                  OptionRowsMarkdown(FactorGraphOptionTable().Rows(FactorGraphOptions{})));
  ExpectDocsBlock("ekf", OptionRowsMarkdown(EkfOptionTable().Rows(EkfOptions{})));
}

}  // namespace
}  // namespace statebench::est
