// The interface every state estimator of StateBench implements (the factor graph here, the EKF
// baseline): measurements go in in arrival order, the state comes out at any stamp up to the
// newest IMU sample.
//
// Contract:
//  - Add() never throws on bad data and never crashes: a measurement with a non-finite or absurd
//    value, a stamp going backwards, an unknown sensor id or a sensor type the estimator does
//    not use is rejected and counted in diagnostics(), and the estimator keeps running.
//  - StateAt(t) returns nullopt before initialisation, after the newest IMU sample, or before
//    the oldest stamp the estimator still holds; otherwise a finite mean and a finite,
//    symmetric 15x15 covariance (core/state.hpp ordering: rotation (right perturbation), position,
//    velocity, gyro bias, accel bias) in the local ENU frame, and the WGS84 position of the IMU.
#pragma once

#include <optional>
#include <string>

#include "core/measurements.hpp"
#include "core/state.hpp"
#include "core/time.hpp"
#include "estimator/estimator_diagnostics.hpp"

namespace statebench::est {

class Estimator {
 public:
  virtual ~Estimator() = default;

  virtual std::string name() const = 0;
  // Feeds one measurement, in arrival order.
  virtual void Add(const Measurement& measurement) = 0;
  virtual std::optional<StateEstimate> StateAt(TimeNs t_ns) const = 0;
  virtual EstimatorDiagnostics diagnostics() const = 0;
  // Every verdict on a measurement from now on also goes to `observer` (estimator_diagnostics.hpp).
  virtual void SetVerdictObserver(VerdictObserver observer) = 0;
  // True for an estimator whose estimate exists only once the whole log is in (the factor
  // graph's full-batch smoother): the caller calls EndOfLog() after the last measurement and
  // reads StateAt only then (before, it returns nullopt).
  virtual bool EstimatesAtEnd() const { return false; }
  // No measurement follows.
  virtual void EndOfLog() {}
};

}  // namespace statebench::est
