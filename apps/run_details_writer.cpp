#include "apps/run_details_writer.hpp"

#include <cmath>

#include "core/csv.hpp"
#include "core/error.hpp"
#include "core/so3.hpp"

namespace statebench::app {

namespace fs = std::filesystem;

// A CSV file written through a buffer of about 1 MB.
class RunDetailsWriter::File {
 public:
  File(const fs::path& path, const char* header) : path_(path), out_(path, std::ios::binary) {
    if (!out_) throw InputError(path.string() + ": cannot create");
    buffer_ = header;
    buffer_ += '\n';
  }
  std::string& row() { return buffer_; }
  void EndRow() {
    buffer_ += '\n';
    if (buffer_.size() > (1u << 20)) Flush();
  }
  void Flush() {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
    if (!out_) throw InputError(path_.string() + ": writing failed");
  }

 private:
  fs::path path_;
  std::ofstream out_;
  std::string buffer_;
};

namespace {

void Add(std::string& o, double v) {
  o += ',';
  AppendNumber(o, v);
}

}  // namespace

RunDetailsWriter::RunDetailsWriter(const fs::path& run_dir,
                                   const std::vector<fs::path>& estimator_dirs, std::string imu_id,
                                   std::optional<LocalEnuFrame> frame)
    : imu_id_(std::move(imu_id)), frame_(std::move(frame)) {
  reference_ = std::make_unique<File>(run_dir / "reference.csv", "t_ns,x,y,z,yaw,v");
  if (frame_) {
    fixes_ = std::make_unique<File>(run_dir / "gnss_fixes.csv",
                                    "t_ns,sensor,x,y,z,sigma_x,sigma_y,sigma_z");
  }
  for (const fs::path& dir : estimator_dirs) {
    errors_.push_back(std::make_unique<File>(
        dir / "errors.csv",
        "t_ns,status,e_x,e_y,e_z,e_along,e_across,e_yaw,e_v_long,sigma_x,sigma_y,sigma_z,"
        "sigma_along,sigma_across,sigma_yaw,sigma_v_long,nees_pose,nees_position,e_roll,e_pitch,"
        "sigma_roll,sigma_pitch"));
    verdicts_.push_back(std::make_unique<File>(dir / "measurements.csv", "t_ns,sensor,verdict"));
  }
}

RunDetailsWriter::~RunDetailsWriter() = default;

void RunDetailsWriter::Measurement(const statebench::Measurement& m) {
  const auto* fix = std::get_if<GnssFix>(&m);
  if (fix == nullptr || !fixes_) return;
  const Vec3 p = frame_->ToEnu({fix->latitude_deg, fix->longitude_deg, fix->altitude_m});
  if (!p.allFinite()) return;  // a broken fix (the estimators reject it too)
  std::string& o = fixes_->row();
  AppendNumber(o, fix->header.stamp_ns);
  o += ',';
  o += fix->header.sensor_id;
  for (int i = 0; i < 3; ++i) Add(o, p[i]);
  for (int i = 0; i < 3; ++i) Add(o, std::sqrt(std::max(0.0, fix->covariance_enu(i, i))));
  fixes_->EndRow();
}

void RunDetailsWriter::Verdict(std::size_t estimator, const std::string& sensor_id,
                               TimeNs stamp_ns, std::optional<est::RejectReason> rejected) {
  if (!rejected && sensor_id == imu_id_) return;  // 100 Hz of "accepted" says nothing
  std::string& o = verdicts_[estimator]->row();
  AppendNumber(o, stamp_ns);
  o += ',';
  o += sensor_id;
  o += ',';
  o += rejected ? est::RejectReasonName(*rejected) : "accepted";
  verdicts_[estimator]->EndRow();
}

void RunDetailsWriter::Epoch(const reports::ReferenceState& r,
                             const std::vector<std::optional<reports::EpochErrors>>& errors) {
  std::string& o = reference_->row();
  AppendNumber(o, r.t_ns);
  const Vec3 p = r.T_world_frame.translation();
  for (int i = 0; i < 3; ++i) Add(o, p[i]);
  Add(o, so3::ToRollPitchYaw(r.T_world_frame.rotation()).z());
  Add(o, r.v_world.norm());
  reference_->EndRow();
  for (std::size_t k = 0; k < errors.size() && k < errors_.size(); ++k) {
    if (!errors[k]) continue;
    const reports::EpochErrors& e = *errors[k];
    std::string& row = errors_[k]->row();
    AppendNumber(row, e.t_ns);
    row += ',';
    row += EstimateStatusName(e.status);
    for (const double v : {e.errors.dp_world.x(), e.errors.dp_world.y(), e.errors.dp_world.z(),
                           e.along_m, e.across_m, e.errors.drpy.z(), e.errors.dv_own_frame.x(),
                           e.sigma_world.x(), e.sigma_world.y(), e.sigma_world.z(),
                           e.sigma_along_m, e.sigma_across_m, e.sigma_yaw_rad,
                           e.sigma_v_longitudinal_mps}) {
      Add(row, v);
    }
    for (const auto& nees : {e.nees_pose, e.nees_position}) {
      row += ',';
      if (nees) AppendNumber(row, *nees);
    }
    for (const double v : {e.errors.drpy.x(), e.errors.drpy.y(), e.sigma_roll_rad,
                           e.sigma_pitch_rad}) {
      Add(row, v);
    }
    errors_[k]->EndRow();
  }
}

void RunDetailsWriter::Close() {
  reference_->Flush();
  if (fixes_) fixes_->Flush();
  for (auto& f : errors_) f->Flush();
  for (auto& f : verdicts_) f->Flush();
}

}  // namespace statebench::app
