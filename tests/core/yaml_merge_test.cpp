#include "core/yaml_merge.hpp"

#include <gtest/gtest.h>

namespace statebench {
namespace {

TEST(YamlMerge, MergesMapsRecursivelyAndReplacesEverythingElse) {
  const YAML::Node base = YAML::Load(
      "window_s: 1.0\n"
      "gnss: {max_sigma_m: 5.0, gate_chi2: 16.27, robust_kernel: {type: huber, scale: 3.0}}\n"
      "list: [1, 2, 3]\n"
      "kinematic: {enabled: auto}\n");
  const YAML::Node overrides = YAML::Load(
      "window_s: 0.5\n"
      "gnss: {robust_kernel: {scale: 2.0}}\n"
      "list: [9]\n"
      "kinematic: false\n"
      "lidar: {enabled: true}\n");
  const YAML::Node merged = MergeYaml(base, overrides);
  EXPECT_EQ(merged["window_s"].as<double>(), 0.5);
  EXPECT_EQ(merged["gnss"]["max_sigma_m"].as<double>(), 5.0);
  EXPECT_EQ(merged["gnss"]["gate_chi2"].as<double>(), 16.27);
  EXPECT_EQ(merged["gnss"]["robust_kernel"]["type"].as<std::string>(), "huber");
  EXPECT_EQ(merged["gnss"]["robust_kernel"]["scale"].as<double>(), 2.0);
  ASSERT_TRUE(merged["list"].IsSequence());
  ASSERT_EQ(merged["list"].size(), 1u);  // sequences are replaced, not appended to
  EXPECT_EQ(merged["list"][0].as<int>(), 9);
  EXPECT_FALSE(merged["kinematic"].as<bool>());        // a scalar replaces a map
  EXPECT_TRUE(merged["lidar"]["enabled"].as<bool>());  // keys only in the overrides are added
}

TEST(YamlMerge, LeavesInputsUntouched) {
  const YAML::Node base = YAML::Load("a: {b: 1, c: 2}\n");
  const YAML::Node overrides = YAML::Load("a: {b: 7}\n");
  YAML::Node merged = MergeYaml(base, overrides);
  merged["a"]["c"] = 99;
  EXPECT_EQ(base["a"]["b"].as<int>(), 1);
  EXPECT_EQ(base["a"]["c"].as<int>(), 2);
  EXPECT_EQ(overrides["a"].size(), 1u);
}

TEST(YamlMerge, MissingOverridesKeepTheBaseAndEmptyBaseTakesTheOverrides) {
  const YAML::Node base = YAML::Load("a: 1\n");
  EXPECT_EQ(MergeYaml(base, YAML::Node())["a"].as<int>(), 1);
  const YAML::Node merged = MergeYaml(YAML::Node(YAML::NodeType::Map), YAML::Load("x: {y: 2}\n"));
  EXPECT_EQ(merged["x"]["y"].as<int>(), 2);
}

TEST(YamlMerge, TextRoundTripsWithOneKeyPerLine) {
  const YAML::Node merged =
      MergeYaml(YAML::Load("a: 1\nb: {c: auto}\n"), YAML::Load("b: {d: 1.0e-5}\n"));
  const std::string text = ToYamlText(merged);
  EXPECT_EQ(text, "a: 1\nb:\n  c: auto\n  d: 1.0e-5\n");
  EXPECT_EQ(ToYamlText(YAML::Node()), "");
}

}  // namespace
}  // namespace statebench
