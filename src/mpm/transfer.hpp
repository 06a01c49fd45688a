#pragma once
// The stencil loops of the transfers (P2G, G2P) over whole grid records: a
// record of N·4 doubles (GridNode: 1 vector, HeatSums: 2, HeatState: 3) is
// read and added as N four-lane vectors, so a node costs one load (and
// store) and a fused multiply-add or two per vector instead of a dozen
// scalar operations per field (issue 25: AVX2 in the native build, two SSE2
// halves otherwise). Unused lanes (a gather reads every field) cost nothing
// extra: the vector does them alongside.
#include <Eigen/Core>
#include <cstddef>
#include <cstring>

#include "mpm/grid.hpp"

namespace bakesim::mpm {

template <class Node>
inline constexpr int kLanes = int(sizeof(Node) / (4 * sizeof(Real)));

// Lane vector l of a record, read and written in place with unaligned access
// (vector storage is only 16-byte aligned). A copy through memcpy went through
// the stack and cost more than the scalar code did.
template <class Node>
inline Eigen::Map<const Lane4, Eigen::Unaligned> lanes(const Node& n, int l) {
  static_assert(sizeof(Node) == kLanes<Node> * 4 * sizeof(Real), "a record is whole 4-lane vectors of Real");
  return Eigen::Map<const Lane4, Eigen::Unaligned>(reinterpret_cast<const Real*>(&n) + 4 * l);
}
template <class Node>
inline Eigen::Map<Lane4, Eigen::Unaligned> lanes(Node& n, int l) {
  static_assert(sizeof(Node) == kLanes<Node> * 4 * sizeof(Real), "a record is whole 4-lane vectors of Real");
  return Eigen::Map<Lane4, Eigen::Unaligned>(reinterpret_cast<Real*>(&n) + 4 * l);
}

// The record whose fields are the lanes of v (to read a gathered moment by name).
template <class Node, int N = kLanes<Node>>
inline Node as_record(const Lane4 (&v)[N]) {
  Node n;
  for (int l = 0; l < N; ++l) std::memcpy(reinterpret_cast<Real*>(&n) + 4 * l, v[l].data(), 4 * sizeof(Real));
  return n;
}

// Where the stencil of a particle lies: its three axes' weights, and the
// grid's strides (node index = i·syz + j·nz + k).
struct Stencil {
  Axis x, y, z;
  std::size_t nz, syz;
  std::size_t row(int i, int j) const {
    return std::size_t(x.base + i) * syz + std::size_t(y.base + j) * nz + std::size_t(z.base);
  }
};

// Σ w_i f_i and the first moments Σ w_i o_i f_i along x, y and z over the 27
// nodes (o the node's offset from the particle in cells), for every field f of
// the record: APIC's velocity and affine sums, and the FLIP and gradient sums
// of the heat fields.
template <int N>
struct StencilMoments {
  Lane4 sum[N], x[N], y[N], z[N];
};

// M: how many of the record's vectors need their moments; the rest are
// summed only (their moments come back zero), a third of the work for them.
template <int M, class Node, int N = kLanes<Node>>
inline StencilMoments<N> gather_moments(const Node* grid, const Stencil& st) {
  static_assert(M >= 0 && M <= N, "moments of at most the record's vectors");
  const Axis& az = st.z;
  const Real wz_oz[3] = {az.w[0] * (0 - az.frac), az.w[1] * (1 - az.frac), az.w[2] * (2 - az.frac)};
  StencilMoments<N> m;
  for (int l = 0; l < N; ++l) m.sum[l] = m.x[l] = m.y[l] = m.z[l] = Lane4::Zero();
  for (int i = 0; i < 3; ++i) {
    Lane4 si[N], yi[M + 1], zi[M + 1];  // Σ over j and k at this i
    for (int l = 0; l < N; ++l) si[l] = Lane4::Zero();
    for (int l = 0; l < M; ++l) yi[l] = zi[l] = Lane4::Zero();
    for (int j = 0; j < 3; ++j) {
      const Node* row = grid + st.row(i, j);
      Lane4 sj[N], zj[M + 1];  // Σ over k
      for (int l = 0; l < N; ++l) sj[l] = Lane4::Zero();
      for (int l = 0; l < M; ++l) zj[l] = Lane4::Zero();
#pragma GCC unroll 3
      for (int k = 0; k < 3; ++k) {
        for (int l = 0; l < M; ++l) {
          const auto f = lanes(row[k], l);
          sj[l] += az.w[k] * f;
          zj[l] += wz_oz[k] * f;
        }
        for (int l = M; l < N; ++l) sj[l] += az.w[k] * lanes(row[k], l);
      }
      const Real wy = st.y.w[j], wy_oy = wy * (j - st.y.frac);
      for (int l = 0; l < M; ++l) yi[l] += wy_oy * sj[l], zi[l] += wy * zj[l];
      for (int l = 0; l < N; ++l) si[l] += wy * sj[l];
    }
    const Real wx = st.x.w[i], wx_ox = wx * (i - st.x.frac);
    for (int l = 0; l < M; ++l) m.x[l] += wx_ox * si[l], m.y[l] += wx * yi[l], m.z[l] += wx * zi[l];
    for (int l = 0; l < N; ++l) m.sum[l] += wx * si[l];
  }
  return m;
}

// Adds w_i (base + o_x slope_x + o_y slope_y + o_z slope_z) to the record of
// every node of the stencil: the APIC momentum with the MLS force, and the
// heat and water sums with their flux terms. The arguments are copied: the
// node stores could alias anything reached through a reference, and the
// compiler would reload it after each one.
template <class Node, int N = kLanes<Node>>
inline void scatter_affine(Node* grid, const Stencil st, const Lane4 (&base)[N], const Lane4 (&slope_x)[N],
                           const Lane4 (&slope_y)[N], const Lane4 (&slope_z)[N]) {
  Lane4 b[N], sx[N], sy[N], tz[3][N];
  for (int l = 0; l < N; ++l) {
    b[l] = base[l], sx[l] = slope_x[l], sy[l] = slope_y[l];
    for (int k = 0; k < 3; ++k) tz[k][l] = (k - st.z.frac) * slope_z[l];
  }
  for (int i = 0; i < 3; ++i) {
    Lane4 ti[N];
    for (int l = 0; l < N; ++l) ti[l] = b[l] + (i - st.x.frac) * sx[l];
    for (int j = 0; j < 3; ++j) {
      const Real wij = st.x.w[i] * st.y.w[j];
      Lane4 tj[N];
      for (int l = 0; l < N; ++l) tj[l] = ti[l] + (j - st.y.frac) * sy[l];
      Node* row = grid + st.row(i, j);
#pragma GCC unroll 3
      for (int k = 0; k < 3; ++k) {
        const Real w = wij * st.z.w[k];
        for (int l = 0; l < N; ++l) lanes(row[k], l) += w * (tj[l] + tz[k][l]);
      }
    }
  }
}

}  // namespace bakesim::mpm
