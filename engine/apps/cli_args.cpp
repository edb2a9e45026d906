// Flags map one to one onto the JSON keys of the scene (--cells-per-unit -> cells_per_unit),
// so that a flag and a scene file say the same thing and are validated by the same code
// (validate(), whose ranges the help prints from compaction::limits; the defaults it prints are
// SceneParams').
#include "cli_args.hpp"

#include <filesystem>
#include <fstream>
#include <string_view>

#include <nlohmann/json.hpp>

#include "command_line.hpp"
#include "compaction/checkpoint.hpp"
#include "compaction/number_text.hpp"
#include "compaction/params_json.hpp"
#include "compaction/presets.hpp"

namespace compaction::cli {

using nlohmann::json;

namespace {

enum class Kind { real, integer, unsigned_integer, text, real_list };

struct SceneFlag {
  const char* flag;
  const char* key;     // JSON key of SceneParams
  Kind kind;
  const Range* range;  // validate()'s, or nullptr
  const char* help;
};

const SceneFlag kSceneFlags[] = {
    {"--S", "S", Kind::real, &limits::S, "Mach number V / sqrt(E/rho)"},
    {"--R", "R", Kind::real, &limits::R, "relative strength q_y / E"},
    {"--phi", "phi", Kind::real, &limits::phi, "solid area fraction"},
    {"--geometry", "geometry", Kind::text, nullptr, "pseudo1d | full2d | pseudo1d_3d"},
    {"--n-cols", "n_cols", Kind::integer, &limits::n_cols, "unit cells across (full2d)"},
    {"--n-rows", "n_rows", Kind::integer, &limits::n_rows, "unit cells along the compression axis"},
    {"--structure", "structure", Kind::text, nullptr,
     "voids: regular | random (areas and centres drawn from --seed)"},
    {"--cells-per-strut", "cells_per_strut", Kind::real, &limits::cells_per_strut,
     "grid cells across the thinnest strut (sets the grid at every phi)"},
    {"--cells-per-unit", "cells_per_unit", Kind::integer, &limits::cells_per_unit,
     "grid cells per unit cell side, overriding --cells-per-strut (0: not set)"},
    {"--particles-per-cell", "particles_per_cell", Kind::integer, &limits::particles_per_cell,
     "particles per cell and direction"},
    {"--cfl", "cfl", Kind::real, &limits::cfl, "CFL number of the time step"},
    {"--transfer", "transfer", Kind::text, nullptr, "apic | pic_flip"},
    {"--flip-ratio", "flip_ratio", Kind::real, &limits::flip_ratio, "FLIP share of pic_flip"},
    {"--contact", "contact", Kind::text, nullptr, "plate contact: bonded | unilateral"},
    {"--gradient", "gradient", Kind::text, nullptr, "force and Fe gradient: mls | bspline"},
    {"--pore-contact", "pore_contact", Kind::text, nullptr,
     "closing pores: single_field | split_fields (two velocity fields until a gap closes) | "
     "auto (split_fields where 3 grid cells span the thinnest strut)"},
    {"--perturbation", "perturbation", Kind::real, &limits::perturbation,
     "random particle offset / spacing"},
    {"--seed", "seed", Kind::unsigned_integer, nullptr,
     "seed of the perturbation and the random structure"},
    {"--eps-end", "eps_end", Kind::real, &limits::eps_end,
     "final imposed strain (<= 0: until fully dense, 1 - phi)"},
    {"--d-eps", "d_eps", Kind::real, &limits::d_eps, "imposed strain between frames"},
    {"--snapshot-eps", "snapshot_eps", Kind::real_list, &limits::snapshot_eps,
     "strains of particle snapshots, comma list ('': none), each"},
    {"--movie-d-eps", "movie_d_eps", Kind::real, &limits::movie_d_eps,
     "strain between the frames of movie.bin (0: no movie; else >= --d-eps)"},
    {"--rho", "rho", Kind::real, &limits::rho, "density of the solid, kg/m^2"},
    {"--nu", "nu", Kind::real, &limits::nu, "Poisson's ratio"},
    {"--q-y", "q_y", Kind::real, &limits::q_y, "yield strength, N/m"},
    {"--h0", "h0", Kind::real, &limits::h0, "specimen height, m (only scales time)"},
    {"--threads", "threads", Kind::integer, &limits::threads, "threads of the time step"},
};

// The value of a flag as JSON; throws UsageError naming the value.
json convert(const SceneFlag& f, const std::string& text) {
  auto fail = [&](const std::string& expected) -> UsageError {
    return {f.flag, "expected " + expected + ", got '" + text + "'"};
  };
  switch (f.kind) {
    case Kind::real: {
      double v;
      if (!parse_finite_real(text, v)) throw fail("a finite number");
      return v;
    }
    case Kind::integer:
    case Kind::unsigned_integer: {
      long long v;
      if (!parse_int(text, v)) throw fail("an integer");
      if (f.kind == Kind::integer) return v;
      if (v < 0) throw fail("a non-negative integer");
      return static_cast<std::uint64_t>(v);
    }
    case Kind::text:
      return text;
    case Kind::real_list: {
      json list = json::array();
      if (text.empty()) return list;  // "--snapshot-eps ''": no snapshots
      std::size_t start = 0;
      while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        double v;
        if (!parse_finite_real(text.substr(start, comma - start), v)) {
          throw fail("comma-separated numbers");
        }
        list.push_back(v);
        start = comma + 1;
      }
      return list;
    }
  }
  throw fail("a value");
}

// The default of a field as the help shows it: SceneParams' own (the default preset's numerics).
std::string default_of(const SceneFlag& f) {
  static const SceneParams params;
  // to_json writes the strain a run goes to; the field's own default means "until dense"
  if (std::string_view(f.key) == "eps_end" && !(params.eps_end > 0)) return "1 - phi";
  static const json defaults = to_json(params);
  const json& v = defaults.at(f.key);
  if (v.is_string()) return v.get<std::string>();
  if (v.is_array()) {
    std::string s;
    for (const json& x : v) {
      if (!s.empty()) s += ',';
      s += x.dump();
    }
    return s;
  }
  return v.dump();
}

std::string flag_of(const std::string& key) {
  for (const SceneFlag& f : kSceneFlags)
    if (key == f.key) return f.flag;
  return key.empty() ? "--scene" : key;
}

const char* kAbout =
    "run one MPM simulation of a structured porous column under confined\n"
    "compression (Blatny et al., PRL 128, 228002, 2022) and write its result bundle.";

const char* kNotes =
    "E = q_y / R and V = S sqrt(E / rho): runs with equal S, R and phi give the same\n"
    "dimensionless result whatever rho, nu, q_y and h0 are.\n"
    "Yield: sqrt(3/2 s:s) <= q_y, s the 2D deviator of the Kirchhoff stress.\n\n"
    "Checkpoints: with --checkpoint FILE the run writes its whole state to FILE (atomically)\n"
    "every --checkpoint-every seconds of wall time and when SIGTERM/SIGINT stops it;\n"
    "--resume FILE goes on from such a file and ends with the bits of an uninterrupted run\n"
    "(same engine version, scene and threads). Format: schema/checkpoint-format.md.\n\n"
    "exit status: 0 bundle written (status ok or unstable), or --check: the scene is valid,\n"
    "             2 invalid input,\n"
    "             3 cancelled by SIGINT/SIGTERM (bundle written), 1 other error,\n"
    "             4 the --resume checkpoint is refused (another engine version or scene,\n"
    "             damaged; the reason on stderr, nothing written)\n";

}  // namespace

