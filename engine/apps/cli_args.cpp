// Flags map one to one onto the JSON keys of the scene (--cells-per-unit -> cells_per_unit),
// so that a flag and a scene file say the same thing and are validated by the same code.
#include "cli_args.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <map>

#include "compaction/params_json.hpp"
#include "compaction/text_numbers.hpp"

namespace compaction::cli {

using nlohmann::json;

namespace {

enum class Kind { real, integer, unsigned_integer, text, real_list };

struct Flag {
  const char* key;  // JSON key of SceneParams
  Kind kind;
  const char* help;
};

const std::map<std::string, Flag>& flags() {
  static const std::map<std::string, Flag> table = {
      {"--S", {"S", Kind::real, "Mach number V / sqrt(E/rho), in (0, 1)            [4e-3]"}},
      {"--R", {"R", Kind::real, "relative strength q_y / E, in (0, 1)              [1e-5]"}},
      {"--phi", {"phi", Kind::real, "solid area fraction, in [0.2, 0.8]               [0.4]"}},
      {"--geometry", {"geometry", Kind::text, "pseudo1d | full2d                        [pseudo1d]"}},
      {"--n-cols", {"n_cols", Kind::integer, "unit cells across (full2d)                    [17]"}},
      {"--n-rows", {"n_rows", Kind::integer, "unit cells along the compression axis         [34]"}},
      {"--cells-per-unit", {"cells_per_unit", Kind::integer, "grid cells per unit cell side   [20]"}},
      {"--particles-per-cell", {"particles_per_cell", Kind::integer, "particles per cell and direction, 1-4 [2]"}},
      {"--cfl", {"cfl", Kind::real, "CFL number of the time step, in (0, 2)           [0.5]"}},
      {"--transfer", {"transfer", Kind::text, "apic | pic_flip                              [apic]"}},
      {"--flip-ratio", {"flip_ratio", Kind::real, "FLIP share of pic_flip, in [0, 1]        [0.95]"}},
      {"--contact", {"contact", Kind::text, "plate contact: bonded | unilateral         [bonded]"}},
      {"--gradient", {"gradient", Kind::text, "force and Fe gradient: mls | bspline          [mls]"}},
      {"--perturbation", {"perturbation", Kind::real, "random particle offset / spacing, [0, 0.5] [0]"}},
      {"--seed", {"seed", Kind::unsigned_integer, "seed of the perturbation                  [1]"}},
      {"--eps-end", {"eps_end", Kind::real, "final imposed strain; <= 0: fully dense, 1 - phi [1-phi]"}},
      {"--d-eps", {"d_eps", Kind::real, "imposed strain between frames               [0.002]"}},
      {"--snapshot-eps", {"snapshot_eps", Kind::real_list, "strains of particle snapshots, comma list [0.2]"}},
      {"--rho", {"rho", Kind::real, "density of the solid, kg/m^2                  [1000]"}},
      {"--nu", {"nu", Kind::real, "Poisson's ratio, in [0, 0.49]                    [0.3]"}},
      {"--q-y", {"q_y", Kind::real, "yield strength, N/m                             [250]"}},
      {"--h0", {"h0", Kind::real, "specimen height, m (only scales time)             [1]"}},
      {"--threads", {"threads", Kind::integer, "threads of the time step                    [1]"}},
  };
  return table;
}

bool to_real(const std::string& s, double& v) { return parse_finite_real(s, v); }

// The value of a flag as JSON, or an error message.
std::string convert(const Flag& f, const std::string& text, json& value) {
  switch (f.kind) {
    case Kind::real: {
      double v;
      if (!to_real(text, v)) return "expected a finite number, got '" + text + "'";
      value = v;
      return {};
    }
    case Kind::integer:
    case Kind::unsigned_integer: {
      long long v;
      if (!parse_int(text, v)) return "expected an integer, got '" + text + "'";
      if (f.kind == Kind::unsigned_integer) {
        if (v < 0) return "expected a non-negative integer, got '" + text + "'";
        value = static_cast<std::uint64_t>(v);
      } else {
        value = v;
      }
      return {};
    }
    case Kind::text:
      value = text;
      return {};
    case Kind::real_list: {
      value = json::array();
      std::size_t start = 0;
      while (start <= text.size()) {
        const std::size_t comma = std::min(text.find(',', start), text.size());
        const std::string item = text.substr(start, comma - start);
        double v;
        if (item.empty() && text.empty()) break;  // "--snapshot-eps ''": no snapshots
        if (!to_real(item, v)) return "expected comma-separated numbers, got '" + text + "'";
        value.push_back(v);
        start = comma + 1;
      }
      return {};
    }
  }
  return "unhandled flag kind";
}

std::string flag_of(const std::string& key) {
  for (const auto& [name, f] : flags())
    if (key == f.key) return name;
  return key.empty() ? "scene" : key;
}

}  // namespace

std::vector<std::string> parse(int argc, const char* const* argv, Options& out) {
  std::vector<std::string> errors;
  json scene = json::object();
  json overrides = json::object();
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i], value;
    const auto eq = arg.find('=');
    const bool inline_value = arg.rfind("--", 0) == 0 && eq != std::string::npos;
    if (inline_value) value = arg.substr(eq + 1), arg = arg.substr(0, eq);
    if (arg == "-h" || arg == "--help") {
      out.help = true;
      continue;
    }
    if (arg == "--version") {
      out.version = true;
      continue;
    }
    auto take_value = [&]() -> bool {
      if (inline_value) return true;
      if (i + 1 >= argc) {
        errors.push_back(arg + ": missing value");
        return false;
      }
      value = argv[++i];
      return true;
    };
    if (arg == "--out") {
      if (take_value()) out.out_dir = value;
    } else if (arg == "--progress") {
      if (!take_value()) continue;
      static const std::map<std::string, ProgressMode> modes = {
          {"auto", ProgressMode::automatic}, {"bar", ProgressMode::bar},
          {"log", ProgressMode::log},        {"json", ProgressMode::json},
          {"none", ProgressMode::none}};
      const auto it = modes.find(value);
      if (it == modes.end()) errors.push_back("--progress: expected auto|bar|log|json|none, got '" + value + "'");
      else out.progress = it->second;
    } else if (arg == "--scene") {
      if (!take_value()) continue;
      std::ifstream f(value);
      if (!f) {
        errors.push_back("--scene: cannot read '" + value + "'");
        continue;
      }
      try {
        scene = json::parse(f);
      } catch (const json::exception& e) {
        errors.push_back("--scene: '" + value + "' is not valid JSON: " + e.what());
      }
    } else if (const auto it = flags().find(arg); it != flags().end()) {
      if (!take_value()) continue;
      json v;
      if (std::string why = convert(it->second, value, v); !why.empty()) {
        errors.push_back(arg + ": " + why);
      } else {
        overrides[it->second.key] = v;
      }
    } else {
      errors.push_back(arg + ": unknown option (see --help)");
    }
  }
  if (out.help || out.version) return {};
  if (!errors.empty()) return errors;
  if (!scene.is_object()) return {"--scene: the scene file must hold a JSON object"};
  scene.update(overrides);  // flags win over the scene file
  for (const FieldError& e : from_json(scene, out.params)) {
    errors.push_back(flag_of(e.field) + (e.field.empty() ? "" : " (" + e.field + ")") + ": " +
                     e.message);
  }
  if (out.out_dir.empty()) errors.push_back("--out: required (the bundle's directory)");
  return errors;
}

