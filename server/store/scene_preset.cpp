#include "store/scene_preset.hpp"

#include <nlohmann/json.hpp>

#include "compaction/params_json.hpp"
#include "compaction/presets.hpp"

namespace compaction::server {

const Preset* scene_preset(const SceneParams& scene) {
  for (const Preset& p : presets()) {
    // A preset of other cells across a strut cannot match: that skips overridden_keys, which
    // writes the whole scene as JSON, for all but one preset (the sweeps' inserts call this).
    if (scene.cells_per_strut != p.cells_per_strut) continue;
    SceneParams asked = scene;  // the scene as a sweep of the preset asked for it
    asked.pore_contact = p.pore_contact;
    if (resolved_pore_contact(asked) == scene.pore_contact && overridden_keys(p, asked).empty()) {
      return &p;
    }
  }
  return nullptr;
}

std::optional<std::string> scene_preset_name(std::string_view scene_json) {
  const auto j = nlohmann::json::parse(scene_json, nullptr, false);
  SceneParams p;
  if (j.is_discarded() || !read_json(j, p).empty()) return std::nullopt;
  const Preset* preset = scene_preset(p);
  return preset ? std::optional<std::string>(preset->name) : std::nullopt;
}

}  // namespace compaction::server
