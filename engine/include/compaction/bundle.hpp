// The result bundle: a directory holding one run's summary, arrays and pictures.
//
//   summary.json           parameters, versions, counts, timings, status (schema/result.schema.json)
//   frames.csv             per-frame observables: eps, plate stresses (also / q_y), diagnostics
//   spacetime.npy          float32 [n_frames, n_rows]: plastic strain rate / (V / h0)
//   spacetime.png          a picture of it (height up, eps to the right)
//   snapshot_<eps>.npy     float32 [n_particles, 5]: x, y, strain rate / (V/h0), plastic strain, J
//   snapshot_<eps>.png     the particles coloured by plastic strain rate
//   velocity.npy           float32 [n_frames, n_rows]: row-averaged vertical velocity / V
//   movie.bin              the particles every movie_d_eps of strain (compaction/movie.hpp),
//                          written during the run (RunControl::movie_file), not by write_bundle
//
// The .npy files follow NumPy's documented format 1.0 (schema/bundle-format.md).
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "compaction/params.hpp"
#include "compaction/result.hpp"

namespace compaction {

// How many files a bundle holds: the five above without a snapshot or a movie, two per
// snapshot, one movie.
inline constexpr std::size_t kBundleFixedFiles = 5;
inline constexpr std::size_t kFilesPerSnapshot = 2;
inline constexpr std::size_t kMovieFiles = 1;
inline constexpr std::size_t kMaxBundleFiles =
    kBundleFixedFiles + kFilesPerSnapshot * kMaxSnapshots + kMovieFiles;

// An upper bound of the bytes a run's bundle takes (the snapshots' particle tables, 20 bytes
// per particle, and the movie's frames, 5 per particle, dominate), from the parameters alone,
// so a service can refuse a scene whose result it could not take.
std::size_t bundle_size_bound(const SceneParams& p);
// The part of that bound the movie takes.
std::size_t movie_size_bound(const SceneParams& p);

// Writes the whole bundle into dir (created if needed). summary.json goes last, by rename, so
// that its presence marks a complete bundle; `summary_extras` are fields added to it (the
// runner's classification). Throws std::runtime_error on I/O errors.
void write_bundle(const std::filesystem::path& dir, const SceneParams& p, const RunResult& r,
                  const nlohmann::json& summary_extras = nlohmann::json::object());

// The summary.json of a run, without the big arrays.
nlohmann::json summary_json(const SceneParams& p, const RunResult& r);

// Reads a bundle back: the parameters, the status and counts from summary.json, the frames from
// frames.csv, the space-time map and the snapshots from their .npy files.
// Throws std::runtime_error naming the file when something is missing or malformed.
struct Bundle {
  SceneParams params;
  RunResult result;
  nlohmann::json summary;
};
Bundle read_bundle(const std::filesystem::path& dir);

}  // namespace compaction
