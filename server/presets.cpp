#include "presets.hpp"

namespace compaction::server {

const std::vector<Preset>& presets() {
  // Points on the measured front of error against run time (docs/accuracy.md): 8 cells per
  // unit cell labels (b)-(f) right at 1/16 of the default's cost; 20 is the coarsest grid that
  // keeps all six of the paper's labels; 30 is the finest grid measured (the accuracy
  // study's reference).
  static const std::vector<Preset> all = {
      {"fast", "coarse grid for quick maps (8 cells per unit cell): about 1/16 of the default's "
               "cost; labels (b)-(f) right, (a) comes out as (b)", 8, 2, 0.5},
      {"default", "20 cells per unit cell: the coarsest grid that gives all six of the paper's "
                  "labels", 20, 2, 0.5},
      {"reference", "30 cells per unit cell, for convergence checks: about 3.4x the default's "
                    "cost", 30, 2, 0.5},
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
  return {{"cells_per_unit", p.cells_per_unit},
          {"particles_per_cell", p.particles_per_cell},
          {"cfl", p.cfl}};
}

}  // namespace compaction::server
