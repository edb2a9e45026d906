// The checkpoint file of every geometry (schema/checkpoint-format.md): its framing (magic,
// format version, JSON header, CRC-32, atomic write), the refusal of a file of another engine
// version or scene, and the sections all geometries share (clock, step measures, the loop's
// position, the result so far, the movie). A geometry brings its particle section only
// (checkpoint.cpp for 2D, checkpoint_3d.cpp for the 3D column).
#pragma once

#include <cstdint>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

#include "compaction/checkpoint.hpp"
#include "compaction/params.hpp"
#include "compaction/result.hpp"
#include "state.hpp"  // Clock, StepMeasure (dimension-free)

namespace compaction {

// Where the run loop stands between two steps, besides the state and the result so far.
struct RunPosition {
  std::int64_t frame = 0;         // frames closed
  double eps_frame_begin = 0.0;   // imposed strain at which the open frame began       [-]
  std::uint64_t snapshots_passed = 0;  // snapshot strains behind the recorder (FrameRecorder)
  double wall_seconds = 0.0;      // wall time of the run's sessions before this one      [s]
  double loop_seconds = 0.0;      // of which in the step loop                            [s]
  std::int64_t movie_frames = 0;  // frames of the movie written (FrameRecorder)
};

namespace checkpoint_file {

// Appends plain values and arrays (a 64-bit count, then the elements) to a byte buffer.
class Out {
 public:
  template <typename T>
  void put(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    buf_.append(reinterpret_cast<const char*>(&v), sizeof v);
  }
  template <typename T>
  void put_array(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    put(static_cast<std::uint64_t>(v.size()));
    if (!v.empty()) buf_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  void put_bytes(const std::string& s) { buf_.append(s); }
  std::string& bytes() { return buf_; }

 private:
  std::string buf_;
};

// Reads what Out wrote, refusing a file that ends early (CheckpointRefused).
class In {
 public:
  In(const std::string& buf, std::size_t pos, std::size_t end) : buf_(buf), pos_(pos), end_(end) {}
  template <typename T>
  T get() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    std::memcpy(&v, take(sizeof v), sizeof v);
    return v;
  }
  template <typename T>
  void get_array(std::vector<T>& v) {
    const auto n = get<std::uint64_t>();
    if (n > (end_ - pos_) / sizeof(T)) throw CheckpointRefused("checkpoint truncated (an array)");
    v.resize(n);
    if (n > 0) std::memcpy(v.data(), take(n * sizeof(T)), n * sizeof(T));  // data() may be null
  }
  // An array that must hold exactly n elements (a particle array).
  template <typename T>
  void get_array(std::vector<T>& v, std::size_t n, const char* what) {
    get_array(v);
    if (v.size() != n) {
      throw CheckpointRefused(std::string("checkpoint damaged: ") + what + " holds " +
                              std::to_string(v.size()) + " values for " + std::to_string(n) +
                              " particles");
    }
  }
  bool at_end() const { return pos_ == end_; }

 private:
  const char* take(std::size_t n);
  const std::string& buf_;
  std::size_t pos_, end_;
};

// The head of every particle section: count, mass and initial volume of the particles
// (the same for all of them). The reader refuses a checkpoint of other particles than those
// the scene builds (n, mass, vol0).
void put_particle_set(Out& o, std::size_t n, double mass, double vol0);
void get_particle_set(In& in, std::size_t n, double mass, double vol0);

// Writes the checkpoint of a state with this clock, last step's measures and n_particles
// particles at imposed strain eps (V t / h0, the header's) to `path` atomically (a temporary
// file beside it, flushed, renamed over it): the framing and shared sections around the
// geometry's particle section, which `particles` appends. `reserve`: the particle section's
// expected bytes. With at.movie_frames > 0 it holds the bytes of `movie_file` as written so
// far. Throws std::runtime_error on I/O errors; an earlier checkpoint at `path` then stays.
CheckpointInfo write(const std::string& path, const SceneParams& p, const Clock& clock,
                     const StepMeasure& measure, double eps, std::size_t n_particles,
                     const RunResult& r, const RunPosition& at, const std::string& movie_file,
                     std::size_t reserve, const std::function<void(Out&)>& particles);

// Reads the checkpoint at `path` over a state freshly built from p, the scene to run (its
// clock, measures, n_particles particles and maps of map_rows rows), its start result r and
// the loop's position; `particles` reads the geometry's particle section and refuses
// particles the scene does not build. movie_bytes, when given, receives the movie file as it
// was. Throws CheckpointRefused when the file is damaged or of another format, engine
// version or scene (threads aside).
CheckpointInfo restore(const std::string& path, const SceneParams& p, Clock& clock,
                       StepMeasure& measure, std::size_t n_particles, int map_rows,
                       RunResult& r, RunPosition& at, std::string* movie_bytes,
                       const std::function<void(In&)>& particles);

}  // namespace checkpoint_file
}  // namespace compaction
