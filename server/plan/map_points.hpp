// The map's points from its runs (GET /api/v1/phase-map, the export): the runs of the map grouped
// by their point (migration 0011: a computation up to its seed) and read together through
// point_tally.hpp. A point's band-speed readings are those of the runs that carry its label, so
// that a point split between (a) and (b) reports the speed of its majority's mechanism.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "plan/point_tally.hpp"
#include "store/store_reads.hpp"

namespace compaction::server {

struct MapPoint {
  std::int64_t point_id = 0;
  double S = 0, R = 0, phi = 0, eps_end = 0;
  std::int64_t cells_per_unit = 0;
  std::string structure, geometry;
  std::vector<std::int64_t> jobs;  // its runs, by id
  Tally tally;
  std::optional<Spread> band_speed_ratio, band_speed_early, band_speed_lead, band_speed_transit,
      n_reflections;
};

// One MapPoint per point of the runs, in the order of each point's first run.
std::vector<MapPoint> map_points(const std::vector<PhaseMapPoint>& runs);

// Whether a run has ended for good: succeeded, failed or cancelled (not queued or running).
bool run_finished(const std::string& state);

}  // namespace compaction::server
