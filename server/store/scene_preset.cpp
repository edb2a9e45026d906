#include "store/scene_preset.hpp"

#include <nlohmann/json.hpp>

#include "compaction/params_json.hpp"
#include "compaction/presets.hpp"

namespace compaction::server {

const Preset* scene_preset(const SceneParams& scene) {
  for (const Preset& p : presets()) {
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
  if (j.is_discarded() || !from_json(j, p).empty()) return std::nullopt;
  const Preset* preset = scene_preset(p);
  return preset ? std::optional<std::string>(preset->name) : std::nullopt;
}

}  // namespace compaction::server
