#include "sensors/sensor_options_yaml.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <sstream>

#include "core/option_table.hpp"

namespace statebench::sensors {
namespace {

// Keys every entry has (sensor_setup.cpp reads them), and `estimator`: what the estimators are
// told beyond the setup (estimator-config.md, "Per-sensor estimator overrides"), not simulated.
constexpr std::array<std::string_view, 6> kCommonSensorKeys = {
    "type", "id", "rate_hz", "T_body_sensor", "latency_s", "estimator"};

// Throws on a key that is neither common nor one of the type's own keys (catches typos).
void ExpectEntryKeys(const YamlNode& entry, std::initializer_list<std::string_view> own) {
  for (const std::string& key : entry.Keys()) {
    const auto matches = [&key](std::string_view k) { return k == key; };
    if (std::any_of(kCommonSensorKeys.begin(), kCommonSensorKeys.end(), matches) ||
        std::any_of(own.begin(), own.end(), matches)) {
      continue;
    }
    std::string list;
    for (const auto k : kCommonSensorKeys) list += std::string(k) + ", ";
    for (const auto k : own) list += std::string(k) + ", ";
    list.resize(list.size() - 2);
    entry[key].Fail("unknown field (expected one of: " + list + ")");
  }
}

// Overrides *value with entry[key] when present.
void ReadOptional(const YamlNode& node, const std::string& key, double* value,
                  double (*check)(const YamlNode&)) {
  if (const auto child = node.Find(key)) *value = check(*child);
}

ImuTriadOptions ParseTriad(const YamlNode& node, ImuTriadOptions triad, bool require_noise) {
  node.ExpectOnlyKeys({"noise_density", "random_walk", "turn_on_bias_sigma", "gauss_markov",
                       "scale_factor_sigma", "misalignment_sigma_rad", "quantization"});
  if (require_noise) {
    triad.noise_density = NonNegative(node["noise_density"]);
    triad.random_walk = NonNegative(node["random_walk"]);
  }
  ReadOptional(node, "noise_density", &triad.noise_density, NonNegative);
  ReadOptional(node, "random_walk", &triad.random_walk, NonNegative);
  ReadOptional(node, "turn_on_bias_sigma", &triad.turn_on_bias_sigma, NonNegative);
  ReadOptional(node, "scale_factor_sigma", &triad.scale_factor_sigma, NonNegative);
  ReadOptional(node, "misalignment_sigma_rad", &triad.misalignment_sigma_rad, NonNegative);
  ReadOptional(node, "quantization", &triad.quantization, NonNegative);
  if (const auto gm = node.Find("gauss_markov")) {
    gm->ExpectOnlyKeys({"sigma", "tau_s"});
    triad.gauss_markov_sigma = NonNegative((*gm)["sigma"]);
    triad.gauss_markov_tau_s = Positive((*gm)["tau_s"]);
  }
  return triad;
}

Vec3 NonNegativeVec3(const YamlNode& node) {
  const Vec3 v = node.As<Vec3>();
  if (!(v.minCoeff() >= 0.0)) node.Fail("must be three numbers >= 0");
  return v;
}

ImuVibrationOptions ParseVibration(const YamlNode& node) {
  node.ExpectOnlyKeys({"engine", "road"});
  ImuVibrationOptions o;
  if (const auto engine = node.Find("engine")) {
    engine->ExpectOnlyKeys({"idle_rpm", "rpm_per_mps", "max_rpm", "harmonics"});
    EngineVibrationOptions e;
    e.idle_rpm = Positive((*engine)["idle_rpm"]);
    ReadOptional(*engine, "rpm_per_mps", &e.rpm_per_mps, NonNegative);
    ReadOptional(*engine, "max_rpm", &e.max_rpm, Positive);
    if (e.max_rpm < e.idle_rpm) (*engine)["max_rpm"].Fail("must be at least idle_rpm");
    const YamlNode harmonics = (*engine)["harmonics"];
    harmonics.ExpectSequence();
    if (harmonics.size() == 0) harmonics.Fail("needs at least one harmonic");
    for (std::size_t i = 0; i < harmonics.size(); ++i) {
      const YamlNode h = harmonics.At(i);
      h.ExpectOnlyKeys({"order", "gyro_rms_radps", "accel_rms_mps2"});
      EngineHarmonic harmonic;
      harmonic.order = Positive(h["order"]);
      if (const auto g = h.Find("gyro_rms_radps")) harmonic.gyro_rms_radps = NonNegativeVec3(*g);
      if (const auto a = h.Find("accel_rms_mps2")) harmonic.accel_rms_mps2 = NonNegativeVec3(*a);
      e.harmonics.push_back(harmonic);
    }
    o.engine = e;
  }
  if (const auto road = node.Find("road")) {
    road->ExpectOnlyKeys({"gyro_rms_per_mps", "accel_rms_per_mps", "frequency_hz", "damping"});
    RoadVibrationOptions r;
    if (const auto g = road->Find("gyro_rms_per_mps")) r.gyro_rms_per_mps = NonNegativeVec3(*g);
    if (const auto a = road->Find("accel_rms_per_mps")) r.accel_rms_per_mps = NonNegativeVec3(*a);
    ReadOptional(*road, "frequency_hz", &r.frequency_hz, Positive);
    if (const auto d = road->Find("damping")) {
      r.damping = CheckedNumber(*d, OptionRange{0.0, false, 1.0, false});
    }
    o.road = r;
  }
  return o;
}

GnssAccuracy ParseAccuracy(const YamlNode& node) {
  node.ExpectOnlyKeys({"cep_m", "vertical_sigma_m"});
  GnssAccuracy a;
  a.cep_m = NonNegative(node["cep_m"]);
  a.vertical_sigma_m = node.Has("vertical_sigma_m") ? NonNegative(node["vertical_sigma_m"])
                                                    : 1.5 * a.HorizontalSigma();
  return a;
}

GnssMode ParseMode(const YamlNode& node) {
  const auto mode = ParseGnssMode(node.As<std::string>());
  if (!mode)
    node.Fail("unknown mode '" + node.As<std::string>() +
              "' (expected one of: rtk_fixed, rtk_float, single)");
  return *mode;
}

std::vector<GnssOutage> ParseOutages(const YamlNode& node) {
  node.ExpectSequence();
  std::vector<GnssOutage> outages;
  for (std::size_t i = 0; i < node.size(); ++i) {
    const YamlNode o = node.At(i);
    o.ExpectOnlyKeys({"start_s", "end_s"});
    GnssOutage outage;
    outage.start_s = o.Get<double>("start_s");
    outage.end_s =
        o.Has("end_s") ? o.Get<double>("end_s") : std::numeric_limits<double>::infinity();
    if (!(outage.end_s > outage.start_s)) o["end_s"].Fail("must be after start_s");
    outages.push_back(outage);
  }
  return outages;
}

}  // namespace

double NonNegative(const YamlNode& node) { return CheckedNumber(node, OptionRange::NonNegative()); }

double Positive(const YamlNode& node) { return CheckedNumber(node, OptionRange::Positive()); }

double InRange(const YamlNode& node, double lo, double hi) {
  return CheckedNumber(node, OptionRange::Closed(lo, hi));
}

ImuOptions ParseImuOptions(const YamlNode& entry) {
  ExpectEntryKeys(entry, {"preset", "gyro", "accel", "vibration"});
  ImuOptions o;
  const bool has_preset = entry.Has("preset");
  if (has_preset) {
    const YamlNode p = entry["preset"];
    const auto grade = ParseImuGrade(p.As<std::string>());
    if (!grade)
      p.Fail("unknown preset '" + p.As<std::string>() +
             "' (expected one of: consumer, industrial, tactical)");
    o = ImuPreset(*grade);
  }
  // Without a preset the gyro and accel blocks with their noise terms are required.
  if (!has_preset || entry.Has("gyro")) o.gyro = ParseTriad(entry["gyro"], o.gyro, !has_preset);
  if (!has_preset || entry.Has("accel")) {
    o.accel = ParseTriad(entry["accel"], o.accel, !has_preset);
  }
  if (const auto vibration = entry.Find("vibration")) o.vibration = ParseVibration(*vibration);
  return o;
}

GnssOptions ParseGnssOptions(const YamlNode& entry) {
  ExpectEntryKeys(
      entry, {"mode", "cep_m", "vertical_sigma_m", "gauss_markov", "covariance_scale", "outages",
              "multipath", "degraded_accuracy", "min_satellites", "velocity"});
  GnssOptions o;
  if (const auto degraded = entry.Find("degraded_accuracy")) {
    degraded->ExpectOnlyKeys({"rtk_fixed", "rtk_float", "single"});
    for (const char* key : {"rtk_fixed", "rtk_float", "single"}) {
      if (const auto a = degraded->Find(key)) o.AccuracyOf(*ParseGnssMode(key)) = ParseAccuracy(*a);
    }
  }
  o.mode = ParseMode(entry["mode"]);
  GnssAccuracy& accuracy = o.AccuracyOf(o.mode);
  if (const auto cep = entry.Find("cep_m")) {
    accuracy.cep_m = NonNegative(*cep);
    accuracy.vertical_sigma_m = 1.5 * accuracy.HorizontalSigma();
  }
  ReadOptional(entry, "vertical_sigma_m", &accuracy.vertical_sigma_m, NonNegative);
  if (const auto gm = entry.Find("gauss_markov")) {
    gm->ExpectOnlyKeys({"fraction", "tau_s"});
    o.correlated_fraction = InRange((*gm)["fraction"], 0.0, 1.0);
    o.gauss_markov_tau_s = Positive((*gm)["tau_s"]);
  }
  ReadOptional(entry, "covariance_scale", &o.covariance_scale, Positive);
  if (const auto outages = entry.Find("outages")) o.outages = ParseOutages(*outages);
  if (const auto mp = entry.Find("multipath")) {
    mp->ExpectOnlyKeys({"events_per_hour", "magnitude_m", "duration_s"});
    o.multipath.events_per_hour = NonNegative((*mp)["events_per_hour"]);
    ReadOptional(*mp, "magnitude_m", &o.multipath.magnitude_m, NonNegative);
    ReadOptional(*mp, "duration_s", &o.multipath.duration_s, Positive);
  }
  if (const auto v = entry.Find("velocity")) {  // a map, possibly empty: Doppler velocity on
    v->ExpectOnlyKeys({"horizontal_sigma_mps", "vertical_sigma_mps"});
    o.velocity.enabled = true;
    ReadOptional(*v, "horizontal_sigma_mps", &o.velocity.horizontal_sigma_mps, NonNegative);
    ReadOptional(*v, "vertical_sigma_mps", &o.velocity.vertical_sigma_mps, NonNegative);
  }
  if (const auto sats = entry.Find("min_satellites")) {
    sats->ExpectOnlyKeys({"rtk_fixed", "rtk_float", "single"});
    GnssSatelliteThresholds& th = o.min_satellites;
    th.rtk_fixed = sats->Get<int>("rtk_fixed", th.rtk_fixed);
    th.rtk_float = sats->Get<int>("rtk_float", th.rtk_float);
    th.single = sats->Get<int>("single", th.single);
    if (!(th.rtk_fixed >= th.rtk_float && th.rtk_float >= th.single && th.single >= 0)) {
      sats->Fail("expected rtk_fixed >= rtk_float >= single >= 0");
    }
  }
  return o;
}

WheelEncoderOptions ParseWheelEncoderOptions(const YamlNode& entry) {
  ExpectEntryKeys(entry, {"ticks_per_rev", "radius_error"});
  WheelEncoderOptions o;
  const YamlNode ticks = entry["ticks_per_rev"];
  o.ticks_per_rev = ticks.As<int>();
  if (o.ticks_per_rev <= 0) ticks.Fail("must be > 0");
  if (const auto err = entry.Find("radius_error")) {
    err->ExpectSequence();
    if (err->size() != 4) err->Fail("expected 4 numbers [FL, FR, RL, RR]");
    for (std::size_t i = 0; i < 4; ++i) o.radius_error[i] = InRange(err->At(i), -0.5, 0.5);
  }
  return o;
}

SpeedEncoderOptions ParseSpeedEncoderOptions(const YamlNode& entry) {
  ExpectEntryKeys(entry, {"distance_per_tick_m", "radius_error"});
  SpeedEncoderOptions o;
  o.distance_per_tick_m = Positive(entry["distance_per_tick_m"]);
  if (const auto err = entry.Find("radius_error")) o.radius_error = InRange(*err, -0.5, 0.5);
  return o;
}

SteeringEncoderOptions ParseSteeringEncoderOptions(const YamlNode& entry) {
  ExpectEntryKeys(entry, {"resolution_rad", "offset_rad", "noise_sigma_rad"});
  SteeringEncoderOptions o;
  ReadOptional(entry, "resolution_rad", &o.resolution_rad, NonNegative);
  if (const auto off = entry.Find("offset_rad")) o.offset_rad = InRange(*off, -0.5, 0.5);
  ReadOptional(entry, "noise_sigma_rad", &o.noise_sigma_rad, NonNegative);
  return o;
}

LidarOptions ParseLidarOptions(const YamlNode& entry) {
  ExpectEntryKeys(
      entry, {"model", "min_range_m", "max_range_m", "range_noise_sigma_m", "dropout_probability"});
  const YamlNode m = entry["model"];
  const auto model = ParseLidarModel(m.As<std::string>());
  if (!model)
    m.Fail("unknown lidar model '" + m.As<std::string>() +
           "' (expected one of: hesai_xt32, velodyne_vlp16)");
  LidarOptions o = DefaultLidarOptions(*model);
  ReadOptional(entry, "min_range_m", &o.min_range_m, NonNegative);
  ReadOptional(entry, "max_range_m", &o.max_range_m, Positive);
  ReadOptional(entry, "range_noise_sigma_m", &o.range_noise_sigma_m, NonNegative);
  if (const auto p = entry.Find("dropout_probability"))
    o.dropout_probability = InRange(*p, 0.0, 1.0);
  if (!(o.max_range_m > o.min_range_m)) {
    (entry.Has("max_range_m") ? entry["max_range_m"] : entry).Fail("must exceed min_range_m");
  }
  return o;
}

}  // namespace statebench::sensors
