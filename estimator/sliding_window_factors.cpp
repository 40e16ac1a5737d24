// SlidingWindowSmoother's measurements onto their anchor state: the GNSS, heading, relative-pose
// and body-velocity factors with the globals they carry, and the factors that wait for the IMU
// (sliding_window_impl.hpp).
#include <iterator>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/error.hpp"
#include "estimator/body_velocity_factor.hpp"
#include "estimator/dual_antenna_factor.hpp"
#include "estimator/gnss_error_state_factor.hpp"
#include "estimator/gnss_propagated_position_factor.hpp"
#include "estimator/gnss_time_offset_factor.hpp"
#include "estimator/relative_pose_factor.hpp"
#include "estimator/sliding_window_impl.hpp"

namespace statebench::est {

void SlidingWindowSmoother::Impl::AttachGnss(Node& anchor, const GnssPositionEnu& fix,
                                             const Vec3& p_imu_antenna,
                                             std::optional<int> time_offset,
                                             std::optional<std::array<int, 3>> error) {
  std::vector<double*> blocks{anchor.x.q_world_imu.data(), anchor.x.p_world.data(),
                              anchor.x.v_world.data(), anchor.x.bias.data()};
  std::unique_ptr<ceres::CostFunction> cost;
  Mat3 S;
  if (time_offset) {
    auto f = std::make_unique<GnssTimeOffsetFactor>(
        fix.p_enu, fix.covariance, p_imu_antenna, Preintegrate(anchor, fix.header.stamp_ns),
        anchor.State().q_world_imu, GyroAt(fix.header.stamp_ns));
    S = f->sqrt_information();
    cost = std::move(f);
    blocks.push_back(globals[*time_offset].value.get());
  } else {
    auto f = std::make_unique<GnssPropagatedPositionFactor>(
        fix.p_enu, fix.covariance, p_imu_antenna, Preintegrate(anchor, fix.header.stamp_ns),
        anchor.State().q_world_imu);
    S = f->sqrt_information();
    cost = std::move(f);
  }
  if (error) {
    cost = std::make_unique<GnssErrorStateFactor>(std::move(cost), S);
    for (int index : *error) blocks.push_back(globals[index].value.get());
  }
  AddFactor(anchor, FactorKind::kGnss, cost.release(),
            options.gnss_kernel.MakeLossFunction().release(), std::move(blocks));
}

void SlidingWindowSmoother::Impl::AttachHeading(Node& anchor, const DualAntennaHeading& heading,
                                                const Vec3& p_imu_main, const Vec3& p_imu_aux,
                                                std::optional<std::array<int, 2>> baseline) {
  const Quat dR = Preintegrate(anchor, heading.header.stamp_ns).delta_q();
  if (!baseline) {
    AddFactor(anchor, FactorKind::kHeading,
              DualAntennaFactor::Create(heading, p_imu_main, p_imu_aux, dR),
              options.heading_kernel.MakeLossFunction().release(), {anchor.x.q_world_imu.data()});
    return;
  }
  AddFactor(anchor, FactorKind::kHeading,
            DualAntennaFactor::CreateWithBaselineCorrection(heading, p_imu_main, p_imu_aux, dR),
            options.heading_kernel.MakeLossFunction().release(),
            {anchor.x.q_world_imu.data(), globals[(*baseline)[0]].value.get(),
             globals[(*baseline)[1]].value.get()});
}

void SlidingWindowSmoother::Impl::CheckMount(const SlidingWindowSmoother::MountCorrection& mount,
                                             const char* what, bool roll_allowed) const {
  if (!KnownGlobal(mount.pitch) || !KnownGlobal(mount.yaw) ||
      (mount.roll != -1 && (!roll_allowed || !KnownGlobal(mount.roll)))) {
    throw InputError(std::string(what) + ": unknown mount correction index");
  }
}

void SlidingWindowSmoother::Impl::AppendMountBlocks(
    const std::optional<SlidingWindowSmoother::MountCorrection>& mount,
    std::vector<double*>* blocks) const {
  if (!mount) return;
  for (int index : {mount->roll, mount->pitch, mount->yaw}) {
    if (index >= 0) blocks->push_back(globals[index].value.get());
  }
}

void SlidingWindowSmoother::Impl::AttachRelativePose(Node& a, const RelativePose& r) {
  // The state after a, when it is not after t2, carries t2 (neighbouring states only).
  Node* b = nullptr;
  for (std::size_t k = 0; k + 1 < states.size(); ++k) {
    if (states[k].get() == &a) {
      if (states[k + 1]->t_ns <= r.t2_ns) b = states[k + 1].get();
      break;
    }
  }
  MountAxes axes;
  if (r.mount) axes = {r.mount->roll >= 0, r.mount->pitch >= 0, r.mount->yaw >= 0};
  ceres::LossFunction* loss = r.kernel.MakeLossFunction().release();
  std::vector<double*> blocks = a.Blocks();
  ceres::CostFunction* cost = nullptr;
  if (b == nullptr) {
    cost = CreateRelativePoseFactorOneAnchor(r.m, Preintegrate(a, r.t1_ns),
                                             Preintegrate(a, r.t2_ns), axes);
  } else {
    for (double* block : b->Blocks()) blocks.push_back(block);
    cost = CreateRelativePoseFactor(r.m, Preintegrate(a, r.t1_ns), Preintegrate(*b, r.t2_ns), axes);
  }
  AppendMountBlocks(r.mount, &blocks);
  AddFactor(a, FactorKind::kRelativePose, cost, loss, std::move(blocks));
}

void SlidingWindowSmoother::Impl::AttachVelocity(
    Node& a, TimeNs t_ns, BodyVelocityMeasurement m, const RobustKernel& kernel,
    std::optional<SlidingWindowSmoother::MountCorrection> mount) {
  m.gyro_raw = GyroAt(t_ns);
  std::vector<double*> blocks{a.x.q_world_imu.data(), a.x.v_world.data(), a.x.bias.data()};
  AppendMountBlocks(mount, &blocks);  // pitch and yaw (no roll: CheckMount)
  ceres::CostFunction* cost = mount
                                  ? CreateMountCorrectedBodyVelocityFactor(m, Preintegrate(a, t_ns))
                                  : CreateBodyVelocityFactor(m, Preintegrate(a, t_ns));
  AddFactor(a, FactorKind::kVelocity, cost, kernel.MakeLossFunction().release(), std::move(blocks));
}

AddResult SlidingWindowSmoother::Impl::Add(Pending p) {
  Node* anchor = Anchor(p.anchor_ns);
  if (anchor == nullptr) return AddResult::kTooOld;
  if (p.ready_ns > imu.back().header.stamp_ns) {
    pending.push_back(std::move(p));
    return AddResult::kPending;
  }
  p.attach(*anchor);
  return AddResult::kAdded;
}

void SlidingWindowSmoother::Impl::FlushPending() {
  const TimeNs newest = imu.back().header.stamp_ns;
  for (FactorKind kind : {FactorKind::kGnss, FactorKind::kHeading, FactorKind::kVelocity,
                          FactorKind::kRelativePose, FactorKind::kZeroRate}) {
    std::erase_if(pending, [&](const Pending& p) {
      if (p.kind != kind || p.ready_ns > newest) return false;
      if (Node* anchor = Anchor(p.anchor_ns)) {
        p.attach(*anchor);
      } else {
        ++num_dropped;  // the window moved past it while it waited
      }
      return true;
    });
  }
}

}  // namespace statebench::est
