// Writes a run's result bundle: summary.json, frames.csv, the .npy arrays and the pictures.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "colormap.hpp"
#include "compaction/bundle.hpp"
#include "compaction/movie.hpp"
#include "compaction/params_json.hpp"
#include "npy.hpp"
#include "png_image.hpp"
#include "spacetime_figure.hpp"

namespace compaction {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string snapshot_name(double eps) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "snapshot_%.3f", eps);
  return buf;
}

// Colour scale of strain rates: log10(1 + v) up to a high percentile of the data, so that a
// few extreme values do not wash out the picture.
double colour_scale(std::vector<float> values) {
  values.erase(std::remove_if(values.begin(), values.end(),
                              [](float v) { return !(v > 0.0f) || !std::isfinite(v); }),
               values.end());
  if (values.empty()) return 1.0;
  const std::size_t k = static_cast<std::size_t>(0.995 * (values.size() - 1));
  std::nth_element(values.begin(), values.begin() + k, values.end());
  return std::max(1e-12, std::log10(1.0 + values[k]));
}

void write_snapshot_png(const fs::path& path, const SceneParams& p, const RunResult& r,
                        const Snapshot& s) {
  // Pseudo-1D shows eight periods side by side so that the structure reads as a structure.
  const int copies = p.geometry == Geometry::pseudo1d ? 8 : 1;
  const double width = p.width() * copies;
  const int height = 1400;
  const double px_per_m = height / p.h0;
  Image img(std::max(1, static_cast<int>(width * px_per_m)), height, {255, 255, 255});
  const double spacing = r.dx / p.particles_per_cell;
  const int dot = std::max(1, static_cast<int>(std::ceil(spacing * px_per_m)));
  const double scale = colour_scale(s.strain_rate);
  for (std::size_t i = 0; i < s.x.size(); ++i) {
    const Rgb c = inferno(0.15 + 0.85 * std::log10(1.0 + s.strain_rate[i]) / scale);
    for (int k = 0; k < copies; ++k) {
      const int x = static_cast<int>((s.x[i] + k * p.width()) * px_per_m);
      const int y = img.height - 1 - static_cast<int>(s.y[i] * px_per_m);
      img.fill_rect(x - dot / 2, y - dot / 2, x - dot / 2 + dot, y - dot / 2 + dot, c);
    }
  }
  write_png(path, img);
}

void write_frames_csv(const fs::path& path, const SceneParams& p, const RunResult& r) {
  std::ofstream f(path);
  if (!f) throw std::runtime_error("cannot write " + path.string());
  f << "eps,sigma_top,sigma_bottom,sigma_top_over_qy,sigma_bottom_over_qy,kinetic_energy,"
       "plate_work,plastic_fraction,max_deflection,rms_deflection,max_speed_over_V\n";
  char line[512];
  for (const Frame& fr : r.frames) {
    std::snprintf(line, sizeof line, "%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g,%.9g\n",
                  fr.eps, fr.sigma_top, fr.sigma_bottom, fr.sigma_top / p.q_y,
                  fr.sigma_bottom / p.q_y, fr.kinetic_energy, fr.plate_work,
                  fr.plastic_fraction, fr.max_deflection, fr.rms_deflection, fr.max_speed);
    f << line;
  }
  if (!f) throw std::runtime_error("error writing " + path.string());
}

}  // namespace

json summary_json(const SceneParams& p, const RunResult& r) {
  json snaps = json::array();
  for (const Snapshot& s : r.snapshots) {
    snaps.push_back({{"eps", s.eps},
                     {"file", snapshot_name(s.eps) + ".npy"},
                     {"image", snapshot_name(s.eps) + ".png"},
                     {"n_particles", s.x.size()},
                     {"columns", {"x", "y", "strain_rate", "plastic_strain", "jacobian"}}});
  }
  return json{
      {"params", to_json(p)},
      {"engine_version", engine_version()},
      {"source_revision", source_revision()},
      {"status", to_string(r.status)},
      {"reason", r.reason},
      {"failed_step", r.failed_step},
      {"seed", p.seed},
      {"n_particles", r.n_particles},
      {"grid",
       {{"nx", r.grid_nx},
        {"ny", r.grid_ny},
        {"dx", r.dx},
        {"cells_per_unit", p.grid_cells_per_unit()},
        {"cells_per_strut", p.grid_cells_per_strut()},
        {"pore_contact", to_string(resolved_pore_contact(p))}}},
      {"phi_discrete", r.phi_discrete},
      {"steps", r.steps},
      {"dt_mean", r.dt_mean},
      {"eps_reached", r.eps_reached},
      {"wall_seconds", r.wall_seconds},
      {"ns_per_particle_step", r.ns_per_particle_step},
      {"stage_seconds",
       {{"p2g", r.stage_seconds.p2g},
        {"grid_update", r.stage_seconds.grid_update},
        {"g2p", r.stage_seconds.g2p},
        {"diagnostics", r.stage_seconds.diagnostics}}},
      {"derived",
       {{"E", p.youngs_modulus()},
        {"V", p.plate_speed()},
        {"bar_wave_speed", p.bar_wave_speed()},
        {"p_wave_speed", p.p_wave_speed()},
        {"lame_lambda", p.lame_lambda()},
        {"lame_mu", p.lame_mu()},
        {"unit_cell", p.unit_cell()},
        {"hole_side", p.hole_side()}}},
      {"frames", {{"file", "frames.csv"}, {"count", r.frames.size()}}},
      {"spacetime",
       {{"file", "spacetime.npy"},
        {"image", "spacetime.png"},
        {"shape", {r.spacetime.n_frames, r.spacetime.n_rows}},
        {"row_height", r.spacetime.row_height},
        {"quantity", "row-averaged |d eps_P/dt| / (V/h0)"}}},
      {"velocity",
       {{"file", "velocity.npy"},
        {"shape", {r.velocity.n_frames, r.velocity.n_rows}},
        {"row_height", r.velocity.row_height},
        {"quantity", "row-averaged vertical particle velocity / V at the end of each frame"}}},
      {"snapshots", snaps},
  };
}

