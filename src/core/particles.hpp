#pragma once
// Structure-of-arrays particle storage with a registry of named attributes.
// Sorting, export and (later) checkpoints walk the registry, so no solver
// re-sorts its own arrays by hand. Solvers keep references to the attribute
// vectors they use in hot loops; the registry never reallocates them behind
// their back except through resize()/permute(), which solvers call themselves.
#include <cstdint>
#include <deque>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace bakesim {

struct AttributeInfo {
  std::string name;
  std::string unit;      // SI unit, "" for dimensionless, "degC" for temperatures
  bool exported = true;  // written to frame files
};

template <class T>
struct Attribute {
  AttributeInfo info;
  std::vector<T> data;
};

class ParticleSet {
 public:
  std::vector<Real>& add_scalar(const std::string& name, const std::string& unit, bool exported = true,
                                Real fill = 0.0);
  std::vector<Vec3>& add_vector(const std::string& name, const std::string& unit, bool exported = true);
  std::vector<std::int32_t>& add_int(const std::string& name, bool exported = true, std::int32_t fill = 0);

  std::vector<Real>& scalar(const std::string& name);
  std::vector<Vec3>& vector(const std::string& name);
  std::vector<std::int32_t>& integer(const std::string& name);
  const std::vector<Real>& scalar(const std::string& name) const;
  const std::vector<Vec3>& vector(const std::string& name) const;
  const std::vector<std::int32_t>& integer(const std::string& name) const;
  bool has(const std::string& name) const;

  std::size_t size() const { return size_; }
  void resize(std::size_t n);
  // Reorders every attribute: new[i] = old[order[i]].
  void permute(const std::vector<std::uint32_t>& order);

  const std::deque<Attribute<Real>>& scalars() const { return scalars_; }
  const std::deque<Attribute<Vec3>>& vectors() const { return vectors_; }
  const std::deque<Attribute<std::int32_t>>& integers() const { return ints_; }

 private:
  // deque: references to elements stay valid when attributes are added.
  std::deque<Attribute<Real>> scalars_;
  std::deque<Attribute<Vec3>> vectors_;
  std::deque<Attribute<std::int32_t>> ints_;
  std::size_t size_ = 0;
  std::vector<Real> scratch_real_;
  std::vector<Vec3> scratch_vec_;
  std::vector<std::int32_t> scratch_int_;
};

}  // namespace bakesim
