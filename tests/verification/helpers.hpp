#pragma once
// Shared helpers for verification tests: build scenes from JSON text and
// step solvers to a given time.
#include <nlohmann/json.hpp>

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/scene.hpp"
#include "surface/surface.hpp"
#include "sph/solver.hpp"

namespace bakesim::test_support {

// Writes an axis-aligned box from `lo` to `hi` as an OBJ mesh (six quads,
// faces outward), for mesh-collider tests.
inline void write_box_obj(const std::string& path, const Vec3& lo, const Vec3& hi) {
  std::ofstream f(path);
  for (int k = 0; k < 8; ++k) {
    const bool x = (k % 4 == 1 || k % 4 == 2), y = (k % 4 >= 2), z = k >= 4;
    f << "v " << (x ? hi : lo).x() << ' ' << (y ? hi : lo).y() << ' ' << (z ? hi : lo).z() << '\n';
  }
  f << "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n";
}

// Lattice particles inside a ball, as the scene sampler fills a body (each
// stands for a cube of side s), shifted by `centre`, spread by ρ0/ρ.
inline surface::SurfaceParticles lattice_ball(Real radius, Real s, Vec3 centre, Real density_ratio = 1.0) {
  surface::SurfaceParticles p;
  p.spacing = s;
  const int n = int(std::ceil(radius / s)) + 1;
  for (int i = -n; i <= n; ++i)
    for (int j = -n; j <= n; ++j)
      for (int k = -n; k <= n; ++k) {
        const Vec3 x = (Vec3(i, j, k) + Vec3::Constant(0.5)) * s;
        if (x.norm() < radius) {
          p.position.push_back(centre + x * std::cbrt(density_ratio));
          p.density_ratio.push_back(density_ratio);
        }
      }
  return p;
}

inline std::unique_ptr<sph::SphSolver> make_sph(const nlohmann::json& doc) {
  Scene scene = parse_scene(doc.dump(), "test-scene.json", ".");
  return std::make_unique<sph::SphSolver>(scene.sph);
}

// A fully periodic SPH box w × λ × w filled with one material (the shear-wave
// tests): `sph_settings` are solver.sph's keys, `material` the material's.
inline nlohmann::json periodic_box_scene(double w, double wavelength, const nlohmann::json& sph_settings,
                                         const nlohmann::json& material, double max_dt = 1e-3) {
  return {{"solver", {{"type", "sph"}, {"max_dt", max_dt}, {"sph", sph_settings}}},
          {"time", {{"end", 1.0}}},
          {"gravity", {0, 0, 0}},
          {"domain", {{"min", {0, 0, 0}}, {"max", {w, wavelength, w}}, {"periodic", {"x", "y", "z"}}}},
          {"materials", {{"fluid", material}}},
          {"bodies",
           nlohmann::json::array({{{"name", "fluid"},
                                   {"material", "fluid"},
                                   {"shape", {{"type", "box"}, {"min", {0, 0, 0}}, {"max", {w, wavelength, w}}}}}})}};
}

// v_x = A sin(k y) on every particle, then the solver's state refreshed.
inline void start_shear_wave(sph::SphSolver& sph, double k, double amplitude) {
  auto& ps = sph.mutable_particles();
  for (std::size_t i = 0; i < ps.size(); ++i)
    ps.vector("velocity")[i] = Vec3(amplitude * std::sin(k * ps.vector("position")[i].y()), 0, 0);
  sph.refresh();
}

// The projection of v_x on sin(k y): the shear wave's amplitude.
inline double shear_wave_amplitude(const sph::SphSolver& sph, double k) {
  const auto& x = sph.particles().vector("position");
  const auto& v = sph.particles().vector("velocity");
  double num = 0, den = 0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double sn = std::sin(k * x[i].y());
    num += v[i].x() * sn;
    den += sn * sn;
  }
  return num / den;
}

inline std::unique_ptr<mpm::MpmSolver> make_mpm(const nlohmann::json& doc) {
  Scene scene = parse_scene(doc.dump(), "test-scene.json", ".");
  return std::make_unique<mpm::MpmSolver>(scene.mpm);
}

// Steps with the solver's stable dt, landing exactly on t_end, where every
// field is brought to t_end (Solver::synchronize, as the frame loop does
// before a frame); on_step sees the state as the steps leave it.
template <class OnStep>
inline void advance_to(Solver& s, double t_end, OnStep&& on_step) {
  while (s.time() < t_end - 1e-12) {
    double dt = std::min(s.max_stable_dt(), t_end - s.time());
    s.step(dt);
    on_step();
  }
  s.synchronize();
}
inline void advance_to(Solver& s, double t_end) {
  advance_to(s, t_end, [] {});
}

