#include "plan/map_points.hpp"

#include <unordered_map>

#include "plan/counted_label.hpp"

namespace compaction::server {

bool run_finished(const std::string& state) { return state != "queued" && state != "running"; }

namespace {

// A run's counted label (counted_label.hpp); none for a run that did not succeed.
adaptive::Labelled label_of(const PhaseMapPoint& r) {
  const adaptive::Point at{r.S, r.R};
  if (r.state != "succeeded") return {at, std::nullopt, 0.0, std::nullopt};
  return counted_label(at, r.human_label, r.cls, r.confidence, r.runner_up);
}

// The spread of one reading over the runs that carry the label.
template <typename Get>
std::optional<Spread> reading(const std::vector<const PhaseMapPoint*>& runs,
                              const std::vector<adaptive::Labelled>& labels,
                              const std::optional<std::string>& label, Get get) {
  std::vector<double> values;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    if (!label || labels[i].label != label) continue;
    if (const auto v = get(*runs[i])) values.push_back(static_cast<double>(*v));
  }
  return spread(values);
}

}  // namespace

std::vector<MapPoint> map_points(const std::vector<PhaseMapPoint>& runs) {
  std::vector<std::vector<const PhaseMapPoint*>> groups;
  std::unordered_map<std::int64_t, std::size_t> index;
  for (const PhaseMapPoint& r : runs) {
    // A job without a point (none is, after migration 0011) stands alone.
    const auto [it, fresh] = index.try_emplace(r.point_id ? r.point_id : -r.job_id, groups.size());
    if (fresh) groups.emplace_back();
    groups[it->second].push_back(&r);
  }
  std::vector<MapPoint> out;
  out.reserve(groups.size());
  for (const auto& g : groups) {
    const PhaseMapPoint& first = *g.front();
    MapPoint p;
    p.point_id = first.point_id;
    p.S = first.S, p.R = first.R, p.phi = first.phi, p.eps_end = first.eps_end;
    p.cells_per_unit = first.cells_per_unit;
    p.structure = first.structure;
    p.geometry = first.geometry;
    std::vector<adaptive::Labelled> labels, finished;
    for (const PhaseMapPoint* r : g) {
      p.jobs.push_back(r->job_id);
      labels.push_back(label_of(*r));
      if (run_finished(r->state)) finished.push_back(labels.back());
    }
    p.tally = tally({p.S, p.R}, finished, g.size());
    const auto& label = p.tally.label;
    p.band_speed_ratio = reading(g, labels, label, [](const PhaseMapPoint& r) { return r.band_speed_ratio; });
    p.band_speed_early = reading(g, labels, label, [](const PhaseMapPoint& r) { return r.band_speed_early; });
    p.band_speed_lead = reading(g, labels, label, [](const PhaseMapPoint& r) { return r.band_speed_lead; });
    p.band_speed_transit =
        reading(g, labels, label, [](const PhaseMapPoint& r) { return r.band_speed_transit; });
    p.n_reflections = reading(g, labels, label, [](const PhaseMapPoint& r) { return r.n_reflections; });
    out.push_back(std::move(p));
  }
  return out;
}

}  // namespace compaction::server
