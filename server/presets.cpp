#include "presets.hpp"

namespace compaction::server {

const std::vector<Preset>& presets() {
  // Resolution is counted across the thinnest strut, L (1 - sqrt(1 - phi)), so that a preset
  // means the same accuracy at every phi (8, 20 and 40 cells per unit cell at phi = 0.4). The
  // errors are those of studies/validation/results/solid-fractions-split-fields.md (default) and
  // studies/reference/README.md (fast) for the band of example (a). The default preset's numbers are the
  // engine's defaults (SceneParams), which the scene schema serves to the scripts.
  static const SceneParams engine_default;
  static const std::vector<Preset> all = {
      {"fast", "1.8 cells across a strut (8 per unit cell at phi = 0.4), one velocity field: "
               "about 1/40 of the default's cost; labels (b)-(f) right, (a) comes out as (b)",
       1.8, 2, 0.5, PoreContact::single_field},
      {"default", "4.5 cells across a strut (20 per unit cell at phi = 0.4), two velocity fields "
                  "across closing pores where 3 cells span the thinnest strut (pore_contact auto): "
                  "all six of the paper's labels at phi = 0.4; band speed of (a) within 5 % of "
                  "1/(1 - phi) at phi 0.3-0.6 (+3 % at 0.4)",
       engine_default.cells_per_strut, engine_default.particles_per_cell, engine_default.cfl,
       PoreContact::automatic},
      {"reference", "9 cells across a strut (40 per unit cell at phi = 0.4), the default's pore "
                    "contact at twice its resolution, for convergence checks: about 8x the "
                    "default's cost",
       9.0, 2, 0.5, PoreContact::automatic},
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
          {"cfl", p.cfl},
          {"pore_contact", to_string(p.pore_contact)}};
}

}  // namespace compaction::server