std::string help_text() {
  std::string s =
      "compaction-run: run one MPM simulation of a structured porous column under confined\n"
      "compression (Blatny et al., PRL 128, 228002, 2022) and write its result bundle.\n\n"
      "usage: compaction-run [--scene FILE] [flags] --out DIR\n\n"
      "  --scene FILE         scene parameters as JSON (keys as the flags, '-' -> '_');\n"
      "                       flags given as well override the file's values\n"
      "  --out DIR            where to write the bundle (summary.json, frames.csv,\n"
      "                       spacetime.npy/.png, snapshot_<eps>.npy/.png)\n"
      "  --progress MODE      auto (bar on a terminal, else log lines) | bar | log |\n"
      "                       json (one JSON object per line on stdout) | none   [auto]\n"
      "  --version            print the engine version and source revision\n"
      "  -h, --help           this text\n\n"
      "scene parameters [default]:\n";
  for (const auto& [name, f] : flags()) {
    std::string line = "  " + name + " X";
    line.resize(24, ' ');
    s += line + " " + f.help + "\n";
  }
  s += "\nE = q_y / R and V = S sqrt(E / rho): runs with equal S, R and phi give the same\n"
       "dimensionless result whatever rho, nu, q_y and h0 are.\n"
       "Yield: sqrt(3/2 s:s) <= q_y, s the 2D deviator of the Kirchhoff stress.\n\n"
       "exit status: 0 bundle written (status ok or unstable), 2 invalid input,\n"
       "             3 cancelled by SIGINT/SIGTERM (bundle written), 1 other error\n";
  return s;
}

}  // namespace compaction::cli
