#include "sensors/measurement_record.hpp"

#include <type_traits>

namespace statebench::sensors {
namespace {

template <typename Matrix>
void PutMatrix(BinaryWriter& out, const Matrix& m) {
  out.PutBytes(m.data(), sizeof(typename Matrix::Scalar) * static_cast<std::size_t>(m.size()));
}

template <typename Matrix>
void GetMatrix(BinaryReader& in, Matrix* m) {
  in.GetBytes(m->data(), sizeof(typename Matrix::Scalar) * static_cast<std::size_t>(m->size()));
}

void PutHeader(BinaryWriter& out, const MeasurementHeader& h) {
  out.PutString(h.sensor_id);
  out.Put(h.stamp_ns);
  out.Put(h.arrival_ns);
}

MeasurementHeader GetHeader(BinaryReader& in) {
  MeasurementHeader h;
  h.sensor_id = in.GetString();
  h.stamp_ns = in.Get<TimeNs>();
  h.arrival_ns = in.Get<TimeNs>();
  return h;
}

// The fields of each type after its header, in one place for both directions.
struct Fields {
  BinaryWriter* out = nullptr;
  BinaryReader* in = nullptr;

  template <typename T>
  void Scalar(T* v) {
    if (out) {
      out->Put(*v);
    } else {
      *v = in->Get<T>();
    }
  }
  template <typename Matrix>
  void Matrix_(Matrix* m) {
    if (out) {
      PutMatrix(*out, *m);
    } else {
      GetMatrix(*in, m);
    }
  }

  void Body(ImuSample* m) {
    Matrix_(&m->gyro);
    Matrix_(&m->accel);
  }
  void Body(GnssFix* m) {
    Scalar(&m->latitude_deg);
    Scalar(&m->longitude_deg);
    Scalar(&m->altitude_m);
    Matrix_(&m->covariance_enu);
    Scalar(&m->status);
    bool has_velocity = m->velocity.has_value();
    Scalar(&has_velocity);
    if (!has_velocity) return;
    if (!m->velocity) m->velocity.emplace();
    Matrix_(&m->velocity->v_enu);
    Matrix_(&m->velocity->sigma_enu);
  }
  void Body(DualAntennaHeading* m) {
    Scalar(&m->yaw_rad);
    Scalar(&m->pitch_rad);
    Scalar(&m->yaw_sigma_rad);
    Scalar(&m->pitch_sigma_rad);
  }
  void Body(WheelSpeeds* m) { Scalar(&m->omega_radps); }
  void Body(VehicleSpeed* m) { Scalar(&m->speed_mps); }
  void Body(SteeringAngle* m) { Scalar(&m->angle_rad); }
  void Body(LidarScan* m) {
    if (out) {
      static const std::vector<LidarPoint> kNone;
      out->PutVector(m->points ? *m->points : kNone);
    } else {
      m->points = std::make_shared<const std::vector<LidarPoint>>(in->GetVector<LidarPoint>());
    }
  }
  void Body(BodyVelocity* m) {
    Matrix_(&m->velocity);
    Matrix_(&m->angular_velocity);
    Matrix_(&m->covariance);
  }
};

template <std::size_t I = 0>
Measurement ReadAlternative(std::size_t index, BinaryReader& in) {
  if constexpr (I < std::variant_size_v<Measurement>) {
    if (index != I) return ReadAlternative<I + 1>(index, in);
    std::variant_alternative_t<I, Measurement> m;
    m.header = GetHeader(in);
    Fields fields{nullptr, &in};
    fields.Body(&m);
    return m;
  } else {
    throw InputError("cached measurement stream: unknown measurement type " +
                     std::to_string(index));
  }
}

}  // namespace

void WriteMeasurement(BinaryWriter& out, const Measurement& m) {
  out.Put<std::uint8_t>(static_cast<std::uint8_t>(m.index()));
  std::visit(
      [&out](const auto& x) {
        PutHeader(out, x.header);
        auto copy = x;  // Fields takes pointers for both directions; measurements are small
        Fields fields{&out, nullptr};
        fields.Body(&copy);
      },
      m);
}

Measurement ReadMeasurement(BinaryReader& in) {
  return ReadAlternative(in.Get<std::uint8_t>(), in);
}

}  // namespace statebench::sensors
