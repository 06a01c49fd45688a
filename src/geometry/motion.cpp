#include "geometry/motion.hpp"

#include <Eigen/Geometry>

#include <algorithm>

namespace bakesim {

RigidMotion::RigidMotion(Vec3 pivot, std::vector<RigidKeyframe> keyframes)
    : pivot_(std::move(pivot)), keyframes_(std::move(keyframes)) {}

RigidPose RigidMotion::at(Real time) const {
  RigidPose pose;
  if (keyframes_.empty()) {
    pose.centre = pivot_;
    return pose;
  }
  auto hold = [&](const RigidKeyframe& k) {
    pose.rotation = k.rotation;
    pose.translation = k.translation;
    pose.centre = pivot_ + k.translation;
    return pose;
  };
  if (time <= keyframes_.front().time) return hold(keyframes_.front());
  if (time >= keyframes_.back().time) return hold(keyframes_.back());
  const auto next = std::upper_bound(keyframes_.begin(), keyframes_.end(), time,
                                     [](Real t, const RigidKeyframe& k) { return t < k.time; });
  const RigidKeyframe& a = *(next - 1);
  const RigidKeyframe& b = *next;
  const Real span = b.time - a.time, s = (time - a.time) / span;
  pose.velocity = (b.translation - a.translation) / span;
  pose.translation = a.translation + s * (b.translation - a.translation);
  pose.centre = pivot_ + pose.translation;
  // R(t) = exp(s log(R_b R_aᵀ)) R_a: constant angular velocity in world axes.
  const Eigen::AngleAxis<Real> step(Mat3(b.rotation * a.rotation.transpose()));
  pose.angular_velocity = step.axis() * (step.angle() / span);
  pose.rotation = Eigen::AngleAxis<Real>(s * step.angle(), step.axis()).toRotationMatrix() * a.rotation;
  return pose;
}

}  // namespace bakesim
