#include "reports/estimate_writer.hpp"

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/truth_io.hpp"

namespace statebench::reports {
namespace {

constexpr const char* kBlocks[] = {"rot", "pos", "vel", "bg", "ba"};

std::string Header(bool full) {
  std::string h =
      "t_ns,p_x,p_y,p_z,q_w,q_x,q_y,q_z,v_x,v_y,v_z,bg_x,bg_y,bg_z,ba_x,ba_y,ba_z,"
      "latitude_deg,longitude_deg,altitude_m,status";
  for (const char* b : kBlocks) {
    for (const char* a : {"x", "y", "z"}) h += std::string(",var_") + b + "_" + a;
  }
  if (full) {
    for (int r = 0; r < 15; ++r) {
      for (int c = 0; c < 15; ++c) h += ",cov_" + std::to_string(r) + "_" + std::to_string(c);
    }
  }
  return h + "\n";
}

}  // namespace

EstimateWriter::EstimateWriter(const std::filesystem::path& dir, bool full_covariance)
    : dir_(dir), full_covariance_(full_covariance) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  csv_.open(dir / "estimate.csv", std::ios::binary);
  tum_.open(dir / "estimate.tum", std::ios::binary);
  if (!csv_ || !tum_) throw InputError(dir.string() + ": cannot create estimate files");
  csv_buf_ = Header(full_covariance);
  tum_buf_ = "# t tx ty tz qx qy qz qw  (T_world_imu, estimate)\n";
}

EstimateWriter::~EstimateWriter() {
  if (!closed_) {
    try {
      Close();
    } catch (...) {
      // Close() reports failures to callers that use it; a destructor must not throw.
    }
  }
}

void EstimateWriter::Write(const StateEstimate& e) {
  const NavState& s = e.state;
  std::string& o = csv_buf_;
  AppendNumber(o, s.t_ns);
  auto add = [&o](double v) {
    o.push_back(',');
    AppendNumber(o, v);
  };
  for (int i = 0; i < 3; ++i) add(s.p_world[i]);
  for (const double c : {s.q_world_imu.w(), s.q_world_imu.x(), s.q_world_imu.y(),
                         s.q_world_imu.z()}) {
    add(c);
  }
  for (int i = 0; i < 3; ++i) add(s.v_world[i]);
  for (int i = 0; i < 3; ++i) add(s.gyro_bias[i]);
  for (int i = 0; i < 3; ++i) add(s.accel_bias[i]);
  add(e.latitude_deg);
  add(e.longitude_deg);
  add(e.altitude_m);
  o.push_back(',');
  o += EstimateStatusName(e.status);
  for (int i = 0; i < 15; ++i) add(e.covariance(i, i));
  if (full_covariance_) {
    for (int r = 0; r < 15; ++r) {
      for (int c = 0; c < 15; ++c) add(e.covariance(r, c));
    }
  }
  o.push_back('\n');
  AppendTumLine(tum_buf_, s.t_ns, SE3(s.q_world_imu, s.p_world));
  if (csv_buf_.size() > (1u << 20)) Flush();
}

void EstimateWriter::Flush() {
  csv_.write(csv_buf_.data(), static_cast<std::streamsize>(csv_buf_.size()));
  tum_.write(tum_buf_.data(), static_cast<std::streamsize>(tum_buf_.size()));
  csv_buf_.clear();
  tum_buf_.clear();
  if (!csv_ || !tum_) throw InputError(dir_.string() + ": writing the estimate failed");
}

void EstimateWriter::Close() {
  if (closed_) return;
  closed_ = true;
  Flush();
  csv_.close();
  tum_.close();
}

}  // namespace statebench::reports
