#include "estimator/lidar_registration_record.hpp"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <type_traits>

#include "core/error.hpp"

namespace statebench::est {
namespace {

constexpr char kMagic[] = "statebench lidar registrations v1\n";

class Writer {
 public:
  template <typename T>
  void Put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    const char* p = reinterpret_cast<const char*>(&v);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  void Put(const std::string& s) {
    Put<std::uint64_t>(s.size());
    bytes_.insert(bytes_.end(), s.begin(), s.end());
  }
  void Put(const SE3& T) {
    for (int k = 0; k < 4; ++k) Put(T.rotation().coeffs()[k]);
    for (int k = 0; k < 3; ++k) Put(T.translation()[k]);
  }
  template <int R, int C>
  void Put(const Eigen::Matrix<double, R, C>& m) {
    for (Eigen::Index k = 0; k < m.size(); ++k) Put(m.data()[k]);
  }
  const std::vector<char>& bytes() const { return bytes_; }

 private:
  std::vector<char> bytes_;
};

class Reader {
 public:
  Reader(const std::vector<char>& bytes, const std::filesystem::path& file)
      : bytes_(bytes), file_(file) {}
  template <typename T>
  T Get() {
    static_assert(std::is_trivially_copyable_v<T>);
    Need(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + at_, sizeof(T));
    at_ += sizeof(T);
    return v;
  }
  std::string GetString() {
    const auto n = Get<std::uint64_t>();
    Need(n);
    std::string s(bytes_.data() + at_, n);
    at_ += n;
    return s;
  }
  SE3 GetSE3() {
    Eigen::Vector4d q;
    for (int k = 0; k < 4; ++k) q[k] = Get<double>();
    Vec3 t;
    for (int k = 0; k < 3; ++k) t[k] = Get<double>();
    return SE3(Quat(q[3], q[0], q[1], q[2]), t);
  }
  template <int R, int C>
  void GetMatrix(Eigen::Matrix<double, R, C>* m) {
    for (Eigen::Index k = 0; k < m->size(); ++k) m->data()[k] = Get<double>();
  }
  bool AtEnd() const { return at_ == bytes_.size(); }
  void Need(std::uint64_t n) const {
    if (n > bytes_.size() - at_) {
      throw InputError(file_.string() + ": truncated lidar registration record at byte " +
                       std::to_string(at_));
    }
  }

 private:
  const std::vector<char>& bytes_;
  const std::filesystem::path& file_;
  std::size_t at_ = 0;
};

}  // namespace

void WriteRegistrations(const std::filesystem::path& file,
                        const std::vector<RecordedRegistration>& registrations) {
  Writer w;
  for (const char* c = kMagic; *c != '\0'; ++c) w.Put(*c);
  w.Put<std::uint64_t>(registrations.size());
  for (const RecordedRegistration& e : registrations) {
    const LidarOdometryResult& r = e.result;
    const LidarOdometryDiagnostics& d = r.diagnostics;
    w.Put<std::int64_t>(e.stamp_ns);
    w.Put<std::uint64_t>(e.points);
    w.Put<std::uint8_t>(r.accepted);
    w.Put(r.reject_reason);
    w.Put<std::uint8_t>(r.first_scan);
    w.Put<std::int64_t>(r.stamp_ns);
    w.Put<std::int64_t>(r.prev_stamp_ns);
    w.Put(r.T_prev_curr);
    w.Put(r.covariance);
    w.Put(r.T_world_lidar);
    for (const std::size_t n : {d.points_in, d.non_finite, d.out_of_range, d.points_kept,
                                d.points_registered, d.correspondences}) {
      w.Put<std::uint64_t>(n);
    }
    w.Put<std::int32_t>(d.iterations);
    w.Put<std::uint8_t>(d.degenerate);
    w.Put<std::int32_t>(d.degenerate_directions);
    w.Put(d.information_eigenvalues);
    w.Put(d.weakest_direction);
    w.Put(d.threshold_m);
    w.Put(d.residual_sigma_m);
  }
  std::ofstream out(file, std::ios::binary);
  out.write(w.bytes().data(), static_cast<std::streamsize>(w.bytes().size()));
  if (!out.flush()) throw InputError(file.string() + ": cannot write lidar registrations");
}

std::vector<RecordedRegistration> ReadRegistrations(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open lidar registrations");
  const std::vector<char> bytes{std::istreambuf_iterator<char>(in),
                                std::istreambuf_iterator<char>()};
  Reader r(bytes, file);
  for (const char* c = kMagic; *c != '\0'; ++c) {
    if (r.Get<char>() != *c) throw InputError(file.string() + ": not a lidar registration record");
  }
  const auto count = r.Get<std::uint64_t>();
  std::vector<RecordedRegistration> out;
  for (std::uint64_t k = 0; k < count; ++k) {
    RecordedRegistration e;
    LidarOdometryResult& res = e.result;
    LidarOdometryDiagnostics& d = res.diagnostics;
    e.stamp_ns = r.Get<std::int64_t>();
    e.points = r.Get<std::uint64_t>();
    res.accepted = r.Get<std::uint8_t>() != 0;
    res.reject_reason = r.GetString();
    res.first_scan = r.Get<std::uint8_t>() != 0;
    res.stamp_ns = r.Get<std::int64_t>();
    res.prev_stamp_ns = r.Get<std::int64_t>();
    res.T_prev_curr = r.GetSE3();
    r.GetMatrix(&res.covariance);
    res.T_world_lidar = r.GetSE3();
    for (std::size_t* n : {&d.points_in, &d.non_finite, &d.out_of_range, &d.points_kept,
                           &d.points_registered, &d.correspondences}) {
      *n = r.Get<std::uint64_t>();
    }
    d.iterations = r.Get<std::int32_t>();
    d.degenerate = r.Get<std::uint8_t>() != 0;
    d.degenerate_directions = r.Get<std::int32_t>();
    r.GetMatrix(&d.information_eigenvalues);
    r.GetMatrix(&d.weakest_direction);
    d.threshold_m = r.Get<double>();
    d.residual_sigma_m = r.Get<double>();
    out.push_back(std::move(e));
  }
  if (!r.AtEnd()) throw InputError(file.string() + ": trailing bytes after the lidar registrations");
  return out;
}

}  // namespace statebench::est
