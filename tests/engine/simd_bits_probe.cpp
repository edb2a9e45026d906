// Runs a few small scenes that reach every hot loop the engine compiles twice (simd_clones.hpp:
// P2G and G2P with APIC and PIC/FLIP, MLS and B-spline gradients, elastic, plastic and
// out-of-series-range particles, pseudo-1D and full 2D, one and two threads) and prints one
// 64-bit FNV-1a hash of each result's bits. simd_clones_test.sh builds it twice, against the
// engine with and without the AVX2 copies, and requires the same lines from both.
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <vector>

#include "compaction/simulation.hpp"

namespace {

struct Fnv {
  std::uint64_t h = 1469598103934665603ull;
  void bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 1099511628211ull;
  }
  template <class T>
  void vec(const std::vector<T>& v) {
    bytes(v.data(), v.size() * sizeof(T));
  }
};

std::uint64_t hash(const compaction::RunResult& r) {
  Fnv f;
  f.bytes(&r.steps, sizeof r.steps);
  f.vec(r.frames);
  f.vec(r.spacetime.values);
  f.vec(r.velocity.values);
  for (const auto& s : r.snapshots) {
    f.vec(s.x), f.vec(s.y), f.vec(s.strain_rate), f.vec(s.plastic_strain), f.vec(s.jacobian);
  }
  return f.h;
}

compaction::SceneParams base(double S, double R) {
  compaction::SceneParams p;
  p.S = S, p.R = R, p.phi = 0.4, p.cells_per_unit = 6, p.eps_end = 0.05;
  p.perturbation = 0.05, p.seed = 11, p.snapshot_eps = {0.04};
  return p;
}

}  // namespace

int main() {
#if defined(__x86_64__) && defined(__GNUC__)
  std::printf("cpu has avx2: %s\n", __builtin_cpu_supports("avx2") ? "yes" : "no");
#endif
  struct Case {
    const char* name;
    compaction::SceneParams p;
  };
  std::vector<Case> cases;
  cases.push_back({"apic-mls plastic band", base(0.05, 1e-3)});
  cases.push_back({"apic-mls large elastic strain (scalar return map)", base(0.05, 0.1)});
  auto flip = base(0.05, 1e-3);
  flip.transfer = compaction::Transfer::pic_flip, flip.gradient = compaction::Gradient::bspline;
  cases.push_back({"pic/flip b-spline", flip});
  auto full = base(0.05, 4e-4);
  full.geometry = compaction::Geometry::full2d, full.n_cols = 3, full.n_rows = 8;
  full.gradient = compaction::Gradient::bspline, full.threads = 2;
  cases.push_back({"apic b-spline full 2D, two threads", full});
  auto two = base(0.02, 4e-4);
  two.threads = 2;
  cases.push_back({"apic-mls two threads", two});
  int bad = 0;
  for (const Case& c : cases) {
    const compaction::RunResult r = compaction::run_scene(c.p);
    if (r.status != compaction::RunStatus::ok) ++bad;
    std::printf("%-52s %s steps %lld hash %016llx\n", c.name, compaction::to_string(r.status),
                static_cast<long long>(r.steps), static_cast<unsigned long long>(hash(r)));
  }
  return bad == 0 ? 0 : 1;
}
