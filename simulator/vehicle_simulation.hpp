// The ego vehicle re-driving SUMO's route at 1 kHz: model + path tracker + speed controller on
// the smoothed route and the terrain, producing exact truth.
//
// Each Step integrates the model over exactly 1 ms with classic RK4. The controllers are
// evaluated inside every RK4 stage as functions of the stage state (and of the SUMO reference
// extrapolated to the stage time), so the closed-loop right-hand side is continuous in time:
// accelerations and angular rates have no steps at the 1 ms boundaries, and the truth's rates
// are consistent with its poses to the accuracy of a 4th-order integrator.
//
// Truth() evaluates the state derivative at the current state and lifts both to 3D
// (body_kinematics.hpp): nothing is differentiated numerically. Same inputs, same bits (no
// threads, no unordered containers, no randomness).
#pragma once

#include <memory>

#include "core/time.hpp"
#include "core/truth.hpp"
#include "simulator/path.hpp"
#include "simulator/path_tracker.hpp"
#include "simulator/speed_controller.hpp"
#include "simulator/terrain.hpp"
#include "simulator/vehicle_model.hpp"

namespace statebench::sim {

struct VehicleSimulationOptions {
  VehicleModelOptions model;
  PathTrackerOptions tracker;
  SpeedControllerOptions speed;
};

// Path smoothing suited to the vehicle: corners no tighter than 70 % of the curvature its
// steering limit allows (the tracker keeps a margin for corrections).
PathOptions PathOptionsFor(const VehicleParams& params);

class VehicleSimulation {
 public:
  static constexpr TimeNs kStepNs = kNsPerMillisecond;

  VehicleSimulation(VehicleParams params, std::shared_ptr<const Path> path,
                    std::shared_ptr<const Terrain> terrain, VehicleSimulationOptions options = {});

  // Puts the body origin on the path at SUMO arc length s_raw_m, aligned with the path, at
  // horizontal speed v_mps with the steady-state steering and drive force; clock at t_ns.
  void Reset(double s_raw_m, double v_mps, TimeNs t_ns = 0);

  // Advances exactly 1 ms. The reference is SUMO's, at the start of the step: arc length of
  // the BODY ORIGIN along the raw route polyline (SUMO's front-bumper position minus
  // VehicleParams::front_bumper_to_origin_m()), speed and acceleration. It is mapped onto the
  // smoothed path and extrapolated with constant acceleration inside the step.
  void Step(double s_raw_ref_m, double v_ref_mps, double a_ref_mps2);

  // Exact truth at time_ns(): body pose/velocity/acceleration/rates, steering, wheel speeds,
  // side slip, distance.
  TruthSample Truth() const;

  TimeNs time_ns() const { return t_ns_; }
  const VehicleState& state() const { return state_; }
  // Projection of the body origin on the smoothed path (arc length, lateral error left +).
  const PathProjection& projection() const { return projection_; }
  // Last reference mapped onto the smoothed path.
  const SpeedReference& reference() const { return reference_; }
  const Path& path() const { return *path_; }
  const VehicleModel& model() const { return model_; }

 private:
  // Closed-loop right-hand side at `x`, `tau_s` into the current step.
  VehicleState ClosedLoopDerivative(const VehicleState& x, double tau_s) const;

  VehicleModel model_;
  std::shared_ptr<const Path> path_;
  PathTracker tracker_;
  SpeedController speed_;
  VehicleState state_;
  TimeNs t_ns_ = 0;
  PathProjection projection_;
  SpeedReference reference_;
};

}  // namespace statebench::sim
