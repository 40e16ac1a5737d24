// The topic map of a bag import: written and read back unchanged; the static-transform tree that
// turns /tf_static into mounts.
#include "sensors/rosbag_topic_map.hpp"

#include <gtest/gtest.h>

#include "core/yaml_node.hpp"
#include "sensors/static_transform_tree.hpp"

namespace statebench::sensors {
namespace {

RosTopicEntry Entry(const std::string& topic, const std::string& id, RosTopicKind kind) {
  RosTopicEntry e;
  e.topic = topic;
  e.id = id;
  e.kind = kind;
  return e;
}

TEST(RosTopicMap, WritesAndReadsBackEveryField) {
  RosTopicMap map;
  map.base_frame = "base_footprint";
  map.scenario = "a \"drive\"";
  map.origin = GeodeticPoint{48.78461234567, -2.1, 130.25};
  RosTopicEntry imu;
  imu.topic = "/imu/data";
  imu.id = "imu";
  imu.kind = RosTopicKind::kImu;
  imu.frame_id = "imu_link";
  imu.T_body_sensor = SE3(Quat(0.5, 0.5, 0.5, 0.5), Vec3(0.1, 0.2, 0.3));
  imu.latency_s = 0.003;
  RosTopicEntry gnss = Entry("/fix", "gnss", RosTopicKind::kGnss);
  gnss.position_sigma_m = Vec3(1.0, 1.5, 2.0);
  gnss.estimator = "{covariance_scale: 4, correlated_error_sigma_m: 0.17}";
  RosTopicEntry odom = Entry("/odom", "odom", RosTopicKind::kBodyVelocity);
  odom.twist_sigma = (Vec6() << 0.1, 0.2, 0.3, 0.4, 0.5, 0.6).finished();
  RosTopicEntry wheels = Entry("/joints", "wheels", RosTopicKind::kWheelEncoders);
  wheels.joints = {"a", "b", "c", "d"};
  RosTopicEntry steering = Entry("/joints", "steer", RosTopicKind::kSteeringEncoder);
  steering.joint = "steering_joint";
  RosTopicEntry lidar = Entry("/points", "lidar", RosTopicKind::kLidar);
  lidar.time_field = "offset_time";
  lidar.time_scale_s = 1e-6;
  map.topics = {imu, gnss, odom, wheels, steering, lidar};
  map.static_transforms.push_back(
      RosStaticTransform{"base_footprint", "imu_link", SE3(Quat::Identity(), Vec3(0, 0, 1)), ""});

  const std::string yaml = RosTopicMapYaml(map, "# test\n");
  const RosTopicMap back = ParseRosTopicMap(YamlNode::LoadString(yaml, "map.yaml"));
  EXPECT_EQ(back.base_frame, map.base_frame);
  EXPECT_EQ(back.scenario, map.scenario);
  EXPECT_EQ(back.origin->latitude_deg, map.origin->latitude_deg);
  EXPECT_EQ(back.origin->longitude_deg, -2.1);
  ASSERT_EQ(back.topics.size(), 6u);
  EXPECT_EQ(back.topics[0].frame_id, "imu_link");
  EXPECT_EQ(back.topics[0].T_body_sensor->translation(), Vec3(0.1, 0.2, 0.3));
  EXPECT_EQ(back.topics[0].T_body_sensor->rotation().coeffs(),
            imu.T_body_sensor->rotation().coeffs());
  EXPECT_EQ(back.topics[0].latency_s, 0.003);
  EXPECT_EQ(back.topics[1].position_sigma_m, gnss.position_sigma_m);
  EXPECT_EQ(back.topics[1].estimator, gnss.estimator);  // the setup's block, as written
  EXPECT_TRUE(back.topics[0].estimator.empty());
  EXPECT_EQ(back.topics[2].twist_sigma, odom.twist_sigma);
  EXPECT_EQ(back.topics[3].joints, wheels.joints);
  EXPECT_EQ(back.topics[4].joint, "steering_joint");
  EXPECT_EQ(back.topics[5].time_field, "offset_time");
  EXPECT_EQ(back.topics[5].time_scale_s, 1e-6);
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_EQ(back.topics[i].kind, map.topics[i].kind);
    EXPECT_EQ(back.topics[i].topic, map.topics[i].topic);
  }
  ASSERT_EQ(back.static_transforms.size(), 1u);
  EXPECT_EQ(back.static_transforms[0].child, "imu_link");
  EXPECT_EQ(back.static_transforms[0].T_parent_child.translation(), Vec3(0, 0, 1));
  // Defaults: the steering joint is the id, the wheel joints <id>_fl, _fr, _rl, _rr.
  const RosTopicMap defaults = ParseRosTopicMap(YamlNode::LoadString(
      "topics: [{topic: /j, id: w, type: wheel_encoders}, {topic: /j, id: s, type: "
      "steering_encoder}]",
      "d.yaml"));
  EXPECT_EQ(defaults.base_frame, "base_link");
  EXPECT_EQ(defaults.topics[0].joints,
            (std::array<std::string, 4>{"w_fl", "w_fr", "w_rl", "w_rr"}));
  EXPECT_EQ(defaults.topics[1].joint, "s");
}

TEST(StaticTransformTree, ComposesChainsBranchesAndInverses) {
  StaticTransformTree tree;
  const SE3 T_base_chassis(Quat(Eigen::AngleAxisd(0.3, Vec3::UnitZ())), Vec3(1, 0, 0));
  const SE3 T_chassis_imu(Quat(Eigen::AngleAxisd(-0.2, Vec3::UnitX())), Vec3(0, 0.5, 0.2));
  const SE3 T_base_gps(Quat::Identity(), Vec3(0.2, 0, 1.5));
  tree.Set("base_link", "chassis", T_base_chassis);
  tree.Set("chassis", "imu", T_chassis_imu);
  tree.Set("base_link", "gps", SE3(Quat::Identity(), Vec3(9, 9, 9)));
  tree.Set("base_link", "gps", T_base_gps);  // the later edge replaces the earlier
  tree.Set("map", "odom", SE3());            // another tree

  const SE3 T_base_imu = T_base_chassis * T_chassis_imu;
  const auto near = [](const SE3& a, const SE3& b) {
    return (a.translation() - b.translation()).norm() < 1e-14 &&
           a.rotation().angularDistance(b.rotation()) < 1e-14;
  };
  EXPECT_EQ(tree.Lookup("base_link", "gps")->translation(), T_base_gps.translation());  // exact
  EXPECT_TRUE(near(*tree.Lookup("base_link", "imu"), T_base_imu));
  EXPECT_TRUE(near(*tree.Lookup("imu", "base_link"), T_base_imu.Inverse()));
  EXPECT_TRUE(near(*tree.Lookup("gps", "imu"), T_base_gps.Inverse() * T_base_imu));
  EXPECT_TRUE(near(*tree.Lookup("nowhere", "nowhere"), SE3()));
  EXPECT_FALSE(tree.Lookup("base_link", "odom").has_value());
  EXPECT_FALSE(tree.Lookup("base_link", "nowhere").has_value());
  tree.Set("imu", "base_link", SE3());  // a loop
  EXPECT_FALSE(tree.Lookup("gps", "imu").has_value());
}

}  // namespace
}  // namespace statebench::sensors
