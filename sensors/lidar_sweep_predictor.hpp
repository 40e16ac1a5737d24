// The predictions of lidar_sweep_codec.hpp, shared by its encoder and decoder so that both make
// them from the same state in the same order. Private to the codec.
//
// Floating-point guard: a formula is used only when every float operand and every double result
// along the way is a normal number (not zero, subnormal, infinite or NaN) and the final value fits
// a normal float. Such operations round the same way on every IEEE-754 machine, also on one that
// flushes subnormals to zero, where a subnormal would become 0 on one side only.
#pragma once

#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

namespace statebench::sensors::sweep_codec {

inline std::uint32_t Bits(float f) {
  std::uint32_t u;
  std::memcpy(&u, &f, sizeof(u));
  return u;
}

inline float FromBits(std::uint32_t u) {
  float f;
  std::memcpy(&f, &u, sizeof(f));
  return f;
}

// Double arithmetic that remembers whether every value it produced was normal.
class Checked {
 public:
  double Use(double v) {
    ok_ = ok_ && std::isnormal(v);
    return v;
  }
  // The float of these bits as a double (the float must be normal).
  double Float(std::uint32_t bits) {
    ok_ = ok_ && ((bits >> 23) & 0xFFu) - 1u < 0xFEu;
    return static_cast<double>(FromBits(bits));
  }
  bool ok() const { return ok_; }

 private:
  bool ok_ = true;
};

// The bits of v as a float when `checked` saw only normal numbers and v is a normal float.
inline bool ToFloatBits(const Checked& checked, double v, std::uint32_t* bits) {
  const double a = std::fabs(v);
  if (!checked.ok() || !(a >= FLT_MIN && a <= FLT_MAX)) return false;
  *bits = Bits(static_cast<float>(v));
  return true;
}

class SweepPredictor {
 public:
  std::uint16_t Ring() const { return static_cast<std::uint16_t>(previous_ring_ + 1); }
  std::uint32_t T() const { return previous_t_; }

  // A point of this ring and t starts: selects the ring's memory, and at a column's first point
  // (first point or t changed) predicts the column's azimuth.
  void Begin(std::uint16_t ring, std::uint32_t t_bits) {
    if (ring >= rings_.size()) rings_.resize(std::size_t{ring} + 1);
    r_ = &rings_[ring];
    previous_ring_ = ring;
    head_ = first_ || t_bits != previous_t_;
    first_ = false;
    previous_t_ = t_bits;
    if (head_) {
      older_ = last_;
      last_ = column_;
      column_ = Extrapolate(older_, last_);
    }
  }

  std::uint32_t X() const {
    std::uint32_t bits = r_->x;
    if (r_->h_ok && column_.ok) {
      Checked k;
      ToFloatBits(k, k.Use(r_->h * column_.c), &bits);
    }
    return bits;
  }

  std::uint32_t Y(std::uint32_t x_bits) const {
    std::uint32_t bits = r_->y;
    if (column_.ok) {
      Checked k;
      ToFloatBits(k, k.Use(k.Float(x_bits) * column_.q), &bits);
    }
    return bits;
  }

  // x and y of the point are known: its horizontal distance h (at a column's first point
  // sqrt(x^2 + y^2), which gives the column's azimuth; then |x| / |c|, or |y| / |s| when
  // |s| > |c|), without a square root or division per point.
  [[gnu::always_inline]] void XY(std::uint32_t x_bits, std::uint32_t y_bits) {
    Checked k;
    if (head_) {
      const double x = k.Float(x_bits), y = k.Float(y_bits);
      h_ = k.Use(std::sqrt(k.Use(k.Use(x * x) + k.Use(y * y))));
      h_ok_ = k.ok();
      if (h_ok_) {
        const Direction measured = MakeDirection(x / h_, y / h_);
        if (measured.ok) column_ = measured;
      }
      return;
    }
    h_ok_ = false;
    if (!column_.ok) return;
    const double along = k.Float(column_.by_x ? x_bits : y_bits);
    h_ = k.Use(std::fabs(along) * column_.inverse);
    h_ok_ = k.ok();
  }

  std::uint32_t Z() const {
    std::uint32_t bits = r_->z;
    if (h_ok_ && r_->e_ok) {
      Checked k;
      ToFloatBits(k, k.Use(h_ * r_->e), &bits);
    }
    return bits;
  }

  // Linear extrapolation of the ring's last two: intensity has no noise and varies smoothly
  // along a surface.
  std::uint32_t Intensity() const {
    std::uint32_t bits = r_->intensity;
    if (r_->count >= 2) {
      Checked k;
      const double last = k.Float(r_->intensity), older = k.Float(r_->intensity_older);
      ToFloatBits(k, k.Use(k.Use(2.0 * last) - older), &bits);
    }
    return bits;
  }

  void End(std::uint32_t x_bits, std::uint32_t y_bits, std::uint32_t z_bits,
           std::uint32_t intensity_bits) {
    RingMemory& r = *r_;
    r.x = x_bits;
    r.y = y_bits;
    r.z = z_bits;
    r.intensity_older = r.intensity;
    r.intensity = intensity_bits;
    if (r.count < 2) ++r.count;
    r.h = h_;
    r.h_ok = h_ok_;
    if (h_ok_ && !r.e_ok) {  // a ring keeps its elevation: e from its first usable point
      Checked k;
      r.e = k.Use(k.Float(z_bits) / h_);
      r.e_ok = k.ok();
    }
  }

 private:
  struct RingMemory {
    std::uint32_t x = 0, y = 0, z = 0, intensity = 0, intensity_older = 0;
    std::uint32_t count = 0;  // points of the ring so far (saturates at 2)
    double h = 0.0, e = 0.0;
    bool h_ok = false, e_ok = false;
  };
  // A column's unit azimuth (c, s), q = s / c, and how a point's horizontal distance follows
  // from x (by_x, |c| >= |s|: h = |x| / |c|) or y (h = |y| / |s|): inverse = 1 / |c| or 1 / |s|.
  struct Direction {
    double c = 0.0, s = 0.0, q = 0.0, inverse = 0.0;
    bool by_x = true, ok = false;
  };

  static Direction MakeDirection(double c, double s) {
    Checked k;
    Direction d{k.Use(c), k.Use(s)};
    d.q = k.Use(d.s / d.c);
    d.by_x = std::fabs(d.c) >= std::fabs(d.s);
    d.inverse = k.Use(1.0 / std::fabs(d.by_x ? d.c : d.s));
    d.ok = k.ok();
    return d;
  }

  // b turned by the angle from a to b (a column's step), or b alone without a.
  static Direction Extrapolate(const Direction& a, const Direction& b) {
    if (!b.ok || !a.ok) return b;
    Checked k;
    const double cr = k.Use(k.Use(b.c * a.c) + k.Use(b.s * a.s));
    const double sr = k.Use(k.Use(b.s * a.c) - k.Use(b.c * a.s));
    const double c = k.Use(k.Use(b.c * cr) - k.Use(b.s * sr));
    const double s = k.Use(k.Use(b.s * cr) + k.Use(b.c * sr));
    if (!k.ok()) return b;
    const Direction d = MakeDirection(c, s);
    return d.ok ? d : b;
  }

  std::vector<RingMemory> rings_;
  RingMemory* r_ = nullptr;
  std::uint16_t previous_ring_ = 0xFFFF;
  std::uint32_t previous_t_ = 0;
  bool first_ = true, head_ = false;
  Direction older_, last_, column_;
  double h_ = 0.0;
  bool h_ok_ = false;
};

}  // namespace statebench::sensors::sweep_codec
