// Simulated IMU: the angular velocity the engine gives the body, and the
// change of its linear velocity over the last tick minus gravity, both turned
// into the robot's frame; then noise on each axis.
#include "core/device.h"
#include "core/simulation.h"
#include "sensors/imu/imu.h"

namespace colony {
namespace {

constexpr double kGravity = 9.81;

struct ImuInstance : Imu, InstanceBase {
  using Interface = Imu;
  Vec3 last_velocity = Vec3::Zero();  // world frame, at the previous reading
  void Set(const Vec3& gyro, const Vec3& accel) {
    for (int k = 0; k < 3; ++k) {
      gyro_[k] = gyro[k];
      accel_[k] = accel[k];
    }
  }
};

class ImuSystem : public SensorSystem {
 public:
  void Configure(const ConfigNode& node) override {
    gyro_noise_ = node.GetDouble("gyro_noise_std_dev", 0, Range::NonNegative());
    accel_noise_ = node.GetDouble("accel_noise_std_dev", 0, Range::NonNegative());
  }
  Sensor* Attach(EntityHandle robot, const RandomStream& rng) override {
    ImuInstance& imu = instances_.Add(robot, rng);
    imu.last_velocity = sim().space().twist(robot.index).linear;
    return &imu;
  }
  void Detach(Sensor* s) override { instances_.Remove(static_cast<Imu*>(s)); }
  size_t size() const override { return instances_.size(); }

  void Update(size_t begin, size_t end) override {
    const Space& space = sim().space();
    const double dt = sim().dt();
    for (size_t k = begin; k < end; ++k) {
      ImuInstance& imu = instances_[k];
      if (!imu.alive) continue;
      const Pose& pose = space.pose(imu.robot.index);
      const Twist& twist = space.twist(imu.robot.index);
      const Quat to_body = pose.orientation.conjugate();
      Vec3 gyro = to_body * twist.angular;
      Vec3 accel = to_body * ((twist.linear - imu.last_velocity) / dt + Vec3(0, 0, kGravity));
      imu.last_velocity = twist.linear;
      for (int a = 0; a < 3; ++a) {
        if (gyro_noise_ > 0) gyro[a] += imu.rng.Gaussian(0, gyro_noise_);
        if (accel_noise_ > 0) accel[a] += imu.rng.Gaussian(0, accel_noise_);
      }
      imu.Set(gyro, accel);
    }
  }

  void Hash(StateHasher& h) const override {
    for (size_t k = 0; k < instances_.size(); ++k) {
      const auto& imu = instances_[k];
      if (!imu.alive) continue;
      h.Add(imu.angular_velocity().data(), sizeof(double) * 3);
      h.Add(imu.acceleration().data(), sizeof(double) * 3);
    }
  }

 private:
  double gyro_noise_ = 0, accel_noise_ = 0;
  InstanceStore<ImuInstance> instances_;
};

COLONY_REGISTER_SENSOR(
    ImuSystem, "imu", "default",
    "gyroscope (rad/s) and accelerometer (m/s^2, gravity included) in the robot's frame",
    DeviceInterface{
        "sensors/imu/imu.h",
        "colony::Imu",
        {"angular_velocity(): about x, y, z of the robot's frame (rad/s; turning left is +z)",
         "acceleration(): proper acceleration along x, y, z (m/s^2; at rest +9.81 on z)"}},
    (std::vector<AttributeDoc>{
        {"gyro_noise_std_dev", "a number >= 0 (rad/s)", "0",
         "gaussian noise on each gyroscope axis"},
        {"accel_noise_std_dev", "a number >= 0 (m/s^2)", "0",
         "gaussian noise on each accelerometer axis"},
    }),
    {"footbot_imu"});

}  // namespace
}  // namespace colony
