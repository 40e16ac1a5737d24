#include "simulator/synthetic_route.hpp"

#include <algorithm>
#include <cmath>

namespace statebench::sim {
namespace {

constexpr double kDt = 0.1;        // SUMO step
constexpr double kGridStep = 0.1;  // arc-length grid of the speed envelope

// 3 % grade to the east, 1.5 % to the north, and a 5 m hill: grades and cross slopes up to
// about 7 % on the route.
double Height(double x, double y, bool hilly) {
  if (!hilly) return 0.0;
  const double dx = x - 150.0;
  const double dy = y - 120.0;
  return 30.0 + 0.03 * x + 0.015 * y + 5.0 * std::exp(-(dx * dx + dy * dy) / (2.0 * 60.0 * 60.0));
}

// Corners of the route: left, left, right, right, right, left turns, 810 m in all.
const std::vector<Vec2>& Corners() {
  static const std::vector<Vec2> corners = {Vec2(0, 0),    Vec2(150, 0),  Vec2(150, 100),
                                            Vec2(60, 100), Vec2(60, 180), Vec2(250, 180),
                                            Vec2(250, 60), Vec2(330, 60)};
  return corners;
}

std::vector<Vec3> Sampled(const std::vector<Vec2>& vertices, double step, bool hilly) {
  std::vector<Vec3> out;
  for (std::size_t i = 0; i + 1 < vertices.size(); ++i) {
    const Vec2 a = vertices[i];
    const Vec2 b = vertices[i + 1];
    const int n = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
    for (int k = (i == 0 ? 0 : 1); k <= n; ++k) {
      const Vec2 p = a + (b - a) * (double(k) / n);
      out.emplace_back(p.x(), p.y(), Height(p.x(), p.y(), hilly));
    }
  }
  return out;
}

// Speed limit along the route including the braking envelope towards every constraint
// (corners, remaining stops, the end of the route): v(s) <= sqrt(v_c^2 + 2 a_dec (s_c - s)).
std::vector<double> Envelope(const SyntheticRouteOptions& o, const std::vector<double>& corners_s,
                             const std::vector<double>& stops_s, double end_s) {
  const int n = static_cast<int>(end_s / kGridStep) + 1;
  std::vector<double> v(n, o.cruise_speed_mps);
  for (int i = 0; i < n; ++i) {
    const double s = i * kGridStep;
    for (double c : corners_s) {
      if (std::abs(s - c) <= o.corner_zone_m) v[i] = std::min(v[i], o.corner_speed_mps);
    }
    for (double stop : stops_s) {
      if (s >= stop) v[i] = 0.0;
    }
  }
  v[n - 1] = 0.0;
  for (int i = n - 2; i >= 0; --i) {
    v[i] = std::min(v[i], std::sqrt(v[i + 1] * v[i + 1] + 2.0 * o.deceleration_mps2 * kGridStep));
  }
  return v;
}

double EnvelopeAt(const std::vector<double>& v, double s) {
  const double t = std::clamp(s / kGridStep, 0.0, static_cast<double>(v.size() - 1));
  const int i = std::min(static_cast<int>(t), static_cast<int>(v.size()) - 2);
  return v[i] + (t - i) * (v[i + 1] - v[i]);
}

}  // namespace

SyntheticRoute MakeSyntheticRoute(const SyntheticRouteOptions& o) {
  SyntheticRoute route;
  const std::vector<Vec2>& corners = Corners();
  route.polyline = Sampled(corners, 10.0, o.hilly);

  // Street grid around the route (every 50 m) plus the route itself: the terrain's data.
  route.network.push_back(route.polyline);
  for (double y = -20.0; y <= 220.0; y += 50.0) {
    route.network.push_back(Sampled({Vec2(-20.0, y), Vec2(350.0, y)}, 10.0, o.hilly));
  }
  for (double x = -20.0; x <= 350.0; x += 50.0) {
    route.network.push_back(Sampled({Vec2(x, -20.0), Vec2(x, 220.0)}, 10.0, o.hilly));
  }

  std::vector<double> corners_s;
  double length = 0.0;
  for (std::size_t i = 1; i < corners.size(); ++i) {
    length += (corners[i] - corners[i - 1]).norm();
    if (i + 1 < corners.size()) corners_s.push_back(length);
  }
  const double end_s = length - 5.0;

  std::vector<double> stops = o.stops_m;
  std::sort(stops.begin(), stops.end());
  std::size_t next_stop = 0;
  std::vector<double> envelope = Envelope(o, corners_s, stops, end_s);
  double s = o.start_s_m;
  double v = 0.0;
  double dwell = 0.0;
  for (int k = 0; k * kDt <= o.duration_s + 1e-9; ++k) {
    ReferenceSample sample{k * kDt, s, v, 0.0};
    if (dwell > 0.0) {
      route.profile.push_back(sample);
      dwell -= kDt;
      if (dwell <= 1e-9 && next_stop < stops.size()) {
        dwell = 0.0;
        ++next_stop;  // drive on: the stop leaves the envelope
        envelope = Envelope(o, corners_s,
                            std::vector<double>(stops.begin() + next_stop, stops.end()), end_s);
      }
      continue;
    }
    double v_next =
        std::max(0.0, std::min(v + o.acceleration_mps2 * kDt, EnvelopeAt(envelope, s + v * kDt)));
    const double stop_s = next_stop < stops.size() ? stops[next_stop] : end_s;
    const bool arriving = stop_s - s < 0.5 && v_next < 0.3;
    if (arriving) v_next = 0.0;
    sample.a_mps2 = (v_next - v) / kDt;
    route.profile.push_back(sample);
    s += 0.5 * (v + v_next) * kDt;
    v = v_next;
    if (arriving) dwell = next_stop < stops.size() ? o.stop_duration_s : 1e9;
  }
  return route;
}

ReferenceSample SampleProfile(const std::vector<ReferenceSample>& profile, double t_s) {
  auto it = std::upper_bound(profile.begin(), profile.end(), t_s,
                             [](double t, const ReferenceSample& r) { return t < r.t_s; });
  const ReferenceSample& r = it == profile.begin() ? profile.front() : *(it - 1);
  const double tau = std::max(0.0, t_s - r.t_s);
  if (it == profile.end()) return {t_s, r.s_m + r.v_mps * tau, r.v_mps, 0.0};
  return {t_s, r.s_m + tau * (r.v_mps + 0.5 * tau * r.a_mps2), r.v_mps + tau * r.a_mps2, r.a_mps2};
}

}  // namespace statebench::sim
