// The factor graph's options declared once (core/option_table.hpp): YAML keys, ranges and docs
// of FactorGraphOptions and of the parts it shares with the sensor setup (IMU noise). Parsing,
// validation and the option table of docs/estimator-config.md all come from here.
#pragma once

#include "core/option_table.hpp"
#include "estimator/estimator_config.hpp"

namespace statebench::est {

const OptionTable<FactorGraphOptions>& FactorGraphOptionTable();
const OptionTable<ImuNoise>& ImuNoiseOptionTable();
// The `estimator:` overrides of a gnss entry of the sensor setup.
const OptionTable<GnssAntenna>& GnssAntennaOptionTable();

}  // namespace statebench::est
