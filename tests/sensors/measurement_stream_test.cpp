#include "sensors/measurement_stream.hpp"

#include <gtest/gtest.h>

#include <memory>
#include <vector>

namespace statebench::sensors {
namespace {

template <typename T>
Measurement Make(const std::string& id, TimeNs stamp_ns, TimeNs arrival_ns) {
  T m;
  m.header = MeasurementHeader{id, stamp_ns, arrival_ns};
  return m;
}

std::vector<Measurement> Drain(MeasurementSource& source) {
  std::vector<Measurement> out;
  while (auto m = source.Next()) out.push_back(std::move(*m));
  return out;
}

TEST(MeasurementStream, MergerOrdersByArrivalThenStampThenSensorId) {
  // IMU: no latency. GNSS: 100 ms latency, so a fix taken at 0 arrives after the IMU sample
  // taken at 50 ms. Steering: 10 ms latency.
  std::vector<Measurement> imu, gnss, steering;
  for (int k = 0; k < 20; ++k) {
    imu.push_back(Make<ImuSample>("imu", k * 10'000'000, k * 10'000'000));
  }
  gnss.push_back(Make<GnssFix>("gnss", 0, 100'000'000));
  gnss.push_back(Make<GnssFix>("gnss", 100'000'000, 200'000'000));
  steering.push_back(Make<SteeringAngle>("steering", 90'000'000, 100'000'000));
  // Same arrival and stamp as the IMU sample at 100 ms: broken by sensor id.
  steering.push_back(Make<SteeringAngle>("a_steering", 100'000'000, 100'000'000));

  std::vector<std::unique_ptr<MeasurementSource>> sources;
  sources.push_back(std::make_unique<VectorSource>(gnss));
  sources.push_back(std::make_unique<VectorSource>(imu));
  sources.push_back(std::make_unique<VectorSource>(steering));
  MeasurementMerger merger(std::move(sources));
  const std::vector<Measurement> out = Drain(merger);
  ASSERT_EQ(out.size(), 24u);
  for (std::size_t i = 1; i < out.size(); ++i) {
    EXPECT_FALSE(ArrivesBefore(out[i], out[i - 1])) << i;
    EXPECT_LE(HeaderOf(out[i - 1]).arrival_ns, HeaderOf(out[i]).arrival_ns);
  }
  // Everything arriving at 100 ms: stamp 0 (gnss), stamp 90 ms (steering), then stamp 100 ms
  // with "a_steering" before "imu".
  std::vector<std::string> at_100ms;
  for (const Measurement& m : out) {
    if (HeaderOf(m).arrival_ns == 100'000'000) at_100ms.push_back(HeaderOf(m).sensor_id);
  }
  EXPECT_EQ(at_100ms, (std::vector<std::string>{"gnss", "steering", "a_steering", "imu"}));
}

TEST(MeasurementStream, TiesAreDeterministicWhateverTheSourceOrder) {
  auto run = [](bool reversed) {
    std::vector<Measurement> a{Make<VehicleSpeed>("speed", 5, 10)};
    std::vector<Measurement> b{Make<SteeringAngle>("speed", 5, 10)};  // same id: variant index
    std::vector<std::unique_ptr<MeasurementSource>> sources;
    sources.push_back(std::make_unique<VectorSource>(reversed ? b : a));
    sources.push_back(std::make_unique<VectorSource>(reversed ? a : b));
    MeasurementMerger merger(std::move(sources));
    std::vector<std::size_t> kinds;
    for (const Measurement& m : Drain(merger)) kinds.push_back(m.index());
    return kinds;
  };
  EXPECT_EQ(run(false), run(true));
  EXPECT_LT(run(false)[0], run(false)[1]);
}

TEST(MeasurementStream, ArrivalQueueKeepsInsertionOrderForEqualKeys) {
  ArrivalQueue q;
  ImuSample a, b;
  a.header = {"imu", 5, 5};
  a.gyro.x() = 1.0;
  b.header = {"imu", 5, 5};
  b.gyro.x() = 2.0;
  q.Push(Make<GnssFix>("gnss", 0, 7));
  q.Push(a);
  q.Push(b);
  q.Push(Make<GnssFix>("gnss", 0, 3));
  EXPECT_EQ(HeaderOf(q.Pop()).arrival_ns, 3);
  EXPECT_EQ(std::get<ImuSample>(q.Pop()).gyro.x(), 1.0);
  EXPECT_EQ(std::get<ImuSample>(q.Pop()).gyro.x(), 2.0);
  EXPECT_EQ(HeaderOf(q.Pop()).arrival_ns, 7);
  EXPECT_TRUE(q.empty());
}

}  // namespace
}  // namespace statebench::sensors
