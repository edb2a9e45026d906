#include "void_layout.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "splitmix64.hpp"

namespace compaction {

namespace {

// The random structure's numbers come from their own stream of the seed, so that they do not
// repeat the particle perturbation's, which starts from the seed itself.
constexpr std::uint64_t kStructureStream = 0x7374727563747572ULL;  // "structur"

VoidLayout regular_voids(const SceneParams& p, int per_unit, VoidLayout out) {
  const int side = regular_void_side(p, per_unit);
  const int first = (per_unit - side) / 2;
  out.voids.assign(out.voids.size(), Void{first, first + side, first, first + side});
  return out;
}

VoidLayout random_voids(const SceneParams& p, int per_unit, VoidLayout out) {
  SplitMix64 rng{p.seed ^ kStructureStream};
  const std::size_t n = out.voids.size();
  const double spread = random_structure::area_spread(p.phi);
  // Areas over the regular one: pairs (u, 2 - u), u uniform in [1 - spread, 1 + spread]; an odd
  // cell count leaves one void of the mean area. Dealt to the cells by a seeded shuffle.
  std::vector<double> area(n, 1.0);
  for (std::size_t k = 0; k + 1 < n; k += 2) {
    const double u = 1.0 + spread * (2.0 * rng.uniform() - 1.0);
    area[k] = u, area[k + 1] = 2.0 - u;
  }
  for (std::size_t k = n; k > 1; --k) std::swap(area[k - 1], area[rng.below(k)]);
  // The solid each void keeps to its cell's edges: half the thinnest strut, on the lattice.
  const int margin = std::max(
      1, static_cast<int>(std::lround(0.5 * random_structure::thinnest_strut_fraction(p.phi) *
                                      per_unit)));
  const int widest = std::max(1, per_unit - 2 * margin);
  for (std::size_t k = 0; k < n; ++k) {
    const double side_fraction = std::sqrt(area[k] * (1.0 - p.phi));  // of the unit cell
    const int side = std::clamp(static_cast<int>(std::lround(side_fraction * per_unit)), 1, widest);
    const auto room = static_cast<std::uint64_t>(widest - side + 1);  // lattice positions
    const int x0 = margin + static_cast<int>(rng.below(room));
    const int y0 = margin + static_cast<int>(rng.below(room));
    out.voids[k] = Void{x0, x0 + side, y0, y0 + side};
  }
  return out;
}

}  // namespace

VoidLayout void_layout(const SceneParams& p, int per_unit) {
  VoidLayout out;
  out.cols = p.cols();
  out.rows = p.n_rows;
  out.voids.assign(static_cast<std::size_t>(out.cols) * out.rows, Void{});
  if (p.phi >= kSolidColumnPhi) return out;  // the solid column: no voids
  return p.structure == Structure::random ? random_voids(p, per_unit, std::move(out))
                                          : regular_voids(p, per_unit, std::move(out));
}

}  // namespace compaction
