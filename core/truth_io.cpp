#include "core/truth_io.hpp"

#include "core/csv.hpp"
#include "core/error.hpp"

namespace statebench {
namespace {

constexpr std::size_t kFlushBytes = 1 << 20;

void AppendVec(std::string& out, const Vec3& v) {
  for (int i = 0; i < 3; ++i) {
    out.push_back(',');
    AppendNumber(out, v[i]);
  }
}

void AppendQuat(std::string& out, const Quat& q) {
  for (const double c : {q.w(), q.x(), q.y(), q.z()}) {
    out.push_back(',');
    AppendNumber(out, c);
  }
}

void AppendScalar(std::string& out, double v) {
  out.push_back(',');
  AppendNumber(out, v);
}

std::vector<std::string> MakeColumns() {
  std::vector<std::string> c = {"t_ns"};
  auto add3 = [&c](const std::string& p) {
    for (const char* s : {"_x", "_y", "_z"}) c.push_back(p + s);
  };
  auto add_q = [&c](const std::string& p) {
    for (const char* s : {"_w", "_x", "_y", "_z"}) c.push_back(p + s);
  };
  add3("p_world_body");
  add_q("q_world_body");
  add3("v_world");
  add3("a_world");
  add3("omega_body");
  add3("alpha_body");
  add3("v_body");
  add3("f_body");
  for (const char* s : {"steer_front", "steer_rear", "omega_wheel_fl", "omega_wheel_fr",
                        "omega_wheel_rl", "omega_wheel_rr", "sideslip", "distance"}) {
    c.emplace_back(s);
  }
  add3("p_world_imu");
  add_q("q_world_imu");
  add3("omega_imu");
  add3("f_imu");
  return c;
}

void WriteAll(std::ofstream& f, std::string& buf, const std::filesystem::path& path) {
  f.write(buf.data(), static_cast<std::streamsize>(buf.size()));
  buf.clear();
  if (!f) throw InputError(path.string() + ": write failed");
}

}  // namespace

const std::vector<std::string>& TruthCsvColumns() {
  static const std::vector<std::string> columns = MakeColumns();
  return columns;
}

void AppendTumStamp(std::string& out, TimeNs t_ns) {
  // "[-]sec.nnnnnnnnn" (printf's "%lld.%09lld" without its format parsing).
  const TimeNs sec = t_ns / kNsPerSecond;
  const TimeNs frac = t_ns % kNsPerSecond;
  if (t_ns < 0 && sec == 0) out.push_back('-');
  AppendNumber(out, sec);
  char digits[9];
  TimeNs rest = frac < 0 ? -frac : frac;
  for (int i = 8; i >= 0; --i, rest /= 10) digits[i] = static_cast<char>('0' + rest % 10);
  out.push_back('.');
  out.append(digits, sizeof(digits));
}

void AppendTumLine(std::string& out, TimeNs t_ns, const SE3& T_world_frame) {
  AppendTumStamp(out, t_ns);
  const Vec3& t = T_world_frame.translation();
  const Quat& q = T_world_frame.rotation();
  for (const double v : {t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w()}) {
    out.push_back(' ');
    AppendNumber(out, v);
  }
  out.push_back('\n');
}

TruthWriter::TruthWriter(const std::filesystem::path& dir, const SE3& T_body_imu)
    : dir_(dir), T_body_imu_(T_body_imu) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  csv_.open(dir / "truth.csv", std::ios::binary);
  tum_body_.open(dir / "truth_body.tum", std::ios::binary);
  tum_imu_.open(dir / "truth_imu.tum", std::ios::binary);
  if (!csv_ || !tum_body_ || !tum_imu_) {
    throw InputError(dir.string() + ": cannot create truth files");
  }
  const auto& cols = TruthCsvColumns();
  for (std::size_t i = 0; i < cols.size(); ++i) {
    csv_buf_ += (i == 0 ? "" : ",") + cols[i];
  }
  csv_buf_ += '\n';
  tum_body_buf_ = "# t tx ty tz qx qy qz qw  (T_world_body)\n";
  tum_imu_buf_ = "# t tx ty tz qx qy qz qw  (T_world_imu)\n";
}

TruthWriter::~TruthWriter() {
  if (!closed_) {
    try {
      Close();
    } catch (...) {
      // Destructors must not throw; Close() reports errors to callers that use it.
    }
  }
}

void TruthWriter::Write(const TruthSample& s) {
  const FrameKinematics& b = s.body;
  const FrameKinematics imu = b.AtMount(T_body_imu_);
  std::string& o = csv_buf_;
  AppendNumber(o, s.t_ns);
  AppendVec(o, b.T_world_frame.translation());
  AppendQuat(o, b.T_world_frame.rotation());
  AppendVec(o, b.v_world);
  AppendVec(o, b.a_world);
  AppendVec(o, b.omega_frame);
  AppendVec(o, b.alpha_frame);
  AppendVec(o, b.VelocityInFrame());
  AppendVec(o, b.SpecificForce());
  AppendScalar(o, s.steering_front_rad);
  AppendScalar(o, s.steering_rear_rad);
  for (const double w : s.wheel_omega_radps) AppendScalar(o, w);
  AppendScalar(o, s.sideslip_rad);
  AppendScalar(o, s.distance_m);
  AppendVec(o, imu.T_world_frame.translation());
  AppendQuat(o, imu.T_world_frame.rotation());
  AppendVec(o, imu.omega_frame);
  AppendVec(o, imu.SpecificForce());
  o.push_back('\n');
  AppendTumLine(tum_body_buf_, s.t_ns, b.T_world_frame);
  AppendTumLine(tum_imu_buf_, s.t_ns, imu.T_world_frame);
  if (csv_buf_.size() > kFlushBytes) FlushBuffers();
}

void TruthWriter::FlushBuffers() {
  WriteAll(csv_, csv_buf_, dir_ / "truth.csv");
  WriteAll(tum_body_, tum_body_buf_, dir_ / "truth_body.tum");
  WriteAll(tum_imu_, tum_imu_buf_, dir_ / "truth_imu.tum");
}

void TruthWriter::Close() {
  if (closed_) return;
  closed_ = true;
  FlushBuffers();
  csv_.close();
  tum_body_.close();
  tum_imu_.close();
  if (!csv_ || !tum_body_ || !tum_imu_) throw InputError(dir_.string() + ": closing truth files failed");
}

}  // namespace statebench
