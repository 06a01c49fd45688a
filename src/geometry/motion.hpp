#pragma once
// Rigid scripted motion of a collider: keyframes of translation and rotation
// about a pivot, linear in translation and at constant angular velocity
// (quaternion slerp) in rotation between keyframes; held before the first and
// after the last keyframe.
#include <Eigen/Geometry>
#include <vector>

#include "core/types.hpp"

namespace bakesim {

struct RigidKeyframe {
  Real time = 0;                     // s
  Vec3 translation = Vec3::Zero();   // m
  Mat3 rotation = Mat3::Identity();  // about the pivot
};

// Where the collider is at one time: x_world = R (x_rest − pivot) + pivot + T,
// and how fast it moves: v(x) = velocity + angular_velocity × (x − centre).
struct RigidPose {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
  Vec3 centre = Vec3::Zero();  // the pivot's current position
  Vec3 velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();

  Vec3 to_rest(const Vec3& x) const { return rotation.transpose() * (x - centre) + (centre - translation); }
  Vec3 to_world(const Vec3& x_rest) const { return rotation * (x_rest - (centre - translation)) + centre; }
  Vec3 velocity_at(const Vec3& x) const { return velocity + angular_velocity.cross(x - centre); }
};

class RigidMotion {
 public:
  RigidMotion() = default;
  // Keyframe times must increase strictly (the scene loader checks).
  RigidMotion(Vec3 pivot, std::vector<RigidKeyframe> keyframes);
  RigidPose at(Real time) const;
  bool moves() const { return keyframes_.size() > 1; }
  const std::vector<RigidKeyframe>& keyframes() const { return keyframes_; }

 private:
  Vec3 pivot_ = Vec3::Zero();
  std::vector<RigidKeyframe> keyframes_;
};

}  // namespace bakesim