namespace {

// An upper bound of the particles of a scene.
double particle_bound(const SceneParams& p) {
  const double cells_per_unit = p.grid_cells_per_unit();
  const double cells = cells_per_unit * cells_per_unit * p.cols() * p.n_rows;
  const double ppc = static_cast<double>(p.particles_per_cell) * p.particles_per_cell;
  return std::min(1.0, p.phi) * cells * ppc * 1.05 + 1000;  // rounding margin
}

}  // namespace

std::size_t movie_size_bound(const SceneParams& p) {
  const std::size_t frames = movie::frame_count(p);
  if (frames == 0) return 0;
  return movie::kHeaderBytes +
         frames * movie::frame_bytes(static_cast<std::size_t>(particle_bound(p)));
}

std::size_t bundle_size_bound(const SceneParams& p) {
  const double cells_per_unit = p.grid_cells_per_unit();
  const double particles = particle_bound(p);
  const double frames = p.eps_final() / p.d_eps + 2;
  const double grid_rows = cells_per_unit * p.n_rows + 8;
  constexpr double png_bound = 1400.0 * 1400.0 * 3 + (1 << 16);  // an uncompressed picture
  const double bytes = static_cast<double>(p.snapshot_eps.size()) * (20 * particles + png_bound) +
                       2 * frames * grid_rows * 4 + frames * 512 + png_bound + (1 << 20);
  return static_cast<std::size_t>(bytes) + movie_size_bound(p);
}

void write_bundle(const fs::path& dir, const SceneParams& p, const RunResult& r,
                  const json& summary_extras) {
  fs::create_directories(dir);
  write_frames_csv(dir / "frames.csv", p, r);
  const SpaceTimeMap& m = r.spacetime;
  npy::write(dir / "spacetime.npy", m.values.data(),
             {static_cast<std::size_t>(m.n_frames), static_cast<std::size_t>(m.n_rows)});
  std::vector<double> frame_eps;
  frame_eps.reserve(r.frames.size());
  for (const Frame& f : r.frames) frame_eps.push_back(f.eps);
  write_spacetime_figure(dir / "spacetime.png", m, frame_eps, p.h0);
  const SpaceTimeMap& v = r.velocity;
  npy::write(dir / "velocity.npy", v.values.data(),
             {static_cast<std::size_t>(v.n_frames), static_cast<std::size_t>(v.n_rows)});
  for (const Snapshot& s : r.snapshots) {
    const std::size_t n = s.x.size();
    std::vector<float> table(n * 5);
    for (std::size_t i = 0; i < n; ++i) {
      float* row = &table[i * 5];
      row[0] = s.x[i], row[1] = s.y[i], row[2] = s.strain_rate[i];
      row[3] = s.plastic_strain[i], row[4] = s.jacobian[i];
    }
    npy::write(dir / (snapshot_name(s.eps) + ".npy"), table.data(), {n, 5});
    write_snapshot_png(dir / (snapshot_name(s.eps) + ".png"), p, r, s);
  }
  // The summary goes last, whole or not at all: its presence marks a complete bundle.
  json summary = summary_json(p, r);
  // The movie is written during the run (RunControl::movie_file): listed when the run left one.
  if (const fs::path movie_file = dir / movie::kFileName; fs::exists(movie_file)) {
    const movie::Header h = movie::read_header(movie_file);
    summary["movie"] = {{"file", movie::kFileName},
                        {"frames", h.n_frames},
                        {"n_particles", h.n_particles},
                        {"d_eps", h.movie_d_eps},
                        {"format", "schema/movie-format.md"}};
  }
  summary.update(summary_extras);
  const fs::path tmp = dir / "summary.json.tmp";
  {
    std::ofstream f(tmp);
    f << summary.dump(2) << '\n';
    if (!f) throw std::runtime_error("error writing " + tmp.string());
  }
  fs::rename(tmp, dir / "summary.json");
}

}  // namespace compaction
