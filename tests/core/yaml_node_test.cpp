#include "core/yaml_node.hpp"

#include <gtest/gtest.h>

#include "core/error.hpp"
#include "core/transform_config.hpp"

namespace statebench {
namespace {

std::string ErrorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(YamlNode, ReadsTypedFields) {
  const YamlNode root = YamlNode::LoadString("a: 1.5\nb: 7\nc: [1, 2, 3]\nd: true\n", "x.yaml");
  EXPECT_DOUBLE_EQ(root.Get<double>("a"), 1.5);
  EXPECT_EQ(root.Get<int>("b"), 7);
  EXPECT_EQ(root.Get<Vec3>("c"), Vec3(1, 2, 3));
  EXPECT_TRUE(root.Get<bool>("d"));
  EXPECT_EQ(root.Get<int>("missing", 3), 3);
}

TEST(YamlNode, MissingFieldNamesFileLineAndField) {
  const YamlNode root = YamlNode::LoadString("vehicle:\n  mass: 1\n", "s.yaml");
  const std::string msg = ErrorOf([&] { root["vehicle"].Get<double>("wheelbase_m"); });
  EXPECT_NE(msg.find("s.yaml:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("vehicle.wheelbase_m"), std::string::npos) << msg;
  EXPECT_NE(msg.find("missing field"), std::string::npos) << msg;
}

TEST(YamlNode, WrongTypeNamesLineAndValue) {
  const YamlNode root = YamlNode::LoadString("a: 1\nvehicle:\n  mass: heavy\n", "s.yaml");
  const std::string msg = ErrorOf([&] { root["vehicle"].Get<double>("mass"); });
  EXPECT_NE(msg.find("s.yaml:3:9"), std::string::npos) << msg;
  EXPECT_NE(msg.find("'heavy'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("vehicle.mass"), std::string::npos) << msg;
}

TEST(YamlNode, SyntaxErrorNamesLine) {
  const std::string msg =
      ErrorOf([] { YamlNode::LoadString("a: 1\nb: [1, 2\nc: 3\n", "broken.yaml"); });
  EXPECT_NE(msg.find("broken.yaml:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("syntax error"), std::string::npos) << msg;
}

TEST(YamlNode, AKeyThatIsNotAPlainNameNamesItsLine) {
  // Found by fuzz_config: a flow list as a map key escaped as yaml-cpp's BadConversion.
  const std::string msg = ErrorOf([] {
    YamlNode::LoadString("a: 1\nT: {translation: [0, 0, 0], rpy_deg: 00,[ .0.0, 0.0]}\n",
                         "keys.yaml");
  });
  EXPECT_NE(msg.find("keys.yaml:2:"), std::string::npos) << msg;
  EXPECT_NE(msg.find("a map key must be a plain name"), std::string::npos) << msg;
}

TEST(YamlNode, UnknownKeyIsRejected) {
  const YamlNode root = YamlNode::LoadString("mass: 1\nwheelbase_mm: 2\n", "v.yaml");
  const std::string msg = ErrorOf([&] { root.ExpectOnlyKeys({"mass", "wheelbase_m"}); });
  EXPECT_NE(msg.find("v.yaml:2"), std::string::npos) << msg;
  EXPECT_NE(msg.find("wheelbase_mm"), std::string::npos) << msg;
}

TEST(YamlNode, MissingFileIsReported) {
  const std::string msg = ErrorOf([] { YamlNode::LoadFile("/nonexistent/x.yaml"); });
  EXPECT_NE(msg.find("/nonexistent/x.yaml"), std::string::npos) << msg;
}

TEST(TransformConfig, ParsesRpyAndQuaternion) {
  const YamlNode root = YamlNode::LoadString(
      "a: {translation: [1, 2, 3], rpy_deg: [0, 0, 90]}\n"
      "b: {quaternion_wxyz: [0.7071067811865476, 0, 0, 0.7071067811865476]}\n"
      "c: {quaternion_wxyz: [1, 1, 0, 0]}\n",
      "t.yaml");
  const SE3 a = ParseTransform(root["a"]);
  EXPECT_LT((a * Vec3(1, 0, 0) - Vec3(1, 3, 3)).norm(), 1e-12);
  const SE3 b = ParseTransform(root["b"]);
  EXPECT_TRUE(b.rotation().isApprox(a.rotation(), 1e-12));
  EXPECT_NE(ErrorOf([&] { ParseTransform(root["c"]); }).find("unit norm"), std::string::npos);
}

// TransformYaml writes what ParseTransform reads back bit for bit (the identity rotation left out).
TEST(TransformConfig, WrittenTransformsReadBackBitForBit) {
  for (const SE3& T :
       {SE3(Quat(Eigen::AngleAxisd(0.0031, Vec3(0.3, -0.2, 0.9).normalized())),
            Vec3(0.011, -0.0037, 0.5)),
        SE3(Quat(Eigen::AngleAxisd(2.5, Vec3(-1.0, 0.4, 0.1).normalized())), Vec3(-3.2, 1e-9, 7)),
        SE3(Quat::Identity(), Vec3(0.1, 0.2, 0.3))}) {
    const std::string text = TransformYaml(T);
    const SE3 back = ParseTransform(YamlNode::LoadString("T: " + text + "\n", "t.yaml")["T"]);
    EXPECT_EQ(back.translation(), T.translation()) << text;
    EXPECT_EQ(back.rotation().coeffs(), T.rotation().coeffs()) << text;
  }
  EXPECT_EQ(TransformYaml(SE3(Quat::Identity(), Vec3(0.1, 0.2, 0.3))),
            "{translation: [0.1, 0.2, 0.3]}");
}

}  // namespace
}  // namespace statebench