std::optional<int> parse(int argc, const char* const* argv, Options& out) {
  CommandLine cl("compaction-run", kAbout, "[--scene FILE] [flags] --out DIR");
  json scene = json::object();
  json overrides = json::object();
  cl.custom(
      "--scene",
      [&](const std::string& path) {
        std::ifstream f(path);
        if (!f) throw UsageError{"--scene", "cannot read '" + path + "'"};
        try {
          scene = json::parse(f);
        } catch (const json::exception& e) {
          throw UsageError{"--scene", "'" + path + "' is not valid JSON: " + e.what()};
        }
        if (!scene.is_object()) throw UsageError{"--scene", "the scene file must hold a JSON object"};
      },
      "FILE",
      "scene parameters as JSON (keys as the flags, '-' -> '_');\n"
      "flags given as well override the file's values");
  std::string preset_name;
  cl.text("--preset", preset_name, "NAME",
          "numerics preset: " + preset_names() + " (compaction/presets.hpp); a scene\n"
          "file's and the flags' own values override it key by key",
          std::string(kDefaultPreset), true);
  cl.text("--out", out.out_dir, "DIR",
          "where to write the bundle (summary.json, frames.csv,\n"
          "spacetime.npy/.png, snapshot_<eps>.npy/.png)");
  cl.custom(
      "--progress",
      [&](const std::string& v) {
        static const std::pair<const char*, ProgressMode> modes[] = {
            {"auto", ProgressMode::automatic}, {"bar", ProgressMode::bar},
            {"log", ProgressMode::log},        {"json", ProgressMode::json},
            {"none", ProgressMode::none}};
        for (const auto& [name, mode] : modes) {
          if (v == name) {
            out.progress = mode;
            return;
          }
        }
        throw UsageError{"--progress", "expected auto|bar|log|json|none, got '" + v + "'"};
      },
      "MODE",
      "auto (bar on a terminal, else log lines) | bar | log |\n"
      "json (one JSON object per line on stdout) | none",
      "auto");
  cl.text("--checkpoint", out.checkpoint_file, "FILE",
          "write checkpoints of the run's whole state to FILE (a temporary file\n"
          "renamed over it), every --checkpoint-every seconds and on SIGTERM/SIGINT");
  bool every_given = false;
  cl.custom(
      "--checkpoint-every",
      [&](const std::string& v) {
        double s;
        if (!parse_finite_real(v, s)) {
          throw UsageError{"--checkpoint-every", "expected a finite number, got '" + v + "'"};
        }
        if (!kCheckpointEveryRange.contains(s)) {
          throw UsageError{"--checkpoint-every",
                           "must be in " + to_string(kCheckpointEveryRange) + ", got " + v};
        }
        out.checkpoint_every = s;
        every_given = true;
      },
      "SECONDS",
      "wall time between checkpoints (0: only on SIGTERM/SIGINT), in " +
          to_string(kCheckpointEveryRange),
      text::num(kDefaultCheckpointEvery));
  cl.text("--resume", out.resume_file, "FILE",
          "go on from this checkpoint (of the same engine version and scene)");
  cl.flag("--check", out.check,
          "validate the scene and print it as JSON with its grid (cells per unit\n"
          "cell and across the strut), without running it or needing --out");
  for (const SceneFlag& f : kSceneFlags) {
    std::string help = f.help;
    if (f.range) help += ", in " + to_string(*f.range);
    cl.custom(
        f.flag, [&overrides, &f](const std::string& v) { overrides[f.key] = convert(f, v); }, "X",
        help, default_of(f));
  }
  cl.notes(kNotes);

  if (const auto code = cl.parse(argc, argv)) return code;
  int code = 0;
  const Preset* preset = find_preset(preset_name.empty() ? kDefaultPreset : preset_name);
  if (!preset) {
    return cl.fail("--preset", "unknown preset '" + preset_name + "': the presets are " + preset_names());
  }
  // The preset, then the scene file, then the flags: each later one wins key by key.
  json composed = preset_json(*preset);
  composed.update(scene);
  composed.update(overrides);
  for (const FieldError& e : from_json(composed, out.params)) {
    const std::string flag = flag_of(e.field);
    const std::string geometry = flag != "--geometry" && out.params.geometry != Geometry::pseudo1d
                                     ? std::string(" with --geometry ") + to_string(out.params.geometry)
                                     : std::string();
    code = cl.fail(flag + (e.field.empty() ? "" : " (" + e.field + ")") + geometry, e.message);
  }
  if (!preset_name.empty()) {
    out.preset = preset->name;
  } else if (const Preset* same = matching_preset(out.params)) {
    out.preset = same->name;
  } else {
    out.preset = std::string(kDefaultPreset);
  }
  out.overridden = overridden_keys(*find_preset(out.preset), out.params);
  if (out.out_dir.empty() && !out.check) {
    code = cl.fail("--out", "required (the bundle's directory)");
  }
  if (every_given && out.checkpoint_file.empty()) {
    code = cl.fail("--checkpoint-every", "needs --checkpoint FILE");
  }
  if (!every_given) out.checkpoint_every = kDefaultCheckpointEvery;
  if (!out.resume_file.empty() && !std::filesystem::is_regular_file(out.resume_file)) {
    code = cl.fail("--resume", "no such file '" + out.resume_file + "'");
  }
  return code ? std::optional<int>(code) : std::nullopt;
}

}  // namespace compaction::cli
