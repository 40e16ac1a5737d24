#include "simulator/routes_file.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <stdexcept>

#include "simulator/xml_scan.hpp"

namespace statebench::sim {
namespace {

std::string Join(const std::vector<std::string>& ids) {
  std::string out;
  for (const std::string& id : ids) {
    if (!out.empty()) out += ' ';
    out += XmlEscape(id);
  }
  return out;
}

void WriteEgoType(std::ostream& out, const EgoSpec& ego, const EgoVehicleType& type) {
  const double max_speed = std::min(type.max_speed_mps, ego.max_speed_mps.value_or(1e9));
  out << "  <vType id=\"" << kEgoTypeId << "\" vClass=\"passenger\" length=\""
      << FormatNumber(type.length_m) << "\" width=\"" << FormatNumber(type.width_m)
      << "\" height=\"" << FormatNumber(type.height_m) << "\" maxSpeed=\""
      << FormatNumber(max_speed) << "\" accel=\"" << FormatNumber(type.max_accel_mps2)
      << "\" decel=\"" << FormatNumber(type.max_decel_mps2) << "\" emergencyDecel=\""
      << FormatNumber(type.emergency_decel_mps2) << "\" minGap=\"" << FormatNumber(type.min_gap_m)
      << "\" sigma=\"0\" speedFactor=\"1\" speedDev=\"0\" carFollowModel=\"" << ego.car_follow_model
      << "\" lcStrategic=\"-1\" lcCooperative=\"0\" lcSpeedGain=\"0\" lcKeepRight=\"0\"/>\n";
}

void WriteTrafficTypes(std::ostream& out) {
  for (const TrafficVehicleType& t : TrafficVehicleTypes()) {
    out << "  <vType id=\"" << t.id << "\" vClass=\"passenger\" length=\""
        << FormatNumber(t.length_m) << "\" width=\"" << FormatNumber(t.width_m) << "\" height=\""
        << FormatNumber(t.height_m) << "\" maxSpeed=\"" << FormatNumber(t.max_speed_mps)
        << "\" accel=\"" << FormatNumber(t.accel_mps2) << "\" decel=\""
        << FormatNumber(t.decel_mps2) << "\" sigma=\"0.5\"/>\n";
  }
}

}  // namespace

std::string FormatNumber(double value) {
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  return std::string(buffer, result.ptr);
}

void WriteRoutesFile(const std::filesystem::path& file, const EgoSpec& ego,
                     const EgoVehicleType& type, const std::vector<std::string>& ego_edges,
                     const std::vector<Trip>& trips) {
  std::ofstream out(file);
  if (!out) throw std::runtime_error("cannot write " + file.string());
  out << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- written by StateBench -->\n<routes>\n";
  WriteEgoType(out, ego, type);
  WriteTrafficTypes(out);
  out << "  <route id=\"ego_route\" edges=\"" << Join(ego_edges) << "\"/>\n";
  out << "  <vehicle id=\"" << kEgoId << "\" type=\"" << kEgoTypeId
      << "\" route=\"ego_route\" depart=\"0\" departLane=\"best\" departPos=\""
      << FormatNumber(ego.depart_pos_m) << "\" departSpeed=\"" << FormatNumber(ego.depart_speed_mps)
      << "\"/>\n";
  for (const Trip& trip : trips) {
    out << "  <trip id=\"" << XmlEscape(trip.id) << "\" type=\"" << trip.type_id << "\" depart=\""
        << FormatNumber(trip.depart_s) << "\" from=\"" << XmlEscape(trip.from) << "\" to=\""
        << XmlEscape(trip.to) << "\"";
    if (!trip.via.empty()) out << " via=\"" << Join(trip.via) << "\"";
    out << " departLane=\"best\" departPos=\"base\" departSpeed=\"max\"/>\n";
  }
  out << "</routes>\n";
  if (!out) throw std::runtime_error("error writing " + file.string());
}

}  // namespace statebench::sim
