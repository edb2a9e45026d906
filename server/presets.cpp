#include "presets.hpp"

namespace compaction::server {

const std::vector<Preset>& presets() {
  // Resolution is counted across the thinnest strut, L (1 - sqrt(1 - phi)), so that a preset
  // means the same accuracy at every phi (8, 20 and 40 cells per unit cell at phi = 0.4). The
  // errors are those of docs/reference.md against the converged band of example (a).
  static const std::vector<Preset> all = {
      {"fast", "1.8 cells across a strut (8 per unit cell at phi = 0.4): about 1/16 of the "
               "default's cost; labels (b)-(f) right, (a) comes out as (b)", 1.8, 2, 0.5},
      {"default", "4.5 cells across a strut (20 per unit cell at phi = 0.4): the coarsest grid "
                  "that gives all six of the paper's labels; band speed of (a) 10-12 % fast",
       4.5, 2, 0.5},
      {"reference", "9 cells across a strut (40 per unit cell at phi = 0.4), for convergence "
                    "checks: about 8x the default's cost; band speed of (a) within 3 % of the "
                    "converged value", 9.0, 2, 0.5},
  };
  return all;
}

const Preset* find_preset(std::string_view name) {
  for (const auto& p : presets()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

nlohmann::json preset_scene_json(const Preset& p) {
  return {{"cells_per_strut", p.cells_per_strut},
          {"particles_per_cell", p.particles_per_cell},
          {"cfl", p.cfl}};
}

}  // namespace compaction::server