// Reads a CSV with '#' comment lines and a header; returns rows of numbers.
inline std::vector<std::vector<double>> read_csv(const std::string& path, std::vector<std::string>* header = nullptr) {
  std::ifstream in(path);
  std::vector<std::vector<double>> rows;
  std::string line;
  bool have_header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    std::vector<std::string> cells;
    while (std::getline(ss, cell, ',')) cells.push_back(cell);
    if (!have_header) {
      have_header = true;
      if (header) *header = cells;
      continue;
    }
    std::vector<double> row;
    for (const auto& c : cells) row.push_back(std::stod(c));
    rows.push_back(row);
  }
  return rows;
}

// The root of f between lo and hi (f changes sign there), by `iterations` bisections.
template <class F>
double bisect_root(F&& f, double lo, double hi, int iterations) {
  for (int it = 0; it < iterations; ++it) {
    const double mid = 0.5 * (lo + hi);
    ((f(mid) > 0) == (f(lo) > 0) ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// The n-th root of λ tan λ = Bi, in (nπ, nπ + π/2), by bisection on λ sin λ − Bi cos λ.
inline double plane_wall_root(double biot, int n) {
  return bisect_root([biot](double l) { return l * std::sin(l) - biot * std::cos(l); }, n * kPi + 1e-12,
                     n * kPi + 0.5 * kPi - 1e-12, 200);
}

// Plane wall of half-thickness L, initially uniform, exchanging through
// h (T∞ − T) at x = ±L: (T(x,t) − T∞)/(T0 − T∞) = Σ C_n exp(−λ_n² Fo) cos(λ_n x/L),
// λ_n tan λ_n = Bi, C_n = 4 sin λ_n / (2 λ_n + sin 2 λ_n) (Incropera Eq 5.42);
// `x_over_l` 0 is the centre, 1 the face.
inline double plane_wall(double biot, double fourier, double x_over_l = 0) {
  double sum = 0;
  for (int n = 0; n < 60; ++n) {
    const double l = plane_wall_root(biot, n);
    sum += 4 * std::sin(l) / (2 * l + std::sin(2 * l)) * std::exp(-l * l * fourier) * std::cos(l * x_over_l);
  }
  return sum;
}

// Q/Q0 of the same wall (Incropera Eq 5.46): the share of the heat it can take
// that has come in by Fo; also that of a wall of thickness L heated on one face
// and insulated on the other (its mirror image is the other half).
inline double plane_wall_energy_fraction(double biot, double fourier) {
  double sum = 0;
  for (int n = 0; n < 200; ++n) {
    const double l = plane_wall_root(biot, n);
    sum += 4 * std::sin(l) / (2 * l + std::sin(2 * l)) * std::sin(l) / l * std::exp(-l * l * fourier);
  }
  return 1 - sum;
}

// The mean of (T − T∞)/(T0 − T∞) over the same wall (1 − Q/Q0).
inline double plane_wall_mean(double biot, double fourier) { return 1 - plane_wall_energy_fraction(biot, fourier); }

// The first roots of ζ J1(ζ) = Bi J0(ζ) (the infinite cylinder's eigenvalues),
// by a scan for sign changes and bisection (the function has no poles).
inline std::vector<double> infinite_cylinder_roots(double biot, int count) {
  const auto f = [biot](double z) { return z * std::cyl_bessel_j(1.0, z) - biot * std::cyl_bessel_j(0.0, z); };
  std::vector<double> roots;
  double a = 1e-9, fa = f(a);
  for (double b = 0.01; int(roots.size()) < count; b += 0.01) {
    const double fb = f(b);
    if ((fa > 0) != (fb > 0)) roots.push_back(bisect_root(f, a, b, 100));
    a = b, fa = fb;
  }
  return roots;
}

// Infinite cylinder of radius R, initially uniform, exchanging through h at
// r = R (Incropera Eq 5.49–5.50): (T − T∞)/(T0 − T∞) = Σ C_n exp(−ζ_n² Fo)
// J0(ζ_n r/R), C_n = (2/ζ_n) J1(ζ_n) / (J0²(ζ_n) + J1²(ζ_n)), Fo = α t/R²;
// `mean`: its average over the cross-section, Σ C_n exp(−ζ_n² Fo) 2 J1(ζ_n)/ζ_n.
inline double infinite_cylinder(double biot, double fourier, double r_over_r0, bool mean = false) {
  double sum = 0;
  for (double z : infinite_cylinder_roots(biot, 40)) {
    const double j0 = std::cyl_bessel_j(0.0, z), j1 = std::cyl_bessel_j(1.0, z);
    const double c = 2 / z * j1 / (j0 * j0 + j1 * j1);
    sum += c * std::exp(-z * z * fourier) * (mean ? 2 * j1 / z : std::cyl_bessel_j(0.0, z * r_over_r0));
  }
  return sum;
}

}  // namespace bakesim::test_support
