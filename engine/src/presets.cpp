#include "compaction/presets.hpp"

#include "compaction/params_json.hpp"

namespace compaction {

const std::vector<Preset>& presets() {
  static const SceneParams defaults;
  static const std::vector<Preset> all = {
      {"fast", "1.8 cells across a strut (8 per unit cell at phi = 0.4), one velocity field: "
               "about 1/40 of the default's cost; labels (b)-(f) right, (a) comes out as (b)",
       1.8, 2, 0.5, PoreContact::single_field},
      {"default", "4.5 cells across a strut (20 per unit cell at phi = 0.4), two velocity fields "
                  "across closing pores where 3 cells span the thinnest strut (pore_contact auto): "
                  "all six of the paper's labels at phi = 0.4; band speed of (a) within 5 % of "
                  "1/(1 - phi) at phi 0.3-0.6 (+3 % at 0.4)",
       defaults.cells_per_strut, defaults.particles_per_cell, defaults.cfl, defaults.pore_contact},
      {"reference", "9 cells across a strut (40 per unit cell at phi = 0.4), the default's pore "
                    "contact at twice its resolution, for convergence checks: about 8x the "
                    "default's cost",
       9.0, 2, 0.5, PoreContact::automatic},
  };
  return all;
}

const Preset* find_preset(std::string_view name) {
  for (const Preset& p : presets()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

std::string preset_names() {
  std::string out;
  for (const Preset& p : presets()) out += (out.empty() ? "" : ", ") + p.name;
  return out;
}

nlohmann::json preset_json(const Preset& p) {
  return {{"cells_per_strut", p.cells_per_strut},
          {"particles_per_cell", p.particles_per_cell},
          {"cfl", p.cfl},
          {"pore_contact", to_string(p.pore_contact)}};
}

void apply_preset(const Preset& preset, SceneParams& p) {
  p.cells_per_strut = preset.cells_per_strut;
  p.particles_per_cell = preset.particles_per_cell;
  p.cfl = preset.cfl;
  p.pore_contact = preset.pore_contact;
}

nlohmann::json overridden_keys(const Preset& preset, const SceneParams& p) {
  nlohmann::json out = nlohmann::json::object();
  const nlohmann::json scene = to_json(p);
  const nlohmann::json keys = preset_json(preset);
  for (const auto& [key, value] : keys.items()) {
    if (scene.at(key) != value) out[key] = scene.at(key);
  }
  // A grid given in cells per unit cell overrides any preset's cells across the strut.
  if (p.cells_per_unit > 0) out["cells_per_unit"] = p.cells_per_unit;
  return out;
}

const Preset* matching_preset(const SceneParams& p) {
  for (const Preset& preset : presets()) {
    if (overridden_keys(preset, p).empty()) return &preset;
  }
  return nullptr;
}

}  // namespace compaction
