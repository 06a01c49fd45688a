#include "core/particles.hpp"

#include "core/errors.hpp"
#include "core/parallel.hpp"

namespace bakesim {
namespace {

template <class T>
std::vector<T>* find(std::deque<Attribute<T>>& list, const std::string& name) {
  for (auto& a : list)
    if (a.info.name == name) return &a.data;
  return nullptr;
}

template <class T>
const std::vector<T>* find(const std::deque<Attribute<T>>& list, const std::string& name) {
  for (const auto& a : list)
    if (a.info.name == name) return &a.data;
  return nullptr;
}

template <class T>
void permute_one(std::vector<T>& data, std::vector<T>& scratch, const std::vector<std::uint32_t>& order) {
  scratch.resize(data.size());
  parallel_for(
      data.size(), [&](std::size_t i) { scratch[i] = data[order[i]]; }, 4096);
  data.swap(scratch);
}

}  // namespace

std::vector<Real>& ParticleSet::add_scalar(const std::string& name, const std::string& unit, bool exported, Real fill) {
  if (has(name)) throw Error("particle attribute '" + name + "' registered twice");
  scalars_.push_back({{name, unit, exported}, std::vector<Real>(size_, fill)});
  return scalars_.back().data;
}

std::vector<Vec3>& ParticleSet::add_vector(const std::string& name, const std::string& unit, bool exported) {
  if (has(name)) throw Error("particle attribute '" + name + "' registered twice");
  vectors_.push_back({{name, unit, exported}, std::vector<Vec3>(size_, Vec3::Zero())});
  return vectors_.back().data;
}

std::vector<std::int32_t>& ParticleSet::add_int(const std::string& name, bool exported, std::int32_t fill) {
  if (has(name)) throw Error("particle attribute '" + name + "' registered twice");
  ints_.push_back({{name, "", exported}, std::vector<std::int32_t>(size_, fill)});
  return ints_.back().data;
}

bool ParticleSet::has(const std::string& name) const {
  return find(scalars_, name) || find(vectors_, name) || find(ints_, name);
}

#define BAKESIM_LOOKUP(list, kind)                                            \
  auto* p = find(list, name);                                                 \
  if (!p) throw Error("no " kind " particle attribute named '" + name + "'"); \
  return *p;

std::vector<Real>& ParticleSet::scalar(const std::string& name){
    BAKESIM_LOOKUP(scalars_, "scalar")} std::vector<Vec3>& ParticleSet::vector(const std::string& name){
    BAKESIM_LOOKUP(vectors_, "vector")} std::vector<std::int32_t>& ParticleSet::integer(const std::string& name) {
  BAKESIM_LOOKUP(ints_, "integer")
}
const std::vector<Real>& ParticleSet::scalar(const std::string& name) const { BAKESIM_LOOKUP(scalars_, "scalar") }
const std::vector<Vec3>& ParticleSet::vector(const std::string& name) const { BAKESIM_LOOKUP(vectors_, "vector") }
const std::vector<std::int32_t>& ParticleSet::integer(const std::string& name) const {
  BAKESIM_LOOKUP(ints_, "integer")
}
#undef BAKESIM_LOOKUP

void ParticleSet::resize(std::size_t n) {
  for (auto& a : scalars_) a.data.resize(n, 0.0);
  for (auto& a : vectors_) a.data.resize(n, Vec3::Zero());
  for (auto& a : ints_) a.data.resize(n, 0);
  size_ = n;
}

void ParticleSet::permute(const std::vector<std::uint32_t>& order) {
  if (order.size() != size_) throw Error("ParticleSet::permute: order has the wrong size");
  for (auto& a : scalars_) permute_one(a.data, scratch_real_, order);
  for (auto& a : vectors_) permute_one(a.data, scratch_vec_, order);
  for (auto& a : ints_) permute_one(a.data, scratch_int_, order);
}

}  // namespace bakesim
