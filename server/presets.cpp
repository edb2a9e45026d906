#include "presets.hpp"

namespace compaction::server {

const std::vector<Preset>& presets() {
  static const std::vector<Preset> all = {
      {"fast", "coarse grid for quick maps: about 1/16 of the default's cost per unit strain", 8, 2,
       0.5},
      {"default", "the engine's default resolution (20 cells per unit cell)", 20, 2, 0.5},
      {"reference", "fine grid for convergence checks: about 8x the default's cost", 40, 2, 0.5},
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
