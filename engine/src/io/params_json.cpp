// Strict JSON reading and writing of SceneParams.
#include "compaction/params_json.hpp"

#include <cmath>
#include <functional>
#include <map>

namespace compaction {

using nlohmann::json;

json to_json(const SceneParams& p) {
  return json{
      {"S", p.S},
      {"R", p.R},
      {"phi", p.phi},
      {"rho", p.rho},
      {"nu", p.nu},
      {"q_y", p.q_y},
      {"h0", p.h0},
      {"geometry", to_string(p.geometry)},
      {"n_cols", p.n_cols},
      {"n_rows", p.n_rows},
      {"structure", to_string(p.structure)},
      {"cells_per_strut", p.cells_per_strut},
      {"cells_per_unit", p.cells_per_unit},
      {"particles_per_cell", p.particles_per_cell},
      {"cfl", p.cfl},
      {"transfer", to_string(p.transfer)},
      {"flip_ratio", p.flip_ratio},
      {"gradient", to_string(p.gradient)},
      {"contact", to_string(p.contact)},
      {"pore_contact", to_string(p.pore_contact)},
      {"perturbation", p.perturbation},
      {"seed", p.seed},
      {"eps_end", p.eps_final()},
      {"d_eps", p.d_eps},
      {"snapshot_eps", p.snapshot_eps},
      {"movie_d_eps", p.movie_d_eps},
      {"threads", p.threads},
  };
}

namespace {

using Reader = std::function<bool(const json&, SceneParams&)>;

Reader real(double SceneParams::*field) {
  return [field](const json& v, SceneParams& p) {
    if (!v.is_number()) return false;
    const double d = v.get<double>();
    if (!std::isfinite(d)) return false;
    p.*field = d;
    return true;
  };
}

Reader integer(int SceneParams::*field) {
  return [field](const json& v, SceneParams& p) {
    if (!v.is_number_integer()) return false;
    const auto i = v.get<long long>();
    if (i < -1000000000LL || i > 1000000000LL) return false;
    p.*field = static_cast<int>(i);
    return true;
  };
}

template <typename Enum>
Reader enumeration(Enum SceneParams::*field) {
  return [field](const json& v, SceneParams& p) {
    return v.is_string() && parse(v.get<std::string>(), p.*field);
  };
}

const std::map<std::string, std::pair<Reader, const char*>>& readers() {
  static const std::map<std::string, std::pair<Reader, const char*>> table = {
      {"S", {real(&SceneParams::S), "a number"}},
      {"R", {real(&SceneParams::R), "a number"}},
      {"phi", {real(&SceneParams::phi), "a number"}},
      {"rho", {real(&SceneParams::rho), "a number"}},
      {"nu", {real(&SceneParams::nu), "a number"}},
      {"q_y", {real(&SceneParams::q_y), "a number"}},
      {"h0", {real(&SceneParams::h0), "a number"}},
      {"geometry", {enumeration(&SceneParams::geometry), "\"pseudo1d\", \"full2d\" or \"pseudo1d_3d\""}},
      {"n_cols", {integer(&SceneParams::n_cols), "an integer"}},
      {"n_rows", {integer(&SceneParams::n_rows), "an integer"}},
      {"structure", {enumeration(&SceneParams::structure), "\"regular\" or \"random\""}},
      {"cells_per_strut", {real(&SceneParams::cells_per_strut), "a number"}},
      {"cells_per_unit", {integer(&SceneParams::cells_per_unit), "an integer"}},
      {"particles_per_cell", {integer(&SceneParams::particles_per_cell), "an integer"}},
      {"cfl", {real(&SceneParams::cfl), "a number"}},
      {"transfer", {enumeration(&SceneParams::transfer), "\"apic\" or \"pic_flip\""}},
      {"flip_ratio", {real(&SceneParams::flip_ratio), "a number"}},
      {"gradient", {enumeration(&SceneParams::gradient), "\"mls\" or \"bspline\""}},
      {"contact", {enumeration(&SceneParams::contact), "\"bonded\" or \"unilateral\""}},
      {"pore_contact",
       {enumeration(&SceneParams::pore_contact), "\"single_field\", \"split_fields\" or \"auto\""}},
      {"perturbation", {real(&SceneParams::perturbation), "a number"}},
      {"seed",
       {[](const json& v, SceneParams& p) {
          if (!v.is_number_unsigned()) return false;
          p.seed = v.get<std::uint64_t>();
          return true;
        },
        "a non-negative integer"}},
      {"eps_end", {real(&SceneParams::eps_end), "a number"}},
      {"d_eps", {real(&SceneParams::d_eps), "a number"}},
      {"snapshot_eps",
       {[](const json& v, SceneParams& p) {
          if (!v.is_array()) return false;
          std::vector<double> out;
          for (const auto& e : v) {
            if (!e.is_number() || !std::isfinite(e.get<double>())) return false;
            out.push_back(e.get<double>());
          }
          p.snapshot_eps = std::move(out);
          return true;
        },
        "an array of numbers"}},
      {"movie_d_eps", {real(&SceneParams::movie_d_eps), "a number"}},
      {"threads", {integer(&SceneParams::threads), "an integer"}},
  };
  return table;
}

}  // namespace

namespace {
// A value as error messages show it: short JSON text, or its kind when the text would be long.
std::string short_text(const nlohmann::json& v) {
  if (v.is_array()) return "an array of " + std::to_string(v.size()) + " values";
  if (v.is_object()) return "an object of " + std::to_string(v.size()) + " keys";
  const std::string s = v.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
  return s.size() <= 60 ? s : s.substr(0, 57) + "...";
}
}  // namespace

std::vector<FieldError> read_json(const json& j, SceneParams& p) {
  if (!j.is_object()) return {{"", "scene parameters must be a JSON object"}};
  std::vector<FieldError> errors;
  const auto& table = readers();
  const Geometry given = p.geometry;
  for (const auto& [key, value] : j.items()) {
    const auto it = table.find(key);
    if (it == table.end()) {
      errors.push_back({key, "unknown parameter"});
    } else if (!it->second.first(value, p)) {
      errors.push_back({key, std::string("must be ") + it->second.second + ", got " + short_text(value)});
    }
  }
  // A scene that moves to another geometry takes that geometry's defaults for what it leaves out.
  if (p.geometry != given) {
    const SceneParams d = scene_defaults(p.geometry);
    if (!j.contains("snapshot_eps")) p.snapshot_eps = d.snapshot_eps;
    if (!j.contains("movie_d_eps")) p.movie_d_eps = d.movie_d_eps;
  }
  return errors;
}

std::vector<FieldError> from_json(const json& j, SceneParams& p) {
  std::vector<FieldError> errors = read_json(j, p);
  if (errors.empty()) errors = validate(p);
  return errors;
}

}  // namespace compaction
