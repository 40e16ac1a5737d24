#include "reports/estimate_writer.hpp"

#include <cstring>

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
  // Where the text of p_x p_y p_z q_w q_x q_y q_z starts in o; the TUM line reuses it.
  std::array<std::size_t, 8> pose_text;
  std::size_t n = 0;
  for (int i = 0; i < 3; ++i) {
    pose_text[n++] = o.size() + 1;
    add(s.p_world[i]);
  }
  for (const double c : {s.q_world_imu.w(), s.q_world_imu.x(), s.q_world_imu.y(),
                         s.q_world_imu.z()}) {
    pose_text[n++] = o.size() + 1;
    add(c);
  }
  pose_text[n] = o.size() + 1;
  for (int i = 0; i < 3; ++i) add(s.v_world[i]);
  AppendBiases(s);
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
  AppendTum(s, pose_text);
  if (csv_buf_.size() > (1u << 20)) Flush();
}

// The biases change only where the smoother updates (at 10 Hz between 100 Hz rows): a row whose
// biases are the previous row's, bit for bit, copies that row's text.
void EstimateWriter::AppendBiases(const NavState& s) {
  const std::array<double, 6> bias{s.gyro_bias[0],  s.gyro_bias[1],  s.gyro_bias[2],
                                   s.accel_bias[0], s.accel_bias[1], s.accel_bias[2]};
  if (bias_text_.empty() || std::memcmp(bias.data(), bias_.data(), sizeof(bias)) != 0) {
    bias_ = bias;
    bias_text_.clear();
    for (const double b : bias) {
      bias_text_.push_back(',');
      AppendNumber(bias_text_, b);
    }
  }
  csv_buf_ += bias_text_;
}

// The TUM line writes the pose as SE3 keeps it; where those are the CSV's doubles bit for bit
// (SE3 normalises only a quaternion that is not unit), their text is copied, not made again.
void EstimateWriter::AppendTum(const NavState& s, const std::array<std::size_t, 8>& pose_text) {
  const SE3 T(s.q_world_imu, s.p_world);
  const Quat& q = T.rotation();
  if (std::memcmp(q.coeffs().data(), s.q_world_imu.coeffs().data(), 4 * sizeof(double)) != 0) {
    AppendTumLine(tum_buf_, s.t_ns, T);
    return;
  }
  AppendTumStamp(tum_buf_, s.t_ns);
  // TUM's order: p_x p_y p_z q_x q_y q_z q_w (CSV columns 0-2, 4-6, 3).
  for (const int c : {0, 1, 2, 4, 5, 6, 3}) {
    tum_buf_.push_back(' ');
    tum_buf_.append(csv_buf_, pose_text[c], pose_text[c + 1] - 1 - pose_text[c]);
  }
  tum_buf_.push_back('\n');
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
