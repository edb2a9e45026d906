// Matter (github.com/larsblatny/matter, GPL-3.0) on our reference scene, for
// bench/peers/matter_vs_engine.py. This file is ours and uses only Matter's public API; it is
// compiled against a Matter checkout given on the command line (-I SRC/src together with
// SRC/src/simulation/*.cpp but save_data.cpp), never against a copy of Matter in this
// repository. save_data.cpp needs the tinyply header, which Matter's CMake downloads at configure
// time; this driver writes nothing through Matter, so it defines Matter's save functions as
// no-ops (the end of this file) and Matter's physics is all Matter's own.
//
// The scene is compaction-run's pseudo-1D column (engine/src/scene_builder.cpp, void_layout.cpp):
// one unit cell of side L = h0 / 34 across, periodic in x (Matter's pbc: ghost copies of the
// particles within 4 dx of either side, added before P2G and removed before G2P), 34 unit cells
// tall, each with a centred square hole of side L sqrt(1 - phi) rounded to the particle lattice;
// the particles on the same lattice in the same order (2 x 2 per cell at (i + 1/2) dx / 2), the
// hole's particles left out. Hencky elasticity with E = q_y / R, nu = 0.3, rho = 1000; von
// Mises perfect plasticity with q = sqrt(3/2 s:s) <= q_y (q_prefac = sqrt(3/2); Matter's
// default is sqrt(1/2)), s the 2D deviator of the Kirchhoff stress. No gravity. Plates: the
// bottom one at y = 0 at rest, the top one from y = h0 down at V = S sqrt(E / rho), both
// SlipStick with friction 0 (the normal velocity relative to the plate is set to zero, the
// tangential one is free: our `contact bonded`). Pure APIC: flip_ratio < -1 (Matter's
// positionUpdate takes the APIC velocity below -1 and blends in AFLIP in [-1, 0)). Frames of
// d_eps imposed strain, as ours (Matter clamps the step to a frame's end, as ours does).
//
// The time step: Matter's is min(cfl dx / max particle speed, cfl_elastic dx / sqrt(E / rho)),
// ours cfl dx / (c_P + max particle speed) with cfl 0.5 and c_P = sqrt((lambda + 2 mu) / rho).
// By default cfl_elastic = 0.5 sqrt(E / rho) / c_P (0.431 at nu = 0.3), so that Matter's step
// is ours up to the particle speed in the denominator (under 1 % here); --cfl-elastic 0.5 gives
// Matter's default.
//
// Output: one JSON object on stdout (steps, particles with and without ghosts, wall time of
// Matter's simulate(), ...). Matter's own printing goes through a filter on std::cout that counts
// its per-step "Step:" lines (the step counter is private) and passes the other lines to stderr.
// --check DIR instead runs one frame per simulate() call and writes, for
// matter_vs_engine.py's comparison with compaction-run: DIR/frames.csv (per frame: eps, kinetic
// energy, vertical momentum, and -dP_y/dt / width, which is sigma_top - sigma_bottom since the
// plates are the only external forces), DIR/velocity.csv (the last frame's row-averaged vertical
// particle velocity / V, rows of height dx, as compaction-run's velocity.npy) and
// DIR/particles.bin (float64 x, y, accumulated plastic strain, J per particle, in the order of
// compaction-run's particles).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iostream>
#include <memory>
#include <streambuf>
#include <string>
#include <vector>

#include <simulation/simulation.hpp>  // Matter's, from the checkout given on the command line

namespace {

struct Options {
  double S = 4e-3, R = 1e-5, phi = 0.4;
  int cells_per_unit = 20;
  int particles_per_cell = 2;
  int n_rows = 34;
  double eps_end = 0.008, d_eps = 0.002;
  int threads = 1;
  double cfl_elastic = 0.0;  // 0: matched to ours (see the head of this file)
  std::string check_dir;
};

[[noreturn]] void usage(const char* why) {
  std::fprintf(stderr,
               "matter_driver: %s\nusage: matter_driver [--S X] [--R X] [--phi X] "
               "[--cells-per-unit N] [--eps-end X] [--d-eps X] [--threads N] "
               "[--cfl-elastic X] [--check DIR]\n",
               why);
  std::exit(2);
}

Options parse(int argc, char** argv) {
  Options o;
  for (int k = 1; k < argc; ++k) {
    const std::string flag = argv[k];
    if (k + 1 >= argc) usage(("no value for " + flag).c_str());
    const char* v = argv[++k];
    if (flag == "--S") o.S = std::atof(v);
    else if (flag == "--R") o.R = std::atof(v);
    else if (flag == "--phi") o.phi = std::atof(v);
    else if (flag == "--cells-per-unit") o.cells_per_unit = std::atoi(v);
    else if (flag == "--eps-end") o.eps_end = std::atof(v);
    else if (flag == "--d-eps") o.d_eps = std::atof(v);
    else if (flag == "--threads") o.threads = std::atoi(v);
    else if (flag == "--cfl-elastic") o.cfl_elastic = std::atof(v);
    else if (flag == "--check") o.check_dir = v;
    else usage(("unknown flag " + flag).c_str());
  }
  if (o.cells_per_unit < 2 || o.threads < 1 || o.eps_end <= 0 || o.d_eps <= 0) {
    usage("a value is out of range");
  }
  return o;
}

// std::cout's buffer while Matter runs: counts the lines that Matter's simulate() prints once per
// step ("               Step: N"), keeps the last "Proj: n / Np" line (G2P's count of plastic
// projections), drops the other per-step lines and passes every other line to stderr.
class StepCounter : public std::streambuf {
 public:
  long steps = 0;
  std::string last_proj;

