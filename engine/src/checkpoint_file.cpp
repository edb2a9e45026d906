// The checkpoint file (schema/checkpoint-format.md): a magic, the format version, a JSON header
// (engine version, scene, where the run stands), the binary sections of the state in a fixed
// order, and a CRC-32 of everything before it. Numbers are written as the machine holds them
// (x86-64: little-endian IEEE 754), so restored doubles are the written bits.
#include "checkpoint_file.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <chrono>
#include <fstream>
#include <iterator>

#include <nlohmann/json.hpp>

#include "compaction/params_json.hpp"

namespace compaction::checkpoint_file {

namespace {

using nlohmann::json;

constexpr char kMagic[8] = {'C', 'M', 'P', 'C', 'K', 'P', 'T', '\n'};
constexpr std::uint32_t kFormatVersion = 3;

// The sections below list every field of these types. A field added to one of them changes its
// size and stops the build here: write it into the checkpoint (and read it back), describe it
// in schema/checkpoint-format.md and raise kFormatVersion. (Each geometry's particles: in its
// own file.)
static_assert(sizeof(Clock) == 40, "Clock changed: add the field to the checkpoint");
static_assert(sizeof(StepMeasure) == 48, "StepMeasure changed: add the field to the checkpoint");
static_assert(sizeof(Frame) == 9 * sizeof(double), "Frame changed: raise kFormatVersion");
static_assert(sizeof(Snapshot) == 128, "Snapshot changed: add the field to the checkpoint");
static_assert(sizeof(SpaceTimeMap) == 40, "SpaceTimeMap changed: add the field to the checkpoint");
static_assert(sizeof(StageTimes) == 32, "StageTimes changed: add the field to the checkpoint");
static_assert(sizeof(RunResult) == 280, "RunResult changed: add the field to the checkpoint");
static_assert(sizeof(RunPosition) == 48, "RunPosition changed: add the field to the checkpoint");

std::uint32_t crc_of(const char* data, std::size_t n) {
  uLong crc = crc32(0L, Z_NULL, 0);
  while (n > 0) {  // zlib takes the length as uInt
    const uInt chunk = static_cast<uInt>(std::min<std::size_t>(n, 1u << 30));
    crc = crc32(crc, reinterpret_cast<const Bytef*>(data), chunk);
    data += chunk, n -= chunk;
  }
  return static_cast<std::uint32_t>(crc);
}

void put_map(Out& o, const SpaceTimeMap& m) {
  o.put(static_cast<std::int32_t>(m.n_rows));
  o.put(static_cast<std::int32_t>(m.n_frames));
  o.put(m.row_height);
  o.put_array(m.values);
}

void get_map(In& in, SpaceTimeMap& m) {
  m.n_rows = in.get<std::int32_t>();
  m.n_frames = in.get<std::int32_t>();
  m.row_height = in.get<double>();
  in.get_array(m.values);
  if (m.values.size() != static_cast<std::size_t>(m.n_rows) * static_cast<std::size_t>(m.n_frames)) {
    throw CheckpointRefused("checkpoint damaged: a map's size does not match its rows and frames");
  }
}

// The scene as the checkpoint compares it: everything but the thread count.
json scene_identity(json scene) {
  scene.erase("threads");
  return scene;
}

// The first difference between the scene of a checkpoint and the scene to run, as text.
std::string scene_difference(const json& theirs, const json& ours) {
  for (const auto& [key, value] : ours.items()) {
    if (!theirs.contains(key)) return key + " is not in the checkpoint's scene";
    if (theirs[key] != value) {
      return key + " is " + theirs[key].dump() + " there and " + value.dump() + " here";
    }
  }
  for (const auto& [key, value] : theirs.items()) {
    if (!ours.contains(key)) return key + " (" + value.dump() + ") is not a key of this engine's scene";
  }
  return "";
}

void write_file_atomically(const std::string& path, const std::string& data) {
  const std::string tmp = path + ".tmp";
  const auto fail = [&](const char* what) {
    const std::string why = std::strerror(errno);
    ::unlink(tmp.c_str());
    throw std::runtime_error(std::string("checkpoint ") + path + ": cannot " + what + ": " + why);
  };
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) fail("create its temporary file");
  std::size_t done = 0;
  while (done < data.size()) {
    const ssize_t n = ::write(fd, data.data() + done, data.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      ::close(fd);
      fail("write");
    }
    done += static_cast<std::size_t>(n);
  }
  if (::fsync(fd) != 0) {
    ::close(fd);
    fail("flush");
  }
  ::close(fd);
  if (std::rename(tmp.c_str(), path.c_str()) != 0) fail("rename its temporary file");
}

std::string read_whole(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw CheckpointRefused("cannot read the checkpoint '" + path + "'");
  return std::string(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
}

struct Parsed {
  json header;
  std::size_t payload_begin = 0, payload_end = 0;
};

// Magic, format version, checksum and header of a checkpoint held in memory.
Parsed parse(const std::string& bytes, const std::string& path) {
  const std::size_t fixed = sizeof kMagic + 2 * sizeof(std::uint32_t);
  if (bytes.size() < fixed + sizeof(std::uint32_t) ||
      std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    throw CheckpointRefused("'" + path + "' is not a compaction checkpoint");
  }
  In in(bytes, sizeof kMagic, bytes.size());
  const auto format = in.get<std::uint32_t>();
  if (format != kFormatVersion) {
    throw CheckpointRefused("checkpoint format " + std::to_string(format) + ", this engine reads " +
                            std::to_string(kFormatVersion));
  }
  const std::size_t end = bytes.size() - sizeof(std::uint32_t);
  std::uint32_t stored;
  std::memcpy(&stored, bytes.data() + end, sizeof stored);
  if (crc_of(bytes.data(), end) != stored) {
    throw CheckpointRefused("checkpoint damaged: its CRC-32 checksum does not match");
  }
  const auto header_bytes = in.get<std::uint32_t>();
  if (header_bytes > end - fixed) throw CheckpointRefused("checkpoint truncated (header)");
  Parsed out;
  out.header = json::parse(bytes.begin() + fixed, bytes.begin() + fixed + header_bytes, nullptr,
                           false);
  if (!out.header.is_object()) throw CheckpointRefused("checkpoint damaged: its header is not JSON");
  out.payload_begin = fixed + header_bytes;
  out.payload_end = end;
  return out;
}

CheckpointInfo info_of(const json& h, std::uint64_t bytes) {
  CheckpointInfo info;
  try {
    info.engine_version = h.at("engine_version").get<std::string>();
    info.source_revision = h.at("source_revision").get<std::string>();
    info.step = h.at("step").get<std::int64_t>();
    info.t = h.at("t").get<double>();
    info.eps = h.at("eps").get<double>();
    info.frames = h.at("frames").get<std::int64_t>();
    info.threads = h.at("threads").get<int>();
  } catch (const json::exception& e) {
    throw CheckpointRefused(std::string("checkpoint damaged: header: ") + e.what());
  }
  info.bytes = bytes;
  return info;
}

}  // namespace

const char* In::take(std::size_t n) {
  if (n > end_ - pos_) throw CheckpointRefused("checkpoint truncated");
  const char* p = buf_.data() + pos_;
  pos_ += n;
  return p;
}

void put_particle_set(Out& o, std::size_t n, double mass, double vol0) {
  o.put(static_cast<std::uint64_t>(n)), o.put(mass), o.put(vol0);
}

void get_particle_set(In& in, std::size_t n, double mass, double vol0) {
  const auto theirs = in.get<std::uint64_t>();
  const double their_mass = in.get<double>(), their_vol0 = in.get<double>();
  if (theirs != n || their_mass != mass || their_vol0 != vol0) {
    throw CheckpointRefused("the checkpoint's particles (" + std::to_string(theirs) +
                            ") are not those this scene builds (" + std::to_string(n) + ")");
  }
}

CheckpointInfo write(const std::string& path, const SceneParams& p, const Clock& clock,
                     const StepMeasure& measure, double eps, std::size_t n_particles,
                     const RunResult& r, const RunPosition& at, const std::string& movie_file,
                     std::size_t reserve, const std::function<void(Out&)>& particles) {
  const auto t0 = std::chrono::steady_clock::now();
  const json header = {{"engine_version", engine_version()},
                       {"source_revision", source_revision()},
                       {"scene", to_json(p)},
                       {"step", clock.step},
                       {"t", clock.t},
                       {"eps", eps},
                       {"frames", at.frame},
                       {"threads", p.threads},
                       {"n_particles", n_particles}};
  const std::string header_text = header.dump();

  Out o;
  o.bytes().reserve(reserve + r.spacetime.values.size() * 8 + (1 << 16));
  o.put_bytes(std::string(kMagic, sizeof kMagic));
  o.put(kFormatVersion);
  o.put(static_cast<std::uint32_t>(header_text.size()));
  o.put_bytes(header_text);

  // 1. clock and the last step's measures (the next step's rows and time step read them)
  o.put(clock.t), o.put(clock.step), o.put(clock.top_impulse), o.put(clock.bottom_impulse);
  o.put(clock.plate_work);
  const StepMeasure& m = measure;
  o.put(m.max_v2), o.put(m.y_min), o.put(m.y_max), o.put(m.x_min), o.put(m.x_max);
  o.put(static_cast<std::uint8_t>(m.bad_jacobian));
  // 2. the loop's position
  o.put(at.frame), o.put(at.eps_frame_begin), o.put(at.snapshots_passed);
  o.put(at.wall_seconds), o.put(at.loop_seconds);
  // 3. particles (the geometry's)
  particles(o);
  // 4. the result so far
  o.put(r.eps_reached);
  o.put(r.stage_seconds.p2g), o.put(r.stage_seconds.grid_update), o.put(r.stage_seconds.g2p);
  o.put(r.stage_seconds.diagnostics);
  o.put_array(r.frames);
  put_map(o, r.spacetime);
  put_map(o, r.velocity);
  o.put(static_cast<std::uint64_t>(r.snapshots.size()));
  for (const Snapshot& snap : r.snapshots) {
    o.put(snap.eps);
    o.put_array(snap.x), o.put_array(snap.y), o.put_array(snap.strain_rate);
    o.put_array(snap.plastic_strain), o.put_array(snap.jacobian);
  }
  // 5. the movie written so far (its file is whole after each of its frames)
  o.put(at.movie_frames);
  std::string movie;
  if (at.movie_frames > 0 && !movie_file.empty()) {
    std::ifstream f(movie_file, std::ios::binary);
    if (!f) throw std::runtime_error("checkpoint " + path + ": cannot read the movie " + movie_file);
    movie.assign(std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>());
  }
  o.put(static_cast<std::uint64_t>(movie.size()));
  o.put_bytes(movie);
  o.put(crc_of(o.bytes().data(), o.bytes().size()));

  write_file_atomically(path, o.bytes());
  CheckpointInfo info = info_of(header, o.bytes().size());
  info.write_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return info;
}

CheckpointInfo restore(const std::string& path, const SceneParams& p, Clock& clock,
                       StepMeasure& measure, std::size_t n_particles, int map_rows,
                       RunResult& r, RunPosition& at, std::string* movie_bytes,
                       const std::function<void(In&)>& particles) {
  const std::string bytes = read_whole(path);
  const Parsed parsed = parse(bytes, path);
  const CheckpointInfo info = info_of(parsed.header, bytes.size());
  if (info.engine_version != engine_version()) {
    throw CheckpointRefused("the checkpoint was written by engine " + info.engine_version +
                            ", this is engine " + engine_version());
  }
  if (!parsed.header.contains("scene") || !parsed.header["scene"].is_object()) {
    throw CheckpointRefused("checkpoint damaged: its header has no scene");
  }
  const std::string diff =
      scene_difference(scene_identity(parsed.header["scene"]), scene_identity(to_json(p)));
  if (!diff.empty()) throw CheckpointRefused("the checkpoint is of another scene: " + diff);

  In in(bytes, parsed.payload_begin, parsed.payload_end);
  clock.t = in.get<double>();
  clock.step = in.get<std::int64_t>();
  clock.top_impulse = in.get<double>();
  clock.bottom_impulse = in.get<double>();
  clock.plate_work = in.get<double>();
  StepMeasure& m = measure;
  m.max_v2 = in.get<double>(), m.y_min = in.get<double>(), m.y_max = in.get<double>();
  m.x_min = in.get<double>(), m.x_max = in.get<double>();
  m.bad_jacobian = in.get<std::uint8_t>() != 0;
  at.frame = in.get<std::int64_t>();
  at.eps_frame_begin = in.get<double>();
  at.snapshots_passed = in.get<std::uint64_t>();
  at.wall_seconds = in.get<double>();
  at.loop_seconds = in.get<double>();

  particles(in);

  const std::size_t n = n_particles;
  r.eps_reached = in.get<double>();
  r.stage_seconds.p2g = in.get<double>();
  r.stage_seconds.grid_update = in.get<double>();
  r.stage_seconds.g2p = in.get<double>();
  r.stage_seconds.diagnostics = in.get<double>();
  in.get_array(r.frames);
  get_map(in, r.spacetime);
  get_map(in, r.velocity);
  const auto n_snapshots = in.get<std::uint64_t>();
  r.snapshots.clear();
  for (std::uint64_t k = 0; k < n_snapshots; ++k) {
    Snapshot& snap = r.snapshots.emplace_back();
    snap.eps = in.get<double>();
    in.get_array(snap.x, n, "a snapshot's x"), in.get_array(snap.y, n, "a snapshot's y");
    in.get_array(snap.strain_rate, n, "a snapshot's strain rate");
    in.get_array(snap.plastic_strain, n, "a snapshot's plastic strain");
    in.get_array(snap.jacobian, n, "a snapshot's jacobian");
  }
  at.movie_frames = in.get<std::int64_t>();
  std::vector<char> movie;
  in.get_array(movie);
  if (movie_bytes) movie_bytes->assign(movie.begin(), movie.end());
  if (!in.at_end()) throw CheckpointRefused("checkpoint damaged: bytes left after its sections");
  if (static_cast<std::int64_t>(r.frames.size()) != at.frame || r.spacetime.n_rows != map_rows ||
      clock.step != info.step) {
    throw CheckpointRefused("checkpoint damaged: its sections disagree with its header");
  }
  return info;
}

}  // namespace compaction::checkpoint_file

namespace compaction {

CheckpointInfo read_checkpoint_info(const std::string& path) {
  using namespace checkpoint_file;
  const std::string bytes = read_whole(path);
  return info_of(parse(bytes, path).header, bytes.size());
}

}  // namespace compaction
