// spacetime.png: the space-time map of a run as a figure, drawn as the dashboard's run page
// draws it: the map of height y / h0 against imposed strain, ticks and labels on both axes, the
// top plate's line y / h0 = 1 - eps above which no material is, and a colour bar of
// log10(1 + rate / (V / h0)) clipped at the map's 99.5th percentile (cairo, DejaVu Sans).
#pragma once

#include <filesystem>
#include <vector>

#include "compaction/result.hpp"

namespace compaction {

// frame_eps: the imposed strain at the end of each frame (RunResult::frames). Nothing is written
// for an empty map. Throws std::runtime_error when the file cannot be written.
void write_spacetime_figure(const std::filesystem::path& path, const SpaceTimeMap& map,
                            const std::vector<double>& frame_eps, double h0);

}  // namespace compaction
