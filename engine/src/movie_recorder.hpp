// Records the movie of a run (compaction/movie.hpp) into its file while the run goes: one frame
// of the particles each time the imposed strain passes the next multiple of movie_d_eps. The
// frame buffer is allocated once; a frame is one write of frame_bytes(n) and a rewrite of the
// header's frame count, so the file is whole after every frame.
//
// Its only state is frames_written(): the next frame is due at (frames_written() + 1) *
// movie_d_eps, and frame k sits at kHeaderBytes + k * frame_bytes(n). A run resumed from a
// checkpoint calls resume() with the count the checkpoint kept and goes on from there.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "compaction/params.hpp"
#include "state.hpp"

namespace compaction {

class MovieRecorder {
 public:
  // Nothing is written yet: the file is created by the first frame (a run that records none
  // leaves no file), or reopened by resume().
  MovieRecorder(std::string path, const SceneParams& p, const State& s);
  ~MovieRecorder();
  MovieRecorder(const MovieRecorder&) = delete;
  MovieRecorder& operator=(const MovieRecorder&) = delete;

  // Goes on from a file this scene wrote, keeping its first frames_written frames (a run
  // resumed from a checkpoint that had written them). Throws std::runtime_error when the file
  // is not this scene's movie or holds fewer frames.
  void resume(std::int64_t frames_written);

  // Called when an output frame ends at eps_end: appends a frame when one is due. The rate of
  // a particle is its plastic increment over the last output frame / d_eps, as in snapshots.
  // Throws std::runtime_error when the file cannot be written.
  void record_if_due(const Particles& P, double eps_end, double d_eps);

  std::int64_t frames_written() const { return frames_; }

 private:
  void open(std::int64_t frames_written);
  [[noreturn]] void fail(const char* what) const;

  std::string path_;
  std::FILE* file_ = nullptr;
  double every_;                            // movie_d_eps
  double width_, height_;                   // the box of the positions: [0, width] x [0, h0]
  std::uint32_t flags_;
  std::size_t n_;
  std::vector<unsigned char> frame_;        // one frame, reused
  std::int64_t frames_ = 0;
};

}  // namespace compaction
