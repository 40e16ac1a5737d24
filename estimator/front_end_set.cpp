#include "estimator/front_end_set.hpp"

#include "estimator/body_velocity_front_end.hpp"
#include "estimator/encoder_front_end.hpp"
#include "estimator/lidar_front_end.hpp"
#include "estimator/motion_constraint_front_end.hpp"

namespace statebench::est {

FrontEndSet MakeFrontEnds(const EstimatorSensorSetup& setup, const FactorPlan& plan,
                          const FactorGraphOptions& options, FrontEndContext& ctx,
                          LidarOdometryPool* lidar_pool) {
  FrontEndSet set;
  auto encoders = std::make_unique<EncoderFrontEnd>(setup, plan, options, ctx);
  auto gnss = std::make_unique<GnssFrontEnd>(setup, options, ctx);
  auto motion =
      std::make_unique<MotionConstraintFrontEnd>(setup, plan, options, *encoders, *gnss, ctx);
  set.gnss = gnss.get();
  set.all.push_back(std::move(encoders));
  set.all.push_back(std::move(motion));
  // One lidar front end per lidar (its own odometry and mount globals), or one for all of them
  // with lidar.merge_scans (lidar_front_end.hpp); one without lidars refuses their scans.
  if (options.lidar.merge_scans || plan.lidars.size() <= 1) {
    set.all.push_back(
        std::make_unique<LidarFrontEnd>(setup, plan.lidars, options, ctx, lidar_pool));
  } else {
    for (const EstimatorSensor* lidar : plan.lidars) {
      set.all.push_back(std::make_unique<LidarFrontEnd>(
          setup, std::vector<const EstimatorSensor*>{lidar}, options, ctx, lidar_pool));
    }
  }
  set.all.push_back(std::move(gnss));
  set.all.push_back(std::make_unique<BodyVelocityFrontEnd>(setup, options, ctx));
  return set;
}

}  // namespace statebench::est
