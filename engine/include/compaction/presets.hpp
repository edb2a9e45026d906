// Named numerics of a run: "fast", "default" and "reference", defined here and nowhere else.
// compaction-run --preset, a sweep's "preset" (the server), GET /api/v1/presets and the sweep
// form all read this table. "default" is SceneParams' own numerics: a scene that sets none of
// them runs the default preset. Resolution is counted across the thinnest strut,
// L (1 - sqrt(1 - phi)), so that a preset means the same accuracy at every phi (8, 20 and 40
// cells per unit cell at phi = 0.4); the accuracy each buys is measured in
// studies/validation/results/solid-fractions-split-fields.md (default) and
// studies/reference/README.md (fast, reference) for the band of example (a).
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "compaction/params.hpp"

namespace compaction {

struct Preset {
  std::string name;
  std::string description;
  double cells_per_strut;     // grid cells across the thinnest strut, at any phi  [-]
  int particles_per_cell;     // per direction                                    [-]
  double cfl;                 // time step factor                                 [-]
  PoreContact pore_contact;   // how closing pores are resolved (docs/engine.md)
};

inline constexpr std::string_view kDefaultPreset = "default";

const std::vector<Preset>& presets();
const Preset* find_preset(std::string_view name);  // nullptr when there is none
std::string preset_names();                         // "fast, default, reference"

// The scene keys a preset sets, as compaction::from_json reads them.
nlohmann::json preset_json(const Preset& p);
// Sets the preset's numerics on a scene.
void apply_preset(const Preset& preset, SceneParams& p);

// The preset whose numerics a scene has (all four keys equal), or nullptr.
const Preset* matching_preset(const SceneParams& p);
// The keys of `preset` that the scene sets otherwise, with the scene's values.
nlohmann::json overridden_keys(const Preset& preset, const SceneParams& p);

}  // namespace compaction
