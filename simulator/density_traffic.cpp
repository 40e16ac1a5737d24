#include "simulator/density_traffic.hpp"

#include "core/random.hpp"
#include "simulator/sumo_api.hpp"
#include "simulator/traffic_demand.hpp"

namespace statebench::sim {
namespace {

constexpr int kMinRouteEdges = 3;  // shorter trips vanish within seconds
constexpr int kRouteTries = 20;

}  // namespace

DensityTraffic::DensityTraffic(int target, std::uint64_t seed, const std::set<std::string>& edges,
                               std::set<std::string> avoid_at_start)
    : target_(target),
      rng_(MakeRng(seed, "sumo.density")),
      edges_(edges.begin(), edges.end()),
      avoid_at_start_(std::move(avoid_at_start)) {}

void DensityTraffic::Start() {
  while (static_cast<int>(alive_.size()) < target_ && Add(true)) {
  }
}

void DensityTraffic::AfterStep(const std::vector<std::string>& arrived_ids) {
  for (const std::string& id : arrived_ids) alive_.erase(id);
  while (static_cast<int>(alive_.size()) < target_ && Add(false)) {
  }
}

bool DensityTraffic::Add(bool initial) {
  if (edges_.empty()) return false;
  const TrafficVehicleType& type = PickTrafficType(rng_);
  const auto pick = [&] { return edges_[static_cast<std::size_t>(rng_() % edges_.size())]; };
  std::vector<std::string> route;
  for (int attempt = 0; attempt < kRouteTries; ++attempt) {
    const std::string from = pick();
    const std::string to = pick();
    if (from == to || (initial && avoid_at_start_.count(from) > 0)) continue;
    std::vector<std::string> edges = Sumo().FindRoute(from, to, type.id);
    if (edges.empty()) continue;
    route = std::move(edges);
    if (static_cast<int>(route.size()) >= kMinRouteEdges) break;
  }
  if (route.empty()) return false;  // no connected pair found; the next step tries again
  const std::string id = "density" + std::to_string(next_id_++);
  Sumo().AddRoute(id, route);
  Sumo().AddVehicle(id, id, type.id, "now", "best", "random_free", "max");
  alive_.insert(id);
  return true;
}

}  // namespace statebench::sim
