#include "sensors/lidar_sweep_codec.hpp"

#include <cfloat>

#include "sensors/lidar_sweep_predictor.hpp"

// The predictions must round identically in every build: double evaluated as double.
static_assert(FLT_EVAL_METHOD == 0, "the sweep codec needs float and double evaluated as such");

namespace statebench::sensors {
namespace {

using sweep_codec::Bits;
using sweep_codec::FromBits;
using sweep_codec::SweepPredictor;

std::uint32_t ZigZag(std::uint32_t d) { return (d << 1) ^ (0u - (d >> 31)); }
std::uint32_t UnZigZag(std::uint32_t z) { return (z >> 1) ^ (0u - (z & 1u)); }

// Writes value k of n as its byte planes (lowest byte first).
template <int kBytes>
void PutPlanes(std::uint8_t* planes, std::size_t n, std::size_t k, std::uint32_t value) {
  for (int b = 0; b < kBytes; ++b) planes[b * n + k] = static_cast<std::uint8_t>(value >> (8 * b));
}

template <int kBytes>
std::uint32_t GetPlanes(const std::uint8_t* planes, std::size_t n, std::size_t k) {
  std::uint32_t value = 0;
  for (int b = 0; b < kBytes; ++b) value |= std::uint32_t{planes[b * n + k]} << (8 * b);
  return value;
}

std::uint32_t Difference(std::uint32_t value, std::uint32_t prediction) {
  return ZigZag(value - prediction);
}

std::uint16_t RingDifference(std::uint16_t value, std::uint16_t prediction) {
  const auto d = static_cast<std::uint16_t>(value - prediction);
  return static_cast<std::uint16_t>((d << 1) ^ (0u - (d >> 15)));
}

std::uint16_t RingFromDifference(std::uint16_t prediction, std::uint32_t z) {
  return static_cast<std::uint16_t>(prediction + ((z >> 1) ^ (0u - (z & 1u))));
}

}  // namespace

std::string_view SweepFieldName(SweepField field) {
  switch (field) {
    case SweepField::kT:
      return "t";
    case SweepField::kRing:
      return "ring";
    case SweepField::kX:
      return "x";
    case SweepField::kY:
      return "y";
    case SweepField::kZ:
      return "z";
    case SweepField::kIntensity:
      return "intensity";
  }
  return "?";
}

std::size_t SweepFieldBytes(SweepField field, std::size_t points) {
  return (field == SweepField::kRing ? 2 : 4) * points;
}

void EncodeSweep(const std::vector<LidarPoint>& points, SweepPlanes& planes) {
  const std::size_t n = points.size();
  for (std::size_t f = 0; f < kSweepFieldCount; ++f) {
    planes[f].resize(SweepFieldBytes(static_cast<SweepField>(f), n));
  }
  auto plane = [&](SweepField f) { return planes[static_cast<std::size_t>(f)].data(); };
  std::uint8_t *t = plane(SweepField::kT), *ring = plane(SweepField::kRing),
               *x = plane(SweepField::kX), *y = plane(SweepField::kY), *z = plane(SweepField::kZ),
               *intensity = plane(SweepField::kIntensity);
  SweepPredictor predict;
  for (std::size_t k = 0; k < n; ++k) {
    const LidarPoint& p = points[k];
    const std::uint32_t x_bits = Bits(p.x), y_bits = Bits(p.y), z_bits = Bits(p.z),
                        i_bits = Bits(p.intensity), t_bits = Bits(p.t);
    PutPlanes<2>(ring, n, k, RingDifference(p.ring, predict.Ring()));
    PutPlanes<4>(t, n, k, Difference(t_bits, predict.T()));
    predict.Begin(p.ring, t_bits);
    PutPlanes<4>(x, n, k, Difference(x_bits, predict.X()));
    PutPlanes<4>(y, n, k, Difference(y_bits, predict.Y(x_bits)));
    predict.XY(x_bits, y_bits);
    PutPlanes<4>(z, n, k, Difference(z_bits, predict.Z()));
    PutPlanes<4>(intensity, n, k, Difference(i_bits, predict.Intensity()));
    predict.End(x_bits, y_bits, z_bits, i_bits);
  }
}

void DecodeSweep(const SweepPlanes& planes, std::size_t n, std::vector<LidarPoint>& points) {
  // The differences first, in loops the compiler vectorises, then the predictions point by point.
  thread_local std::array<std::vector<std::uint32_t>, kSweepFieldCount> differences;
  for (std::size_t f = 0; f < kSweepFieldCount; ++f) {
    std::vector<std::uint32_t>& d = differences[f];
    d.resize(n);
    const std::uint8_t* p = planes[f].data();
    if (static_cast<SweepField>(f) == SweepField::kRing) {
      for (std::size_t k = 0; k < n; ++k) d[k] = GetPlanes<2>(p, n, k);
    } else {
      for (std::size_t k = 0; k < n; ++k) d[k] = UnZigZag(GetPlanes<4>(p, n, k));
    }
  }
  auto field = [&](SweepField f) { return differences[static_cast<std::size_t>(f)].data(); };
  const std::uint32_t *t = field(SweepField::kT), *ring = field(SweepField::kRing),
                      *x = field(SweepField::kX), *y = field(SweepField::kY),
                      *z = field(SweepField::kZ), *intensity = field(SweepField::kIntensity);
  points.resize(n);
  SweepPredictor predict;
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint16_t r = RingFromDifference(predict.Ring(), ring[k]);
    const std::uint32_t t_bits = predict.T() + t[k];
    predict.Begin(r, t_bits);
    const std::uint32_t x_bits = predict.X() + x[k];
    const std::uint32_t y_bits = predict.Y(x_bits) + y[k];
    predict.XY(x_bits, y_bits);
    const std::uint32_t z_bits = predict.Z() + z[k];
    const std::uint32_t i_bits = predict.Intensity() + intensity[k];
    predict.End(x_bits, y_bits, z_bits, i_bits);
    points[k] = LidarPoint{FromBits(x_bits), FromBits(y_bits), FromBits(z_bits),
                           FromBits(i_bits), FromBits(t_bits), r};
  }
}

}  // namespace statebench::sensors
