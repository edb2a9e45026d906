// The 3D column's checkpoint: its particle section (schema/checkpoint-format.md) inside the
// framing and shared sections of checkpoint_file.cpp.
#include "checkpoint_3d.hpp"

#include <array>
#include <vector>

namespace compaction {

namespace {

using checkpoint_file::In;
using checkpoint_file::Out;

// The particle section lists every field of Particles3D. A field added to it changes its size
// and stops the build here: write it into the checkpoint (and read it back), describe it in
// schema/checkpoint-format.md and raise the format version (checkpoint_file.cpp).
static_assert(sizeof(Particles3D) == 3 * 8 + 10 * sizeof(std::vector<double>),
              "Particles3D changed: add the field to the checkpoint");

// A matrix as the file keeps it: its 9 entries in Eigen's (column-major) order.
using Entries = std::array<double, 9>;
static_assert(sizeof(Mat3) == sizeof(Entries));

std::vector<Entries> entries_of(const std::vector<Mat3>& m) {
  std::vector<Entries> out(m.size());
  for (std::size_t k = 0; k < m.size(); ++k) std::copy_n(m[k].data(), 9, out[k].begin());
  return out;
}

void set_from_entries(std::vector<Mat3>& m, const std::vector<Entries>& e) {
  m.resize(e.size());
  for (std::size_t k = 0; k < e.size(); ++k) std::copy_n(e[k].begin(), 9, m[k].data());
}

}  // namespace

CheckpointInfo write_checkpoint_3d(const std::string& path, const SceneParams& p,
                                   const State3D& s, const RunResult& r, const RunPosition& at) {
  const Particles3D& P = s.particles;
  return checkpoint_file::write(
      path, p, s.clock, s.measure, s.clock.t * s.setup.V / s.setup.h0, P.n, r, at, {},
      P.n * (7 + 27) * sizeof(double), [&](Out& o) {
        checkpoint_file::put_particle_set(o, P.n, P.mass, P.vol0);
        o.put_array(P.x), o.put_array(P.y), o.put_array(P.z);
        o.put_array(P.vx), o.put_array(P.vy), o.put_array(P.vz);
        o.put_array(entries_of(P.C)), o.put_array(entries_of(P.Fe));
        o.put_array(entries_of(P.tau));
        o.put_array(P.dep);
      });
}

CheckpointInfo restore_checkpoint_3d(const std::string& path, const SceneParams& p, State3D& s,
                                     RunResult& r, RunPosition& at) {
  return checkpoint_file::restore(
      path, p, s.clock, s.measure, s.particles.n, s.grid.cells_y, r, at, nullptr, [&](In& in) {
        Particles3D& P = s.particles;
        const std::size_t n = P.n;
        checkpoint_file::get_particle_set(in, n, P.mass, P.vol0);
        in.get_array(P.x, n, "x"), in.get_array(P.y, n, "y"), in.get_array(P.z, n, "z");
        in.get_array(P.vx, n, "vx"), in.get_array(P.vy, n, "vy"), in.get_array(P.vz, n, "vz");
        std::vector<Entries> c, fe, tau;
        in.get_array(c, n, "C"), in.get_array(fe, n, "Fe"), in.get_array(tau, n, "tau");
        set_from_entries(P.C, c), set_from_entries(P.Fe, fe), set_from_entries(P.tau, tau);
        in.get_array(P.dep, n, "dep");
      });
}

}  // namespace compaction
