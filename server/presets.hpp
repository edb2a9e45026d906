// Named resolution presets of the numerics a sweep may ask for ("fast", "default", "reference").
// A sweep's explicit numerics override its preset's values key by key.
#pragma once

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "compaction/params.hpp"

namespace compaction::server {

struct Preset {
  std::string name;
  std::string description;
  double cells_per_strut;  // grid cells across the thinnest strut, at any phi  [-]
  int particles_per_cell;  // per direction                                    [-]
  double cfl;              // time step factor                                 [-]
  PoreContact pore_contact;  // how closing pores are resolved (docs/engine.md)
};

const std::vector<Preset>& presets();
const Preset* find_preset(std::string_view name);
constexpr std::string_view default_preset_name = "default";

// The scene keys of a preset, ready for compaction::from_json.
nlohmann::json preset_scene_json(const Preset& p);

}  // namespace compaction::server
