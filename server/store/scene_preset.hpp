// The numerics preset a job's scene was made from (compaction/presets.hpp), for the run table's
// preset column (migration 0012 calls it as the SQL function compaction_preset(scene)).
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "compaction/params.hpp"

namespace compaction {
struct Preset;
}

namespace compaction::server {

// The preset whose numerics the scene has as the planner makes a job's scene of it: the
// preset's keys with its pore contact resolved for the scene ("auto" becomes what the scene
// runs, planner.cpp), and no grid of the scene's own (cells_per_unit). nullptr: numerics of its
// own. (compaction::matching_preset compares the contact as asked, so it names no preset for a
// job of a preset with "auto".)
const Preset* scene_preset(const SceneParams& scene);

// The same from a scene's canonical JSON text: the preset's name, nullopt for none or for a
// text that is no scene. The SQL function compaction_preset.
std::optional<std::string> scene_preset_name(std::string_view scene_json);

}  // namespace compaction::server
