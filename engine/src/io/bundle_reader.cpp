// Reads a result bundle back into the public types (used by the classifier and the tests).
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "compaction/bundle.hpp"
#include "compaction/params_json.hpp"
#include "npy.hpp"

namespace compaction {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

json read_json(const fs::path& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path.string());
  try {
    return json::parse(f);
  } catch (const json::exception& e) {
    throw std::runtime_error(path.string() + ": " + e.what());
  }
}

std::vector<Frame> read_frames(const fs::path& path) {
  std::ifstream f(path);
  if (!f) throw std::runtime_error("cannot read " + path.string());
  std::string line;
  std::getline(f, line);  // header
  std::vector<Frame> frames;
  int n = 1;
  while (std::getline(f, line)) {
    ++n;
    std::istringstream s(line);
    double v[11];
    char comma;
    for (int i = 0; i < 11; ++i) {
      if (!(s >> v[i]) || (i < 10 && !(s >> comma))) {
        throw std::runtime_error(path.string() + ":" + std::to_string(n) + ": malformed row");
      }
    }
    Frame fr;
    fr.eps = v[0], fr.sigma_top = v[1], fr.sigma_bottom = v[2];
    fr.kinetic_energy = v[5], fr.plate_work = v[6], fr.plastic_fraction = v[7];
    fr.max_deflection = v[8], fr.rms_deflection = v[9], fr.max_speed = v[10];
    frames.push_back(fr);
  }
  return frames;
}

}  // namespace

Bundle read_bundle(const fs::path& dir) {
  Bundle b;
  b.summary = read_json(dir / "summary.json");
  const auto errors = from_json(b.summary.at("params"), b.params);
  if (!errors.empty()) {
    throw std::runtime_error((dir / "summary.json").string() + ": params." + errors[0].field +
                             " " + errors[0].message);
  }
  RunResult& r = b.result;
  const json& s = b.summary;
  parse(s.at("status").get<std::string>(), r.status);
  r.reason = s.value("reason", "");
  r.failed_step = s.value("failed_step", -1);
  r.n_particles = s.at("n_particles").get<std::int64_t>();
  r.grid_nx = s.at("grid").at("nx").get<int>();
  r.grid_ny = s.at("grid").at("ny").get<int>();
  r.dx = s.at("grid").at("dx").get<double>();
  r.phi_discrete = s.at("phi_discrete").get<double>();
  r.steps = s.at("steps").get<std::int64_t>();
  r.dt_mean = s.at("dt_mean").get<double>();
  r.eps_reached = s.at("eps_reached").get<double>();
  r.wall_seconds = s.at("wall_seconds").get<double>();
  r.ns_per_particle_step = s.at("ns_per_particle_step").get<double>();
  r.frames = read_frames(dir / "frames.csv");

  npy::Array map = npy::read(dir / "spacetime.npy");
  if (map.shape.size() != 2) throw std::runtime_error("spacetime.npy: expected 2 dimensions");
  r.spacetime.n_frames = static_cast<int>(map.shape[0]);
  r.spacetime.n_rows = static_cast<int>(map.shape[1]);
  r.spacetime.row_height = s.at("spacetime").at("row_height").get<double>();
  r.spacetime.values = std::move(map.data);
  if (s.contains("velocity")) {  // bundles from before the velocity map have none
    npy::Array vel = npy::read(dir / "velocity.npy");
    if (vel.shape.size() != 2 || vel.shape[0] != map.shape[0] || vel.shape[1] != map.shape[1]) {
      throw std::runtime_error("velocity.npy: expected the shape of spacetime.npy");
    }
    r.velocity.n_frames = r.spacetime.n_frames;
    r.velocity.n_rows = r.spacetime.n_rows;
    r.velocity.row_height = r.spacetime.row_height;
    r.velocity.values = std::move(vel.data);
  }

  for (const json& js : s.at("snapshots")) {
    npy::Array a = npy::read(dir / js.at("file").get<std::string>());
    if (a.shape.size() != 2 || a.shape[1] != 5) {
      throw std::runtime_error(js.at("file").get<std::string>() + ": expected shape (n, 5)");
    }
    Snapshot snap;
    snap.eps = js.at("eps").get<double>();
    for (std::size_t i = 0; i < a.shape[0]; ++i) {
      const float* row = &a.data[i * 5];
      snap.x.push_back(row[0]), snap.y.push_back(row[1]), snap.strain_rate.push_back(row[2]);
      snap.plastic_strain.push_back(row[3]), snap.jacobian.push_back(row[4]);
    }
    r.snapshots.push_back(std::move(snap));
  }
  return b;
}

}  // namespace compaction
