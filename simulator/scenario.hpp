// A scenario file (docs/scenarios.md): which vehicle drives which route through which SUMO road
// network, with what traffic, for how long. LoadScenario checks every field once and keeps the
// source location of the values that are validated later against the built network.
//
// Frames: the world frame is local ENU anchored at `origin`; SUMO network coordinates (x east,
// y north, z up, metres, after SUMO's netOffset) are used as ENU coordinates unchanged.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/geodetic.hpp"
#include "core/yaml_node.hpp"
#include "simulator/mismatch_options.hpp"
#include "simulator/source_ref.hpp"

namespace statebench::sim {

// netgenerate --grid: junctions on a regular grid; streets of `attach_length_m` hang off the
// boundary junctions (0: none).
struct GridNetwork {
  int x_number = 5;
  int y_number = 5;
  double x_length_m = 100.0;
  double y_length_m = 100.0;
  double attach_length_m = 0.0;
};

// netgenerate --spider: `arm_number` radial streets crossing `circle_number` rings.
struct SpiderNetwork {
  int arm_number = 6;
  int circle_number = 3;
  double space_radius_m = 100.0;
  bool omit_center = false;
};

// netgenerate --rand: random planar network.
struct RandomNetwork {
  int iterations = 50;
  double min_distance_m = 80.0;
  double max_distance_m = 200.0;
  double bidi_probability = 1.0;
};

// Parameters for netgenerate. The network depends on `seed` only, never on the scenario seed,
// so changing the scenario seed changes the traffic but not the roads.
struct GeneratedNetwork {
  enum class Kind { kGrid, kSpider, kRandom };
  Kind kind = Kind::kGrid;
  GridNetwork grid;
  SpiderNetwork spider;
  RandomNetwork random;
  int lanes = 1;
  double lane_width_m = 3.2;
  double speed_mps = 13.89;
  bool traffic_lights = false;  // lights at every junction of 3 or more roads
  int tls_cycle_s = 0;          // traffic-light cycle; 0: netgenerate's default (90 s)
  // Random junction heights (netgenerate --perturb-z normc(0, sigma, -limit, limit)); roads
  // are straight in 3D between junctions. 0: flat.
  double elevation_sigma_m = 0.0;
  double elevation_limit_m = 0.0;
  std::uint64_t seed = 1;
};

// Plain-XML sources built with netconvert (paths resolved against the scenario file). Node and
// shape coordinates are ENU metres (netconvert runs with --offset.disable-normalization); z in
// node attributes or 3D edge shapes gives the elevation.
struct XmlNetwork {
  std::filesystem::path nodes;
  std::filesystem::path edges;
  std::optional<std::filesystem::path> connections;
  std::optional<std::filesystem::path> traffic_lights;
};

struct NetworkSpec {
  std::optional<GeneratedNetwork> generate;  // exactly one of generate / xml is set
  std::optional<XmlNetwork> xml;
  SourceRef source;  // the `network` field
};

struct RouteEdge {
  std::string edge_id;
  SourceRef source;
  bool operator==(const RouteEdge&) const = default;
};

// The ego route: an explicit edge list, or from/to (+ via) routed by duarouter. `loops` repeats
// the route; the last edge must then connect back to the first.
struct EgoSpec {
  std::vector<RouteEdge> route;
  std::optional<RouteEdge> from;
  std::optional<RouteEdge> to;
  std::vector<RouteEdge> via;
  int loops = 1;
  SourceRef loops_source;
  double depart_pos_m = 0.0;
  double depart_speed_mps = 0.0;
  // The ego stands at its departure position this long (engine running: the IMU's vibration
  // model idles) before SUMO's driver model takes over; 0 drives off at once.
  double parked_s = 0.0;
  std::optional<double> max_speed_mps;   // further cap below the vehicle's own maximum
  std::string car_follow_model = "IDM";  // "IDM" or "Krauss"
  SourceRef source;                      // the `ego` field
};

// Poisson arrivals between two edges at `vehs_per_hour` during [begin_s, end_s).
struct FlowSpec {
  RouteEdge from;
  RouteEdge to;
  std::vector<RouteEdge> via;
  double vehs_per_hour = 0.0;
  double begin_s = 0.0;
  double end_s = 0.0;
};

struct TrafficSpec {
  std::vector<FlowSpec> flows;
  int density = 0;  // random trips kept alive so that this many vehicles drive at a time
};

struct SumoSpec {
  double step_s = 0.1;  // (0, 0.1]
};

// One entry of the scenario's `estimators:` list: an estimator of a known type with its options
// file and the scenario's overrides of it (docs/scenarios.md).
struct EstimatorSpec {
  std::string label;                  // unique in the scenario: output folder, table column
  std::string type;                   // one of est::KnownEstimators()
  std::filesystem::path config;       // options file; empty: the type's built-in defaults
  std::optional<YamlNode> overrides;  // a map, deep-merged over `config`
  // The sensors the estimator is given (ids of the setup; empty: all of them). The others are
  // not on its vehicle: it never sees their measurements, and its view of the setup leaves them
  // out (e.g. the paper's setup-2 factor graph: IMU, front GNSS and lidar only).
  std::vector<std::string> inputs;
  SourceRef source;  // the list entry, for messages
};

struct Scenario {
  std::filesystem::path file;
  std::string name;
  std::uint64_t seed = 0;
  double duration_s = 0.0;
  GeodeticPoint origin;
  std::filesystem::path vehicle_file;  // resolved, existing vehicle parameter file
  NetworkSpec network;
  EgoSpec ego;
  TrafficSpec traffic;
  SumoSpec sumo;
  std::optional<YamlNode> sensors;        // unparsed: a file name or an inline map (issue 3)
  std::optional<YamlNode> faults;         // unparsed
  std::optional<MismatchOptions> mismatch;  // simulated vehicle vs. what the estimators are told
  std::vector<EstimatorSpec> estimators;  // empty: none listed (see ScenarioEstimators)
};

// Parses and checks a scenario file; throws InputError "file:line:col: field 'a.b': ...".
Scenario LoadScenario(const std::filesystem::path& path);

// Resolves a vehicle file name the way LoadScenario does: relative to the scenario's folder,
// then `vehicles/` or `scenarios/vehicles/` in any parent folder, then
// $STATEBENCH_SOURCE_DIR/scenarios/vehicles, then ./scenarios/vehicles of the working folder.
// A name without extension gets ".yaml".
// Returns nullopt when not found.
std::optional<std::filesystem::path> FindVehicleFile(const std::filesystem::path& scenario_dir,
                                                     const std::string& name);

// The default options file of an estimator type, <type>.yaml, looked up like vehicle files:
// `estimators/` or `scenarios/estimators/` in the scenario's folder or any parent folder, then
// $STATEBENCH_SOURCE_DIR/scenarios/estimators, then ./scenarios/estimators. nullopt: not found.
std::optional<std::filesystem::path> FindEstimatorConfigFile(
    const std::filesystem::path& scenario_dir, const std::string& type);

// The scenario's `estimators:` list, or when it has none the default: factor_graph and ekf with
// their default options files, labelled by type.
std::vector<EstimatorSpec> ScenarioEstimators(const Scenario& scenario);

// The options an estimator runs with, as YAML text: `config` with `overrides` deep-merged over
// it (core/yaml_merge.hpp), under a comment naming both. Written next to the estimate so a run
// can be repeated; the estimator is built from that written file. Throws InputError when the
// config file cannot be parsed.
std::string EstimatorConfigText(const EstimatorSpec& spec, const Scenario& scenario);

}  // namespace statebench::sim
