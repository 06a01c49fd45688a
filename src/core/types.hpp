#pragma once
// Basic math types shared by every module. SI units everywhere inside the library.
#include <Eigen/Core>
#include <cstdint>

namespace bakesim {

using Real = double;
using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;
using Vec4 = Eigen::Matrix<Real, 4, 1>;
// Four values worked on together, one per SIMD lane (AVX in the native build,
// SSE2 pairs otherwise): four fields of an MPM grid record (mpm/transfer.hpp).
using Lane4 = Eigen::Array<Real, 4, 1>;

struct Aabb {
  Vec3 min = Vec3::Constant(0.0);
  Vec3 max = Vec3::Constant(0.0);
  bool contains(const Vec3& p) const { return (p.array() >= min.array()).all() && (p.array() <= max.array()).all(); }
  Vec3 extent() const { return max - min; }
  static Aabb empty_box() { return {Vec3::Constant(1e300), Vec3::Constant(-1e300)}; }
  void expand(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
};

constexpr Real kPi = 3.14159265358979323846;

}  // namespace bakesim
