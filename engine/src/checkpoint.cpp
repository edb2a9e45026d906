// The 2D scene's checkpoint: its particle section (schema/checkpoint-format.md) inside the
// framing and shared sections of checkpoint_file.cpp.
#include "checkpoint.hpp"

#include <vector>

namespace compaction {

namespace {

using checkpoint_file::In;
using checkpoint_file::Out;

// The particle section lists every field of Particles. A field added to it changes its size
// and stops the build here: write it into the checkpoint (and read it back), describe it in
// schema/checkpoint-format.md and raise the format version (checkpoint_file.cpp).
// Particles::field_bits is left out: p2g writes it before g2p reads it, within every step.
static_assert(sizeof(Particles) == 576, "Particles changed: add the field to the checkpoint");

// The file keeps each particle's C, Fe and tau whole, one matrix after another
// (schema/checkpoint-format.md); the particles keep one array per entry (Mat2Columns,
// Sym2Columns). These convert between the two.
template <class Columns>
auto as_rows(const Columns& c) {
  std::vector<decltype(c[0])> r(c.size());
  for (std::size_t k = 0; k < r.size(); ++k) r[k] = c[k];
  return r;
}
template <class Columns, class Row>
void set_from_rows(Columns& c, const std::vector<Row>& r) {
  c.assign(r.size(), Row{});
  for (std::size_t k = 0; k < r.size(); ++k) c.set(k, r[k]);
}

}  // namespace

CheckpointInfo write_checkpoint(const std::string& path, const SceneParams& p, const State& s,
                                const RunResult& r, const RunPosition& at,
                                const std::string& movie_file) {
  const Particles& P = s.particles;
  const std::size_t reserve = P.n * 150 + r.snapshots.size() * P.n * 20;
  return checkpoint_file::write(path, p, s.clock, s.measure, s.clock.t * s.setup.V / s.setup.h0, P.n,
                               r, at, movie_file, reserve, [&](Out& o) {
    checkpoint_file::put_particle_set(o, P.n, P.mass, P.vol0);
    o.put_array(P.x), o.put_array(P.y), o.put_array(P.vx), o.put_array(P.vy);
    o.put_array(as_rows(P.C)), o.put_array(as_rows(P.Fe)), o.put_array(as_rows(P.tau));
    o.put_array(P.dep), o.put_array(P.ep), o.put_array(P.x0);
    o.put_array(P.strut), o.put_array(P.strut_mid);
    o.put_array(P.nx), o.put_array(P.ny);  // split_fields' face normals, else empty
  });
}

CheckpointInfo restore_checkpoint(const std::string& path, const SceneParams& p, State& s,
                                  RunResult& r, RunPosition& at, std::string* movie_bytes) {
  return checkpoint_file::restore(path, p, s.clock, s.measure, s.particles.n, s.grid.cells_y, r,
                                  at, movie_bytes, [&](In& in) {
    Particles& P = s.particles;
    const std::size_t n = P.n;
    checkpoint_file::get_particle_set(in, n, P.mass, P.vol0);
    in.get_array(P.x, n, "x"), in.get_array(P.y, n, "y");
    in.get_array(P.vx, n, "vx"), in.get_array(P.vy, n, "vy");
    std::vector<Mat2> c, fe;
    std::vector<Sym2> tau;
    in.get_array(c, n, "C"), in.get_array(fe, n, "Fe"), in.get_array(tau, n, "tau");
    set_from_rows(P.C, c), set_from_rows(P.Fe, fe), set_from_rows(P.tau, tau);
    in.get_array(P.dep, n, "dep"), in.get_array(P.ep, n, "ep"), in.get_array(P.x0, n, "x0");
    in.get_array(P.strut, n, "strut"), in.get_array(P.strut_mid, n, "strut_mid");
    const std::size_t normals = s.setup.split_fields ? n : 0;
    in.get_array(P.nx, normals, "nx"), in.get_array(P.ny, normals, "ny");
  });
}

}  // namespace compaction