 protected:
  int overflow(int c) override {
    if (c == traits_type::eof()) return traits_type::not_eof(c);
    if (c != '\n') {
      line_.push_back(static_cast<char>(c));
      return c;
    }
    const std::size_t start = line_.find_first_not_of(' ');
    const std::string text = start == std::string::npos ? "" : line_.substr(start);
    if (text.rfind("Step:", 0) == 0) {
      ++steps;
    } else if (text.rfind("Proj:", 0) == 0) {
      last_proj = text;
    } else if (text.rfind("Frame:", 0) != 0 && text.rfind("Name:", 0) != 0 &&
               text.rfind("Time:", 0) != 0) {
      std::cerr << line_ << '\n';
    }
    line_.clear();
    return c;
  }

 private:
  std::string line_;
};

struct Scene {
  double L, dx, spacing, E, V, c_p, bar_c;
  int n_holes_side;
};

// The particles of compaction-run's pseudo-1D column (place_particles and regular_voids in
// engine/src), in its order: rows of the lattice bottom to top, each left to right.
std::vector<TV> column_particles(const Options& o, Scene& sc) {
  const int per_unit = o.cells_per_unit * o.particles_per_cell;
  const double hole = sc.L * std::sqrt(1.0 - o.phi);
  const int side = std::min(std::max(static_cast<int>(std::lround(hole / sc.spacing)), 0),
                            per_unit - 1);
  const int first = (per_unit - side) / 2;
  sc.n_holes_side = side;
  std::vector<TV> x;
  for (int j = 0; j < o.n_rows * per_unit; ++j) {
    const int ly = j % per_unit;
    for (int i = 0; i < per_unit; ++i) {
      const bool in_hole = ly >= first && ly < first + side && i >= first && i < first + side;
      if (in_hole) continue;
      x.push_back(TV((i + 0.5) * sc.spacing, (j + 0.5) * sc.spacing));
    }
  }
  return x;
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = parse(argc, argv);
  const double h0 = 1.0, rho = 1000.0, nu = 0.3, q_y = 250.0;
  Scene sc{};
  sc.L = h0 / o.n_rows;
  sc.dx = sc.L / o.cells_per_unit;
  sc.spacing = sc.dx / o.particles_per_cell;
  sc.E = q_y / o.R;
  sc.bar_c = std::sqrt(sc.E / rho);
  sc.V = o.S * sc.bar_c;
  const double lambda = nu * sc.E / ((1 + nu) * (1 - 2 * nu)), mu = sc.E / (2 * (1 + nu));
  sc.c_p = std::sqrt((lambda + 2 * mu) / rho);
  const double cfl_elastic = o.cfl_elastic > 0 ? o.cfl_elastic : 0.5 * sc.bar_c / sc.c_p;
  const int frames = static_cast<int>(std::lround(o.eps_end / o.d_eps));
  if (frames < 1 || std::abs(frames * o.d_eps - o.eps_end) > 1e-12) {
    usage("--eps-end must be a whole number of --d-eps frames");
  }
  const double frame_dt = o.d_eps * h0 / sc.V;

  StepCounter counter;
  std::streambuf* const console = std::cout.rdbuf(&counter);

  Simulation sim;
  sim.initialize(/*save*/ false, "", "compaction_column");
  sim.reduce_verbose = false;  // Matter prints "Step:" only then: the filter counts the steps
  sim.n_threads = o.threads;
  sim.fps = 1.0 / frame_dt;
  sim.end_frame = o.check_dir.empty() ? frames : 1;
  sim.cfl = 0.5;  // Matter's advective limit, cfl dx / max speed: far above its elastic one here
  sim.cfl_elastic = cfl_elastic;
  sim.flip_ratio = -2.0;  // below -1: pure APIC
  sim.elastic_model = ElasticModel::Hencky;
  sim.E = sc.E;
  sim.nu = nu;
  sim.rho = rho;
  sim.gravity = TV::Zero();
  sim.plastic_model = PlasticModel::VM;
  sim.q_max = q_y;
  sim.q_prefac = std::sqrt(1.5);  // q = sqrt(3/2 s:s), the paper's convention
  sim.Lx = sc.L;                  // the periodic width
  sim.Ly = h0;                    // the fixed grid's height (remeshFixed)
  sim.pbc = true;
  sim.dx = sc.dx;

  const std::vector<TV> x = column_particles(o, sc);
  sim.Np = static_cast<unsigned int>(x.size());
  sim.particles = Particles(sim.Np);
  sim.particles.x = x;
  sim.particle_volume = sc.spacing * sc.spacing;
  sim.particle_mass = rho * sim.particle_volume;
  // PBCAddParticles appends the ghost copies with push_back inside an omp critical section while
  // the other threads go on reading the same vectors; with their capacity reserved no push_back
  // reallocates, so those reads stay valid on two threads (the copies are at most all particles).
  const std::size_t room = 2 * x.size() + 16;
  sim.particles.x.reserve(room);
  sim.particles.v.reserve(room);
  sim.particles.F.reserve(room);
  sim.particles.Bmat.reserve(room);
  sim.particles.tau.reserve(room);

  sim.plates.push_back(std::make_unique<ObjectPlate>(0.0, PlateType::bottom, BC::SlipStick, 0.0));
  sim.plates.push_back(std::make_unique<ObjectPlate>(h0, PlateType::top, BC::SlipStick, 0.0,
                                                     -1e15, 1e15, 0.0, -sc.V));

  double wall = 0.0;
  if (o.check_dir.empty()) {
    const double t0 = now();
    sim.simulate();
    wall = now() - t0;
  } else {
    // One frame per simulate() call: the state (particles, plates, step counter) carries over,
    // simulate() restarts its clock at 0 and its frame at 0, and the step within a frame is
    // clamped to the frame's end as in one call over all frames.
    std::ofstream fc(o.check_dir + "/frames.csv");
    fc << "eps,kinetic_energy,momentum_y,sigma_top_minus_bottom\n";
    auto momentum = [&] {
      double p = 0.0, ke = 0.0;
      for (unsigned k = 0; k < sim.Np; ++k) {
        p += sim.particle_mass * sim.particles.v[k](1);
        ke += 0.5 * sim.particle_mass * sim.particles.v[k].squaredNorm();
      }
      return std::pair{p, ke};
    };
    double p_before = 0.0;
    for (int f = 1; f <= frames; ++f) {
      const double t0 = now();
      sim.simulate();
      wall += now() - t0;
      const auto [p, ke] = momentum();
      fc << f * o.d_eps << ',' << ke << ',' << p << ',' << -(p - p_before) / (frame_dt * sc.L)
         << '\n';
      p_before = p;
    }
    const int n_rows_dx = static_cast<int>(std::lround(h0 / sc.dx));
    std::vector<double> sum(n_rows_dx, 0.0);
    std::vector<int> count(n_rows_dx, 0);
    std::ofstream pb(o.check_dir + "/particles.bin", std::ios::binary);
    for (unsigned k = 0; k < sim.Np; ++k) {
      const TV& xp = sim.particles.x[k];
      const int r = static_cast<int>(std::floor(xp(1) / sc.dx));
      if (r >= 0 && r < n_rows_dx) sum[r] += sim.particles.v[k](1) / sc.V, ++count[r];
      const double rec[4] = {xp(0), xp(1), sim.particles.eps_pl_dev[k],
                             sim.particles.F[k].determinant()};
      pb.write(reinterpret_cast<const char*>(rec), sizeof rec);
    }
    std::ofstream vc(o.check_dir + "/velocity.csv");
    for (int r = 0; r < n_rows_dx; ++r) vc << (count[r] ? sum[r] / count[r] : 0.0) << '\n';
  }
  std::cout.rdbuf(console);

  const double n = sim.Np;  // after simulate(): the ghost copies are removed before G2P
  const double ghosts = sim.num_add_pbc_particles;  // of the last step
  std::printf(
      "{\"steps\": %ld, \"n_particles\": %.0f, \"n_ghosts_last_step\": %.0f, "
      "\"n_with_ghosts\": %.0f, \"wall_seconds\": %.6f, \"ns_per_particle_step\": %.3f, "
      "\"ns_per_particle_step_with_ghosts\": %.3f, \"dt_elastic\": %.9g, \"cfl_elastic\": %.6f, "
      "\"hole_side_particles\": %d, \"plate_top_y\": %.9g, \"last_proj\": \"%s\", "
      "\"threads\": %d, \"frames\": %d}\n",
      counter.steps, n, ghosts, n + ghosts, wall, 1e9 * wall / (counter.steps * n),
      1e9 * wall / (counter.steps * (n + ghosts)), cfl_elastic * sc.dx / sc.bar_c, cfl_elastic,
      sc.n_holes_side, sim.plates[1]->pos_object, counter.last_proj.c_str(), o.threads, frames);
  return sim.exit;
}

// Matter's output functions (src/simulation/save_data.cpp, which needs tinyply) as no-ops: this
// driver runs with save_sim = false, so simulate() never calls them, but it names them.
void Simulation::saveInfo() {}
void Simulation::saveTiming() {}
void Simulation::saveAvgData() {}
void Simulation::computeAvgData(TM&, TM&, T&) {}
void Simulation::saveParticleData(std::string) {}
void Simulation::saveGridData(std::string) {}
