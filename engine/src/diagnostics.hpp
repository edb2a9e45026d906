// What a run records once per frame: plate stresses, the space-time map row, the row velocity
// profile, energies, strut deflections, the particle snapshots and the movie frames that fall
// due.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "compaction/params.hpp"
#include "compaction/result.hpp"
#include "movie_recorder.hpp"
#include "state.hpp"

namespace compaction {

class FrameRecorder {
 public:
  // movie_file: where the movie goes (movie.hpp) when p.movie_d_eps > 0; empty: no movie.
  FrameRecorder(const SceneParams& p, const State& s, const std::string& movie_file = {});

  // Closes the frame [eps_begin, eps_end] of imposed strain: appends a Frame and a row of the
  // space-time map to `out`, takes a snapshot when one is due, and resets the per-frame
  // accumulators of the particles (plastic increments) and of the clock (plate impulses).
  void record(State& s, double eps_begin, double eps_end, RunResult& out);

  // Frames of the movie written so far (0 without a movie), and going on from a file that
  // held that many (a resumed run; MovieRecorder::resume).
  std::int64_t movie_frames() const { return movie_ ? movie_->frames_written() : 0; }
  void resume_movie(std::int64_t frames) { if (movie_) movie_->resume(frames); }

  // How many of the scene's snapshot strains the frames recorded so far have passed (a
  // checkpoint keeps it; a resumed run's recorder goes on from it).
  std::size_t snapshots_passed() const { return next_snapshot_; }
  void resume_snapshots(std::size_t passed) { next_snapshot_ = passed; }

 private:
  struct ParticleTotals {
    double kinetic = 0.0;  // sum of |v|^2 (times m/2: the kinetic energy)
    double max_v2 = 0.0;
    std::size_t plastic = 0;  // particles that flowed in this frame
  };
  struct Deflections {
    double max = 0.0, rms = 0.0;  // strut deflections / strut thickness
  };

  // Adds each particle's plastic increment into ep and into its row and strut sums.
  ParticleTotals sum_particles(State& s);
  Deflections strut_deflections(double strut_thickness) const;
  void append_map_rows(RunResult& out, double d_eps, double V) const;
  void take_snapshot_if_due(const Particles& P, double eps_end, double d_eps, RunResult& out);

  double x_lo_, x_hi_;  // particles outside [x_lo, x_hi) are left out of the map (wall zones)
  std::vector<double> row_sum_;
  std::vector<double> row_vy_;
  std::vector<int> row_count_;
  std::vector<double> mid_sum_, end_sum_;
  std::vector<int> mid_n_, end_n_;
  std::vector<double> snapshots_due_;  // ascending
  std::size_t next_snapshot_ = 0;
  std::unique_ptr<MovieRecorder> movie_;
};

}  // namespace compaction
